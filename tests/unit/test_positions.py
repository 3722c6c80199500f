"""Node rotations and planar positions from a D field (issue 2 scope; 3D is tested in tests/design)."""
import math

import numpy as np

from metamaterial_wb.core import kinematics
from metamaterial_wb.core.scene import Scene


def test_sign_rule_and_uniform_pitch():
    s = Scene.from_dict({"layout": {"grid": [3, 4]}, "hinge": {"length_mm": 4.0}})
    t = s.topology
    for g in (0.0, 0.5, 1.0, -0.5, -1.0):
        D = np.full(t.n_nodes, g)
        pos, R, phi = kinematics.node_poses(s, D)[:3]
        for k, (i, j) in enumerate(t.nodes):
            ang = math.atan2(R[k][1, 0], R[k][0, 0])
            if g > 0:  # even i+j turns counter-clockwise for D > 0
                assert (ang > 0) == ((i + j) % 2 == 0)
        # closed-form pitch of rotating squares with hinges of length lh, plates of side s
        lh = s.hinge["length_mm"]
        side = s.cell_size_mm - lh
        a = abs(phi[0])
        expected = lh + side * (math.cos(a) - math.sin(a)) if g >= 0 else lh + side * (math.cos(a) + math.sin(a))
        ij = t.node_ij()
        P = pos[:, :2]
        # neighbours in a row are one pitch apart, along x
        for k, (i, j) in enumerate(t.nodes):
            if (i, j + 1) in t.node_index:
                d = P[t.node_index[(i, j + 1)]] - P[k]
                assert abs(np.linalg.norm(d) - expected) < 1e-9
        assert np.allclose(pos[:, 2], 0.0)


def test_flat_state_is_the_grid():
    s = Scene.from_dict({"layout": {"grid": [2, 6]}})
    pos = kinematics.node_poses(s, np.zeros(s.topology.n_nodes))[0]
    ij = s.topology.node_ij()
    assert np.allclose(pos[:, 0] - pos[0, 0], (ij[:, 1] - ij[0, 1]) * s.cell_size_mm)
    assert np.allclose(pos[:, 1] - pos[0, 1], -(ij[:, 0] - ij[0, 0]) * s.cell_size_mm)


def test_nonuniform_field_is_smooth_and_bounded():
    from metamaterial_wb.core.solver import solve_scene
    s = Scene.from_dict({"layout": {"grid": [4, 8]},
                         "actuators": [{"name": "m", "joint": "V1,0", "value": 1.0}]})
    D, *_ = solve_scene(s)
    pos = kinematics.node_poses(s, D)[0]
    flat = kinematics.node_poses(s, np.zeros_like(D))[0]
    # nodes move at most by the closing of their own cells: less than one hinge length per cell
    assert np.all(np.isfinite(pos))
    assert np.abs(pos - flat).max() < s.cell_size_mm
