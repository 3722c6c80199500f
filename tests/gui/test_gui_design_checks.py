"""Defects 2 and 6 of issue 15 through real widgets: invalid designs are refused in the panel (in
words, next to the field; OK disabled), and the Folded shape panel is live, exact (0.1 deg steps, no
rounding, no clamping) and shows the kinematic and the printable limit on the control."""
import json
import math

import numpy as np
import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

import FreeCADGui  # noqa: E402

import metamaterial_wb  # noqa: E402
from metamaterial_wb.core import design, kinematics  # noqa: E402
from metamaterial_wb.core.scene import Scene  # noqa: E402
from metamaterial_wb.core.solver import solve_scene  # noqa: E402
from metamaterial_wb.objects import structure  # noqa: E402
from guihelpers import (click, dialog_button, doc, drag_slider, press_ok, process, run_panel, shown_placements,  # noqa: E402,F401,E501
                        type_into, workbench)


def xyz(arr):
    return np.array([[q.Base.x, q.Base.y, q.Base.z] for q in shown_placements(arr)])


def sheet_with_axis(doc, hinge_mm=None):
    """2 x 6 sheet from the New structure defaults (2 mm hinges), optional Flexibility length, and the
    vertical axis on cell column 3 clicked in Rotary axes; each step confirmed with the OK button."""
    run_panel("MM_NewStructure")
    assert press_ok()
    sc = structure.find_scene_objects(doc)[0]
    FreeCADGui.SendMsgToActiveView("ViewFit")
    if hinge_mm is not None:
        p = run_panel("MM_Flexibility")
        type_into(p.length, f"{hinge_mm:g}")
        assert press_ok(), p.error.text()
    p = run_panel("MM_RotaryAxes")
    click(p.buttons[("vertical", 3)])
    assert press_ok(), p.error.text()
    return sc


def folds(sc):
    return [a["fold_deg"] for a in json.loads(sc.SceneJSON)["axes"]]


def test_scene_file_with_a_fold_beyond_the_maximum_is_refused(doc, tmp_path):
    with open(metamaterial_wb.example_path("fish_axes"), encoding="utf-8") as f:
        d = json.load(f)
    d.pop("hinge", None)              # the default 2 mm hinges: maximum fold 25.6 deg
    d.pop("joint_config", None)
    d["axes"][0]["fold_deg"] = 80.0
    bad = tmp_path / "bent.json"
    bad.write_text(json.dumps(d))
    mx = design.max_fold_deg(Scene.from_dict(d), 0)
    p = run_panel("MM_NewStructure")
    type_into(p.file, str(bad))       # a typed path is used
    lab = p.problem_label("file")
    assert lab.isVisible() and "80 deg" in lab.text() and f"[-{mx:.2f}, {mx:.2f}]" in lab.text(), lab.text()
    assert not dialog_button("Ok").isEnabled()
    assert not press_ok()
    assert structure.find_scene_objects(doc) == [], "nothing is built from an invalid design"
    d["axes"][0]["fold_deg"] = 12.5
    good = tmp_path / "fine.json"
    good.write_text(json.dumps(d))
    type_into(p.file, str(good))
    assert not lab.isVisible() and lab.text() == "", "the message goes once the problem is fixed"
    assert dialog_button("Ok").isEnabled()
    assert press_ok()
    sc = structure.find_scene_objects(doc)[0]
    assert sc.isValid() and folds(sc)[0] == 12.5


def test_shorter_hinges_that_break_a_stored_fold_are_refused(doc):
    sc = sheet_with_axis(doc, hinge_mm=3.0)
    p = run_panel("MM_FoldedShape")
    type_into(p.spins[0], "30")
    assert press_ok(), p.error.text()            # 30 deg < 39.0 deg, the maximum with 3 mm hinges
    assert folds(sc) == [30.0] and sc.isValid()
    p = run_panel("MM_Flexibility")
    type_into(p.length, "1")                     # 1 mm hinges: maximum 12.5 deg
    lab = p.problem_label("hinge")
    assert lab.isVisible() and "30 deg" in lab.text() and "maximum" in lab.text(), lab.text()
    assert not press_ok()
    assert sc.HingeLength.Value == pytest.approx(3.0) and sc.isValid()
    type_into(p.length, "3")
    assert not lab.isVisible()
    assert press_ok()


def test_folded_shape_is_live_exact_and_shows_both_limits(doc):
    sc = sheet_with_axis(doc)
    scene = structure.compose_scene(sc)
    mx = design.max_fold_deg(scene, 0)
    pmx = design.printable_fold_deg(scene, design.plan_axes(scene)[0])[0]
    p = run_panel("MM_FoldedShape")
    s = p.sliders[0][0]
    assert s.maximum() == math.floor(mx * 10) and s.minimum() == -math.floor(mx * 10), "0.1 deg steps, within"
    assert f"kinematic +-{math.floor(mx * 1000) / 1000:.3f} deg" in p.limit_labels[0].text()
    assert f"printable +-{math.floor(pmx * 1000) / 1000:.3f} deg" in p.limit_labels[0].text()
    before = xyz(sc.NodeArray)
    drag_slider(s, 100)
    process(50)
    deg = p.spins[0].value()
    assert 5.0 < deg < 15.0 and abs(deg * 10 - s.value()) < 1e-6
    after = xyz(sc.NodeArray)
    assert np.abs(after - before).max() > 0.5, "the view follows the slider without Preview"
    ref = design.configure_scene(Scene.from_dict(dict(scene.to_dict(), axes=[
        dict(scene.axes[0].to_dict(), fold_deg=deg)])))
    D, _m, _w, _t = solve_scene(ref, global_deformation=1.0)
    np.testing.assert_allclose(after, kinematics.node_poses(ref, D)[0], atol=1e-6)
    # exact values: 12.5 stays 12.5, through OK and a second OK without edits
    type_into(p.spins[0], "12.5")
    assert press_ok()
    assert folds(sc) == [12.5]
    p = run_panel("MM_FoldedShape")
    assert p.spins[0].value() == 12.5
    assert press_ok()
    assert folds(sc) == [12.5]
    # beyond the maximum: kept as typed (not clamped), refused in words next to the axis
    p = run_panel("MM_FoldedShape")
    type_into(p.spins[0], "40")
    assert p.spins[0].value() == 40.0 and 40.0 > mx
    lab = p.problem_label("axis0")
    bound = math.floor(mx * 1000) / 1000
    assert lab.isVisible() and f"[-{bound:.3f}, {bound:.3f}]" in lab.text(), lab.text()
    assert not press_ok()
    # limit to printable: the slider range and the check follow the printable limit
    type_into(p.spins[0], "12.5")
    assert not lab.isVisible()
    click(p.printable)
    assert p.sliders[0][0].maximum() == math.floor(pmx * 10)
    assert lab.isVisible() and "printable maximum" in lab.text()
    type_into(p.spins[0], "3.5")
    assert not lab.isVisible()
    assert press_ok()
    assert folds(sc) == [3.5] and sc.isValid()
