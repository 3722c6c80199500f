"""Audit of ``stream`` (no hardware, no emulator: loop://, --dry-run and the functions directly):

1. a scene with more actuators than firmware channels is refused by its count, not by a ``servo.channel`` field
   the scene does not have;
2. ``--report``'s ``frames_sent.angles_deg`` holds the whole centidegrees the wire carried (never -0.0);
3. flags that ``--mode osc`` ignores (``--clamp``, ``--rate``, ``--rate-tolerance``, ``--max-lost``) are refused;
4. ``--mode osc`` prints a constant channel as a constant;
5. ``check_motion`` samples a long stream block by block (bounded memory), with the same result."""
import json
import os
import re
import subprocess
import sys

import pytest

pytest.importorskip("serial")

from metamaterial_wb.core.errors import SceneError  # noqa: E402
from metamaterial_wb.core.scene import Scene  # noqa: E402
from metamaterial_wb.hardware import Link, Streamer, channel_map, check_motion  # noqa: E402
from metamaterial_wb.hardware import mapping  # noqa: E402
from test_stream import fish  # noqa: E402 - the stream tests' fish with servo fields

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
FISH = os.path.join(REPO, "examples", "fish.json")
JOINTS = ["V0,1", "V0,2", "V0,3", "V0,4", "V0,5", "V1,1", "V1,2", "V1,3", "V1,4"]


def run_cli(*args):
    return subprocess.run([sys.executable, "-m", "metamaterial_wb", "stream", *args], capture_output=True, text=True,
                          cwd=REPO, timeout=60)


def many(n, servo=None):
    with open(FISH, encoding="utf-8") as f:
        d = json.load(f)
    d["actuators"] = [dict({"name": f"a{k}", "joint": JOINTS[k], "value": 0.1},
                           **({"servo": servo[k]} if servo and k in servo else {})) for k in range(n)]
    return d


# ---------------------------------------------------------------------------------------------------------------
# 1. more actuators than channels


def test_nine_actuators_are_refused_by_their_count(tmp_path):
    """Before: `actuators[8].servo.channel: 8: ... map the actuator with --map` (no such field; no --map helps)."""
    with pytest.raises(SceneError) as e:
        channel_map(Scene.from_dict(many(9)))
    assert e.value.field == "actuators", str(e.value)
    assert "9 actuators" in e.value.message and "8 channels (0..7)" in e.value.message, str(e.value)
    assert "servo" not in str(e.value) and "--map" not in str(e.value)
    p = tmp_path / "nine.json"
    p.write_text(json.dumps(many(9)), encoding="utf-8")
    r = run_cli(str(p), "--dry-run", "--seconds", "0.1")
    assert r.returncode == 2, (r.stdout, r.stderr)
    assert r.stderr.count("\n") == 1 and re.match(r"error: actuators: 9 actuators, the firmware drives 8 channels "
                                                  r"\(0\.\.7\)", r.stderr), r.stderr
    # eight still stream; a channel the scene gives out of range still names the scene's field
    assert [c.channel for c in channel_map(Scene.from_dict(many(8)))] == list(range(8))
    with pytest.raises(SceneError, match=r"actuators\[2\]\.servo\.channel"):
        channel_map(Scene.from_dict(many(3, {2: {"channel": 8}})))


# ---------------------------------------------------------------------------------------------------------------
# 2. the report holds what was sent


def test_frame_payloads_report_the_centidegrees_sent_and_no_negative_zero():
    """Before: the float angle (e.g. 12.345678) while the wire carried 1235 cdeg; -0.0 for a tiny negative."""
    with Link.open("loop://", dry_run=True) as link:
        st = Streamer(link, channel_map(fish(tail={"scale_deg": 90})))
        for v in (0.137174, -0.0000555, 0.0, -0.333333):
            (payload, angles, _), = st.frame_payloads({"head": v, "tail": v})
            cdeg = [int.from_bytes(payload[2 + 2 * i:4 + 2 * i], "little", signed=True) for i in range(2)]
            assert [angles["head"], angles["tail"]] == [c / 100 for c in cdeg], (v, angles, cdeg)
            for a in angles.values():
                assert str(a) != "-0.0"


