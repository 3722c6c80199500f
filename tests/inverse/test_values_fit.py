"""Values-only fit (core/inverse/fit.py): exact Jacobians, planted answers recovered to < 1e-6 mm."""
import json
import os

import numpy as np
import pytest
from scipy.optimize import least_squares

from inverse_helpers import grid_surface, planted_result, scene_with, write_stl
from metamaterial_wb import REPO_DIR
from metamaterial_wb.core.inverse.fit import Problem, combined_errors
from metamaterial_wb.core.inverse.rotations import kabsch
from metamaterial_wb.core.inverse.targets import load_target, parse_target
from metamaterial_wb.core.kinematics import axis_angle_matrices
from metamaterial_wb.core.scene import Scene

GRID_FOLD = os.path.join(REPO_DIR, "examples", "grid_fold.json")


def _fd_check(pb, joints, x, h=1e-6, R0=np.eye(3)):
    D0, G = pb.response(joints)
    ns = len(joints)
    r, Jv, Jx, _ = pb.frame_residual(0, x[:ns], x[ns:], R0, D0, G)
    J = np.hstack([Jv, Jx])
    for c in range(len(x)):
        e = np.zeros(len(x))
        e[c] = h
        rp = pb.frame_residual(0, (x + e)[:ns], (x + e)[ns:], R0, D0, G, want_jac=False)[0]
        rm = pb.frame_residual(0, (x - e)[:ns], (x - e)[ns:], R0, D0, G, want_jac=False)[0]
        fd = (rp - rm) / (2 * h)
        assert np.abs(fd - J[:, c]).max() < 1e-5 * max(1.0, np.abs(fd).max()), c


def test_residual_jacobian_nodes_rotations_similarity_folds_equal_finite_differences():
    s = scene_with(GRID_FOLD, [("V1,0", 0.6), ("V2,6", 0.4)])
    res = planted_result(s)
    d = {"nodes": [dict(n, position_mm=[x + 0.3 for x in n["position_mm"]]) for n in res["nodes"][::3]],
         "rotation_weight_mm": 10.0, "align": "similarity",
         "folds": [{"axis": "left_wall", "fold_deg": -20}, {"joint": "H1,4", "fold_deg": 15}]}
    pb = Problem(s, parse_target(s, d))
    R0 = axis_angle_matrices(np.array([0.3, 0.5, 0.8]) / np.linalg.norm([0.3, 0.5, 0.8]), np.array([0.4]))[0]
    _fd_check(pb, ["V1,0", "V2,6"], np.array([0.5, 0.3, 0.05, -0.02, 0.1, 1.0, -2.0, 0.5, 0.01]), R0=R0)


def test_residual_jacobian_surface_equals_finite_differences(tmp_path):
    s = scene_with(GRID_FOLD, [("V1,0", 0.8), ("V2,6", 0.8)])
    res = planted_result(s)
    pos = np.array([n["position_mm"] for n in res["nodes"]])
    path = tmp_path / "s.stl"
    write_stl(path, grid_surface(s, pos + [0, 0, 0.7]))
    pb = Problem(s, load_target(s, str(path)))
    _fd_check(pb, ["V1,0", "V2,6"], np.array([0.5, 0.6, 0.01, 0.02, -0.01, 0.5, 0.3, 0.2]))


@pytest.mark.parametrize("base,acts", [
    (None, [("H2,3", 0.6), ("V6,6", -0.4), ("H8,1", 0.3)]),
    (GRID_FOLD, [("V1,0", 0.7), ("V2,6", 0.5)]),
])
def test_planted_values_recovered_from_a_solve_result_file(tmp_path, base, acts):
    s = scene_with(Scene.grid(10, 10) if base is None else base, acts)
    path = tmp_path / "result.json"
    path.write_text(json.dumps(planted_result(s)))       # a solve result file, accepted as it is
    pb = Problem(s, load_target(s, str(path)))
    fit = pb.fit([j for j, _ in acts])
    err = combined_errors([f.parts for f in fit.frames])
    assert err["rms_mm"] < 1e-6 and err["max_mm"] < 1e-6
    assert np.allclose(fit.values[0], [v for _, v in acts], atol=1e-6)


def test_planted_values_with_a_constraint_and_a_moved_target():
    s = scene_with(Scene.grid(6, 6), [("H1,1", 0.5), ("V3,4", 0.7)], constraints=[("H4,0", -0.3)])
    res = planted_result(s)
    # the target as a user's CAD might give it: rotated and shifted; rigid alignment takes it out
    Rm = axis_angle_matrices(np.array([0.0, 0.6, 0.8]), np.array([0.7]))[0]
    nodes = [dict(n, position_mm=list(Rm @ np.array(n["position_mm"]) + [100, -20, 5])) for n in res["nodes"]]
    pb = Problem(s, parse_target(s, {"nodes": nodes}))
    fit = pb.fit(["H1,1", "V3,4"])
    assert combined_errors([f.parts for f in fit.frames])["max_mm"] < 1e-6
    assert np.allclose(fit.values[0], [0.5, 0.7], atol=1e-6)
    sc, R, t = fit.frames[0].transform
    assert np.allclose(R, Rm, atol=1e-8) and abs(sc - 1) == 0


