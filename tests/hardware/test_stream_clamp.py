"""Nothing clamped silently, nothing past the servo's range (audit of the hardware layer):

* ``--clamp`` counts the frames the host clamps (in total and per actuator) next to the firmware's clamp masks,
  and ``--report`` keeps the wanted angle of every clamped channel;
* ``+-angle + trim_deg`` must stay inside the servo's [-90, 90] deg (its pulse range min_us..max_us), for the
  streamed motion (with or without ``--clamp``), for the on-board oscillators and for a single frame;
* ``max_slew_dps`` is a whole number of deg/s (the protocol's u16; 0 means "no limit", so 0.4 used to turn the
  limit off and 2.5 was sent as 2).

Without hardware (loop://); the firmware side is in tests/firmware/test_emulator_clamp.py."""
import json
import math
import os
import re
import struct
import subprocess
import sys

import pytest

pytest.importorskip("serial")

from metamaterial_wb.core.errors import MetamaterialError, SceneError  # noqa: E402
from metamaterial_wb.hardware import Link, Streamer, channel_map, check_motion  # noqa: E402
from test_stream import fish  # noqa: E402 - the stream tests' fish with servo fields

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
FISH = os.path.join(REPO, "examples", "fish.json")


def TAIL(v):  # joint V1,5 of the fish (node A parity +1): closes by 24.31 deg per unit of v, opens by 90
    phi = math.asin(8.0 / (2 * 19.0)) if v >= 0 else math.pi / 4
    return math.degrees(-2 * v * phi)


def TAIL_AT(t):  # the fish's tail: v = 0.9 sin(2 pi t + 90 deg)
    return TAIL(0.9 * math.sin(2 * math.pi * t + math.pi / 2))




def run_cli(*args):
    return subprocess.run([sys.executable, "-m", "metamaterial_wb", "stream", *args], capture_output=True, text=True,
                          cwd=REPO, timeout=60)


# ---------------------------------------------------------------------------------------------------------------
# 1. --clamp: the host's clamps are counted and reported


def test_cli_clamp_counts_the_frames_the_host_clamps_and_reports_the_wanted_angles(tmp_path):
    """Before: "0 frames clamped" although the host had clamped the tail in 28 of the 50 frames (only the ACKs'
    clamp masks were counted, and the firmware never saw an angle outside its limits)."""
    chans = tmp_path / "c.json"
    chans.write_text(json.dumps({"tail": {"limits_deg": [-20, 20]}}))
    rep = tmp_path / "r.json"
    r = run_cli(FISH, "--dry-run", "--channels", str(chans), "--clamp", "--seconds", "1", "--report", str(rep))
    assert r.returncode == 0, r.stderr
    d = json.loads(rep.read_text())
    wanted = {f["t"]: TAIL_AT(f["t"]) for f in d["frames_sent"]}
    out = [t for t, a in wanted.items() if abs(a) > 20]
    assert len(out) >= 20  # 28 of 50 frames unless a loaded machine skipped some
    n = len(out)
    assert d["host_clamped_frames"] == n and d["firmware_clamped_frames"] == 0 and d["clamped_frames"] == n, d
    assert d["clamped_by_actuator"] == {"head": {"host": 0, "firmware": 0}, "tail": {"host": n, "firmware": 0}}
    assert f"{n} frames clamped (host {n}: tail {n}; firmware 0)" in r.stdout
    for f in d["frames_sent"]:
        a = wanted[f["t"]]
        if abs(a) > 20:  # sent: the clamped angle; wanted: the motion's
            assert f["angles_deg"]["1"] == math.copysign(20, a)
            assert f["wanted_deg"] == {"1": pytest.approx(a, abs=1e-4)}
        else:
            assert "wanted_deg" not in f and f["angles_deg"]["1"] == pytest.approx(a, abs=0.005 + 1e-9)  # cdeg sent


def test_streamer_counts_host_clamps_per_actuator():
    with Link.open("loop://", dry_run=True) as link:
        st = Streamer(link, channel_map(fish()), clamp=True)
        st.prepare()
        seen = []
        st.on_clamp = lambda t, wanted: seen.append(wanted)
        stats = st.run(lambda t: {"head": 0.0, "tail": 1.5}, 0.1)
    assert stats.frames == 5 and stats.host_clamped_frames == 5 and stats.clamped_frames == 5
    assert stats.summary()["clamped_by_actuator"]["tail"] == {"host": 5, "firmware": 0}
    assert seen == [{"tail": pytest.approx(TAIL(1.5))}] * 5


