"""Audit D items 4, 7 and 8: the Flexibility panel's "One joint" boxes follow the global sizes until the joint
has its own (and "Set for this joint" stores only the sizes edited there); a square / triangle wave at 0 Hz is
refused in the Animate panel instead of silently becoming a sine; the keyframe table's headers are translatable."""
import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

from metamaterial_wb.core.calibration import default_calibration  # noqa: E402
from metamaterial_wb.gui import panels  # noqa: E402
from metamaterial_wb.objects import structure  # noqa: E402
from guihelpers import click, dialog_button, doc, press_cancel, press_ok, process, run_panel, type_into, workbench  # noqa: E402,F401
from test_gui_panel_details import open_example  # noqa: E402


def k1_text(length):
    return f"k1 = {default_calibration().k1(length):.3f}"


def test_joint_boxes_follow_the_global_size_and_set_stores_only_the_edited_width(doc):
    sc = open_example("fish")
    p = run_panel("MM_Flexibility")
    process(50)
    j = p.joint.currentText()
    assert j not in p.overrides and p.length.value() == 8.0 and p.j_length.value() == 8.0
    type_into(p.length, "3")
    # the joint without an override shows the global size (and its k1), not the 8 mm it showed at opening
    assert p.j_length.value() == 3.0, p.j_length.value()
    assert p.jk_label.text().startswith(k1_text(3.0)), (p.jk_label.text(), p.k_label.text())
    assert p.jk_label.text().split(",")[0] == p.k_label.text().split(",")[0]
    type_into(p.j_width, "1.5")
    click(p.set_btn)
    # only the width the user edited is pinned; the length keeps following the global size
    assert p.overrides[j] == {"width_mm": 1.5}, p.overrides[j]
    assert p.ov_list.item(0).text() == f"{j}: width_mm 1.5"
    type_into(p.length, "4")
    assert p.j_length.value() == 4.0 and p.j_width.value() == 1.5
    assert not p.problems, p.problems
    assert press_ok(), p.error.text()
    assert sc.HingeLength.Value == pytest.approx(4.0)
    scene = structure.compose_scene(sc)
    assert scene.joint_overrides[j] == {"width_mm": 1.5}
    assert scene.joint_hinge(j)["length_mm"] == pytest.approx(4.0)


def test_a_joint_override_keeps_its_fields_and_use_global_refreshes_the_boxes(doc):
    open_example("fish")
    p = run_panel("MM_Flexibility")
    j = p.joint.itemText(2)
    p.joint.setCurrentText(j)
    process()
    type_into(p.j_length, "5")
    click(p.set_btn)
    assert p.overrides[j] == {"length_mm": 5.0}
    type_into(p.length, "3")                      # an overridden length stays; the width follows the global
    type_into(p.width, "1.2")
    assert p.j_length.value() == 5.0 and p.j_width.value() == 1.2
    type_into(p.j_width, "1.4")                   # an edit in progress is not overwritten by a global change
    type_into(p.thick, "6")
    assert p.j_width.value() == 1.4
    click(p.set_btn)
    assert p.overrides[j] == {"length_mm": 5.0, "width_mm": 1.4}
    click(p.del_btn)                              # back to the global size: the boxes show it at once
    assert j not in p.overrides
    assert (p.j_length.value(), p.j_width.value()) == (3.0, 1.2)
    assert p.jk_label.text().startswith(k1_text(3.0))
    assert press_cancel()


@pytest.mark.parametrize("shape", ["square", "triangle"])
def test_a_square_or_triangle_at_0_hz_is_refused_not_turned_into_a_sine(doc, shape):
    sc = open_example("fish")
    p = run_panel("MM_Animate")
    name = list(p.shapes)[0]
    p.set_shape(name, shape)
    process()
    assert not p.problems, p.problems
    type_into(p.spins[name][1], "0")
    msg = p.problems.get("profiles", "")
    assert name in msg and shape in msg and "needs a frequency > 0 Hz" in msg, p.problems
    assert name in p.problem_labels["profiles"].text()
    assert not dialog_button("Ok").isEnabled()
    it = [i for i in sc.Items if i.ItemName == name][0]
    before = (it.ProfileShape, it.ProfileData)
    assert not press_ok()
    p.accept()                                    # the OK path itself (Enter in the dialog) refuses it too
    assert panels.active() is p and "needs a frequency > 0 Hz" in p.error.text(), p.error.text()
    assert (it.ProfileShape, it.ProfileData) == before          # nothing stored, no sine
    type_into(p.spins[name][1], "0.5")            # a frequency again: the problem goes, OK stores the wave
    assert not p.problems, p.problems
    assert press_ok(), p.error.text()
    assert it.ProfileShape == ("steps" if shape == "square" else "keyframes")


def test_keyframe_table_headers_are_translated(doc, monkeypatch):
    from metamaterial_wb.gui.panels import profiles
    seen = []
    monkeypatch.setattr(profiles, "translate", lambda ctx, text: seen.append(text) or "<" + text + ">")
    t = profiles.KeyframeTable(lambda: None)
    heads = [t.table.horizontalHeaderItem(c).text() for c in range(2)]
    assert heads == ["<time (s)>", "<value (-1..1)>"], heads
    assert "time (s)" in seen and "value (-1..1)" in seen
    t.deleteLater()
