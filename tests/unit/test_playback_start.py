"""A trajectory whose recorded times do not start at 0 s is refused (Animate's Load..., ``core.playback.
TrajectoryPlayer``), naming the file, the field ``trajectory.times_s[0]``, the first value and what is allowed.

Before: a file whose first time was 0.5 s was accepted and frame 0 was held, silently, from 0 to 0.5 s of the
animation (``body_poses`` clamps below the first time). ``simulate --out`` never writes such a file: its first
frame is the initial state at t = 0 (``Simulator.run`` records before the first step; the settling keeps the
time), written rounded to 6 decimals, so a late (or negative) start means the file was cut or edited."""
import json
import os

import numpy as np
import pytest

from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.core import playback
from metamaterial_wb.core.playback import TrajectoryPlayer
from metamaterial_wb.core.scene import Scene

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
WORM = os.path.join(ROOT, "examples", "worm.json")
START_TOL_S = getattr(playback, "START_TOL_S", None)    # the tolerance on the first time (s)


@pytest.fixture(scope="module")
def scene():
    return Scene.load(WORM)


def doc(scene, times):
    cols = sorted({j for _, j in scene.topology.nodes})
    nb = len(cols)
    poses = [[[20.0 * b + f, 3.5, 0.5 * f] for b in range(nb)] for f in range(len(times))]
    return {"format": "metamaterial-trajectory", "version": 1, "model": "sheet", "incline_deg": 0.0,
            "times_s": list(times), "bodies": nb, "poses": poses,
            "body_of_node": {f"N{i},{j}": cols.index(j) for (i, j) in scene.topology.nodes}}


def load(scene, times, source=None):
    return TrajectoryPlayer(doc(scene, times), scene, np.zeros((scene.topology.n_nodes, 3)), source=source)


@pytest.mark.parametrize("times,shown", [([0.5, 0.6, 0.7], "0.5"), ([0.001, 0.1, 0.2], "0.001"),
                                         ([-0.1, 0.0, 0.1], "-0.1"), ([2e-6, 0.1], "2e-06")])
def test_a_late_or_early_start_is_refused_naming_file_field_value_and_allowed(scene, tmp_path, times, shown):
    path = tmp_path / "cut run" / "trajectory.json"
    path.parent.mkdir()
    path.write_text(json.dumps(doc(scene, times)), encoding="utf-8")
    with open(path, encoding="utf-8") as f:
        data = json.load(f)
    with pytest.raises(SceneError) as e:
        TrajectoryPlayer(data, scene, np.zeros((scene.topology.n_nodes, 3)), source=str(path))
    msg = str(e.value)
    assert e.value.field == "trajectory.times_s[0]", msg
    assert msg.startswith(f"trajectory.times_s[0]: {shown} s"), msg
    assert "starts at 0 s" in msg and f"{START_TOL_S:g} s" in msg, msg       # what is allowed, with the tolerance
    assert msg.endswith(f"(in {path})") and msg.count(str(path)) == 1, msg


def test_a_start_within_the_tolerance_plays_unchanged(scene):
    """Within the stated tolerance (the 1e-6 s rounding of times_s) the file is played as written: nothing shifted."""
    assert START_TOL_S == pytest.approx(1e-6)
    p = load(scene, [5e-7, 0.1, 0.2])
    assert list(p.times) == [5e-7, 0.1, 0.2] and p.duration == pytest.approx(0.2)
    assert list(load(scene, [0.0, 0.1]).times) == [0.0, 0.1]
    assert list(load(scene, [0]).times) == [0.0]                   # an integer 0, one frame


def test_what_simulate_writes_starts_at_zero(scene):
    """The reason for the rule: the trajectory of a real (short) run starts at 0 s and is accepted."""
    from metamaterial_wb.core.playback import run_dynamics

    data, _summary = run_dynamics(scene, 0.05, fps=100.0)
    assert data["times_s"][0] == 0.0
    p = TrajectoryPlayer(data, scene, np.zeros((scene.topology.n_nodes, 3)))
    assert p.times[0] == 0.0
