"""Issue 15 items 5 and 7 through real widgets: conflicting modules refused in the panel; export
failures shown in the panel; Cancel leaves a saved document unmodified; stale messages cleared; New
structure beyond 16 x 16 with [row, col] labels; motor sliders disabled under Global deformation and
motor values in servo degrees."""
import os

import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

import FreeCADGui  # noqa: E402

from metamaterial_wb.gui import panels  # noqa: E402
from metamaterial_wb.objects import structure  # noqa: E402
from guihelpers import (click, dialog_button, doc, press_cancel, press_ok, process, run_panel,  # noqa: E402,F401
                        type_into, workbench)


def open_example(name):
    p = run_panel("MM_OpenExample")
    p.select(name)
    assert press_ok()
    return structure.find_scene_objects(FreeCAD.ActiveDocument)[-1]


def test_a_second_module_on_a_joint_or_node_is_refused_in_the_panel(doc):
    sc = open_example("fish_modules")
    n0 = len(sc.Modules)
    p = run_panel("MM_AddModule")
    p.set_type("constraint_clip")
    p.target.setCurrentText("H0,3")              # the joint of the stable hub fin_mount_top
    lab = p.problem_label("target")
    assert lab.isVisible() and "fin_mount_top" in lab.text() and "one module per joint" in lab.text(), lab.text()
    assert not dialog_button("Ok").isEnabled()
    assert not press_ok()
    p.target.setCurrentText("H0,2")
    assert not lab.isVisible()
    # a clip needs an angle (a constraint on its joint): the recompute fails, the panel says why, nothing kept
    assert not press_ok()
    assert "clip's angle" in p.error.text() and len(sc.Modules) == n0 and sc.isValid()
    p.set_type("stable_hub")
    p.target.setCurrentText("H0,2")
    assert press_ok(), p.error.text()
    assert len(sc.Modules) == n0 + 1
    # two pads on one node
    for k, expect in ((0, True), (1, False)):
        p = run_panel("MM_AddModule")
        p.set_type("friction_pad")
        p.target.setCurrentText("N0,0")
        assert press_ok() is expect
    assert "N0,0" in p.problem_label("target").text() and "one module per node socket" in \
        p.problem_label("target").text()
    assert press_cancel()


def test_export_failure_is_shown_in_the_panel(doc, tmp_path):
    run_panel("MM_NewStructure")
    assert press_ok()
    sc = structure.find_scene_objects(doc)[-1]
    # a 10 deg fold on 2 mm hinges: kinematically fine (31.9 deg), not printable (3.96 deg)
    structure.set_scene_fields(sc, axes=[{"direction": "vertical", "line": 3, "fold_deg": 10.0}])
    doc.recompute()
    assert sc.isValid()
    p = run_panel("MM_Export")
    blocker = tmp_path / "a_file"
    blocker.write_text("not a folder")
    type_into(p.path, str(blocker))
    assert p.problem_label("path").isVisible() and "not a folder" in p.problem_label("path").text()
    assert not p.export_btn.isEnabled()
    type_into(p.path, str(tmp_path / "out"))
    assert not p.problem_label("path").isVisible()
    click(p.export_btn)
    assert p.wait(300)
    assert p.job.outcome == "error" and p.error.text().startswith("not exported:"), p.error.text()
    assert "tilt" in p.error.text(), p.error.text()
    assert not os.path.exists(tmp_path / "out") or not os.listdir(tmp_path / "out")
    assert FreeCAD.ActiveDocument is not None


@pytest.mark.xfail(strict=True, reason="FreeCAD 0.20: Gui.Document.Modified is read-only and every PlacementList "
                   "write of the live display marks the document modified (the NoModify property status and an "
                   "aborted transaction do not clear it); needs a live display that does not write the document")
@pytest.mark.parametrize("cmd", ["MM_Simulate", "MM_Animate", "MM_RotaryAxes", "MM_FoldedShape"])
def test_cancel_leaves_a_saved_document_unmodified(doc, tmp_path, cmd):
    open_example("fish_axes")
    path = str(tmp_path / "saved.FCStd")
    doc.saveAs(path)                       # names the file; Std_Save then saves as the user does
    FreeCADGui.runCommand("Std_Save")
    process(50)
    gd = FreeCADGui.getDocument(doc.Name)
    assert not gd.Modified
    p = run_panel(cmd)
    if cmd == "MM_Simulate":
        p.set_value("tail", 0.5)
    elif cmd == "MM_Animate":
        p.step(5)
    process(50)
    assert press_cancel()
    process(50)
    assert not gd.Modified, f"Cancel on {cmd} marked the saved document modified"


def test_stale_messages_go_and_grid_beyond_16(doc):
    p = run_panel("MM_NewStructure")
    p.rows.setValue(3)
    p.cols.setValue(3)
    click(p.grid_btn)
    click(p.buttons[(1, 1)])                      # a hole: closed contour
    lab = p.problem_label("grid")
    assert lab.isVisible() and "closed contour" in lab.text()
    assert p.buttons[(1, 1)].toolTip() == "cell [1, 1]"
    click(p.buttons[(1, 1)])                      # fixed: the red message goes
    assert not lab.isVisible() and lab.text() == ""
    type_into(p.rows, "20")
    type_into(p.cols, "24")
    assert p.rows.value() == 20 and p.cols.value() == 24 and len(p.buttons) == 20 * 24
    click(p.grid_btn)
    assert press_ok(), p.error.text()
    sc = structure.find_scene_objects(doc)[-1]
    assert sc.NodeCount == 21 * 25 and sc.isValid()


def test_motor_sliders_disabled_under_global_and_servo_degrees(doc):
    open_example("fish")
    p = run_panel("MM_Simulate")
    if p.use_global.isChecked():
        click(p.use_global)
    s = p.sliders["tail"]
    assert s.isEnabled()
    p.set_value("tail", 0.5)
    assert p.labels["tail"].text() == "+45.0 deg (+0.500)"
    click(p.use_global)
    assert p.use_global.isChecked() and not s.isEnabled() and "overridden" in s.toolTip()
    click(p.use_global)
    assert s.isEnabled()
    assert press_cancel()
    assert panels.active() is None
