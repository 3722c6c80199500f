"""An OK that changes nothing writes nothing: the stored values are kept exactly, not as the widgets round
them (a fold of 5.25 deg became 5.3, an amplitude of 0.1234 became 0.123, a keyframes period of 0.8 s became the
timeline's 2 s, a global deformation of 0.123 became 0.12 with an undo step), and a value typed is kept as typed."""
import json

import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

from metamaterial_wb.gui.panels import ranges  # noqa: E402
from metamaterial_wb.objects import structure  # noqa: E402
from guihelpers import doc, press_ok, process, qtest, run_panel, type_into, workbench  # noqa: E402,F401
from test_gui_panel_details import open_example  # noqa: E402


def folds(sc):
    return [a["fold_deg"] for a in json.loads(sc.SceneJSON)["axes"]]


def test_folded_shape_keeps_untouched_folds_and_typed_ones(doc):
    sc = open_example("fish_axes")
    axes = json.loads(sc.SceneJSON)["axes"]
    for a, f in zip(axes, (5.25, 8.04, 12.0, 15.0)):
        a["fold_deg"] = f
    structure.set_scene_fields(sc, axes=axes, joint_config=None)
    doc.recompute()
    p = run_panel("MM_FoldedShape")
    assert press_ok()
    assert folds(sc) == [5.25, 8.04, 12.0, 15.0]
    p = run_panel("MM_FoldedShape")
    spin = p.spins[2]
    if spin.isVisible():
        type_into(spin, "12.25")
    else:
        spin.setValue(12.25)
    process()
    assert press_ok()
    assert folds(sc) == [5.25, 8.04, 12.25, 15.0]


def test_animate_keeps_untouched_profiles(doc):
    sc = open_example("fish")
    head, tail = sc.Items[0], sc.Items[1]
    head.Amplitude, head.PhaseDeg = 0.1234, 12.25
    tail.ProfileShape = "keyframes"
    tail.ProfileData = json.dumps({"times_s": [0.0, 0.3], "values": [0.0, 0.4], "period_s": 0.8})
    doc.recompute()
    assert sc.isValid()
    before = (head.Amplitude, head.PhaseDeg, tail.ProfileShape, tail.ProfileData)
    undo0 = doc.UndoCount
    run_panel("MM_Animate")
    assert press_ok()
    assert (head.Amplitude, head.PhaseDeg, tail.ProfileShape, tail.ProfileData) == before
    assert doc.UndoCount == undo0


def test_simulate_keeps_an_untouched_global_deformation(doc):
    sc = open_example("fish")
    sc.UseGlobal, sc.GlobalDeformation = True, 0.123
    doc.recompute()
    undo0 = doc.UndoCount
    run_panel("MM_Simulate")
    assert press_ok()
    assert sc.GlobalDeformation == 0.123 and sc.UseGlobal
    assert doc.UndoCount == undo0                       # nothing changed: no undo step


# ---- an audit of the task panels by hand (session 26) ---------------------------------------------------------
def test_flexibility_keeps_exact_sizes_and_an_untouched_ok_writes_nothing(doc):
    """Flexibility showed 2 decimals and wrote them back: an untouched OK turned 2.345 / 0.8125 into 2.35 / 0.81 with
    an undo step, and changing only the thickness rounded the width."""
    sc = open_example("fish")
    sc.HingeLength, sc.HingeWidth = 2.345, 0.8125
    doc.recompute()
    undo0 = doc.UndoCount
    run_panel("MM_Flexibility")
    assert press_ok()
    assert (sc.HingeLength, sc.HingeWidth) == (2.345, 0.8125)
    assert doc.UndoCount == undo0
    p = run_panel("MM_Flexibility")
    type_into(p.thick, "6.5")
    process()
    assert press_ok()
    assert (sc.HingeLength, sc.HingeWidth, sc.HingeThickness) == (2.345, 0.8125, 6.5)


def test_flexibility_joint_label_is_the_solvers_stiffness(doc):
    """For a joint with its own thickness, or k1 / k2 set directly, the label showed the global hinge's values."""
    from metamaterial_wb.core.calibration import joint_stiffness
    sc = open_example("fish")
    structure.set_scene_fields(sc, joints=[{"joint": "H0,1", "thickness_mm": 3.0},
                                           {"joint": "H0,2", "k1": 0.5, "k2": 2.0}])
    doc.recompute()
    scene = structure.compose_scene(sc)
    k1, k2 = joint_stiffness(scene)
    idx = scene.topology.joint_index
    p = run_panel("MM_Flexibility")
    for name in ("H0,1", "H0,2"):
        p.joint.setCurrentText(name)
        process()
        want = f"k1 = {k1[idx[name]]:.3f}, k2 = {k2[idx[name]]:.3f}"
        assert p.jk_label.text().startswith(want), (name, p.jk_label.text(), want)
    assert "set directly" in p.jk_label.text()
    p.reject()


