"""Whether ``--rate`` can follow the motion, what the summary's rate counts, and the contact pins (audit of the
hardware layer):

* ``stream`` refuses, before it opens a port, a ``--rate`` whose frames (t = k / rate, the servo moving linearly
  between them) stray from the motion sampled at 1 kHz by more than ``--rate-tolerance`` (default 3 deg): the fish
  at 1 Hz (every frame the same while the simulation swims) and a 25 Hz tail at 50 Hz (every frame 0.0 deg) went
  out with exit 0;
* the summary's rate is ticks per second: with channels that are not adjacent each tick sends one SET_ANGLES frame
  per run of adjacent channels, and the rate was frames / duration (100 Hz at 50 Hz);
* ``FirmwareGait(pins=True)`` names the switch inputs the firmware reads (A0..A5, A0..A3 with the PCA9685).

Without hardware (loop://)."""
import json
import math
import os
import re
import subprocess
import sys

import pytest

pytest.importorskip("serial")

from metamaterial_wb.core.errors import SceneError  # noqa: E402
from metamaterial_wb.core.scene import Scene  # noqa: E402
from metamaterial_wb.hardware import Link, Streamer, channel_map, check_motion  # noqa: E402
from test_stream import fish  # noqa: E402 - the stream tests' fish with servo fields

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
FISH = os.path.join(REPO, "examples", "fish.json")


def mapping():
    # imported here: the names below are what this file tests; a missing one fails the test, not the collection
    from metamaterial_wb.hardware import mapping as m
    return m


def run_cli(*args):
    return subprocess.run([sys.executable, "-m", "metamaterial_wb", "stream", *args], capture_output=True, text=True,
                          cwd=REPO, timeout=120)


def fish_with(**profiles):
    """The fish with other motion profiles (``name=profile``) and optional servo fields (``name_servo=...``)."""
    d = json.load(open(FISH, encoding="utf-8"))
    for a in d["actuators"]:
        if a["name"] in profiles:
            a["profile"] = profiles[a["name"]]
        if a["name"] + "_servo" in profiles:
            a["servo"] = profiles[a["name"] + "_servo"]
    return d


def scene_file(tmp_path, d):
    p = tmp_path / "scene.json"
    p.write_text(json.dumps(d))
    return str(p)


RATE_MSG = (r"^error: --rate: (?P<rate>[\d.]+) Hz cannot follow the motion: (?P<name>\w+) \(channel \d\), moving "
            r"linearly between frames [\d.]+ ms apart, would be (?P<dev>[\d.]+) deg off it at t = (?P<t>[\d.]+) s "
            r"\(at -?[\d.]+ deg where the motion is at -?[\d.]+ deg\); allowed: at most 3 deg \(--rate-tolerance\)")


# ---------------------------------------------------------------------------------------------------------------
# 1. a --rate that cannot follow the motion is refused up front


def test_cli_refuses_the_fish_at_1_hz_before_opening_the_port(tmp_path):
    """Before: exit 0 and six identical frames (head 0.5 Hz and tail 1 Hz sines sampled at 1 Hz)."""
    rep = tmp_path / "r.json"
    r = run_cli(FISH, "--port", "/dev/nonexistent-tty", "--seconds", "6", "--rate", "1", "--report", str(rep))
    assert r.returncode == 2 and r.stderr.count("\n") == 1, (r.stdout, r.stderr)
    assert "cannot open" not in r.stderr and not rep.exists()   # refused before the port was opened
    m = re.search(RATE_MSG, r.stderr)
    assert m, r.stderr
    assert m["rate"] == "1" and m["name"] == "tail" and float(m["dev"]) > 90
    # the Nyquist rate of the fastest sine, and the rates that would pass, checked against the rule itself
    assert "1 Hz is not above 2 Hz, twice the 1 Hz of tail's sine (Nyquist)" in r.stderr, r.stderr
    got = re.search(r"the lowest whole rate that passes is (\d+) Hz, and every whole rate from (\d+) to 100 Hz "
                    r"does \(some in between do not\)", r.stderr)
    assert got, r.stderr
    low, every = int(got[1]), int(got[2])
    s = fish()
    ch = channel_map(s)
    dev = mapping().rate_deviation
    assert all(dev(s, ch, 6.0, r_).deg > 3 for r_ in range(1, low))
    assert dev(s, ch, 6.0, low).deg <= 3 and dev(s, ch, 6.0, every - 1).deg > 3
    assert all(dev(s, ch, 6.0, r_).deg <= 3 for r_ in range(every, 101))