# ---------------------------------------------------------------------------------------------------------------
# 2. trim_deg: the servo angle +-angle + trim must stay inside [-90, 90]

# the tail opens to 81 deg at v = -0.9; with trim 12 its servo passes 90 deg (pulse 2500 us) first at 78.06 deg,
# t = 0.457 s (1 kHz samples; 9006 cdeg as sent)
TRIM_MSG = (r"actuators\[1\] \(tail\): its servo would turn to 90\.06 deg at t = 0\.457 s \(joint angle 78\.06 deg "
            r"\+ trim_deg 12\); the servo of channel 1 turns within \[-90, 90\] deg")


def test_check_motion_refuses_a_trim_that_takes_the_servo_past_90_deg():
    s = fish(tail={"trim_deg": 12})
    with pytest.raises(SceneError, match=TRIM_MSG):
        check_motion(s, channel_map(s), 2.0)
    s = fish(tail={"trim_deg": -12, "invert": True})
    with pytest.raises(SceneError, match=r"turn to -90\.06 deg at t = 0\.457 s \(joint angle 78\.06 deg, inverted, "
                                         r"\+ trim_deg -12\)"):
        check_motion(s, channel_map(s), 2.0)
    s = fish(tail={"trim_deg": -12})  # the other side: -21.88 - 12 = -33.88: fine
    check_motion(s, channel_map(s), 2.0)


def test_with_clamp_the_reach_is_checked_on_the_clamped_angles():
    s = fish(tail={"trim_deg": 12})  # clamping to the default limits (-24.31..90) does not help
    with pytest.raises(SceneError, match=TRIM_MSG):
        check_motion(s, channel_map(s), 2.0, clamp=True)
    s = fish(tail={"trim_deg": 12, "limits_deg": [-24.31, 78]})  # 78 + 12 = 90: the servo's end, allowed
    with pytest.raises(SceneError, match=r"motion reaches 78\.1 deg .*pass --clamp"):
        check_motion(s, channel_map(s), 2.0)
    peaks = check_motion(s, channel_map(s), 2.0, clamp=True)
    assert peaks["tail"] == pytest.approx(78.0)
    s = fish(tail={"trim_deg": 12, "limits_deg": [-24.31, 79]})  # 79 + 12 = 91
    with pytest.raises(SceneError, match=r"turn to 90\.06 deg at t = 0\.457 s"):
        check_motion(s, channel_map(s), 2.0, clamp=True)


def test_osc_params_refuse_a_trim_that_takes_the_servo_past_90_deg():
    from metamaterial_wb.hardware.onboard import osc_params
    s = fish(tail={"trim_deg": 12})
    with pytest.raises(SceneError, match=TRIM_MSG):
        osc_params(s, channel_map(s))
    s = fish(tail={"scale_deg": 90, "trim_deg": 20})  # linear: 0.9 * 90 + 20 = 101 deg at t = 0
    with pytest.raises(SceneError, match=r"turn to 101\.00 deg at t = 0\.000 s \(joint angle 81\.00 deg \+ trim_deg "
                                         r"20\)"):
        osc_params(s, channel_map(s))
    s = fish(tail={"scale_deg": 90, "trim_deg": 9})  # 81 + 9 = 90: the servo's end
    osc_params(s, channel_map(s))


def test_frame_payloads_refuse_a_servo_angle_past_90_deg():
    with Link.open("loop://", dry_run=True) as link:
        st = Streamer(link, channel_map(fish(tail={"trim_deg": 12})))
        assert st.frame_payloads({"tail": -0.8})[0][1]["tail"] == pytest.approx(72.0)  # 84 deg: fine
        with pytest.raises(MetamaterialError, match=r"tail.*turn to 93\.00 deg \(joint angle 81\.00 deg \+ trim_deg "
                                                    r"12\).*\[-90, 90\]"):
            st.frame_payloads({"tail": -0.9})
        st.clamp = True  # clamping to the limits (..90) leaves 90 + 12
        with pytest.raises(MetamaterialError, match=r"turn to 102\.00 deg"):
            st.frame_payloads({"tail": -1.0})


