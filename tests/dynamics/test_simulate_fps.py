"""``simulate --fps`` is honoured (audit 2): frames are the states at time steps, so

1. a rate above one frame per time step (``--fps`` > 1 / dt) is refused, naming --fps, the step and the allowed
   range (it was silently lowered: ``--dt 0.01 --fps 1000`` wrote 6 frames of 0.05 s, 100 frames/s);
2. each frame is the state at the step nearest its instant k / fps (within half a step), so the spacing is as even
   as the step grid allows (it was the first step at or after the instant: ``--dt 0.01``, 30 frames/s gave
   0, 0.04, 0.07, 0.1 s);
3. the summary and the trajectory say what was recorded (the rate, the step, the snapping).
"""
import json
import math
import os
import re

import pytest

from clihelpers import one_line_error, run_cli

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
WORM = os.path.join(ROOT, "examples", "worm_crawl.json")
BELT8 = os.path.join(ROOT, "examples", "belt8.json")


def _run(tmp_path, *args, name="run"):
    out = tmp_path / name
    r = run_cli("simulate", WORM, "--no-dt-check", "--out", out, *args)
    return r, out


def _read(out, name):
    with open(out / name, encoding="utf-8") as fh:
        return json.load(fh)


def test_fps_above_one_frame_per_step_is_refused_naming_both(tmp_path):
    """``--dt 0.01 --fps 1000`` wrote times 0, 0.01 ... 0.05 (100 frames/s), exit 0, with no note anywhere."""
    r, out = _run(tmp_path, "--seconds", "0.05", "--dt", "0.01", "--fps", "1000")
    one_line_error(r, "--fps")
    assert "1000" in r.stderr and "0.01 s" in r.stderr and "(0, 100]" in r.stderr, r.stderr
    assert not (out / "trajectory.json").exists() and not (out / "summary.json").exists()


def test_the_scenes_step_bounds_the_rate_too(tmp_path):
    """belt8.json (dt_s 2 ms) --fps 1000 wrote a frame every 2 ms (500 frames/s), exit 0."""
    out = tmp_path / "run"
    r = run_cli("simulate", BELT8, "--seconds", "0.02", "--fps", "1000", "--no-dt-check", "--out", out)
    one_line_error(r, "--fps")
    assert "dynamics.integrator.dt_s" in r.stderr and "0.002 s" in r.stderr and "(0, 500]" in r.stderr, r.stderr
    assert not out.exists()


def test_an_automatic_step_longer_than_the_frame_interval_is_said(tmp_path):
    """Without --dt or dt_s the step is the integrator's (2 ms for belts), known only when the run starts: every
    step is a frame, and stderr, the summary and the trajectory say so (the rate was lowered silently)."""
    with open(BELT8, encoding="utf-8") as fh:
        d = json.load(fh)
    del d["dynamics"]["integrator"]["dt_s"]
    scene = tmp_path / "belt_auto.json"
    scene.write_text(json.dumps(d), encoding="utf-8")
    out = tmp_path / "run"
    r = run_cli("simulate", scene, "--seconds", "0.02", "--fps", "1000", "--method", "implicit", "--no-dt-check",
                "--out", out)
    assert r.returncode == 0, r.stderr
    assert "note: 1000 frames/s is more than one frame per time step (0.002 s)" in r.stderr, r.stderr
    t = _read(out, "trajectory.json")["times_s"]
    assert t == pytest.approx([0.002 * k for k in range(11)], abs=1e-9)
    for doc in (_read(out, "summary.json"), _read(out, "trajectory.json")):
        assert doc["recording"]["every_step_from_s"] == 0 and doc["recording"]["frames"] == 11
        assert "500 frames/s" in doc["recording"]["note"]