def test_cli_refuses_a_25_hz_tail_at_50_hz(tmp_path):
    """Before: exit 0, every frame of the tail 0.0 deg (a 25 Hz sine sampled at 50 Hz, phase 0)."""
    scene = scene_file(tmp_path, fish_with(tail={"shape": "sine", "amplitude": 0.9, "frequency_hz": 25,
                                                 "phase_deg": 0}))
    rep = tmp_path / "r.json"
    r = run_cli(scene, "--dry-run", "--seconds", "1", "--report", str(rep))
    assert r.returncode == 2 and r.stderr.count("\n") == 1, (r.stdout, r.stderr)
    m = re.search(RATE_MSG, r.stderr)
    assert m and m["rate"] == "50" and m["name"] == "tail" and float(m["dev"]) == pytest.approx(81.0, abs=0.5)
    assert "50 Hz is not above 50 Hz, twice the 25 Hz of tail's sine (Nyquist)" in r.stderr
    assert "no rate up to 100 Hz passes" in r.stderr
    assert not rep.exists()


def test_rate_deviation_of_a_sine_is_its_chord_error():
    """A sine of amplitude A (deg) at f Hz, its peak halfway between two frames 1/r apart: the servo's straight
    path between them passes A (1 - cos(pi f / r)) below the peak (the tail turned linearly: scale_deg)."""
    s = Scene.from_dict(fish_with(tail={"shape": "sine", "amplitude": 0.9, "frequency_hz": 1.0, "phase_deg": 72},
                                  tail_servo={"scale_deg": 90}))
    ch = channel_map(s)
    d = mapping().rate_deviation(s, ch, 2.0, 10)
    assert d.name == "tail" and d.channel == 1
    assert d.deg == pytest.approx(81 * (1 - math.cos(math.pi / 10)), abs=0.006)   # 3.964 deg, frames in 0.01 deg
    assert d.t == pytest.approx(0.05) and d.motion_deg == pytest.approx(81.0)
    assert d.servo_deg == pytest.approx(81 * math.cos(math.pi / 10), abs=0.006)
    with pytest.raises(SceneError, match=r"--rate: 10 Hz cannot follow the motion: tail \(channel 1\), moving "
                                         r"linearly between frames 100 ms apart, would be 3\.96 deg off it at "
                                         r"t = 0\.050 s"):
        check_motion(s, ch, 2.0, 10)
    check_motion(s, ch, 2.0, 10, rate_tolerance_deg=4.0)   # a looser tolerance, given explicitly
    with pytest.raises(SceneError, match=r"rate_tolerance_deg: 0(\.0)? deg is outside the allowed range \(0, 180\]"):
        check_motion(s, ch, 2.0, 10, rate_tolerance_deg=0.0)


def scenes_that_stream():
    out = []
    for name in sorted(os.listdir(os.path.join(REPO, "examples"))):
        if name.endswith(".json"):
            d = json.load(open(os.path.join(REPO, "examples", name), encoding="utf-8"))
            if d.get("format") == "metamaterial-scene" and d.get("actuators"):
                out.append(name)
    return out


@pytest.mark.parametrize("name", scenes_that_stream())
def test_bundled_examples_pass_at_the_default_rate(name):
    """Each example streams at the default 50 Hz for the default 10 s (and longer): the tolerance leaves them room
    (the worst, the fish's tail, cuts the corner of its joint's two rotation rates by 1.86 deg)."""
    s = Scene.load(os.path.join(REPO, "examples", name))
    ch = channel_map(s)
    for seconds in (10.0, 30.0):
        check_motion(s, ch, seconds)
        assert mapping().rate_deviation(s, ch, seconds, 50).deg < 2.0


