"""``simulate``: its numeric flags are read strictly (no ``1_0``, no non-ASCII digits, no inf/nan, no subnormals);
the frames x bodies size budget lives in core (``core.dynamics.simulate``), so the GUI's background run (Animate,
``core.playback.run_dynamics``) is refused like the CLI, before any work; a symbolic link ``OUT/frames`` is never
silently replaced by a ``--frames`` run (an audit, session 29)."""
import os

import pytest

from metamaterial_wb.cli import build_parser, main
from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.core.scene import Scene

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
EX = os.path.join(ROOT, "examples")
WORM = os.path.join(EX, "worm_crawl.json")
BELT1000 = os.path.join(EX, "belt1000.json")


# ------------------------------------------------------------------------------------------------------------
# defect 1: the numeric flags are typed numbers
# ------------------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("flag", ["--seconds", "--dt", "--fps", "--incline"])
@pytest.mark.parametrize("text", ["1_0", "\u0661\u0660", "inf", "nan", "1e-310"])
def test_numeric_flags_are_read_strictly(tmp_path, capsys, flag, text):
    """``--seconds 1_0`` ran a 10 s simulation (Python's float() reads 1_0 as 10); Arabic-Indic digits and a
    subnormal were accepted too."""
    args = ["simulate", WORM, "--seconds", "0.1", "--out", str(tmp_path / "run")]
    if flag == "--seconds":
        args[3] = text
    else:
        args += [flag, text]
    with pytest.raises(SystemExit) as e:
        build_parser().parse_args(args)
    assert e.value.code == 2
    err = capsys.readouterr().err
    assert f"argument {flag}" in err, err
    assert not (tmp_path / "run").exists()


def test_good_numbers_still_parse(tmp_path):
    a = build_parser().parse_args(["simulate", WORM, "--seconds", "2.5", "--out", str(tmp_path), "--dt", "1e-3",
                                   "--fps", "60", "--incline", "-3"])
    assert (a.seconds, a.dt, a.fps, a.incline) == (2.5, 1e-3, 60.0, -3.0)


# ------------------------------------------------------------------------------------------------------------
# defect 2: the frames x bodies budget is core's, the GUI's run (core.playback.run_dynamics) is refused too
# ------------------------------------------------------------------------------------------------------------
@pytest.fixture
def no_work(monkeypatch):
    """Starting the simulator (settling, integrating) fails the test: the budget must refuse before it."""
    from metamaterial_wb.core.dynamics import simulate as S

    def started(*a, **k):
        raise AssertionError("the simulation started: the size budget did not refuse it before any work")
    monkeypatch.setattr(S, "_start", started)


def test_core_simulate_refuses_too_many_body_poses_before_any_work(no_work):
    from metamaterial_wb.core.dynamics.simulate import simulate
    scene = Scene.load(BELT1000)
    with pytest.raises(SceneError) as e:
        simulate(scene, 600.0, record_dt=1.0 / 30.0)
    msg = str(e.value)
    assert "18000 frames" in msg and "1000 bodies" in msg, msg
    assert "at most 10000000 are allowed" in msg and "at most 10000 frames for this scene" in msg, msg


def test_core_simulate_refuses_too_many_frames_before_any_work(no_work):
    from metamaterial_wb.core.dynamics.simulate import simulate
    with pytest.raises(SceneError) as e:
        simulate(Scene.load(WORM), 600.0, record_dt=1e-4)      # 6e6 frames (a large AnimationFps preference)
    msg = str(e.value)
    assert "6e+06 recorded frames" in msg and "at most 1000000 are allowed" in msg, msg


def long_sheet():
    """A 1 x 600 strip: the sheet model (a side view) has a body per column line, 601: 600 s at 30 frames/s is
    18000 frames x 601 bodies, 1.08e7 body poses."""
    return Scene.from_dict({"format": "metamaterial-scene", "version": 1, "name": "long",
                            "layout": {"grid": [1, 600]}, "actuators": [{"name": "m", "joint": "H0,1", "value": 0.5}]})


