"""Add module waits for the user's target (docs/gui.md row 6: "OK waits until a target is clicked or chosen in
the list"): the panel opens with no target (a placeholder entry and a red line saying what is missing, OK
refused), a hinge / node the user selected before opening the panel counts as chosen, and the panel fits a
narrow task dock (~300 px, as Folded shape / Export / New structure)."""
import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

import FreeCADGui  # noqa: E402
from PySide import QtGui  # noqa: E402

from metamaterial_wb.objects import structure  # noqa: E402
from guihelpers import (click_view, dialog_button, doc, hinge_mid, process, press_cancel, press_ok,  # noqa: E402,F401
                        run_panel, screen_point, workbench)
from test_gui_panel_details import open_example  # noqa: E402
from test_gui_folded_narrow import narrow  # noqa: E402,F401

NARROW = 300


def test_ok_waits_for_a_target_the_user_chooses(doc):
    sc = open_example("fish")
    FreeCADGui.Selection.clearSelection()
    n0 = len(sc.Modules)
    p = run_panel("MM_AddModule")
    p.set_type("servo_housing")
    process()
    assert p.target.currentText().startswith("(click a hinge"), p.target.currentText()
    lab = p.problem_label("choose")
    assert lab.isVisible() and "On" in lab.text() and "hinge" in lab.text(), lab.text()
    assert not dialog_button("Ok").isEnabled()
    assert not press_ok()
    assert len(sc.Modules) == n0, "a module was added on a target nobody chose"
    assert p.accept() is False and len(sc.Modules) == n0          # a script's accept() is refused too
    # a node module asks for a node
    p.set_type("friction_pad")
    process()
    assert p.target.currentText().startswith("(click a node"), p.target.currentText()
    assert "node" in p.problem_label("choose").text() and not dialog_button("Ok").isEnabled()
    # a click in the 3D view chooses it
    p.set_type("servo_housing")
    process()
    click_view(screen_point(hinge_mid(sc, "H0,2")))
    assert p.target.currentText() == "H0,2", p.pick_label.text()
    assert not lab.isVisible() and dialog_button("Ok").isEnabled()
    assert press_ok(), p.error.text()
    assert len(sc.Modules) == n0 + 1 and sc.Modules[-1].Target == "H0,2"


def test_a_target_chosen_in_the_list_is_used(doc):
    sc = open_example("fish")
    FreeCADGui.Selection.clearSelection()
    p = run_panel("MM_AddModule")
    p.set_type("friction_pad")
    p.target.setCurrentText("N1,3")
    assert not p.problem_label("choose").isVisible() and dialog_button("Ok").isEnabled()
    assert press_ok(), p.error.text()
    assert sc.Modules[-1].Target == "N1,3" and sc.Modules[-1].ModuleType == "friction_pad"


def test_a_hinge_selected_before_opening_counts_as_chosen(doc):
    sc = open_example("fish")
    k = structure.compose_scene(sc).topology.joint_index["V0,1"]
    FreeCADGui.Selection.clearSelection()
    FreeCADGui.Selection.addSelection(doc.Name, sc.HingeArray.Name, f"{k}.Face1")
    process()
    try:
        p = run_panel("MM_AddModule")
        p.set_type("servo_housing")
        process()
        assert p.target.currentText() == "V0,1", p.target.currentText()
        assert dialog_button("Ok").isEnabled(), p.problem_text()
        assert press_ok(), p.error.text()
    finally:
        FreeCADGui.Selection.clearSelection()
    assert sc.Modules[-1].Target == "V0,1" and sc.Modules[-1].ModuleType == "servo_housing"


def test_add_module_fits_a_narrow_task_dock(doc, narrow):
    open_example("fish")
    FreeCADGui.Selection.clearSelection()
    p = run_panel("MM_AddModule")
    for t in ("constraint_clip", "stable_hub"):                 # the longest module names
        p.set_type(t)
    process()
    dock = narrow(p, NARROW)                                    # fails when the panel makes the dock grow
    process(100)
    cut = [(lab.text(), lab.width(), lab.sizeHint().width()) for lab in p.form.findChildren(QtGui.QLabel)
           if lab.isVisible() and not lab.wordWrap() and lab.text() and lab.width() < lab.sizeHint().width()]
    m = {"dock": dock.width(), "form": p.form.width(), "form min": p.form.minimumSizeHint().width(),
         "type": (p.type.width(), p.type.minimumSizeHint().width()), "cut": cut}
    print("narrow add module:", m)
    assert p.form.width() <= dock.width(), m                    # nothing runs off the dock's right edge
    assert p.form.minimumSizeHint().width() <= NARROW, m
    assert not cut, m
    for combo in (p.type, p.target):                            # a cut name is in full in the tooltip
        assert combo.width() >= combo.minimumSizeHint().width(), m
        assert combo.toolTip() == combo.currentText(), (combo.toolTip(), combo.currentText())
    assert press_cancel()


def test_a_target_cleared_by_the_user_stays_cleared_across_a_type_change(doc):
    """Choosing the placeholder again did not forget the earlier choice: switching the module type away and back
    brought back the target the user had cleared (review of the above)."""
    open_example("fish")
    FreeCADGui.Selection.clearSelection()
    p = run_panel("MM_AddModule")
    p.set_type("servo_housing")
    p.target.setCurrentText("H0,2")
    assert dialog_button("Ok").isEnabled()
    p.target.setCurrentIndex(0)                                 # the placeholder: no hinge
    assert not dialog_button("Ok").isEnabled()
    p.set_type("friction_pad")
    p.set_type("servo_housing")
    process()
    assert p.target.currentText().startswith("(click a hinge"), p.target.currentText()
    assert not dialog_button("Ok").isEnabled()
    p.reject()
