"""3D kinematics: closed-form pitch, tilted-hinge folds, exact mechanism, least squares, limits.

References are independent of the code under test: closed forms written out here, rotations built
with scipy.spatial.transform.Rotation, and the normal equations of the least-squares problem.
"""
import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from metamaterial_wb.core import design, kinematics as K
from metamaterial_wb.core.scene import Scene


def strip(n=6, axes=(), lh=5.0, t=7.0, w=0.8, **kw):
    d = {"layout": {"chain": n}, "hinge": {"length_mm": lh, "width_mm": w, "thickness_mm": t},
         "axes": [{"direction": "vertical", "line": k, "fold_deg": f} for k, f in axes]}
    d.update(kw)
    return Scene.from_dict(d)


def normal_angle_deg(R, a, b):
    return math.degrees(math.acos(np.clip(R[a][:, 2] @ R[b][:, 2], -1, 1)))


def end_nodes(s):
    ij = s.topology.node_ij()
    return s.topology.node_id(0, 0), s.topology.node_id(0, int(ij[:, 1].max()))


# ------------------------------------------------------------------------------------------------
# uniform D: closed-form pitch (rotating squares with finite hinges)
# ------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("g", [1.0, 0.6, 0.2, -0.3, -1.0])
def test_uniform_pitch_closed_form_planar(g):
    lh, cell = 4.0, 20.0
    s = Scene.from_dict({"layout": {"grid": [3, 4]}, "hinge": {"length_mm": lh, "width_mm": 0.5}})
    side = cell - lh
    # independent limits: plate contact asin(lh/2s) closing, 45 deg opening (strain 0.5*0.785/4 < 0.5)
    phi = g * math.asin(lh / (2 * side)) if g >= 0 else -g * math.pi / 4
    pitch = lh + side * (math.cos(phi) - math.sin(phi)) if g >= 0 else lh + side * (math.cos(phi) + math.sin(phi))
    pos, R, ph = K.node_poses(s, np.full(s.topology.n_nodes, g), kin=design.kinematics_for(s))
    topo = s.topology
    for (i, j) in topo.nodes:
        k = topo.node_id(i, j)
        for (di, dj) in ((0, 1), (1, 0)):
            k2 = topo.node_id(i + di, j + dj)
            if k2 >= 0:
                assert np.linalg.norm(pos[k2] - pos[k]) == pytest.approx(pitch, abs=1e-9)
        assert abs(ph[k]) == pytest.approx(abs(phi), abs=1e-12)
    assert K.uniform_pitch_mm(s, g) == pytest.approx(pitch, abs=1e-12)
    assert np.allclose(pos[:, 2], 0)


def test_pitch_inside_folded_regions_is_unchanged():
    """Folding is paper-like: within each region the in-plane mechanism keeps its closed-form pitch."""
    s = strip(8, axes=[(2, 50.0), (5, -35.0)])
    design.configure(s)
    pos, R, phi = K.node_poses(s, np.ones(s.topology.n_nodes), kin=design.kinematics_for(s))
    side = s.cell_size_mm - 5.0
    pc = math.asin(5.0 / (2 * side))
    pitch = 5.0 + side * (math.cos(pc) - math.sin(pc))
    topo = s.topology
    for i in (0, 1):
        for j in range(8):
            if j in (2, 5):
                continue  # the bending joints
            d = pos[topo.node_id(i, j + 1)] - pos[topo.node_id(i, j)]
            assert np.linalg.norm(d) == pytest.approx(pitch, abs=1e-9)