def test_a_step_is_followed_but_a_step_shorter_than_a_frame_is_not():
    """A steps profile jumps: no servo follows a jump, so the deviation of a step is measured to the nearer of the
    two frames around each instant; a level shorter than the frame period that falls between two frames is never
    sent and is refused."""
    steps = {"shape": "steps", "times_s": [0, 0.5], "values": [0, 0.5], "period_s": 1.0}
    still = {"shape": "constant", "value": 0.0}
    s = Scene.from_dict(fish_with(head=still, tail=steps))
    assert mapping().rate_deviation(s, channel_map(s), 3.0, 50).deg < 0.01
    check_motion(s, channel_map(s), 3.0, 50)
    blip = {"shape": "steps", "times_s": [0, 0.505, 0.515], "values": [0, 0.5, 0], "period_s": 1.0}
    s = Scene.from_dict(fish_with(head=still, tail=blip))
    with pytest.raises(SceneError, match=r"--rate: 50 Hz cannot follow the motion: tail \(channel 1\).* would be "
                                         r"12\.15 deg off it at t = 0\.505 s"):
        check_motion(s, channel_map(s), 3.0, 50)
    # at 100 Hz the level is sent (frames at 0.50, 0.51, 0.52 s) but the servo gets a pulse every 20 ms with the
    # latest frame: at some phases every pulse misses the 0.51 s one
    with pytest.raises(SceneError, match=r"--rate: 100 Hz cannot follow the motion: tail \(channel 1\), moving "
                                         r"linearly between frames 20 ms apart \(its servo gets a pulse every 20 ms "
                                         r"with the latest of the frames sent 10 ms apart\), would be 12\.15 deg"):
        check_motion(s, channel_map(s), 3.0, 100)
    longer = {"shape": "steps", "times_s": [0, 0.505, 0.535], "values": [0, 0.5, 0], "period_s": 1.0}
    s = Scene.from_dict(fish_with(head=still, tail=longer))
    check_motion(s, channel_map(s), 3.0, 100)   # a 30 ms level reaches a pulse at every phase


def test_with_clamp_the_clamped_motion_is_compared():
    s = fish(tail={"limits_deg": [-20, 20]})
    d = mapping().rate_deviation(s, channel_map(s), 2.0, 1, clamp=True)
    assert -20 <= d.motion_deg <= 20 and -20 <= d.servo_deg <= 20 and d.deg > 3
    with pytest.raises(SceneError, match=r"--rate: 1 Hz cannot follow"):
        check_motion(s, channel_map(s), 2.0, 1, clamp=True)
    check_motion(s, channel_map(s), 2.0, 50, clamp=True)


def test_rate_tolerance_flag_lets_a_slow_rate_through_and_is_checked(tmp_path):
    rep = tmp_path / "r.json"
    r = run_cli(FISH, "--dry-run", "--seconds", "2", "--rate", "1", "--rate-tolerance", "180", "--report", str(rep))
    assert r.returncode == 0, r.stderr
    assert json.loads(rep.read_text(encoding="utf-8"))["ticks"] == 2
    for bad in ("0", "-1", "180.5"):
        r = run_cli(FISH, "--dry-run", "--seconds", "0.1", "--rate-tolerance", bad)
        assert r.returncode == 2 and r.stderr.count("\n") == 1, r.stderr
        assert re.search(r"--rate-tolerance: -?[\d.]+ deg is outside the allowed range \(0, 180\]", r.stderr), r.stderr
    r = run_cli(FISH, "--dry-run", "--seconds", "0.1", "--rate-tolerance", "nan")    # not a number: refused as read
    assert r.returncode == 2 and "argument --rate-tolerance: 'nan' is not a number" in r.stderr, r.stderr


