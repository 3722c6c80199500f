"""``simulate``'s outputs and summary (audit C): the scene is never one of the files the run writes, a user's file
in ``OUT/frames/`` is never deleted, ``rolled_back`` follows the commanded direction, the size budget counts the
bodies of a frame, and ``--help`` tells the real default step."""
import json
import os
import shutil
import subprocess
import sys

import pytest

from metamaterial_wb.core.dynamics.simulate import simulate
from metamaterial_wb.core.scene import Scene

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
EX = os.path.join(ROOT, "examples")
BELT8 = os.path.join(EX, "belt8.json")


def cli(*args, timeout=300):
    env = dict(os.environ, PYTHONPATH=ROOT)
    return subprocess.run([sys.executable, "-m", "metamaterial_wb", "simulate", *map(str, args)],
                          capture_output=True, text=True, cwd=ROOT, env=env, timeout=timeout)


def one_error_line(r, start):
    assert r.returncode == 2, (r.returncode, r.stdout, r.stderr)
    assert r.stderr.startswith(start) and r.stderr.strip().count("\n") == 0, r.stderr
    assert r.stdout == ""


# ------------------------------------------------------------------------------------------------------------
# defect 1: the scene is one of the run's outputs
# ------------------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("name, frames", [("summary.json", False), ("trajectory.json", False),
                                          ("motion.gif", True), ("motion.gif", False)])
def test_a_scene_named_like_an_output_is_refused_before_any_work(tmp_path, name, frames):
    """``cp belt8.json OUT/summary.json; simulate OUT/summary.json --out OUT`` replaced the scene by the summary
    (exit 0)."""
    scene = tmp_path / name
    shutil.copy(BELT8, scene)
    before = scene.read_bytes()
    r = cli(scene, "--seconds", "0.1", "--out", tmp_path, "--no-dt-check", *(["--frames"] if frames else []))
    one_error_line(r, "error: --out: ")
    assert "is the scene this command reads" in r.stderr
    assert scene.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == [name]


def test_a_scene_reached_through_a_link_is_refused(tmp_path):
    scene = tmp_path / "belt.json"
    shutil.copy(BELT8, scene)
    out = tmp_path / "out"
    out.mkdir()
    os.symlink(scene, out / "trajectory.json")
    r = cli(out / "trajectory.json", "--seconds", "0.1", "--out", out, "--no-dt-check")
    one_error_line(r, "error: --out: ")
    assert "is the scene this command reads" in r.stderr
    assert scene.read_bytes() == open(BELT8, "rb").read()
    r = cli(scene, "--seconds", "0.1", "--out", out, "--no-dt-check")         # the link itself is an output
    one_error_line(r, "error: --out: ")


def test_a_scene_inside_out_frames_is_refused(tmp_path):
    frames = tmp_path / "frames"
    frames.mkdir()
    scene = frames / "belt.json"
    shutil.copy(BELT8, scene)
    for extra in (["--frames"], []):
        r = cli(scene, "--seconds", "0.1", "--fps", "10", "--out", tmp_path, "--no-dt-check", *extra)
        one_error_line(r, "error: --out: ")
        assert str(scene) in r.stderr and "frames" in r.stderr
        assert scene.exists() and sorted(p.name for p in tmp_path.iterdir()) == ["frames"]


def test_a_scene_beside_the_outputs_is_fine(tmp_path):
    scene = tmp_path / "belt.json"
    shutil.copy(BELT8, scene)
    r = cli(scene, "--seconds", "0.1", "--out", tmp_path, "--no-dt-check")
    assert r.returncode == 0, r.stderr
    assert scene.read_bytes() == open(BELT8, "rb").read()
    assert (tmp_path / "summary.json").is_file() and (tmp_path / "trajectory.json").is_file()


# ------------------------------------------------------------------------------------------------------------
# defect 2: a user's file in OUT/frames/
# ------------------------------------------------------------------------------------------------------------
def test_a_users_file_in_frames_is_not_deleted_by_a_frames_run(tmp_path):
    frames = tmp_path / "frames"
    frames.mkdir()
    (frames / "mine.txt").write_text("x", encoding="utf-8")
    r = cli(BELT8, "--seconds", "0.1", "--fps", "10", "--frames", "--out", tmp_path, "--no-dt-check")
    one_error_line(r, "error: --out: ")
    assert "mine.txt" in r.stderr and str(frames) in r.stderr
    assert (frames / "mine.txt").read_text(encoding="utf-8") == "x"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["frames"]
    assert sorted(p.name for p in frames.iterdir()) == ["mine.txt"]


