"""``mapping.wrap_jumps``: the step each servo is sent where a looping timeline wraps from its end back to its start
(the Animate panel's Loop while streaming). The stream's rate check compares the motion over [0, T] only; at the
wrap the frames go from the angle at t = T to the one at t = 0, which nothing compared. Without FreeCAD."""
import json
import math
import os

import pytest

from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.core.motion import profile_value
from metamaterial_wb.core.scene import Scene
from metamaterial_wb.hardware.mapping import channel_map, wrap_jumps

FISH = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))),
                    "examples", "fish.json")
SCALE = 60.0      # servo.scale_deg: the angle sent is v * 60 deg (closed form)


def fish(head=None, tail=None, tail_servo=None):
    """The fish; ``head`` / ``tail``: other profiles (None: keep); both servos ``v * SCALE`` unless ``tail_servo``."""
    with open(FISH, encoding="utf-8") as f:
        d = json.load(f)
    for a in d["actuators"]:
        a["servo"] = {"scale_deg": SCALE}
        new = {"head": head, "tail": tail}[a["name"]]
        if new is not None:
            a["profile"] = new
    if tail_servo is not None:
        d["actuators"][1]["servo"] = tail_servo
    return Scene.from_dict(d)


def jumps(scene, duration_s, clamp=False):
    return {j.name: j for j in wrap_jumps(scene, channel_map(scene), duration_s, clamp=clamp)}


@pytest.mark.parametrize("T", [1.1, 1.25, 2.7, 0.3])
def test_a_sine_whose_period_does_not_divide_the_timeline_jumps_by_its_value_at_the_end(T):
    """A 1 s sine (amplitude 0.5, phase 0) starts at 0 deg; at T it is at 0.5 * 60 * sin(2 pi T / 1 s) deg."""
    sc = fish(tail={"shape": "sine", "amplitude": 0.5, "frequency_hz": 1.0, "phase_deg": 0.0})
    j = jumps(sc, T)["tail"]
    end = round(100 * SCALE * 0.5 * math.sin(2 * math.pi * T / 1.0))
    assert j.channel == 1
    assert (j.end_cdeg, j.start_cdeg) == (end, 0)
    assert j.end_deg == end / 100 and j.start_deg == 0.0
    assert j.deg == pytest.approx(abs(end) / 100, abs=1e-12) and j.deg > 3.0


def test_whole_periods_do_not_jump_and_the_order_is_the_channels():
    sc = fish()                     # head 0.5 Hz, tail 1 Hz: 2 s and 6 s are whole periods of both
    for T in (2.0, 6.0):
        js = wrap_jumps(sc, channel_map(sc), T)
        assert [j.name for j in js] == ["head", "tail"]
        assert all(j.deg == 0.0 for j in js), js
    js = jumps(sc, 1.0)             # half the head's period: 0.3 * sin(pi) = 0, the tail's whole period
    assert js["head"].deg == 0.0 and js["tail"].deg == 0.0
    js = jumps(sc, 0.5)             # the head a quarter period on (0.3 sin(pi / 2) = 0.3), the tail at its trough
    assert js["head"].end_cdeg == round(100 * SCALE * 0.3) and js["head"].start_cdeg == 0
    tail0 = round(100 * SCALE * 0.9 * math.sin(math.radians(90)))
    assert js["tail"].start_cdeg == tail0 and js["tail"].end_cdeg == -tail0


def test_a_ramp_and_keys_that_end_elsewhere_jump_by_the_difference():
    ramp = {"shape": "keyframes", "times_s": [0.0, 4.0], "values": [-0.5, 0.5]}
    j = jumps(fish(tail=ramp), 3.0)["tail"]
    assert (j.start_cdeg, j.end_cdeg) == (round(100 * SCALE * -0.5), round(100 * SCALE * 0.25))
    assert j.deg == pytest.approx(SCALE * 0.75)
    # keys that end where they start (a closed loop of keys): no jump at their last key
    closed = {"shape": "keyframes", "times_s": [0.0, 1.0, 2.0], "values": [0.2, 0.7, 0.2]}
    assert jumps(fish(tail=closed), 2.0)["tail"].deg == 0.0
    assert jumps(fish(tail=closed), 1.0)["tail"].deg == pytest.approx(SCALE * 0.5)


def test_a_periodic_steps_profile_at_whole_periods_counts_as_its_start():
    """A square (steps with period_s 0.4 s) over 2 s: floating-point mod puts t = 2.0 on its last level (2.0 % 0.4 =
    0.3999...), yet 2 s is five whole periods and the motion ends where it starts."""
    square = {"shape": "steps", "times_s": [0.0, 0.2], "values": [0.5, -0.5], "period_s": 0.4}
    assert profile_value(square, 2.0) == -0.5          # what a plain evaluation at T gives
    assert jumps(fish(tail=square), 2.0)["tail"].deg == 0.0
    j = jumps(fish(tail=square), 2.3)["tail"]          # 5.75 periods: on the low level
    assert (j.end_cdeg, j.start_cdeg) == (round(100 * SCALE * -0.5), round(100 * SCALE * 0.5))


def test_the_joint_rotation_mapping_in_whole_centidegrees_as_sent():
    """Without scale_deg the angle is the joint's simulated rotation; the jump is in the centidegrees the Streamer
    puts on the wire (ChannelConfig.cdeg)."""
    with open(FISH, encoding="utf-8") as f:
        sc = Scene.from_dict(json.load(f))
    chans = {c.name: c for c in channel_map(sc)}
    T = 1.3
    for name, j in jumps(sc, T).items():
        a = [x for x in sc.actuators if x.name == name][0]
        assert j.end_cdeg == chans[name].cdeg(profile_value(a.profile, T))
        assert j.start_cdeg == chans[name].cdeg(profile_value(a.profile, 0.0))
    assert jumps(sc, T)["tail"].deg > 3.0


def test_clamp_clamps_as_sent_and_without_it_nothing_is_clamped():
    servo = {"scale_deg": SCALE, "limits_deg": [-10.0, 10.0], "park_deg": 0.0}
    sc = fish(tail={"shape": "sine", "amplitude": 0.5, "frequency_hz": 1.0, "phase_deg": 0.0}, tail_servo=servo)
    assert jumps(sc, 1.25)["tail"].end_cdeg == 3000            # 0.5 * 60 deg, outside the limits: as computed
    j = jumps(sc, 1.25, clamp=True)["tail"]
    assert (j.end_cdeg, j.start_cdeg) == (1000, 0)            # clamped to 10 deg, as Streamer(clamp=True) sends


def test_no_profile_or_a_constant_one_never_jumps():
    sc = fish(tail={"shape": "constant", "value": 0.4})
    assert jumps(sc, 1.7)["tail"].deg == 0.0
    with open(FISH, encoding="utf-8") as f:
        d = json.load(f)
    del d["actuators"][0]["profile"]
    sc = Scene.from_dict(d)
    assert jumps(sc, 1.7)["head"].deg == 0.0


@pytest.mark.parametrize("bad", [0.0, -1.0, float("nan"), "2"])
def test_a_timeline_length_that_is_not_a_positive_number_is_refused(bad):
    sc = fish()
    with pytest.raises(SceneError) as e:
        wrap_jumps(sc, channel_map(sc), bad)
    assert "duration_s" in str(e.value) and repr(bad) in str(e.value)