def test_cli_report_angles_are_whole_centidegrees(tmp_path):
    rep = tmp_path / "r.json"
    r = run_cli(FISH, "--dry-run", "--seconds", "0.5", "--report", str(rep))
    assert r.returncode == 0, r.stderr
    d = json.loads(rep.read_text(encoding="utf-8"))
    vals = [a for f in d["frames_sent"] for a in f["angles_deg"].values()]
    assert len(vals) == 2 * len(d["frames_sent"]) > 40
    assert all(a * 100 == round(a * 100) or abs(a * 100 - round(a * 100)) < 1e-7 for a in vals), vals
    assert all(round(a * 100) / 100 == a for a in vals), vals
    assert "-0.0," not in rep.read_text(encoding="utf-8") and "-0.0}" not in rep.read_text(encoding="utf-8")


# ---------------------------------------------------------------------------------------------------------------
# 3. flags --mode osc ignores


@pytest.mark.parametrize("flag", [["--clamp"], ["--rate", "20"], ["--max-lost", "3"]])   # (--rate-tolerance bounds the on-board sine)
def test_osc_refuses_the_flags_it_ignores(tmp_path, flag):
    """Before: exit 0 (the flag silently ignored)."""
    rep = tmp_path / "r.json"
    r = run_cli(FISH, "--dry-run", "--mode", "osc", "--seconds", "0.1", "--report", str(rep), *flag)
    assert r.returncode == 2, (r.stdout, r.stderr)
    assert r.stderr.count("\n") == 1 and r.stderr.startswith(f"error: {flag[0]}:") and "--mode osc" in r.stderr, \
        r.stderr
    assert not rep.exists()


def test_stream_mode_keeps_the_default_rate(tmp_path):
    rep = tmp_path / "r.json"
    r = run_cli(FISH, "--dry-run", "--seconds", "0.2", "--report", str(rep))
    assert r.returncode == 0, r.stderr
    assert "at 50 Hz" in r.stderr
    assert len(json.loads(rep.read_text(encoding="utf-8"))["frames_sent"]) in (10, 11)


# ---------------------------------------------------------------------------------------------------------------
# 4. osc prints a constant channel as a constant


def test_osc_prints_a_constant_channel_as_a_constant(tmp_path):
    """Before: `v = 0.2 + 0 sin(2 pi constant t + 0 deg)`."""
    with open(FISH, encoding="utf-8") as f:
        d = json.load(f)
    d["actuators"][0]["profile"] = {"shape": "constant", "value": 0.2}
    p = tmp_path / "c.json"
    p.write_text(json.dumps(d), encoding="utf-8")
    r = run_cli(str(p), "--dry-run", "--mode", "osc", "--seconds", "0.1")
    assert r.returncode == 0, r.stderr
    assert re.search(r"head -> ch0: v = 0\.2 \(constant\), joint angle -?\d+\.\d\d deg", r.stderr), r.stderr
    assert "sin(2 pi constant" not in r.stderr and "tail -> ch1: v = 0 + 0.9 sin(2 pi 1 Hz t + 90 deg)" in r.stderr
    chans = tmp_path / "ch.json"
    chans.write_text(json.dumps({"head": {"scale_deg": 90}}), encoding="utf-8")
    r = run_cli(str(p), "--dry-run", "--mode", "osc", "--seconds", "0.1", "--channels", str(chans))
    assert r.returncode == 0, r.stderr
    assert "head -> ch0: 18 deg (constant)" in r.stderr and "sin(2 pi constant" not in r.stderr, r.stderr


# ---------------------------------------------------------------------------------------------------------------
# 5. check_motion in blocks


def test_check_motion_samples_in_blocks(monkeypatch):
    """Before: the whole --seconds at 1 kHz in one array (3600 s: 388 MB; 86400 s: ~8 GB)."""
    import metamaterial_wb.core.motion as motion
    s = fish()
    ch = channel_map(s)
    whole = check_motion(s, ch, 3.0)
    seen = []
    real = motion.profile_value

    def spy(profile, t, value):
        seen.append(len(t) if hasattr(t, "__len__") else 1)
        return real(profile, t, value)
    monkeypatch.setattr(motion, "profile_value", spy)
    monkeypatch.setattr(mapping, "_WINDOW", 500)
    assert check_motion(s, ch, 3.0) == pytest.approx(whole, abs=1e-12)
    assert seen and max(seen) <= 2 * 500 + 2, max(seen)
    # an error past the first block names the same place as before
    s = fish(tail={"limits_deg": [-60, 60]})
    with pytest.raises(SceneError, match=r"actuators\[1\] \(tail\): the motion reaches 60\.1 deg at t = 0\.383 s"):
        check_motion(s, channel_map(s), 3.0)