def test_the_printed_bound_typed_back_is_accepted(tmp_path):
    """1 / 0.003 s = 333.33... frames/s: the bound is printed rounded down, and that rate runs, one frame per step
    (the step nearest each instant k / fps is a different step for each k)."""
    r, _ = _run(tmp_path, "--seconds", "0.03", "--dt", "0.003", "--fps", "400", name="refused")
    one_line_error(r, "--fps")
    m = re.search(r"\(0, ([0-9.]+)\]", r.stderr)
    assert m, r.stderr
    bound = float(m.group(1))
    assert 333.0 <= bound <= 1 / 0.003
    r, out = _run(tmp_path, "--seconds", "0.03", "--dt", "0.003", "--fps", m.group(1))
    assert r.returncode == 0, r.stderr
    t = _read(out, "trajectory.json")["times_s"]
    assert t == [round(0.003 * k, 6) for k in range(11)]


@pytest.mark.parametrize("dt, fps, seconds", [(0.01, 30, 0.1), (0.003, 30, 1.0), (0.007, 11, 1.0)])
def test_frames_are_the_steps_nearest_each_instant(tmp_path, dt, fps, seconds):
    """Frame k is the state at the step nearest k / fps (within half a step; the final state at t = seconds
    always). The first step at or after the instant lagged by up to a whole step: 0, 0.04, 0.07, 0.1 s."""
    r, out = _run(tmp_path, "--seconds", seconds, "--dt", dt, "--fps", fps)
    assert r.returncode == 0, r.stderr
    t = _read(out, "trajectory.json")["times_s"]
    n = math.floor(seconds * fps + 1e-9)
    steps = [j * dt for j in range(math.floor(seconds / dt + 1e-9) + 1)]
    if steps[-1] < seconds - 1e-9:
        steps.append(seconds)                    # the last step ends the run (shorter than dt)
    expect = [min(steps, key=lambda s: (abs(s - k / fps), s)) for k in range(n + 1)]
    if expect[-1] < seconds - 1e-9:
        expect.append(seconds)
    assert t == pytest.approx(expect, abs=1e-9)
    for k, tk in enumerate(t[:n + 1]):
        assert abs(tk - k / fps) <= 0.5 * dt + 1e-9, (k, tk)
    gaps = [b - a for a, b in zip(t[:n + 1], t[1:n + 1])]
    assert max(gaps) - min(gaps) <= dt + 1e-9


def test_a_whole_number_of_steps_per_frame_is_even(tmp_path):
    r, out = _run(tmp_path, "--seconds", "0.2", "--dt", "0.01", "--fps", "25")
    assert r.returncode == 0, r.stderr
    assert _read(out, "trajectory.json")["times_s"] == pytest.approx([0.04 * k for k in range(6)], abs=1e-9)


def test_summary_and_trajectory_say_what_was_recorded(tmp_path):
    r, out = _run(tmp_path, "--seconds", "0.1", "--dt", "0.01")
    assert r.returncode == 0, r.stderr
    for doc in (_read(out, "summary.json"), _read(out, "trajectory.json")):
        rec = doc["recording"]
        assert rec["fps"] == 30 and rec["step_s"] == pytest.approx(0.01) and rec["frames"] == 4
        assert rec["max_offset_s"] == pytest.approx(1 / 30 - 0.03, abs=1e-9)     # 0.03 for 1/30, 0.07 for 2/30
        assert "nearest" in rec["snapping"]


def test_the_python_default_frame_interval_follows_a_long_step():
    """simulate() without record_dt (tests, benchmarks) records at most one frame per step: its default interval
    is never refused."""
    from metamaterial_wb.core.dynamics.simulate import simulate
    from metamaterial_wb.core.scene import Scene

    summary, traj, _m, _s = simulate(Scene.load(WORM), 0.05, dt=0.01)
    assert list(traj.t) == pytest.approx([0.0, 0.01, 0.02, 0.03, 0.04, 0.05], abs=1e-12)


def test_a_zero_frame_interval_records_every_step_and_ends():
    """record_dt 0 (a run of no length asked for frames every seconds / 7): every step is a frame, and the clock
    moves on (FrameClock.recorded looped for ever at instant 0: test_speed_kernel's step-limit test hung)."""
    from metamaterial_wb.core.dynamics.frames import FrameClock
    c = FrameClock(0.0)
    for i in range(5):
        c.recorded(i * 1e-3, 1e-3, 1e-12)
    assert c.frames == 5 and c.report()["fps"] is None and c.every_step is None