@pytest.mark.parametrize("extra", [[], ["--clamp"], ["--mode", "osc"]])
def test_cli_refuses_the_trimmed_fish_before_opening_the_port(tmp_path, extra):
    """Before: exit 0 and "10 frames clamped" on the board (the pin stopped at 2500 us, 3 deg short)."""
    chans = tmp_path / "c.json"
    chans.write_text(json.dumps({"tail": {"trim_deg": 12}}))
    rep = tmp_path / "r.json"
    r = run_cli(FISH, "--dry-run", "--channels", str(chans), "--seconds", "1", "--report", str(rep), *extra)
    assert r.returncode == 2, (r.stdout, r.stderr)
    assert r.stderr.count("\n") == 1 and re.search(TRIM_MSG, r.stderr), r.stderr
    assert not rep.exists()


# ---------------------------------------------------------------------------------------------------------------
# 3. max_slew_dps: a whole number of deg/s


@pytest.mark.parametrize("dps", [2.5, 0.4, 3599.5])
def test_max_slew_dps_must_be_a_whole_number(dps):
    with pytest.raises(SceneError, match=rf"actuators\[0\]\.servo\.max_slew_dps: {dps}.*a whole number 0\.\.3600 "
                                         rf"deg/s \(0: no limit\)"):
        channel_map(fish(head={"max_slew_dps": dps}))
    with pytest.raises(SceneError, match=rf"--channels head\.max_slew_dps: {dps}.*whole number"):
        channel_map(fish(), overrides={"head": {"max_slew_dps": dps}})


@pytest.mark.parametrize("field", ["min_us", "max_us"])
def test_pulse_widths_are_whole_microseconds_with_one_wording(field):
    """min_us / max_us share max_slew_dps's whole-number check and its wording (value, unit, range)."""
    with pytest.raises(SceneError, match=rf"actuators\[0\]\.servo\.{field}: 1500\.5 us is not a whole number; "
                                         rf"allowed: a whole number 400\.\.2600 us"):
        channel_map(fish(head={field: 1500.5}))
    assert getattr(channel_map(fish(head={field: 1500.0}))[0], field) == 1500


def test_whole_max_slew_dps_is_sent_as_is():
    for dps in (16.0, 16, 0, 3600):
        c = channel_map(fish(head={"max_slew_dps": dps}))[0]
        assert struct.unpack("<BHHhBhhhH", c.config_payload())[-1] == int(dps)
    with pytest.raises(SceneError, match=r"max_slew_dps: 3601"):
        channel_map(fish(head={"max_slew_dps": 3601}))


def test_trim_message_names_the_pulse_the_firmware_would_stop_at():
    s = fish(tail={"trim_deg": 12, "min_us": 600, "max_us": 2400})
    with pytest.raises(SceneError, match=r"\(min_us 600 \.\. max_us 2400 us\): the firmware would stop it at "
                                         r"2400 us"):
        check_motion(s, channel_map(s), 2.0)
    s = fish(tail={"trim_deg": -12, "invert": True})
    with pytest.raises(SceneError, match=r"\(min_us 500 \.\. max_us 2500 us\): the firmware would stop it at "
                                         r"500 us"):
        check_motion(s, channel_map(s), 2.0)



@pytest.mark.parametrize("servo,where", [
    ({"trim_deg": 12, "park_deg": 85, "limits_deg": [-90, 90]}, "actuators[1].servo.park_deg"),
    ({"invert": True, "trim_deg": -10, "park_deg": 81, "limits_deg": [-90, 90]}, "actuators[1].servo.park_deg"),
])
def test_park_past_the_servo_end_is_refused(servo, where):
    """The firmware parks the servo at +-park_deg + trim_deg: past +-90 deg it would stop at min/max_us."""
    with pytest.raises(SceneError, match=re.escape(where) + r".*servo would park at (97|-91)\.00 deg.*\[-90, 90\]"):
        channel_map(fish(tail=servo))
    assert channel_map(fish(tail=dict(servo, park_deg=78)))   # inside: accepted
