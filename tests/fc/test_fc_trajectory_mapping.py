"""The side-view -> 3D mapping of simulated trajectories (core.playback.TrajectoryPlayer), App level.

Synthetic trajectories with known motion: a flat first frame lands on the flat layout, a slide along
the floor of an incline moves the nodes along the tilted floor, a body angle turns the plates about y,
and trajectories that do not fit the structure are refused with the reason.
"""
import math

import numpy as np
import pytest

from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.core.scene import Scene
from metamaterial_wb.core.live import LiveSolver
from metamaterial_wb.core.playback import TrajectoryPlayer


def chain_scene(n=3):
    return Scene.from_dict({"format": "metamaterial-scene", "version": 1, "cell_size_mm": 20,
                            "layout": {"chain": n}})


def traj(scene, poses, times, incline=0.0):
    nodes = {f"N{i},{j}": j for (i, j) in scene.topology.nodes}
    return {"format": "metamaterial-trajectory", "version": 1, "model": "sheet", "incline_deg": incline,
            "times_s": times, "bodies": len(poses[0]), "poses": poses, "body_of_node": nodes}


def make_player(incline, d=5.0, angle=0.0):
    sc = chain_scene()
    solver = LiveSolver(sc)
    flat, _ = solver.poses(np.zeros(sc.topology.n_nodes))
    cols = sorted({j for _, j in sc.topology.nodes})
    P0 = [[20.0 * k, 3.5, 0.0] for k in range(len(cols))]
    P1 = [[20.0 * k + d, 3.5, angle] for k in range(len(cols))]
    return sc, solver, flat, TrajectoryPlayer(traj(sc, [P0, P1], [0.0, 1.0], incline), sc, flat)


@pytest.mark.parametrize("incline", [0.0, 8.0])
def test_slide_along_the_floor_follows_the_incline(incline):
    sc, solver, flat, pl = make_player(incline, d=5.0)
    pos0, R0 = pl.node_poses(0.0)
    i = math.radians(incline)
    if incline == 0.0:
        np.testing.assert_allclose(pos0, flat, atol=1e-9)      # the flat first frame is the flat layout
    pos1, R1 = pl.node_poses(1.0)
    np.testing.assert_allclose(pos1 - pos0, np.tile([5.0 * math.cos(i), 0.0, 5.0 * math.sin(i)], (len(flat), 1)),
                               atol=1e-9)
    # halfway: linear interpolation
    np.testing.assert_allclose(pl.node_poses(0.5)[0] - pos0, 0.5 * (pos1 - pos0), atol=1e-9)
    # the incline tilts the plates: their x axis runs up the slope
    np.testing.assert_allclose(R0[:, :, 0], np.tile([math.cos(i), 0.0, math.sin(i)], (len(flat), 1)), atol=1e-12)
    # the floor lies under the sheet, on the tilted plane, at the rest height below the nodes' mid-plane
    n = np.array([-math.sin(i), 0.0, math.cos(i)])
    fc = pl.floor_corners(10.0)
    assert np.allclose((fc - fc[0]) @ n, 0.0, atol=1e-9)
    np.testing.assert_allclose((pos1 - fc[0]) @ n, 3.5, atol=1e-9)
    assert fc[:, 1].min() < pos1[:, 1].min() and fc[:, 1].max() > pos1[:, 1].max()
    fr = pl.frame(solver, 1.0)
    assert fr.hinge_positions.shape == (sc.topology.n_joints, 3)


def test_body_angle_turns_plates_counter_clockwise_in_the_side_view():
    _sc, _s, flat, pl = make_player(0.0, d=0.0, angle=30.0)
    _p, R = pl.node_poses(1.0)
    a = math.radians(30.0)
    np.testing.assert_allclose(R[:, :, 0], np.tile([math.cos(a), 0, math.sin(a)], (len(flat), 1)), atol=1e-12)
    np.testing.assert_allclose(R[:, :, 1], np.tile([0, 1, 0], (len(flat), 1)), atol=1e-12)
    assert np.allclose(np.linalg.det(R), 1.0)


def test_mismatched_trajectories_are_refused():
    sc = chain_scene()
    flat = np.zeros((sc.topology.n_nodes, 3))
    good = traj(sc, [[[0, 3.5, 0]] * 4], [0.0])
    with pytest.raises(SceneError, match="only the 'sheet' model"):
        TrajectoryPlayer(dict(good, model="belt"), sc, flat)
    with pytest.raises(SceneError, match="format"):
        TrajectoryPlayer(dict(good, format="x"), sc, flat)
    other = chain_scene(5)
    with pytest.raises(SceneError, match="different layout"):
        TrajectoryPlayer(good, other, np.zeros((other.topology.n_nodes, 3)))
    with pytest.raises(SceneError, match="times must increase"):
        TrajectoryPlayer(traj(sc, [[[0, 3.5, 0]] * 4] * 2, [0.0, 0.0]), sc, flat)
