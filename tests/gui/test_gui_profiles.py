"""Issue 15 item 7: motion profiles beyond sine in the Animate panel (square, triangle, keyframes table,
phase in degrees), checked against the closed forms and stored through OK."""
import math

import numpy as np
import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

from metamaterial_wb.core.motion import profile_value  # noqa: E402
from metamaterial_wb.objects import structure  # noqa: E402
from guihelpers import click, doc, press_ok, run_panel, type_into, workbench  # noqa: E402,F401


def open_fish():
    p = run_panel("MM_OpenExample")
    p.select("fish")
    assert press_ok()
    return structure.find_scene_objects(FreeCAD.ActiveDocument)[-1]


def test_square_triangle_and_keyframes(doc):
    sc = open_fish()
    from metamaterial_wb.hardware.mapping import channel_map
    tail_servo = {c.name: c for c in channel_map(structure.compose_scene(sc))}["tail"]
    p = run_panel("MM_Animate")
    amp, f, ph = 0.6, 0.8, 60.0
    t = np.linspace(0.013, 5.0, 397)
    for shape, closed in (("square", lambda x: amp * np.sign(np.sin(x))),
                          ("triangle", lambda x: amp * 2 / math.pi * np.arcsin(np.sin(x)))):
        p.set_shape("tail", shape)
        a, fr, phase = p.spins["tail"]
        type_into(a, f"{amp}")
        type_into(fr, f"{f}")
        type_into(phase, f"{ph:g}")
        x = 2 * math.pi * f * t + math.radians(ph)
        prof = p.profiles()["tail"]
        got = profile_value(prof, t)
        keep = np.abs(np.sin(x)) > 0.05 if shape == "square" else np.ones_like(t, dtype=bool)
        np.testing.assert_allclose(got[keep], closed(x)[keep], atol=1e-9)
        # the servo column: the angle range stream sends over the swing -amp..+amp (not amp x 90)
        ang = tail_servo.angle_deg(np.linspace(-amp, amp, 201))
        assert p.amp_deg["tail"].text() == f"{ang.min():+.1f} .. {ang.max():+.1f} deg"
    # keyframes: a small time / value table
    p.set_shape("head", "keyframes")
    assert p.keyframes.isVisible() and p.keyframes.title.text() == "Keyframes of head"
    while p.keyframes.table.rowCount() > 1:
        click(p.keyframes.del_btn)
    click(p.keyframes.add_btn)
    click(p.keyframes.add_btn)
    tbl = p.keyframes.table
    for r, (tk, vk) in enumerate(((0.0, 0.0), (0.5, 0.8), (1.5, -0.4))):
        type_into(tbl.cellWidget(r, 0), f"{tk}")
        type_into(tbl.cellWidget(r, 1), f"{vk}")
    prof = p.profiles()["head"]
    assert prof["shape"] == "keyframes" and prof["times_s"] == [0.0, 0.5, 1.5] and prof["values"] == [0.0, 0.8, -0.4]
    assert profile_value(prof, 1.0) == pytest.approx(0.2)
    assert not p.problems, p.problems
    assert press_ok(), p.error.text()
    scene = structure.compose_scene(sc)
    by = {a.name: a.profile for a in scene.actuators}
    assert by["head"]["shape"] == "keyframes" and by["head"]["values"] == [0.0, 0.8, -0.4]
    assert by["tail"]["shape"] == "keyframes"     # the triangle, stored as keyframes
    np.testing.assert_allclose(profile_value(by["tail"], t), amp * 2 / math.pi * np.arcsin(np.sin(
        2 * math.pi * f * t + math.radians(ph))), atol=1e-9)
    p = run_panel("MM_Animate")
    assert p.shapes["head"].currentText() == "keyframes"