def test_docs_describe_the_rate_rule_and_its_tolerance():
    text = open(os.path.join(REPO, "docs", "firmware.md"), encoding="utf-8").read()
    assert "`--rate-tolerance DEG`" in text
    tol = mapping().RATE_TOLERANCE_DEG
    assert f"default {tol:g}" in text and "Nyquist" in text


# ---------------------------------------------------------------------------------------------------------------
# 2. the summary's rate: ticks per second, frames counted apart


def test_cli_rate_is_ticks_per_second_with_channels_that_are_not_adjacent(tmp_path):
    """Before: ``100 frames in 1.00 s (99.9 Hz)`` and ``"rate_hz": 99.9`` for a 50 Hz stream (two frames a tick)."""
    rep = tmp_path / "r.json"
    r = run_cli(FISH, "--dry-run", "--seconds", "1", "--map", "head=2,tail=5", "--report", str(rep))
    assert r.returncode == 0, r.stderr
    d = json.loads(rep.read_text(encoding="utf-8"))
    # a loaded machine may skip a late tick (counted in "skipped"): then fewer ticks, each still two frames
    n = d["ticks"]
    assert n + d["skipped"] == 50 and n >= 40 and d["frames"] == 2 * n == d["acked"] and d["frames_per_tick"] == 2
    assert d["rate_hz"] == pytest.approx(n / d["duration_s"], abs=0.01) and d["rate_hz"] <= 50.01, d
    m = re.search(rf"^{n} ticks in (\d+\.\d\d) s \((\d+\.\d) Hz\), {2 * n} frames \(2 a tick: one per run of "
                  rf"adjacent channels\): {2 * n} acked, ", r.stdout)
    assert m and float(m[2]) == pytest.approx(d["rate_hz"], abs=0.051), r.stdout
    r = run_cli(FISH, "--dry-run", "--seconds", "0.5")
    assert re.search(r"^(\d+) ticks in \d+\.\d\d s \(\d+\.\d Hz\), \1 frames: \1 acked, ", r.stdout), r.stdout


def test_streamer_counts_ticks_and_frames_apart():
    s = fish(head={"channel": 2}, tail={"channel": 5})
    link = Link.open("loop://", dry_run=True)
    st = Streamer(link, channel_map(s), catch_up=True)
    st.prepare()
    stats = st.run(s, 0.2)
    summ = stats.summary()
    assert stats.ticks == 10 and stats.frames == 20 and summ["frames_per_tick"] == 2
    assert summ["rate_hz"] == pytest.approx(stats.ticks / stats.duration_s, abs=1e-3)


def test_docs_sample_summary_has_the_cli_format():
    text = open(os.path.join(REPO, "docs", "firmware.md"), encoding="utf-8").read()
    m = re.search(r"one summary line, e\.g\. `([^`]+)`", text.replace("\n", " "))
    assert m and re.match(r"\d+ ticks in \d+\.\d\d s \(\d+\.\d Hz\), \d+ frames: \d+ acked, \d+ NAKed, +\d+ lost",
                          m[1]), m and m[1]


# ---------------------------------------------------------------------------------------------------------------
# 3. the contact switches FirmwareGait(pins=True) reads


def test_firmware_gait_names_the_contact_pins_the_firmware_reads():
    from metamaterial_wb.hardware.onboard import FirmwareGait
    src = os.path.join(REPO, "firmware", "src", "avr")
    main = open(os.path.join(src, "main.c"), encoding="utf-8").read()
    body = main[main.index("static void read_contacts"):main.index("int main(void)")]
    assert "PINC" in body and "PIND" not in body and "PINB" not in body   # port C: A0..A5
    cells = {}
    for backend in ("servo_isr.c", "servo_pca9685.c"):
        cells[backend] = int(re.search(r"hal_contact_cells = (\d+);", open(os.path.join(src, backend), encoding="utf-8").read())[1])
    doc = " ".join(FirmwareGait.__doc__.split())
    assert f"A0..A{cells['servo_isr.c'] - 1}" in doc and f"A0..A{cells['servo_pca9685.c'] - 1} with the PCA9685" in doc
    assert "D2" not in doc and "D3" not in doc, doc
