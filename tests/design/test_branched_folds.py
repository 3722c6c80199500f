"""Branched layouts with perpendicular axes: every fold of the design is reached, no hinge is pulled apart.

A line of the grid may hold several stretches of one axis (a U's two legs, a comb's teeth). Each stretch
folds its own branch, and a branch beyond a perpendicular axis must see that axis's fold first (nested
folds compose from the root outwards). References are independent of the code under test: the plate
corners and fold vectors written out here, the tilted-hinge law of docs/kinematics.md, and fold frames
composed joint by joint along a breadth-first tree of the node graph.
"""
import glob
import json
import math
import os
from collections import deque

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from metamaterial_wb.core import design, kinematics as K
from metamaterial_wb.core.scene import Scene

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
HINGE = {"length_mm": 9.5, "width_mm": 0.8, "thickness_mm": 3}


def u_scene():
    """Two legs on horizontal line 1 (one stretch each), the bridge's vertical axis between them."""
    return Scene.from_dict({"cell_size_mm": 35, "hinge": HINGE, "layout": {"rows": ["###", "#.#"]},
                            "axes": [{"name": "legs", "direction": "horizontal", "line": 1, "fold_deg": 40},
                                     {"name": "mid", "direction": "vertical", "line": 1, "fold_deg": 30}]})


def comb_scene():
    """Three teeth on horizontal line 2, two spine axes between them (5 x 3 cells)."""
    return Scene.from_dict({"cell_size_mm": 35, "hinge": HINGE,
                            "layout": {"rows": ["#####", "#.#.#", "#.#.#"]},
                            "axes": [{"name": "teeth", "direction": "horizontal", "line": 2, "fold_deg": 40},
                                     {"name": "spine1", "direction": "vertical", "line": 1, "fold_deg": 30},
                                     {"name": "spine3", "direction": "vertical", "line": 3, "fold_deg": -20}]})


def f_vector(kind):
    return np.array([0.0, -1.0, 0.0]) if kind == "H" else np.array([-1.0, 0.0, 0.0])


def corners(kind, i, j, half):
    """Hinge attachment corners (plate frames) of joint kind(i, j): docs/kinematics.md, checkerboard."""
    even = (i + j) % 2 == 0
    if kind == "H":
        y = half if even else -half
        return np.array([half, y, 0.0]), np.array([-half, y, 0.0])
    x = half if even else -half
    return np.array([x, -half, 0.0]), np.array([x, half, 0.0])


def signed_fold_deg(RA, RB, f):
    na, nb = RA[:, 2], RB[:, 2]
    ang = math.degrees(math.atan2(np.linalg.norm(np.cross(na, nb)), na @ nb))
    return ang if np.cross(na, nb) @ (RA @ f) >= 0 else -ang


def law_fold(alpha, phi_a, phi_b):
    """Tilted-hinge law: tan(gamma/2) = -tan(alpha) sin(phi_A) with phi_A the antisymmetric turn."""
    return -2.0 * math.atan(math.tan(alpha) * math.sin(0.5 * (phi_a - phi_b)))


def reference_rotations(s, phi):
    """Fold frames composed joint by joint along a breadth-first tree from node 0: F_B = F_A Rot(f, gamma)."""
    topo = s.topology
    n = topo.n_nodes
    nbrs = [[] for _ in range(n)]
    for k, (kind, i, j) in enumerate(topo.joints):
        a, b = (int(x) for x in topo.joint_pairs[k])
        gamma = law_fold(math.radians(s.joint_tilt_deg(f"{kind}{i},{j}")), phi[a], phi[b])
        step = Rotation.from_rotvec(gamma * f_vector(kind)).as_matrix()
        nbrs[a].append((b, step))
        nbrs[b].append((a, step.T))
    F = [None] * n
    F[0] = np.eye(3)
    todo = deque([0])
    while todo:
        a = todo.popleft()
        for b, step in nbrs[a]:
            if F[b] is None:
                F[b] = F[a] @ step
                todo.append(b)
    return np.array([Fk @ Rotation.from_euler("z", p).as_matrix() for Fk, p in zip(F, phi)])