def test_planted_fold_targets_per_axis_and_joint():
    s = scene_with(GRID_FOLD, [("V1,0", 0.9), ("V2,6", 0.35)])
    from metamaterial_wb.core import kinematics
    from metamaterial_wb.core.models import run_model
    fold, _ = kinematics.joint_angles(s, run_model("quadratic", s).rotations)
    topo = s.topology
    jl = [topo.joint_id("H", i, 1) for i in range(4)]
    tgt = {"folds": [{"axis": "left_wall", "fold_deg": float(np.mean(fold[jl]))},
                     {"joint": "H2,4", "fold_deg": float(fold[topo.joint_id("H", 2, 4)])}]}
    pb = Problem(s, parse_target(s, tgt))
    fit = pb.fit(["V1,0", "V2,6"])
    err = combined_errors([f.parts for f in fit.frames])
    assert err["max_deg"] < 1e-6 and err["rms_mm"] is None


def test_planted_surface_target_moved_rigidly(tmp_path):
    s = scene_with(GRID_FOLD, [("V1,0", 0.8), ("V2,6", 0.6)])
    res = planted_result(s)
    pos = np.array([n["position_mm"] for n in res["nodes"]])
    Rm = axis_angle_matrices(np.array([1.0, 0.0, 0.0]), np.array([0.05]))[0]
    tri = grid_surface(s, pos) @ Rm.T + [1.5, -2.0, 1.0]
    path = tmp_path / "target.stl"
    write_stl(path, tri)
    pb = Problem(s, load_target(s, str(path)))
    fit = pb.fit(["V1,0", "V2,6"], starts=[0.5])
    err = combined_errors([f.parts for f in fit.frames])
    assert err["max_mm"] < 1e-6


def test_keyframes_each_recovered():
    s = scene_with(Scene.grid(5, 5), [("H1,1", 0.0), ("V3,3", 0.0)])
    frames, planted = [], [(0.2, 0.8), (0.7, -0.3), (-0.5, 0.5)]
    for t, (a, b) in enumerate(planted):
        s.set_value("m1", a)
        s.set_value("m2", b)
        frames.append({"time_s": t, "nodes": planted_result(s)["nodes"]})
    pb = Problem(s, parse_target(s, {"keyframes": frames, "period_s": 3}))
    fit = pb.fit(["H1,1", "V3,3"])
    assert np.allclose(fit.values, planted, atol=1e-6)
    assert combined_errors([f.parts for f in fit.frames])["max_mm"] < 1e-6


def test_box_gauss_newton_matches_scipy_least_squares_on_an_unreachable_target():
    """A target the placement cannot reach exactly: our optimum equals scipy's (trf, same Jacobian)."""
    s = scene_with(Scene.grid(6, 6), [("H1,1", 0.5), ("V3,4", 0.7)])
    res = planted_result(s)
    rng = np.random.default_rng(2)
    nodes = [dict(n, position_mm=list(np.array(n["position_mm"]) + rng.normal(0, 0.5, 3))) for n in res["nodes"]]
    pb = Problem(s, parse_target(s, {"nodes": nodes}))
    joints = ["H1,1", "V3,4"]
    fit = pb.fit(joints)
    D0, G = pb.response(joints)
    fr = pb.frames[0]
    R0, xi0 = fr.initial_alignment(pb.kin.poses(D0 + G @ [0.5, 0.7])[0])
    x0 = np.concatenate([[0.5, 0.7], xi0])
    fun = lambda x: pb.frame_residual(0, x[:2], x[2:], R0, D0, G, want_jac=False)[0]  # noqa: E731
    jac = lambda x: np.hstack(pb.frame_residual(0, x[:2], x[2:], R0, D0, G)[1:3])  # noqa: E731
    lo = np.r_[-1, -1, [-np.inf] * 6]
    sol = least_squares(fun, x0, jac=jac, bounds=(lo, -lo), method="trf", xtol=1e-15, ftol=1e-15, gtol=1e-15)
    assert abs(fit.cost - sol.cost) < 1e-9 * sol.cost
    assert np.allclose(fit.values[0], sol.x[:2], atol=1e-6)


@pytest.mark.parametrize("axis,deg", [((0.0, 0.0, 1.0), 150.0), ((1.0, 1.0, 0.3), 150.0), ((1.0, 0.0, 0.0), 180.0)])
def test_planted_surface_target_turned_far_is_aligned_globally(tmp_path, axis, deg):
    """The target surface turned by 150 deg (or flipped over) and moved: the alignment is global (PCA
    starts with sign flips, then ICP), so the planted values are recovered below 1e-6 mm."""
    s = scene_with(GRID_FOLD, [("V1,0", 0.8), ("V2,6", 0.6)])
    res = planted_result(s)
    pos = np.array([n["position_mm"] for n in res["nodes"]])
    ax = np.array(axis) / np.linalg.norm(axis)
    Rm = axis_angle_matrices(ax, np.array([np.radians(deg)]))[0]
    tri = grid_surface(s, pos) @ Rm.T + [40.0, -25.0, 12.0]
    path = tmp_path / "target.stl"
    write_stl(path, tri)
    pb = Problem(s, load_target(s, str(path)))
    fit = pb.fit(["V1,0", "V2,6"], starts=[0.5])
    err = combined_errors([f.parts for f in fit.frames])
    assert err["max_mm"] < 1e-6
    assert np.allclose(fit.values[0], [0.8, 0.6], atol=1e-5)
