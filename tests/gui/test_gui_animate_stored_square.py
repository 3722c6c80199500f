"""Animate: a square wave the panel stored (as the scene format's ``steps`` profile) is shown as a square again
when the panel reopens, with its amplitude / frequency / phase editable; OK without edits leaves the stored
profile byte-identical. A steps profile that is not exactly such a square stays "stored steps"."""
import json

import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

from guihelpers import doc, press_ok, process, run_panel, type_into, workbench  # noqa: E402,F401
from test_gui_panel_details import open_example  # noqa: E402


def items(sc):
    return {i.ItemName: i for i in sc.Items}


def set_square(p, name, amp, f, ph):
    p.set_shape(name, "square")
    process()
    a, fr, phase = p.spins[name]
    type_into(a, f"{amp:g}")
    type_into(fr, f"{f:g}")
    type_into(phase, f"{ph:g}")


@pytest.mark.parametrize("amp, f, ph", [(0.35, 0.8, 60.0), (0.6, 0.5, -90.0), (1.0, 1.3, 37.5), (0.2, 0.7, 180.0)])
def test_a_stored_square_reopens_as_a_square(doc, amp, f, ph):
    sc = open_example("fish")
    p = run_panel("MM_Animate")
    head = list(p.shapes)[0]
    set_square(p, head, amp, f, ph)
    assert press_ok(), p.error.text()
    it = items(sc)[head]
    assert it.ProfileShape == "steps"
    stored = it.ProfileData
    p = run_panel("MM_Animate")
    process(50)
    assert p.shapes[head].currentText() == "square", "the stored square is not recognised"
    assert all(w.isEnabled() for w in p.spins[head]), "the square's boxes are not editable"
    assert tuple(w.value() for w in p.spins[head]) == pytest.approx((amp, f, ph))
    assert p.profiles()[head] == dict(json.loads(stored), shape="steps")
    n = doc.UndoCount
    assert press_ok(), p.error.text()
    assert it.ProfileData == stored and it.ProfileShape == "steps", "OK without edits changed the profile"
    assert doc.UndoCount == n
    # an edit of the recognised square writes the square with the new value, the others kept
    p = run_panel("MM_Animate")
    type_into(p.spins[head][0], "0.15")
    assert press_ok(), p.error.text()
    p = run_panel("MM_Animate")
    assert p.shapes[head].currentText() == "square"
    assert tuple(w.value() for w in p.spins[head]) == pytest.approx((0.15, f, ph))
    assert max(json.loads(items(sc)[head].ProfileData)["values"]) == pytest.approx(0.15)
    p.reject()


@pytest.mark.parametrize("data", [
    {"times_s": [0.0, 0.5, 1.0], "values": [0.5, -0.5, 0.25], "period_s": 2.0},       # not +-A
    {"times_s": [0.0, 0.7], "values": [0.5, -0.5], "period_s": 2.0},                  # not a half period
    {"times_s": [0.0, 0.5000001], "values": [0.5, -0.5], "period_s": 1.0},  # a hair off
    {"times_s": [0.0, 0.5], "values": [0.5, -0.5]},                                   # no period
    {"times_s": [0.0, 1.0, 2.0, 3.0], "values": [0.5, -0.5, 0.5, -0.5], "period_s": 4.0},  # two cycles
])
def test_other_steps_stay_stored_steps(doc, data):
    sc = open_example("fish")
    head = [i.ItemName for i in sc.Items if i.Kind == "actuator"][0]
    it = items(sc)[head]
    doc.openTransaction("steps")
    it.ProfileShape = "steps"
    it.ProfileData = json.dumps(data)
    doc.commitTransaction()
    doc.recompute()
    stored = it.ProfileData
    p = run_panel("MM_Animate")
    process(50)
    assert p.shapes[head].currentText() == "stored steps"
    assert not any(w.isEnabled() for w in p.spins[head])
    assert press_ok(), p.error.text()
    assert it.ProfileData == stored


@pytest.mark.parametrize("amp, f, ph", [(0.58, 0.603, 540.0), (0.3, 0.603, -540.0), (0.5, 0.7, 900.0)])
def test_a_square_half_a_turn_off_writes_a_profile_the_scene_accepts(amp, f, ph):
    # the step times were rounded to 9 decimals and one could land on the period itself (0.58 / 0.603 Hz / 540 deg:
    # times [0, 0.829187396, 1.658374793], period 1.6583747927...): the scene refused the panel's own profile
    from metamaterial_wb.core.motion import profile_value, validate_profile
    from metamaterial_wb.gui.panels.profiles import square_fields, wave_profile
    prof = wave_profile("square", amp, f, ph)
    validate_profile(prof)
    assert all(0 <= t < prof["period_s"] for t in prof["times_s"]), prof
    for t in (0.01, 0.3, 0.6, 0.9, 1.2, 1.5):      # the wave it stands for: sign of sin(2 pi f t + phase)
        import math
        s = math.sin(2 * math.pi * f * t + math.radians(ph))
        if abs(s) > 1e-6:
            assert profile_value(prof, t) == pytest.approx(amp if s > 0 else -amp), (t, prof)
    assert square_fields(prof) is not None