def check_exact_fold(s, g):
    """Every joint folds by the hinge law (the axis's fold_deg at g = 1), keeps its chord length and turns
    about its tilted axis; rotations equal the joint-by-joint composition."""
    design.configure(s)
    kin = design.kinematics_for(s)
    topo = s.topology
    pos, R, phi = kin.poses(np.full(topo.n_nodes, g))
    half = 0.5 * (s.cell_size_mm - s.hinge["length_mm"])
    lh = s.hinge["length_mm"]
    folds = {ax.name or f"{ax.direction[0]}{ax.line}": ax.fold_deg for ax in s.axes}
    for k, (kind, i, j) in enumerate(topo.joints):
        name = f"{kind}{i},{j}"
        a, b = (int(x) for x in topo.joint_pairs[k])
        alpha = math.radians(s.joint_tilt_deg(name))
        f = f_vector(kind)
        fold = signed_fold_deg(R[a], R[b], f)
        assert fold == pytest.approx(math.degrees(law_fold(alpha, phi[a], phi[b])), abs=1e-9), name
        axis = s.joint_config.get(name, {}).get("axis")
        if g == 1.0 and (axis or alpha == 0.0):
            assert fold == pytest.approx(folds[axis] if axis else 0.0, abs=1e-9), name
        ra, rb = corners(kind, i, j, half)
        chord = pos[b] + R[b] @ rb - pos[a] - R[a] @ ra
        assert np.linalg.norm(chord) == pytest.approx(lh, abs=1e-9), name
        rv = Rotation.from_matrix(R[a].T @ R[b]).as_rotvec()
        n = math.cos(alpha) * np.array([0.0, 0.0, 1.0]) + math.sin(alpha) * f
        psi = np.linalg.norm(rv)
        assert abs(abs(rv @ n) - psi) < 1e-9 * max(1.0, psi), name
    assert np.abs(R - reference_rotations(s, phi)).max() < 1e-12
    assert kin.closure_residual(phi, pos) < 1e-9
    return s


@pytest.mark.parametrize("g", [1.0, 0.5, -0.5])
@pytest.mark.parametrize("make", [u_scene, comb_scene], ids=["U", "comb"])
def test_branched_axes_fold_exactly_and_keep_hinges_closed(make, g):
    check_exact_fold(make(), g)


def test_u_far_leg_is_folded_by_the_bridge_then_by_its_leg():
    """The far leg's normal is Rot(-y, 30) Rot(-x, 40) z: the bridge's fold first (scipy reference)."""
    s = u_scene()
    design.configure(s)
    R = design.kinematics_for(s).poses(np.ones(s.topology.n_nodes))[1]
    tip = s.topology.node_id(2, 3)
    want = (Rotation.from_rotvec(math.radians(30) * np.array([0, -1, 0]))
            * Rotation.from_rotvec(math.radians(40) * np.array([-1, 0, 0]))).apply([0, 0, 1])
    assert np.allclose(R[tip][:, 2], want, atol=1e-12)


def example_scenes_with_axes():
    out = []
    for path in sorted(glob.glob(os.path.join(REPO, "examples", "*.json"))):
        with open(path) as fh:
            data = json.load(fh)
        if isinstance(data, dict) and data.get("axes"):
            out.append(os.path.basename(path))
    return out


@pytest.mark.parametrize("g", [1.0, 0.5, -0.5])
@pytest.mark.parametrize("name", example_scenes_with_axes())
def test_examples_with_axes_keep_their_exact_folds(name, g):
    """The examples' poses are the exact mechanism (their rotations equal the joint-by-joint composition
    to 1e-12): the per-stretch grouping leaves them as they were."""
    s = Scene.load(os.path.join(REPO, "examples", name))
    assert not np.any(K.joint_hinge_arrays(s)[0] != s.hinge["length_mm"])   # corners as written here
    check_exact_fold(s, g)


def test_pose_tangents_follow_the_stretch_groups():
    """The inverse design's exact tangents use the same fold groups: central differences agree on the U."""
    from metamaterial_wb.core.inverse.tangent import PoseTangent

    s = u_scene()
    design.configure(s)
    kin = K.Kinematics(s)
    assert [d for d, _f, _js in kin.groups] == ["horizontal", "vertical", "horizontal"]   # near leg, bridge, far leg
    rng = np.random.default_rng(3)
    D = rng.uniform(0.1, 0.8, kin.n)
    dD = rng.normal(size=(2, kin.n))
    pos, R, dpos, dR, F, dF = PoseTangent(kin).poses(D, dD)
    h = 1e-6
    for i in range(2):
        pp, Rp, _ = kin.poses(D + h * dD[i])
        pm, Rm, _ = kin.poses(D - h * dD[i])
        assert np.abs((pp - pm) / (2 * h) - dpos[i]).max() < 1e-6 * max(1.0, np.abs(dpos[i]).max())
        assert np.abs((Rp - Rm) / (2 * h) - dR[i]).max() < 1e-7
