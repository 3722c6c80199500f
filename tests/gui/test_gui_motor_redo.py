"""Undo then Redo (Std_Undo, Std_Redo: Ctrl+Z, then Ctrl+Shift+Z on Linux / Ctrl+Y on Windows) of "Place motor"
while Simulate or Animate is open (session 31).

Ctrl+Z of the Place motor takes the motor away under the open panel: the panel names it as deleted and refuses OK
(as designed, ``BasePanel.check_items``). Redo brings it back: the red line must go and OK be taken again, as
after Ctrl+Z of a Delete (``test_gui_sim_animate_details.test_a_deleted_motor_brought_back_by_undo_clears_the_line``)."""

import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

import FreeCADGui  # noqa: E402

from guihelpers import doc, press_cancel, press_ok, process, run_panel, tracebacks, type_into, workbench  # noqa: E402,F401
from test_gui_panel_details import open_example  # noqa: E402

NEW = "redo_motor"


def items(sc):
    return {i.ItemName: i for i in sc.Items}


def rows(p, cmd):
    return list(p.sliders if cmd == "MM_Simulate" else p.shapes)


@pytest.mark.parametrize("cmd", ["MM_Simulate", "MM_Animate"])
def test_redo_of_place_motor_while_the_panel_is_open_clears_the_line(doc, tracebacks, cmd):
    sc = open_example("fish")
    p = run_panel("MM_PlaceMotor")
    p.joint.setCurrentText("H0,3")                 # a free joint
    type_into(p.name, NEW)
    process()
    assert press_ok(), p.error.text()
    assert NEW in items(sc), sorted(items(sc))
    undo_name = FreeCADGui.getDocument(doc.Name).Document.UndoNames[0] if doc.UndoNames else ""
    p = run_panel(cmd)
    assert NEW in rows(p, cmd), rows(p, cmd)
    FreeCADGui.runCommand("Std_Undo")              # Ctrl+Z: the Place motor goes
    process(100)
    assert NEW not in items(sc), (undo_name, sorted(items(sc)))
    text = p.problem_label("items").text()
    assert repr(NEW) in text and "deleted" in text, text
    assert p.problem_label("items").isVisible()
    assert press_ok() is False, "OK taken for a motor that is gone"
    FreeCADGui.runCommand("Std_Redo")              # Redo: it comes back
    process(100)
    assert NEW in items(sc), sorted(items(sc))
    assert "items" not in p.problems, p.problems
    assert not p.problem_label("items").isVisible()
    assert "deleted" not in p.error.text(), p.error.text()
    assert not tracebacks, tracebacks[0]
    assert press_ok(), p.error.text()
    assert NEW in items(sc)
