"""When the workbench commands are enabled and on which structure they open (driven through
``FreeCADGui.runCommand`` and the commands' own enabled state):

* while another tool's task dialog is open (a sketch in edit) every command is disabled, running one
  opens nothing and leaves that dialog (and the sketch's edit mode) as it was; ``panels.show`` refuses too;
* one of our own panels open never disables them: the next one replaces it;
* with nothing selected a command opens on the last structure that is not invalid, and when only invalid
  ones exist it says why in the Report view and opens nothing."""
import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

import FreeCADGui  # noqa: E402
from PySide import QtGui  # noqa: E402

from metamaterial_wb.gui import commands, panels  # noqa: E402
from metamaterial_wb.gui.panels import base  # noqa: E402
from metamaterial_wb.objects import structure  # noqa: E402
from guihelpers import click, doc, press_cancel, press_ok, process, run_panel, workbench  # noqa: E402,F401
from test_gui_panel_details import open_example  # noqa: E402

NEED_SCENE = ["MM_Flexibility", "MM_Simulate", "MM_Export", "MM_Animate", "MM_AddModule"]
ALL = ["MM_NewStructure", "MM_OpenExample"] + NEED_SCENE


def enabled(name):
    """The command's enabled state as FreeCAD asks it (``Command.get(...).isActive()``, else IsActive)."""
    get = getattr(getattr(FreeCADGui, "Command", None), "get", None)
    cmd = get(name) if get is not None else None
    if cmd is not None and hasattr(cmd, "isActive"):
        return bool(cmd.isActive())
    return bool(commands.INSTANCES[name].IsActive())


def ours_open():
    """One of our panels is the open task dialog (FreeCAD sets a closed dialog's ``form`` to None)."""
    p = panels.active()
    return p is not None and getattr(p, "form", None) is not None


def edit_a_sketch(d):
    sk = d.addObject("Sketcher::SketchObject", "Sketch")
    d.recompute()
    FreeCADGui.ActiveDocument.setEdit(sk.Name)
    process(50)
    assert FreeCADGui.Control.activeDialog() and not ours_open()
    assert FreeCADGui.ActiveDocument.getInEdit() is not None
    return sk


def leave_sketch():
    FreeCADGui.ActiveDocument.resetEdit()
    process(50)
    if FreeCADGui.Control.activeDialog() and not ours_open():
        FreeCADGui.Control.closeDialog()
        process()


def test_commands_are_disabled_and_open_nothing_while_a_sketch_is_in_edit(doc):
    sc = open_example("fish")
    assert all(enabled(n) for n in ALL), [n for n in ALL if not enabled(n)]
    edit_a_sketch(doc)
    try:
        still_on = [n for n in ALL if enabled(n)]
        assert not still_on, f"enabled while the sketch's task dialog is open: {still_on}"
        for name in ("MM_Flexibility", "MM_Simulate", "MM_NewStructure"):
            FreeCADGui.runCommand(name)
            process()
            assert not ours_open(), f"{name} opened a panel over the sketch's task dialog"
            assert FreeCADGui.Control.activeDialog(), f"{name} closed the sketch's task dialog"
            assert FreeCADGui.ActiveDocument.getInEdit() is not None, f"{name}: the sketch left edit mode"
        assert panels.show(panels.FlexibilityPanel(sc)) is None, "show() opened a panel over another dialog"
        assert sc.ViewObject.Proxy.setEdit(sc.ViewObject, 0) is False, "edit mode entered with no panel"
        assert not ours_open() and FreeCADGui.Control.activeDialog()
    finally:
        leave_sketch()
    assert not FreeCADGui.Control.activeDialog()
    assert all(enabled(n) for n in ALL), "the commands stay disabled after the sketch's dialog closed"
    p = run_panel("MM_Flexibility")
    assert p.obj is sc
    assert press_cancel()


def test_a_dialog_of_ours_closed_by_another_tool_does_not_count_as_ours(doc):
    open_example("fish")
    run_panel("MM_Simulate")
    FreeCADGui.Control.closeDialog()      # closed from outside: our reject never ran
    process()
    edit_a_sketch(doc)
    try:
        assert not enabled("MM_Flexibility")
        FreeCADGui.runCommand("MM_Flexibility")
        process()
        assert FreeCADGui.ActiveDocument.getInEdit() is not None, "the sketch's dialog was thrown away"
    finally:
        leave_sketch()


def test_our_own_panel_keeps_the_commands_enabled_and_is_replaced(doc):
    sc = open_example("fish")
    first = run_panel("MM_Flexibility")
    assert all(enabled(n) for n in ALL), [n for n in ALL if not enabled(n)]
    second = run_panel("MM_Simulate")
    assert second is not first and panels.active() is second and second.obj is sc
    assert press_cancel()


def close_panel():
    """Cancel (or Close, for panels that only have Close) in the task dialog's own button box."""
    box = base.task_buttons()
    sb = QtGui.QDialogButtonBox.StandardButton
    click(box.button(sb.Cancel) or box.button(sb.Close))
    process()
    assert panels.active() is None


def invalid_copy(d, sc):
    cp = d.copyObject(sc, False)
    cp.touch()
    d.recompute()
    assert "Invalid" in cp.State, cp.State
    return cp


@pytest.mark.parametrize("name", NEED_SCENE)
def test_with_nothing_selected_a_command_opens_on_the_valid_structure(doc, name):
    sc = open_example("fish")
    cp = invalid_copy(doc, sc)
    assert structure.find_scene_objects(doc)[-1] is cp
    FreeCADGui.Selection.clearSelection()
    p = run_panel(name)
    assert p.obj is sc, f"{name} opened on {p.obj.Label} (State {p.obj.State}), not on {sc.Label}"
    close_panel()


def test_with_only_invalid_structures_nothing_opens_and_the_reason_is_given(doc):
    sc = open_example("fish")
    cp = invalid_copy(doc, sc)
    doc.removeObject(sc.Name)             # the valid structure goes: only the invalid copy is left
    assert structure.find_scene_objects(doc) == [cp] and "Invalid" in cp.State, cp.State
    FreeCADGui.Selection.clearSelection()
    for name in NEED_SCENE:
        assert enabled(name), f"{name} is disabled: the user could not learn why the structure is invalid"
        commands.INSTANCES[name].last_error = ""
        FreeCADGui.runCommand(name)
        process()
        assert panels.active() is None and not FreeCADGui.Control.activeDialog(), f"{name} opened a panel"
        err = commands.INSTANCES[name].last_error
        assert "invalid" in err and cp.Label in err and cp.getStatusString() in err, (err, cp.getStatusString())


def test_the_refusal_says_how_to_open_a_panel_on_the_invalid_structure_and_that_way_works(doc):
    sc = open_example("fish")
    cp = invalid_copy(doc, sc)
    doc.removeObject(sc.Name)
    FreeCADGui.Selection.clearSelection()
    commands.INSTANCES["MM_Flexibility"].last_error = ""
    FreeCADGui.runCommand("MM_Flexibility")
    process()
    err = commands.INSTANCES["MM_Flexibility"].last_error
    assert "select it in the tree" in err, err          # the user learns how to open the panel to mend it
    FreeCADGui.Selection.addSelection(cp)
    p = run_panel("MM_Flexibility")
    assert p.obj is cp
    close_panel()
