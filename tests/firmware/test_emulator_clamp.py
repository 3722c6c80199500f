"""Clamping on the real firmware (simavr): what the host clamps and what the firmware clamps are counted apart,
and a trim that would take a servo past its pulse range is refused before anything moves.

Pulse widths in closed form: 1500 us + servo angle / 90 deg * 1000 us (500..2500 us), servo angle = angle + trim."""
import json
import math
import os
import subprocess
import sys

import pytest

from metamaterial_wb.core.scene import Scene
from metamaterial_wb.hardware import Link, Streamer, channel_map
from metamaterial_wb.hardware.mapping import ChannelConfig

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
FISH = os.path.join(REPO, "examples", "fish.json")
TOL_US = 10.0


def TAIL_AT(t):  # the fish's tail, joint V1,5: v = 0.9 sin(2 pi t + 90 deg); 24.31 deg closed / 90 deg open per v
    v = 0.9 * math.sin(2 * math.pi * t + math.pi / 2)
    phi = math.asin(8.0 / 38.0) if v >= 0 else math.pi / 4
    return math.degrees(-2 * v * phi)


def stream(sim, tmp_path, channels, *extra):
    chans = tmp_path / "c.json"
    chans.write_text(json.dumps(channels))
    rep = tmp_path / "r.json"
    r = subprocess.run([sys.executable, "-m", "metamaterial_wb", "stream", FISH, "--port", sim.port, "--seconds", "2",
                        "--channels", str(chans), "--report", str(rep), *extra],
                       capture_output=True, text=True, cwd=REPO, timeout=60)
    return r, (json.loads(rep.read_text()) if rep.exists() else None)


def ch1_pulses(sim):
    return [w for _, ch, w in sim.pulse_lines() if ch == 1 and w]


def test_cli_clamp_counts_the_host_clamps_and_the_pins_stay_inside_the_limits(sim, tmp_path):
    """The auditor's case: --clamp to [-20, 20] printed "0 frames clamped" while the host clamped 56 frames."""
    r, d = stream(sim, tmp_path, {"tail": {"limits_deg": [-20, 20]}}, "--clamp")
    assert r.returncode == 0, r.stdout + r.stderr
    out = [f for f in d["frames_sent"] if abs(TAIL_AT(f["t"])) > 20]
    assert len(out) >= 40 and d["host_clamped_frames"] == len(out) == d["clamped_frames"], d
    assert d["firmware_clamped_frames"] == 0 and d["clamped_by_actuator"]["tail"] == {"host": len(out), "firmware": 0}
    assert f"{len(out)} frames clamped (host {len(out)}: tail {len(out)}; firmware 0)" in r.stdout
    assert all(f["wanted_deg"]["1"] == pytest.approx(TAIL_AT(f["t"]), abs=1e-3) for f in out)
    p = ch1_pulses(sim)
    assert p and max(p) <= 1500 + 20 / 90 * 1000 + TOL_US and min(p) >= 1500 - 20 / 90 * 1000 - TOL_US


def test_cli_clamp_with_trim_up_to_the_servo_end(sim, tmp_path):
    """trim 12 and limits up to 78 deg: the clamped angle plus trim reaches exactly 90 deg (2500 us), which the
    firmware does not clamp."""
    r, d = stream(sim, tmp_path, {"tail": {"trim_deg": 12, "limits_deg": [-24.31, 78]}}, "--clamp")
    assert r.returncode == 0, r.stdout + r.stderr
    assert d["firmware_clamped_frames"] == 0 and d["host_clamped_frames"] > 0, d
    assert max(ch1_pulses(sim)) == pytest.approx(2500, abs=1)


def test_cli_refuses_a_trim_past_the_servo_end_before_anything_moves(sim, tmp_path):
    """Before: exit 0, "10 frames clamped", the pin stopped at 2500 us while the servo should have gone to 93 deg."""
    for extra in ((), ("--clamp",)):
        r, d = stream(sim, tmp_path, {"tail": {"trim_deg": 12}}, *extra)
        assert r.returncode == 2 and "trim_deg 12" in r.stderr and "[-90, 90]" in r.stderr, r.stdout + r.stderr
        assert d is None and not ch1_pulses(sim)


def test_streamer_counts_the_firmware_clamps_per_actuator(sim):
    """A board whose limits are narrower than the host's (configured behind the streamer's back): the ACKs' clamp
    masks are counted per actuator, apart from the host's clamps."""
    scene = Scene.load(FISH)
    with Link.open(sim.port) as link:
        st = Streamer(link, channel_map(scene), reply_timeout_s=2.0)
        st.prepare()
        link.configure([ChannelConfig("tail", 1, limits_deg=(-10.0, 10.0))])
        stats = st.run(lambda t: {"head": 0.1, "tail": -0.5}, 0.4)
        link.disarm()
    s = stats.summary()
    assert stats.frames == stats.acked and stats.frames >= 15, s
    assert s["firmware_clamped_frames"] == s["clamped_frames"] == stats.frames and s["host_clamped_frames"] == 0, s
    assert s["clamped_by_actuator"] == {"head": {"host": 0, "firmware": 0},
                                        "tail": {"host": 0, "firmware": stats.frames}}, s