# ------------------------------------------------------------------------------------------------
# a 1 x N strip with one axis
# ------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("theta", [60.0, 25.0, -45.0])
def test_strip_one_axis_fold_at_g1_and_intermediate(theta):
    s = strip(6, axes=[(3, theta)])
    design.configure(s)
    a, b = end_nodes(s)
    kin = design.kinematics_for(s)
    info = K.rotation_limit_info(s)
    side = s.cell_size_mm - 5.0
    phi_c = math.asin(5.0 / (2 * side))
    assert info["closing_rad"] == pytest.approx(phi_c)
    for g in (1.0, 0.75, 0.5, 0.1, 0.0, -0.4, -1.0):
        pos, R, phi = kin.poses(np.full(s.topology.n_nodes, g))
        ang = normal_angle_deg(R, a, b)
        # exact tilted-hinge law at uniform g: tan(gamma/2) = tan(theta/2) sin(phi(g)) / sin(phi_c)
        phi_g = g * phi_c if g >= 0 else g * info["opening_rad"]
        expect = abs(math.degrees(2 * math.atan(math.tan(math.radians(theta) / 2) * math.sin(phi_g)
                                                / math.sin(phi_c))))
        assert ang == pytest.approx(expect, abs=1e-7), g
        if g == 1.0:
            assert ang == pytest.approx(abs(theta), abs=1e-7)
        # sign: positive theta raises the far end (+z) at g > 0; reversed for g < 0
        nb = R[b][:, 2]
        if g != 0:
            assert np.sign(nb[0]) == -np.sign(theta) * np.sign(g)


def test_intermediate_fold_is_close_to_linear_but_not_exactly():
    """At intermediate g the fold is 2 atan(tan(theta/2) sin(g phi_c)/sin(phi_c)): within 2 % of g*theta
    for these hinges, and exactly theta at g = 1 (stated in docs/kinematics.md)."""
    s = strip(4, axes=[(1, 60.0)])
    a, b = end_nodes(s)
    kin = design.kinematics_for(s)
    for g in (0.25, 0.5, 0.75):
        R = kin.poses(np.full(s.topology.n_nodes, g))[1]
        ang = normal_angle_deg(R, a, b)
        assert abs(ang - 60 * g) / (60 * g) < 0.12
        assert abs(ang - 60 * g) > 1e-3


def test_parallel_axes_add_with_their_signs():
    for f1, f2 in ((30.0, -50.0), (25.0, 35.0), (-20.0, -15.0), (40.0, -40.0)):
        s = strip(8, axes=[(2, f1), (5, f2)])
        design.configure(s)
        a, b = end_nodes(s)
        R = K.node_poses(s, np.ones(s.topology.n_nodes), kin=design.kinematics_for(s))[1]
        assert normal_angle_deg(R, a, b) == pytest.approx(abs(f1 + f2), abs=1e-7)
        # and the middle region is folded by f1 alone
        m = s.topology.node_id(0, 4)
        assert normal_angle_deg(R, a, m) == pytest.approx(abs(f1), abs=1e-7)


# ------------------------------------------------------------------------------------------------
# the tilted hinge is a revolute joint about n = cos(a) z + sin(a) f
# ------------------------------------------------------------------------------------------------
def test_relative_rotation_is_about_the_tilted_hinge_axis():
    s = strip(5, axes=[(2, 50.0)])
    design.configure(s)
    kin = design.kinematics_for(s)
    topo = s.topology
    for name in ("H0,2", "H1,2"):
        alpha = math.radians(s.joint_tilt_deg(name))
        k = topo.joint_id("H", int(name[1]), 2)
        a, b = topo.joint_pairs[k]
        n = np.array([0.0, -math.sin(alpha), math.cos(alpha)])   # f = -y for H joints
        for g in (1.0, 0.5, -0.5, -1.0):
            R = kin.poses(np.full(topo.n_nodes, g))[1]
            rv = Rotation.from_matrix(R[a].T @ R[b]).as_rotvec()
            psi = np.linalg.norm(rv)
            assert abs(abs(rv @ n) - psi) < 1e-9 * max(1, psi)        # parallel to the fixed axis
            gamma = math.radians(normal_angle_deg(R, a, b))
            # the note's formula (checked here): sin(gamma/2) = sin(alpha) sin(psi/2)
            assert math.sin(gamma / 2) == pytest.approx(abs(math.sin(alpha)) * math.sin(psi / 2), abs=1e-12)
            # small-angle form gamma ~ 2 phi tan(alpha) is the first-order term of the exact law
            phi = abs(kin.angles(np.full(topo.n_nodes, g))[a])
            assert math.tan(gamma / 2) == pytest.approx(abs(math.tan(alpha)) * math.sin(phi), rel=1e-9)


