"""Animate's "Simulated trajectory" label says what really plays after a simulation is cancelled, fails or is
refused (an audit on FreeCAD 1.0, session 34): with a CLI trajectory loaded (the table greyed, the floor shown,
Motors enabled) a cancelled Simulate read "simulation cancelled; playing: the motors' profiles" and a failed one
"playing: the motors' profiles" while the loaded trajectory still played. Load..., Simulate, Cancel and Motors are
clicked for real; the file dialog is patched to answer the file."""
import json
import os

import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

from PySide import QtGui  # noqa: E402

import metamaterial_wb  # noqa: E402
from metamaterial_wb.core import playback  # noqa: E402
from metamaterial_wb.core.scene import Scene  # noqa: E402
from metamaterial_wb.objects import structure  # noqa: E402
from guihelpers import click, doc, process, run_panel, tracebacks, type_into, workbench  # noqa: E402,F401

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(metamaterial_wb.__file__)))
WORM = os.path.join(ROOT, "examples", "worm.json")
MOTORS = "playing: the motors' profiles"


def cli_trajectory(tmp_path):
    """``DIR/trajectory.json`` as ``simulate examples/worm.json --seconds 1 --out DIR`` writes it."""
    data, _summary = playback.run_dynamics(Scene.load(WORM), 1.0)
    path = tmp_path / "worm" / "trajectory.json"
    path.parent.mkdir()
    path.write_text(json.dumps(data), encoding="utf-8")
    return str(path)


def load_with_button(p, path, monkeypatch):
    monkeypatch.setattr(QtGui.QFileDialog, "getOpenFileName", staticmethod(lambda *a, **k: (path, "")))
    try:
        click(p.traj_load_btn)
        process(50)
    finally:
        monkeypatch.undo()


def simulate(p, seconds):
    type_into(p.traj_seconds, seconds)
    click(p.traj_sim_btn)


def cancel_running(p):
    process(300)
    assert p.sim.running, "the 30 s simulation ended before Cancel"
    click(p.sim_box.cancel_btn)
    process(50)
    assert not p.sim.running and p.traj_sim_btn.isEnabled()


def still_playing(p, kept):
    assert p.trajectory is kept and p.floor is not None
    assert not p.table.isEnabled() and p.traj_off_btn.isEnabled()


@pytest.fixture
def panel(doc, tmp_path, monkeypatch):
    path = cli_trajectory(tmp_path)
    # the worm with a fixed integrator step of 10 us: a 600 s run is over the step budget, refused at once
    scene = json.loads(open(WORM, encoding="utf-8").read())
    scene["dynamics"] = {"integrator": {"dt_s": 1e-5}}
    fine = tmp_path / "worm_fine_step.json"
    fine.write_text(json.dumps(scene), encoding="utf-8")
    structure.load_scene_file(doc, str(fine))
    doc.recompute()
    p = run_panel("MM_Animate")
    load_with_button(p, path, monkeypatch)
    assert p.trajectory is not None, p.error.text()
    playing = p.traj_label.text()
    assert playing.startswith("playing: worm/trajectory.json, ") and " frames, 1.00 s" in playing, playing
    yield p, playing
    p.reject()


def test_cancel_with_a_loaded_trajectory_says_it_still_plays(panel, tracebacks):
    p, playing = panel
    kept = p.trajectory
    simulate(p, "30")
    cancel_running(p)
    assert p.traj_label.text() == "simulation cancelled; " + playing, p.traj_label.text()
    still_playing(p, kept)
    # Motors: the profiles play, and a cancel then says so
    click(p.traj_off_btn)
    assert p.trajectory is None and p.traj_label.text() == MOTORS
    simulate(p, "30")
    cancel_running(p)
    assert p.traj_label.text() == "simulation cancelled; " + MOTORS, p.traj_label.text()
    assert p.trajectory is None and p.table.isEnabled()
    assert not tracebacks, tracebacks[-1]


def test_a_refused_or_failed_simulation_keeps_the_loaded_trajectory_label(panel, tracebacks, monkeypatch):
    p, playing = panel
    kept = p.trajectory
    # refused at once (over the step budget): the red line says why, the label what still plays
    simulate(p, "600")
    assert not p.sim.running
    assert "simulation failed" in p.error.text() and "time steps" in p.error.text(), p.error.text()
    assert p.traj_label.text() == playing, p.traj_label.text()
    still_playing(p, kept)
    # failed in the background thread
    monkeypatch.setattr(playback, "run_dynamics", lambda *a, **k: (_ for _ in ()).throw(RuntimeError("boom")))
    simulate(p, "1")
    assert p.wait_simulation(60)
    assert "simulation failed: boom" in p.error.text(), p.error.text()
    assert p.traj_label.text() == playing, p.traj_label.text()
    still_playing(p, kept)
    # finished, but its trajectory refused by the player: not "simulating ..." any more
    bad = json.loads(json.dumps(p.trajectory_data))
    bad["times_s"] = [float("nan")] * len(bad["times_s"])
    monkeypatch.setattr(playback, "run_dynamics", lambda *a, **k: (bad, {"displacement_mm": 0.0}))
    simulate(p, "1")
    assert p.wait_simulation(60)
    assert "times_s" in p.error.text(), p.error.text()
    assert p.traj_label.text() == playing, p.traj_label.text()
    still_playing(p, kept)
    assert not tracebacks, tracebacks[-1]
