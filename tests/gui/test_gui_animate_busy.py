"""Animate: while its background simulation runs, Load... and Motors are refused with a message in the panel,
and the trajectory label keeps saying "simulating ..." (an audit, session 35).

Before: Load... (a trajectory file) or Motors during a run replaced the "simulating 1 s ..." label with
"playing: ...", so the run no longer showed, and when it ended its trajectory replaced what the user had chosen
meanwhile, unasked. Now the choice stays with the user: wait for the run (its trajectory then plays, as Simulate
says) or press Cancel, then Load... / Motors act as usual. The run is held by a gate (no timing): the patched
``run_dynamics`` waits until the test lets it finish. Buttons are clicked for real; the file dialog is patched."""
import json
import os
import threading

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
SIMULATING = "simulating 1 s ..."


@pytest.fixture(scope="module")
def runs():
    """Two short real trajectories of the worm: one for the file the user loads, one the held run returns."""
    scene = Scene.load(WORM)
    return playback.run_dynamics(scene, 0.3), playback.run_dynamics(scene, 0.2)


def write(tmp_path, name, data):
    path = tmp_path / name / "trajectory.json"
    path.parent.mkdir()
    path.write_text(json.dumps(data), encoding="utf-8")
    return str(path)


class Dialog:
    """QFileDialog.getOpenFileName answering ``path``; counts how often it was asked."""

    def __init__(self, monkeypatch, path):
        self.asked = 0
        self.path = path
        monkeypatch.setattr(QtGui.QFileDialog, "getOpenFileName", staticmethod(self))

    def __call__(self, *a, **k):
        self.asked += 1
        return self.path, ""


@pytest.fixture
def held(doc, tmp_path, monkeypatch, runs):
    """The Animate panel of the worm with ``first/trajectory.json`` loaded (Load...) and a Simulate of 1 s held
    running by a gate; yields (panel, gate, the loaded player, the file ``second/trajectory.json``)."""
    (first, _s1), (simulated, summary) = runs
    structure.load_scene_file(doc, WORM)
    doc.recompute()
    p = run_panel("MM_Animate")
    Dialog(monkeypatch, write(tmp_path, "first", first))
    click(p.traj_load_btn)
    process(50)
    loaded = p.trajectory
    assert loaded is not None and p.traj_label.text().startswith("playing: first/trajectory.json"), p.error.text()
    gate = threading.Event()

    def held_run(scene, seconds, fps=30.0, progress=None):
        assert gate.wait(120), "the test never released the run"
        if progress is not None:
            progress(1.0)             # raises Cancelled after Cancel: the result is dropped
        return simulated, dict(summary, displacement_mm=1.25)

    monkeypatch.setattr(playback, "run_dynamics", held_run)
    type_into(p.traj_seconds, "1")
    click(p.traj_sim_btn)
    process(50)
    assert p.sim.running and p.traj_label.text() == SIMULATING, p.traj_label.text()
    yield p, gate, loaded, write(tmp_path, "second", first)
    gate.set()
    p.reject()


def refused(p, loaded, what):
    """Nothing changed but the red line, which says why and what to do."""
    assert p.sim.running
    assert p.traj_label.text() == SIMULATING, f"{what}: the label became {p.traj_label.text()!r}"
    assert p.trajectory is loaded and p.floor is not None and not p.table.isEnabled()
    err = p.error.text()
    assert p.error.isVisible() and what in err and "a simulation is running" in err, err
    assert "Cancel" in err, err


def test_load_during_a_simulation_is_refused_and_the_run_still_shows(held, monkeypatch, tracebacks):
    p, gate, loaded, second = held
    dialog = Dialog(monkeypatch, second)
    click(p.traj_load_btn)
    process(50)
    assert dialog.asked == 0, "the file dialog opened although the load is refused"
    refused(p, loaded, "Load...")
    assert p.load_trajectory(second) is False       # a script: refused alike
    refused(p, loaded, "Load...")
    # the run ends: its trajectory plays, as Simulate said, and the red line is cleared
    gate.set()
    assert p.wait_simulation(60)
    assert p.trajectory is not loaded and p.trajectory_data["times_s"][-1] == pytest.approx(0.2)
    assert p.traj_label.text().startswith("playing: simulated here, "), p.traj_label.text()
    assert p.traj_label.text().endswith("centre of mass moved +1.25 mm"), p.traj_label.text()
    assert p.error.text() == "", p.error.text()
    # afterwards Load... works as usual
    click(p.traj_load_btn)
    process(50)
    assert dialog.asked == 1 and p.traj_label.text().startswith("playing: second/trajectory.json"), p.error.text()
    assert not tracebacks, tracebacks[-1]


def test_motors_during_a_simulation_is_refused_until_cancel(held, tracebacks):
    p, gate, loaded, _second = held
    assert p.traj_off_btn.isEnabled()
    click(p.traj_off_btn)
    process(50)
    refused(p, loaded, "Motors")
    # Cancel: the loaded file still plays (said so), and Motors now acts
    click(p.sim_box.cancel_btn)
    process(50)
    assert not p.sim.running
    assert p.traj_label.text().startswith("simulation cancelled; playing: first/trajectory.json"), p.traj_label.text()
    assert p.trajectory is loaded and "refused" not in p.error.text(), p.error.text()   # no longer holds
    gate.set()                        # the cancelled run's thread ends; its result is dropped
    process(300)
    assert p.trajectory is loaded
    click(p.traj_off_btn)
    process(50)
    assert p.trajectory is None and p.traj_label.text() == "playing: the motors' profiles"
    assert p.table.isEnabled()
    assert not tracebacks, tracebacks[-1]