def test_tilt_in_the_chord_plane_would_fold_about_the_chord():
    """Why the tilt leans towards the fold vector (perpendicular to the chord): a revolute axis leaning
    in the plane of the chord turns the normal about the chord, not about the axis line."""
    alpha, psi = math.radians(60), math.radians(30)
    n_chord = np.array([math.sin(alpha), 0, math.cos(alpha)])  # H joint chord along x
    z2 = Rotation.from_rotvec(psi * n_chord).apply([0, 0, 1])
    assert abs(z2[1]) > 5 * abs(z2[0])            # the normal turns mainly about x, the chord itself
    n_fold = np.array([0, -math.sin(alpha), math.cos(alpha)])  # leaning towards f = -y instead
    z3 = Rotation.from_rotvec(psi * n_fold).apply([0, 0, 1])
    assert abs(z3[0]) > 5 * abs(z3[1])            # mainly about y: along the axis line


# ------------------------------------------------------------------------------------------------
# exact mechanism, least squares, orthonormality
# ------------------------------------------------------------------------------------------------
def l_scene():
    # a hook: top row of 4 cells and an arm of 2 cells down the last column; a vertical axis in the
    # row (line 1) and a horizontal axis in the arm (line 1): they do not cross (cell (1,1) is empty)
    return Scene.from_dict({"layout": {"rows": ["####", "...#", "...#"]},
                            "hinge": {"length_mm": 5.0, "width_mm": 0.8, "thickness_mm": 7.0},
                            "axes": [{"direction": "vertical", "line": 1, "fold_deg": 40},
                                     {"direction": "horizontal", "line": 1, "fold_deg": -55}]})


@pytest.mark.parametrize("make", [lambda: strip(7, axes=[(1, 45.0), (4, -60.0)]),
                                  lambda: Scene.from_dict({"layout": {"grid": [4, 6]}, "hinge": {"length_mm": 5.0},
                                                           "axes": [{"direction": "vertical", "line": 1,
                                                                     "fold_deg": 50},
                                                                    {"direction": "vertical", "line": 4,
                                                                     "fold_deg": 50}]}),
                                  l_scene])
def test_hinge_closure_residual_vanishes_for_exact_mechanism(make):
    s = make()
    design.configure(s)
    kin = design.kinematics_for(s)
    for g in (1.0, 0.3, -0.7, -1.0):
        pos, R, phi = kin.poses(np.full(s.topology.n_nodes, g))
        assert kin.closure_residual(phi, pos) < 1e-9
        assert kin.rotation_closure_residual(phi) < 1e-12
        assert np.abs(np.einsum("nji,njk->nik", R, R) - np.eye(3)).max() < 1e-12
        assert np.allclose(np.linalg.det(R), 1.0)


def test_nested_perpendicular_folds_compose_in_tree_order():
    """The arm's end is beyond both axes: its normal is Rot(-y, 40) Rot(-x, -55) z (scipy reference)."""
    s = l_scene()
    design.configure(s)
    R = K.node_poses(s, np.ones(s.topology.n_nodes), kin=design.kinematics_for(s))[1]
    root = s.topology.node_id(0, 0)
    tip = s.topology.node_id(3, 4)
    want = (Rotation.from_rotvec(math.radians(40) * np.array([0, -1, 0]))
            * Rotation.from_rotvec(math.radians(-55) * np.array([-1, 0, 0]))).apply([0, 0, 1])
    assert np.allclose(R[root][:, 2], [0, 0, 1], atol=1e-12)     # the root region stays level
    assert np.allclose(R[tip][:, 2], want, atol=1e-9)
    # the reverse order would be wrong
    wrong = (Rotation.from_rotvec(math.radians(-55) * np.array([-1, 0, 0]))
             * Rotation.from_rotvec(math.radians(40) * np.array([0, -1, 0]))).apply([0, 0, 1])
    assert not np.allclose(R[tip][:, 2], wrong, atol=1e-3)


