"""The servo angles the GUI shows are the angles ``stream`` sends (auditor's defect): Simulate's motor labels,
Animate's values line and its servo column, and Place motor's value all use ``ChannelConfig.angle_deg`` of
``hardware.mapping.channel_map`` (the joint's simulated rotation with the servo's sign, closing and opening
differ; ``v * servo.scale_deg`` when a servo sets it), not ``v * 90 deg``. On the fish (27 mm cells, 8 mm
hinges) the head at +0.3 closes by 7.3 deg (v * 90 showed +27.0) and the tail at -0.9 is sent +81.0 deg
(v * 90 showed -81.0). Driven through the widgets: slider drags, the timeline, typed values, the joint box."""
import numpy as np
import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

from metamaterial_wb.objects import structure  # noqa: E402
from guihelpers import doc, drag_slider, press_cancel, press_ok, process, run_panel, type_into, workbench  # noqa: E402,F401,E501

mapping = pytest.importorskip("metamaterial_wb.hardware.mapping")


def open_fish(doc):
    p = run_panel("MM_OpenExample")
    p.select("fish")
    assert press_ok()
    return structure.find_scene_objects(doc)[-1]


def streamed(sc):
    """{actuator: ChannelConfig} exactly as ``stream`` builds them."""
    return {c.name: c for c in mapping.channel_map(structure.compose_scene(sc))}


def angle_range_text(cfg, lo, hi):
    a = np.asarray(cfg.angle_deg(np.linspace(lo, hi, 201)))
    return f"{a.min():+.1f} .. {a.max():+.1f} deg"


def test_simulate_labels_show_the_streamed_angle(doc):
    sc = open_fish(doc)
    ch = streamed(sc)
    p = run_panel("MM_Simulate")
    if p.use_global.isChecked():
        p.use_global.setChecked(False)
        process()
    # the head at its stored +0.3: closes by 7.3 deg (v * 90 showed +27.0)
    assert p.labels["head"].text() == f"{ch['head'].angle_deg(0.3):+.1f} deg (+0.300)"
    assert p.labels["head"].text().startswith("+7.3 deg"), p.labels["head"].text()
    # the tail dragged to about -0.9: the servo opens by about +81 deg (v * 90 showed a negative angle)
    drag_slider(p.sliders["tail"], -900)
    v = p.values()["tail"]
    assert v < -0.8, v
    assert p.labels["tail"].text() == f"{ch['tail'].angle_deg(v):+.1f} deg ({v:+.3f})"
    assert ch["tail"].angle_deg(v) > 70.0
    # and closing: the tail at +0.5 closes by 12.2 deg, negative on its servo
    drag_slider(p.sliders["tail"], 500)
    v = p.values()["tail"]
    assert p.labels["tail"].text() == f"{ch['tail'].angle_deg(v):+.1f} deg ({v:+.3f})"
    assert ch["tail"].angle_deg(v) < 0.0
    assert press_cancel()


def test_animate_values_line_shows_the_streamed_angle(doc):
    sc = open_fish(doc)
    ch = streamed(sc)
    p = run_panel("MM_Animate")
    # scrub to about t = 0.5 s (timeline of 2 s): head +0.3, tail -0.9
    drag_slider(p.timeline, 250)
    vals = p.shown_values
    assert vals["tail"] < -0.8 and vals["head"] > 0.25, vals
    want = "  ".join(f"{n} {ch[n].angle_deg(v):+.1f} deg ({v:+.2f})" for n, v in vals.items())
    assert p.values_label.text() == want
    assert p.values_label.text().startswith("head +7."), p.values_label.text()
    assert press_cancel()


def test_animate_servo_column_shows_the_angle_range_over_the_swing(doc):
    sc = open_fish(doc)
    ch = streamed(sc)
    p = run_panel("MM_Animate")
    header = p.table.horizontalHeaderItem(5).text()
    assert "range" in header, header
    # the stored sines: head 0.3 and tail 0.9 around 0
    assert p.amp_deg["head"].text() == angle_range_text(ch["head"], -0.3, 0.3)
    assert p.amp_deg["tail"].text() == angle_range_text(ch["tail"], -0.9, 0.9)
    assert p.amp_deg["tail"].text() == "-21.9 .. +81.0 deg", p.amp_deg["tail"].text()
    # a typed amplitude follows
    type_into(p.spins["tail"][0], "0.5")
    assert p.amp_deg["tail"].text() == angle_range_text(ch["tail"], -0.5, 0.5)
    # a square wave swings between -A and +A too; keyframes between their lowest and highest key
    p.set_shape("tail", "square")
    process()
    assert p.amp_deg["tail"].text() == angle_range_text(ch["tail"], -0.5, 0.5)
    p.set_shape("head", "keyframes")
    process()
    keys = [v for _t, v in p.keys["head"]]
    assert p.amp_deg["head"].text() == angle_range_text(ch["head"], min(keys), max(keys))
    assert press_cancel()


def test_place_motor_shows_the_joint_rotation_for_the_value(doc):
    from metamaterial_wb.hardware.joint_angle import joint_rotation
    sc = open_fish(doc)
    scene = structure.compose_scene(sc)
    p = run_panel("MM_PlaceMotor")
    seen = []
    for joint in ("H0,3", "H0,4"):                     # neighbouring joints: opposite parity, opposite sign
        p.joint.setCurrentText(joint)
        process()
        for value in ("0.5", "-0.8"):
            type_into(p.value, value)
            v = float(p.value.value())
            deg = joint_rotation(scene, joint).angle_deg(v)
            assert p.value_deg.text().startswith(f"= {deg:+.1f} deg"), (joint, v, p.value_deg.text())
            seen.append(deg)
    assert seen[0] == pytest.approx(-seen[2]) and abs(seen[1]) > 5 * abs(seen[0]), seen
    assert press_cancel()


def test_ten_motors_and_servo_scales(doc):
    """More motors than the firmware's 8 channels (channel_map refuses): each still shows its joint's rotation;
    a servo with ``scale_deg`` shows v * scale_deg; an invalid ``scale_deg`` shows no angle and the reason."""
    from metamaterial_wb.hardware.joint_angle import joint_rotation
    sc = open_fish(doc)
    extra = ["H0,2", "H0,4", "H1,2", "H2,0", "H2,2", "V0,0", "V0,6"]
    for k, j in enumerate(extra):
        structure.make_item(doc, sc, "actuator", f"x{k}", j, 0.1 * (k + 1),
                            extra={"servo": {"scale_deg": 30.0}} if k == 0 else None)
    structure.make_item(doc, sc, "actuator", "bad", "V1,4", 0.2, extra={"servo": {"scale_deg": 200.0}})
    doc.recompute()
    scene = structure.compose_scene(sc)
    assert len(scene.actuators) == 10
    with pytest.raises(Exception):
        mapping.channel_map(scene)
    p = run_panel("MM_Simulate")
    if p.use_global.isChecked():
        p.use_global.setChecked(False)
        process()
    assert p.labels["x0"].text() == "+3.0 deg (+0.100)", p.labels["x0"].text()
    for k, j in enumerate(extra[1:], start=1):
        v = round(0.1 * (k + 1), 3)
        assert p.labels[f"x{k}"].text() == f"{joint_rotation(scene, j).angle_deg(v):+.1f} deg ({v:+.3f})"
    # a servo scale the mapping refuses: no angle, and why (never v * 90)
    assert p.labels["bad"].text() == "? deg (+0.200)", p.labels["bad"].text()
    assert "scale_deg" in p.labels["bad"].toolTip() and "200" in p.labels["bad"].toolTip()
    assert press_cancel()