def test_an_earlier_runs_frames_with_a_users_file_are_not_removed(tmp_path):
    """After a --frames run, a user's file added to frames/ and a run without --frames: "removed 1 file(s) ...:
    frames" deleted the whole folder."""
    r = cli(BELT8, "--seconds", "0.1", "--fps", "10", "--frames", "--out", tmp_path, "--no-dt-check")
    assert r.returncode == 0, r.stderr
    frames = tmp_path / "frames"
    pngs = sorted(p.name for p in frames.iterdir())
    assert pngs and all(n.startswith("frame_") and n.endswith(".png") for n in pngs)
    (frames / "notes.txt").write_text("mine", encoding="utf-8")
    summary = (tmp_path / "summary.json").read_bytes()
    for extra in ([], ["--frames"]):
        r = cli(BELT8, "--seconds", "0.1", "--fps", "10", "--out", tmp_path, "--no-dt-check", *extra)
        one_error_line(r, "error: --out: ")
        assert "notes.txt" in r.stderr
        assert (frames / "notes.txt").read_text(encoding="utf-8") == "mine"
        assert sorted(p.name for p in frames.iterdir()) == sorted(pngs + ["notes.txt"])
        assert (tmp_path / "summary.json").read_bytes() == summary
    # once the user's file is gone, the earlier run's frames are replaced / removed as before
    (frames / "notes.txt").unlink()
    r = cli(BELT8, "--seconds", "0.1", "--fps", "10", "--out", tmp_path, "--no-dt-check")
    assert r.returncode == 0 and "removed" in r.stderr and not frames.exists(), r.stderr


def test_frames_of_an_earlier_run_are_replaced(tmp_path):
    r = cli(BELT8, "--seconds", "0.2", "--fps", "10", "--frames", "--out", tmp_path, "--no-dt-check")
    assert r.returncode == 0, r.stderr
    assert len(list((tmp_path / "frames").iterdir())) == 3
    r = cli(BELT8, "--seconds", "0.1", "--fps", "10", "--frames", "--out", tmp_path, "--no-dt-check")
    assert r.returncode == 0, r.stderr
    assert sorted(p.name for p in (tmp_path / "frames").iterdir()) == ["frame_0000.png", "frame_0001.png"]


def test_a_users_frames_folder_is_left_alone_without_frames(tmp_path):
    frames = tmp_path / "frames"
    frames.mkdir()
    (frames / "mine.txt").write_text("x", encoding="utf-8")
    r = cli(BELT8, "--seconds", "0.1", "--out", tmp_path, "--no-dt-check")
    assert r.returncode == 0, r.stderr
    assert (frames / "mine.txt").read_text(encoding="utf-8") == "x"


# ------------------------------------------------------------------------------------------------------------
# defect 3: rolled_back and the commanded direction
# ------------------------------------------------------------------------------------------------------------
def open_loop(direction, incline):
    with open(os.path.join(EX, "belt8_open_loop.json"), encoding="utf-8") as f:
        d = json.load(f)
    d["dynamics"]["gait"]["direction"] = direction
    del d["dynamics"]["gait"]["start_cell"]
    d["dynamics"]["incline_deg"] = incline
    return Scene.from_dict(d)


@pytest.mark.parametrize("direction, incline, rolled_back", [(1, 0, False), (-1, 0, False),
                                                             (1, 6, True), (-1, -6, True)])
def test_rolled_back_is_relative_to_the_commanded_direction(direction, incline, rolled_back):
    """direction -1 on the flat floor rolls -135 mm (the mirror of +1) and was reported as rolled back."""
    s, *_ = simulate(open_loop(direction, incline), 4.0)
    cell = 38.0
    assert s["rolled_back"] is rolled_back, s["displacement_mm"]
    assert bool(direction * s["displacement_mm"] < -cell) is rolled_back
    if not rolled_back:
        assert direction * s["displacement_mm"] > 3 * cell       # it rolled the commanded way


# ------------------------------------------------------------------------------------------------------------
# defect 5: the size budget counts the bodies
# ------------------------------------------------------------------------------------------------------------
def test_frames_times_bodies_are_checked_after_build_before_the_run(tmp_path):
    """belt1000 --seconds 2000 --fps 500 passed the 1e6-frame check; each frame holds 1000 bodies (a 36 GB
    trajectory after tens of minutes)."""
    out = tmp_path / "run"
    r = cli(os.path.join(EX, "belt1000.json"), "--seconds", "2000", "--fps", "500", "--out", out, "--no-dt-check",
            timeout=60)
    one_error_line(r, "error: --fps: ")
    assert "--seconds 2000 x --fps 500 x 1000 bodies" in r.stderr
    assert "at most 10000 frames for this scene" in r.stderr and "at most 10000000 are allowed" in r.stderr
    assert "recorded body poses" in r.stderr and not out.exists()


def test_the_documented_runs_are_within_the_budget():
    """The bundled examples' documented runs (docs/dynamics.md, docs/benchmarks.md) still pass the check."""
    from metamaterial_wb.cli.simulate import MAX_POSES
    for bodies, seconds, fps in ((1000, 10, 30), (16, 10, 30), (9, 6, 30), (16, 20, 500)):
        assert seconds * fps * bodies <= MAX_POSES


def test_a_small_run_of_the_big_belt_passes_the_budget(tmp_path):
    out = tmp_path / "run"
    r = cli(os.path.join(EX, "belt1000.json"), "--seconds", "0.01", "--fps", "500", "--out", out, "--no-dt-check",
            timeout=300)
    assert r.returncode == 0, r.stderr
    assert json.loads((out / "trajectory.json").read_text(encoding="utf-8"))["bodies"] == 1000


# ------------------------------------------------------------------------------------------------------------
# defect 6: --help tells the real default of --dt
# ------------------------------------------------------------------------------------------------------------
def test_help_names_the_scenes_step_as_the_default():
    r = cli("--help")
    assert r.returncode == 0
    text = " ".join(r.stdout.split())
    assert "default: automatic" not in text
    assert "default: the scene's dynamics.integrator.dt_s, else automatic" in text