def test_the_guis_background_run_is_refused_before_any_work(no_work):
    """Animate's "Simulate" runs core.playback.run_dynamics (up to 600 s at the animation frame rate): a 1 x 600
    strip there is 18000 frames x 601 bodies, 1.08e7 poses (the CLI refuses more than 1e7), and nothing checked it
    (a belt is refused first, as no sheet: test_playback_guards.py)."""
    from metamaterial_wb.core.playback import run_dynamics
    with pytest.raises(SceneError) as e:
        run_dynamics(long_sheet(), 600.0, fps=30.0, progress=lambda f: None)
    msg = str(e.value)
    assert "18000 frames" in msg and "601 bodies" in msg and "10000000" in msg, msg


def test_the_cli_uses_the_core_budget():
    from metamaterial_wb.cli import simulate as C
    from metamaterial_wb.core.dynamics import simulate as S
    assert C.MAX_POSES == S.MAX_POSES and C.MAX_FRAMES == S.MAX_FRAMES
    assert C.check_output_budget is S.check_output_budget


def test_a_run_within_the_budget_is_not_refused():
    from metamaterial_wb.core.dynamics.simulate import check_output_budget
    check_output_budget(10.0, 30.0, 1000)          # docs/dynamics.md: belt1000 for 10 s at 30 fps
    check_output_budget(20.0, 1000.0, 16)


# ------------------------------------------------------------------------------------------------------------
# defect 3: a symbolic link OUT/frames
# ------------------------------------------------------------------------------------------------------------
def test_a_symlinked_frames_folder_is_refused_before_any_work(tmp_path, monkeypatch, capsys):
    """``OUT/frames -> elsewhere`` with ``--frames``: the run replaced the user's link by a folder of its own
    (exit 0, the link gone); the command already refuses user files inside OUT/frames."""
    from metamaterial_wb.core.dynamics import simulate as S

    def started(*a, **k):
        raise AssertionError("the simulation started")
    monkeypatch.setattr(S, "simulate", started)
    out = tmp_path / "out"
    out.mkdir()
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    (elsewhere / "note.txt").write_text("mine", encoding="utf-8")
    os.symlink(elsewhere, out / "frames")
    code = main(["simulate", WORM, "--seconds", "0.1", "--out", str(out), "--frames", "--no-dt-check"])
    err = capsys.readouterr().err
    assert code == 2, err
    assert err.startswith("error: --out: ") and str(out / "frames") in err and "symbolic link" in err, err
    assert os.path.islink(out / "frames") and os.listdir(out) == ["frames"]
    assert os.listdir(elsewhere) == ["note.txt"]


def test_a_symlinked_frames_folder_is_left_alone_without_frames(tmp_path, capsys):
    """Without ``--frames`` the link is neither replaced nor removed: the run goes ahead and leaves it."""
    out = tmp_path / "out"
    out.mkdir()
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    os.symlink(elsewhere, out / "frames")
    code = main(["simulate", WORM, "--seconds", "0.05", "--out", str(out), "--no-dt-check"])
    assert code == 0, capsys.readouterr().err
    assert os.path.islink(out / "frames") and (out / "summary.json").is_file()
    assert os.listdir(elsewhere) == []


# ------------------------------------------------------------------------------------------------------------
# the step budget: the command line uses core's check_step_budget for --dt and the scene's dt_s (one wording)
# ------------------------------------------------------------------------------------------------------------
def test_cli_step_budget_names_dt_flag(tmp_path, capsys, no_work):
    rc = main(["simulate", WORM, "--seconds", "300", "--dt", "1e-5", "--fps", "1", "--out", str(tmp_path / "r")])
    err = capsys.readouterr().err
    assert rc != 0
    assert "--dt" in err and "--seconds 300 / --dt 1e-05 asks for 3e+07 time steps" in err, err
    assert "at most 20000000 are allowed (the size budget)" in err, err
    assert not (tmp_path / "r").exists()


def test_cli_step_budget_names_scene_dt_s(tmp_path, capsys, no_work):
    import json
    data = json.load(open(WORM, encoding="utf-8"))
    data.setdefault("dynamics", {}).setdefault("integrator", {})["dt_s"] = 1e-5
    p = tmp_path / "worm_fine.json"
    p.write_text(json.dumps(data), encoding="utf-8")
    rc = main(["simulate", str(p), "--seconds", "300", "--fps", "1", "--out", str(tmp_path / "r")])
    err = capsys.readouterr().err
    assert rc != 0
    assert "dynamics.integrator.dt_s" in err and "--seconds 300 / dt_s 1e-05 asks for 3e+07 time steps" in err, err
    assert not (tmp_path / "r").exists()
