"""Add module: an angular-constraint clip takes its angle from the scene's constraint on its joint (docs/gui.md row 6).
On a joint without a constraint the panel says so in a red line before OK, naming the joint and what to do (place a
constraint there with Angular constraint), and OK stays disabled: it was enabled, and OK then failed with the module
named twice, an internal name (``constraint_clip_1``) and a traceback in the Report view."""
import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

import FreeCADGui  # noqa: E402

from metamaterial_wb.objects import structure  # noqa: E402
from guihelpers import (click, dialog_button, doc, press_ok, process, run_panel, workbench)  # noqa: E402,F401


def new_chain(cols=7):
    """New structure, a 1 x ``cols`` grid (the Chain preset), OK: as a user makes it."""
    p = run_panel("MM_NewStructure")
    p.rows.setValue(1)
    p.cols.setValue(cols)
    click(p.chain_btn)
    assert press_ok(), p.error.text()
    return structure.find_scene_objects(FreeCAD.ActiveDocument)[-1]


def open_clip_on(joint):
    FreeCADGui.Selection.clearSelection()
    p = run_panel("MM_AddModule")
    p.set_type("constraint_clip")
    p.target.setCurrentText(joint)
    process()
    assert p.target_name() == joint, p.target.currentText()
    return p


def test_a_clip_on_a_joint_without_constraint_is_refused_before_ok(doc, capfd):
    sc = new_chain()
    n0 = len(sc.Modules)
    p = open_clip_on("H0,4")
    text = p.problem_text()
    assert text, "no problem shown for a clip on a joint without a constraint"
    assert "H0,4" in text and "constraint" in text and "Angular constraint" in text, text
    assert "constraint_clip_1" not in text, text
    assert not dialog_button("Ok").isEnabled(), "OK enabled for a clip that cannot be built"
    assert not press_ok()
    assert p.accept() is False, "a script's accept() added the clip"
    assert len(sc.Modules) == n0 and not [o for o in doc.Objects if getattr(o, "ModuleType", "") == "constraint_clip"]
    err = capfd.readouterr().err
    assert "Traceback" not in err, err[-1500:]
    # another joint without a constraint: the line follows the target
    p.target.setCurrentText("H0,2")
    process()
    assert "H0,2" in p.problem_text() and "H0,4" not in p.problem_text(), p.problem_text()
    # a module that needs no constraint on the same joint: no such line, OK enabled
    p.set_type("stable_hub")
    p.target.setCurrentText("H0,4")
    process()
    assert "Angular constraint" not in p.problem_text(), p.problem_text()
    assert dialog_button("Ok").isEnabled(), p.problem_text()
    p.reject()


def test_a_clip_on_a_joint_with_a_constraint_is_added(doc, capfd):
    sc = new_chain()
    structure.make_item(doc, sc, "constraint", "hold", "H0,4", value=0.3)
    doc.recompute()
    p = open_clip_on("H0,4")
    assert not p.problems, p.problem_text()
    assert dialog_button("Ok").isEnabled()
    assert press_ok(), p.error.text()
    m = sc.Modules[-1]
    assert m.ModuleType == "constraint_clip" and m.Target == "H0,4" and m.isValid(), m.getStatusString()
    assert "Traceback" not in capfd.readouterr().err