def test_folded_shape_and_rotary_axes_untouched_ok_add_no_undo_step(doc):
    open_example("fish_axes")
    run_panel("MM_FoldedShape")
    assert press_ok()                                  # (designs the joints if the example had no design)
    for cmd in ("MM_FoldedShape", "MM_RotaryAxes"):
        undo0 = doc.UndoCount
        run_panel(cmd)
        assert press_ok()
        assert doc.UndoCount == undo0, cmd


def test_animate_keeps_the_fields_not_edited_in_an_edited_row(doc):
    sc = open_example("fish")
    head = sc.Items[0]
    head.Amplitude, head.PhaseDeg = 0.1234, 12.25
    doc.recompute()
    p = run_panel("MM_Animate")
    amp, freq, phase = p.spins[head.ItemName]
    freq.setValue(0.75)
    process()
    assert press_ok()
    assert (head.Amplitude, head.FrequencyHz, head.PhaseDeg) == (0.1234, 0.75, 12.25)


def test_export_of_a_deleted_structure_is_refused(doc, tmp_path):
    sc = open_example("fish")
    p = run_panel("MM_Export")
    p.path.setText(str(tmp_path / "out"))
    for name in [o.Name for o in doc.Objects]:       # the structure and everything it holds, as a user deletes
        if doc.getObject(name) is not None:           # (removing a part removes its children with it)
            doc.removeObject(name)
    process()
    assert p.start_export() is False
    assert "deleted" in p.error.text()
    assert not (tmp_path / "out").exists() or not any((tmp_path / "out").iterdir())
    p.reject()


def test_a_value_typed_past_a_boxs_range_is_refused_not_clamped(doc):
    """Typing 200 into a fold box of range [-180, 180] left 20 (the box drops the keystroke) and OK wrote 20 without
    a word; now OK is refused naming the field, the value typed and the range, until the box takes a keystroke."""
    open_example("fish_axes")
    p = run_panel("MM_FoldedShape")
    spin = p.spins[0]
    type_into(spin, "200")
    assert spin.value() == 20.0                                    # (what Qt leaves in the box)
    assert not press_ok()
    text = spin.property(ranges.REFUSED) or ""
    assert "200" in text and "allowed range [-180, 180]" in text and "fold_deg" in text, text
    assert [lab.text() for lab in p.problem_labels.values() if lab.isVisible()] == [text]    # said under the box
    type_into(spin, "12")
    assert press_ok()


def test_a_box_stepped_by_its_arrow_after_a_refused_keystroke_is_taken(doc):
    """After a refused keystroke (200 typed in [-180, 180]) a user who steps the box with its arrow key to 20.1 sees 20.1
    in the box; OK was still refused quoting the 200 (only a typed key cleared the refusal). The box's own change of
    value now clears it and OK writes what the box shows."""
    from PySide import QtCore
    open_example("fish_axes")
    p = run_panel("MM_FoldedShape")
    spin = p.spins[0]
    type_into(spin, "200")
    assert spin.value() == 20.0
    spin.setFocus()
    qtest().keyClick(spin, QtCore.Qt.Key.Key_Up)
    process()
    assert spin.value() == pytest.approx(20.1)
    assert press_ok(), p.error.text()
    sc = doc.getObject(p.obj.Name)
    assert folds(sc)[0] == pytest.approx(20.1)


def test_keys_typed_together_are_judged_by_the_last_one(doc):
    """Keys that arrive together (fast typing; QTest.keyClicks sends them all before any queued call runs) were each
    judged after all were handled: the "1" of "10" in the sleeve's L box (minimum 2 mm) was read as a refused 1
    once the box already showed 10, and OK stayed refused quoting it. Only the last keystroke is judged now."""
    from metamaterial_wb.gui.panels.ranges import REFUSED
    p = run_panel("MM_Sleeve")
    spin = p.dims["L_mm"]
    type_into(spin, "10")
    assert spin.value() == 10.0
    assert not spin.property(REFUSED), spin.property(REFUSED)
    over = f"{int(spin.maximum()) + 1}"          # past the box's maximum: the last key is refused, and said so
    type_into(spin, over)
    assert over in (spin.property(REFUSED) or ""), (spin.value(), spin.maximum(), spin.property(REFUSED))
    p.reject()