def test_nonuniform_field_is_a_least_squares_solution():
    s = Scene.from_dict({"layout": {"grid": [4, 6]}, "hinge": {"length_mm": 5.0},
                         "axes": [{"direction": "vertical", "line": 2, "fold_deg": 50}],
                         "actuators": [{"name": "m", "joint": "V1,0", "value": 1.0}]})
    from metamaterial_wb.core.solver import solve_scene
    D, *_ = solve_scene(s)
    kin = design.kinematics_for(s)
    pos, R, phi = kin.poses(D)
    assert np.abs(np.einsum("nji,njk->nik", R, R) - np.eye(3)).max() < 1e-12
    F = kin.fold_frames(phi)
    e = kin._chords(phi, F, R)
    r = pos[kin.b] - pos[kin.a] - e
    # not an exact mechanism (hinges must strain) ...
    assert np.abs(r).max() > 1e-6
    # ... but the normal equations of min sum |r|^2 hold: inc^T r = 0 at every node
    assert np.abs(kin.incT @ r).max() < 1e-9
    # and the least squares beats any perturbation
    rng = np.random.default_rng(1)
    base = float((r ** 2).sum())
    for _ in range(5):
        p2 = pos + 0.05 * rng.standard_normal(pos.shape)
        r2 = p2[kin.b] - p2[kin.a] - e
        assert float((r2 ** 2).sum()) > base


def test_random_fields_give_orthonormal_rotations_and_finite_poses():
    s = Scene.from_dict({"layout": {"grid": [5, 7]}, "hinge": {"length_mm": 5.0},
                         "axes": [{"direction": "horizontal", "line": 1, "fold_deg": 30},
                                  {"direction": "horizontal", "line": 3, "fold_deg": -60}]})
    kin = design.kinematics_for(s)
    rng = np.random.default_rng(0)
    for _ in range(5):
        D = rng.uniform(-1, 1, s.topology.n_nodes)
        pos, R, phi = kin.poses(D)
        assert np.all(np.isfinite(pos))
        assert np.abs(np.einsum("nji,njk->nik", R, R) - np.eye(3)).max() < 1e-12
        assert np.allclose(np.linalg.det(R), 1.0)


def test_factored_object_matches_fresh_solves():
    s = strip(6, axes=[(2, 40.0)])
    kin = design.kinematics_for(s)
    for g in (0.2, 0.9, -0.6):
        D = np.linspace(-1, 1, s.topology.n_nodes) * g
        p1, R1, _ = kin.poses(D)
        p2, R2, _ = K.node_poses(s, D, kin=design.kinematics_for(s))
        assert np.allclose(p1, p2) and np.allclose(R1, R2)


def test_flat_state_is_flat_and_on_the_grid():
    s = strip(5, axes=[(2, 60.0)])
    pos, R, _ = K.node_poses(s, np.zeros(s.topology.n_nodes), kin=design.kinematics_for(s))
    ij = s.topology.node_ij()
    assert np.allclose(pos[:, 0] - pos[0, 0], ij[:, 1] * 20.0)
    assert np.allclose(pos[:, 2], 0) and np.allclose(R, np.eye(3))


# ------------------------------------------------------------------------------------------------
# limits
# ------------------------------------------------------------------------------------------------
def test_rotation_limits_report_what_binds():
    s = Scene.from_dict({"layout": {"grid": [2, 2]}, "hinge": {"length_mm": 2.0, "width_mm": 0.8}})
    info = K.rotation_limit_info(s)
    assert info["closing_deg"] == pytest.approx(math.degrees(math.asin(2.0 / 36.0)))
    assert "plate contact" in info["closing_binding"]
    assert info["opening_deg"] == pytest.approx(45.0) and "mechanism" in info["opening_binding"]
    # a wide, short hinge: strain w*phi/lh = 0.5 binds before 45 deg
    s2 = Scene.from_dict({"layout": {"grid": [2, 2]}, "hinge": {"length_mm": 2.0, "width_mm": 3.5}})
    info2 = K.rotation_limit_info(s2)
    assert info2["opening_rad"] == pytest.approx(0.5 * 2.0 / 3.5)
    assert "hinge strain" in info2["opening_binding"]
    assert K.rotation_limits(s2) == (info2["closing_rad"], info2["opening_rad"])


def test_tilted_joint_limits_opening_by_fold_contact():
    s = strip(5, axes=[(2, 60.0)])
    design.configure(s)
    info = K.rotation_limit_info(s)
    alpha = abs(math.radians(s.joint_tilt_deg("H0,2")))
    # the reverse fold 2 atan(tan(alpha) sin(phi)) reaches plate contact 2 atan(lh/t) at phi:
    assert info["opening_rad"] == pytest.approx(math.asin((5.0 / 7.0) / math.tan(alpha)))
    assert "fold contact" in info["opening_binding"]


# ------------------------------------------------------------------------------------------------
# independent geometric checks of the limits and of the non-uniform path
# ------------------------------------------------------------------------------------------------
def _overlap(P, Q):
    """Separating-axis test of two convex quads (2D), touching counts as apart."""
    for poly in (P, Q):
        for k in range(4):
            e = poly[(k + 1) % 4] - poly[k]
            n = np.array([-e[1], e[0]])
            a, b = P @ n, Q @ n
            if a.max() <= b.min() + 1e-12 or b.max() <= a.min() + 1e-12:
                return False
    return True


@pytest.mark.parametrize("lh", [2.0, 5.0, 8.0])
def test_closing_limit_is_where_plates_touch(lh):
    """Plates drawn at their poses overlap just beyond asin(lh/2s) and not just before it; the
    opening sense stays free of contact up to 45 deg."""
    from metamaterial_wb.core.render import plate_corners
    s = Scene.from_dict({"layout": {"grid": [3, 3]}, "hinge": {"length_mm": lh, "width_mm": 0.5}})
    kin = design.kinematics_for(s)
    par = K.node_parity(s)
    phic = math.asin(lh / (2 * (20.0 - lh)))
    for f, expect in ((0.98, False), (1.02, True)):
        pos, R = kin.poses_from_angles(par * phic * f)
        C = plate_corners(s, pos, R)[:, :, :2]
        hit = any(_overlap(C[i], C[j]) for i in range(len(C)) for j in range(i + 1, len(C)))
        assert hit == expect, f
    pos, R = kin.poses_from_angles(-par * math.pi / 4 * 0.999)
    C = plate_corners(s, pos, R)[:, :, :2]
    assert not any(_overlap(C[i], C[j]) for i in range(len(C)) for j in range(i + 1, len(C)))


def test_nonuniform_poses_converge_to_the_exact_mechanism():
    """Least-squares poses are continuous: D = g + eps * noise -> exact uniform poses as eps -> 0."""
    s = Scene.from_dict({"layout": {"grid": [3, 5]}, "hinge": {"length_mm": 5.0},
                         "axes": [{"direction": "vertical", "line": 2, "fold_deg": 45}]})
    kin = design.kinematics_for(s)
    n = s.topology.n_nodes
    noise = np.random.default_rng(3).uniform(-1, 1, n)
    p0, R0, _ = kin.poses(np.full(n, 0.8))
    errs = []
    for eps in (1e-2, 1e-3, 1e-4):
        p, R, _ = kin.poses(np.clip(0.8 + eps * noise, -1, 1))
        errs.append(max(np.abs(p - p0).max(), np.abs(R - R0).max()))
    assert errs[0] > errs[1] > errs[2]
    assert errs[2] < 1e-2 * errs[0] * 1.5      # first order in eps
