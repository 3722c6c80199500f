"""The stiff and extreme suite (issue 6, item 6). Every case has a documented outcome
(docs/fidelity-models.md, "Stiff and extreme cases"): CONVERGED, WARNED or REJECTED, and this file
checks exactly that outcome plus a correctness property from an independent reference.
"""
import math
import time

import numpy as np
import pytest
import scipy.linalg as sla

from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.core.lattice.geometry import LatticeGeometry
from metamaterial_wb.core.lattice.mechanics import ElementState
from metamaterial_wb.core.lattice.solve import NonlinearLattice
from metamaterial_wb.core.models import run_model
from metamaterial_wb.core.scene import Scene
from metamaterial_wb.core.solver import QuadraticModel


def grid_pairs(r, c):
    idx = np.arange(r * c).reshape(r, c)
    h = np.column_stack([idx[:, :-1].ravel(), idx[:, 1:].ravel()])
    v = np.column_stack([idx[:-1, :].ravel(), idx[1:, :].ravel()])
    return idx, np.vstack([h, v])


def scene(n, actuators=(), **extra):
    d = {"format": "metamaterial-scene", "version": 1, "layout": {"grid": [n, n]}, "actuators": list(actuators)}
    d.update(extra)
    return Scene.from_dict(d)


def dense_reference(n, pairs, k1, k2, fixed, values):
    """Jacobi-scaled dense solve of the free-node equations written from eq. (1) (an independent path)."""
    H = np.zeros((n, n))
    for e, (a, b) in enumerate(pairs):
        H[a, a] += 2 * k2[e]
        H[b, b] += 2 * k2[e]
        H[a, b] -= 2 * k1[e] * k2[e]
        H[b, a] -= 2 * k1[e] * k2[e]
    free = np.setdiff1d(np.arange(n), fixed)
    D = np.zeros(n)
    D[fixed] = values
    s = 1.0 / np.sqrt(np.diag(H)[free])
    A = H[np.ix_(free, free)] * s[:, None] * s[None, :]
    rhs = -(H[np.ix_(free, fixed)] @ D[fixed]) * s
    D[free] = s * sla.cho_solve(sla.cho_factor(A), rhs)
    return D


# ---------------------------------------------------------------------------------------------------
# k1 -> 1 (CONVERGED; exact limit; WARNED for an island)
# ---------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("k1", [1.0 - 1e-6, 1.0 - 1e-12, 1.0])
def test_k1_to_one_converges_and_keeps_the_maximum_principle(k1):
    r = c = 20
    idx, pairs = grid_pairs(r, c)
    n = r * c
    k1a = np.full(len(pairs), k1)
    k2 = np.ones(len(pairs))
    groups = [("a", [idx[5, 5], idx[5, 6]]), ("b", [idx[14, 12], idx[15, 12]])]
    m = QuadraticModel(n, pairs, k1a, k2, groups)
    D = m.solve([0.8, -0.4])
    assert np.all(np.isfinite(D)) and not m.warnings
    assert D.min() >= -0.4 - 1e-9 and D.max() <= 0.8 + 1e-9
    assert m.residual(D) < 1e-13
    ref = dense_reference(n, pairs, k1a, k2, m.fixed, D[m.fixed])
    assert np.abs(D - ref).max() < 1e-9


def test_k1_equal_one_single_actuator_gives_perfect_propagation():
    idx, pairs = grid_pairs(12, 12)
    m = QuadraticModel(144, pairs, np.ones(len(pairs)), np.ones(len(pairs)), [("a", [idx[3, 3], idx[3, 4]])])
    D = m.solve([0.7])
    assert np.abs(D - 0.7).max() < 1e-12


def test_k1_equal_one_island_is_zero_and_warned_never_arbitrary():
    # two 1 x 5 strips joined only through the constrained nodes: the right part sees only a clip at 0 ...
    sc = Scene.from_dict({"layout": {"grid": [1, 6]},
                          "joints": [{"joint": j, "k1": 1.0} for j in Scene.grid(1, 6).topology.joint_names],
                          "constraints": [{"name": "c", "joint": "V0,3", "value": 0.0}]})
    res = run_model("quadratic", sc)
    assert np.all(res.D == 0.0)
    # ... and a scene without any actuator: every node is an island -> D = 0 and a warning
    sc2 = Scene.from_dict({"layout": {"grid": [3, 3]},
                           "joints": [{"joint": j, "k1": 1.0} for j in Scene.grid(3, 3).topology.joint_names]})
    res2 = run_model("quadratic", sc2)
    assert np.all(res2.D == 0.0)
    assert any("no actuator" in w for w in res2.warnings)


# ---------------------------------------------------------------------------------------------------
# k2 over twelve decades (CONVERGED; accuracy set by the Jacobi-scaled condition number only)
# ---------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("k1", [0.5, 0.99, 0.999999])
def test_k2_over_twelve_decades(k1):
    rng = np.random.default_rng(12)
    idx, pairs = grid_pairs(15, 15)
    n = 225
    k2 = 10.0 ** rng.uniform(-6, 6, len(pairs))
    k1a = np.full(len(pairs), k1)
    groups = [("a", [idx[3, 3], idx[3, 4]]), ("b", [idx[10, 9], idx[11, 9]]), ("c", [idx[7, 12], idx[7, 13]])]
    vals = [1.0, -0.6, 0.3]
    m = QuadraticModel(n, pairs, k1a, k2, groups)
    D = m.solve(vals)
    ref = dense_reference(n, pairs, k1a, k2, m.fixed, D[m.fixed])
    kappa_bound = (1 + k1) / (1 - k1)
    assert np.abs(D - ref).max() < 1e-13 * kappa_bound + 1e-14
    assert D.min() >= min(0, -0.6) - 1e-9 and D.max() <= 1.0 + 1e-9
    # scale invariance: all k2 times 2^20 gives bit-identical D
    m2 = QuadraticModel(n, pairs, k1a, k2 * 2.0 ** 20, groups)
    assert np.array_equal(m2.solve(vals), D)


def test_twelve_decades_of_hinge_stiffness_in_the_lattice():
    """Lattice models with hinge widths from 0.05 to 4 mm (in-plane bending stiffness over ~5.7 decades)
    and moduli over 6 decades: still CONVERGED, and the nonlinear equilibrium is independent of a common
    modulus (statics with position-controlled actuators)."""
    joints = []
    rng = np.random.default_rng(2)
    base = Scene.grid(5, 5)
    for name in base.topology.joint_names:
        joints.append({"joint": name, "width_mm": float(10 ** rng.uniform(math.log10(0.05), math.log10(4.0)))})
    acts = [{"name": "m", "joint": "H2,2", "value": 0.5}]
    D = {}
    for E in (1e-3, 1e3):
        sc = scene(5, acts, joints=joints, material={"hinge_modulus_MPa": E})
        res = run_model("nonlinear", sc)
        assert res.converged
        D[E] = res.D
    assert np.abs(D[1e-3] - D[1e3]).max() < 1e-6


# ---------------------------------------------------------------------------------------------------
# 1000 x 1000 nodes, quadratic model (CONVERGED in a few seconds)
# ---------------------------------------------------------------------------------------------------
def test_one_million_nodes_quadratic():
    r = c = 1000
    idx, pairs = grid_pairs(r, c)
    n = r * c
    k1 = 0.95
    groups = [("a", [idx[250, 250], idx[250, 251]]), ("b", [idx[700, 640], idx[701, 640]]),
              ("c", [idx[500, 900], idx[500, 901]])]
    t = time.perf_counter()
    m = QuadraticModel(n, pairs, np.full(len(pairs), k1), np.ones(len(pairs)), groups, backend="auto")
    D = m.solve([1.0, -0.5, 0.25])
    dt = time.perf_counter() - t
    print(f"1000 x 1000 nodes: prepare + solve {dt:.2f} s ({m.backend})")
    assert np.all(np.isfinite(D))
    assert m.residual(D) < 1e-14
    assert D.min() >= -0.5 - 1e-12 and D.max() <= 1.0 + 1e-12
    # far from everything the response decays like the screened Laplacian: check the row through
    # actuator a against the isotropic continuum decay length sqrt(k1 / (4 (1 - k1))) cells
    row = D[idx[250, 260:300]]
    ell = math.sqrt(k1 / (4 * (1 - k1)))
    rate = -np.polyfit(np.arange(40), np.log(np.abs(row)), 1)[0]
    assert rate == pytest.approx(1 / ell, rel=0.15)


# ---------------------------------------------------------------------------------------------------
# hinge length near zero and very long
# ---------------------------------------------------------------------------------------------------
def test_hinge_length_zero_and_half_cell_are_rejected_by_the_scene():
    with pytest.raises(SceneError, match="length_mm"):
        scene(3, hinge={"length_mm": 0.0, "width_mm": 0.8, "thickness_mm": 7})
    with pytest.raises(SceneError, match="length_mm"):
        scene(3, hinge={"length_mm": 10.0, "width_mm": 0.8, "thickness_mm": 7})


@pytest.mark.parametrize("length", [0.01, 9.99])
def test_extreme_hinge_lengths(length):
    sc = scene(4, [{"name": "m", "joint": "H2,1", "value": 0.5}],
               hinge={"length_mm": length, "width_mm": 0.8, "thickness_mm": 7})
    # quadratic: REJECTED, the calibration table does not cover it (message gives its range)
    with pytest.raises(SceneError, match=r"length_mm.*calibration table"):
        run_model("quadratic", sc)
    # lattice models: CONVERGED, with finite D and the actuated pair at the requested relative rotation
    for model in ("linear", "nonlinear"):
        res = run_model(model, sc)
        assert res.converged and np.all(np.isfinite(res.D))
        k = sc.topology.joint_index["H2,1"]
        a, b = sc.topology.joint_pairs[k]
        assert res.D[a] + res.D[b] == pytest.approx(1.0, abs=1e-6)


# ---------------------------------------------------------------------------------------------------
# actuators at +-1, up to plate contact
# ---------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("value", [1.0, -1.0])
def test_actuators_at_full_range(value):
    sc = scene(6, [{"name": "m", "joint": "H3,2", "value": value}, {"name": "n", "joint": "V1,4", "value": value}])
    res = run_model("nonlinear", sc)
    assert res.converged                                   # CONVERGED (nonlinear)
    geo = LatticeGeometry(sc)
    m = NonlinearLattice(sc, geo)
    X, R, ok = m.solve()
    st = ElementState(geo, X, R, tangent=False)
    closing = m.close_sign * st.eps[:, 5] / (2 * geo.contact_rad)
    assert closing.max() <= 1.0 + 1e-3                     # no plates overlap
    lin = run_model("linear", sc)
    assert lin.converged                                   # CONVERGED (linear, contact active set)
    if value > 0:                                          # WARNED: plates beyond D = 1 (edge amplification)
        assert any("further than the actuators' range" in w for w in lin.warnings)
        assert lin.info["contact_hinges"] > 0
        from metamaterial_wb.core.lattice.solve import LinearLattice
        ll = LinearLattice(sc, geo)
        q = ll.solve()[2]
        closing = ll._closing(q) / (2 * geo.contact_rad)
        assert closing.max() <= 1.0 + 1e-3                 # no overlap (the servos sit exactly at contact)
        free = np.setdiff1d(np.arange(geo.m), ll.joints)
        assert closing[free].max() <= 0.98 + 1e-3          # free hinges held at the contact onset


def test_actuator_beyond_range_is_rejected():
    with pytest.raises(SceneError, match=r"value"):
        scene(3, [{"name": "m", "joint": "H1,1", "value": 1.0001}])


# ---------------------------------------------------------------------------------------------------
# opposite actuators one cell apart (CONVERGED + WARNED); on one node (REJECTED)
# ---------------------------------------------------------------------------------------------------
def test_opposite_actuators_one_cell_apart():
    acts = [{"name": "a", "joint": "H2,2", "value": 1.0}, {"name": "b", "joint": "H3,2", "value": -1.0}]
    sc = scene(5, acts)
    res = run_model("nonlinear", sc)
    assert res.converged
    assert any("further than the actuators' range" in w for w in res.warnings)
    geo = LatticeGeometry(sc)
    topo = sc.topology
    for name, v in (("H2,2", 1.0), ("H3,2", -1.0)):
        a, b = topo.joint_pairs[topo.joint_index[name]]
        assert res.D[a] + res.D[b] == pytest.approx(2 * v, abs=1e-6)
    q = run_model("quadratic", sc)
    assert q.converged and np.abs(q.D).max() <= 1.0 + 1e-12


def test_opposite_actuators_on_one_node_are_rejected():
    acts = [{"name": "a", "joint": "H2,2", "value": 1.0}, {"name": "b", "joint": "V2,2", "value": -1.0}]
    with pytest.raises(SceneError, match="a node can take only one fixed value"):
        scene(5, acts)


# ---------------------------------------------------------------------------------------------------
# islands without actuators
# ---------------------------------------------------------------------------------------------------
def test_islands_without_actuators():
    sc = scene(4)
    q = run_model("quadratic", sc)                 # WARNED, D = 0
    assert np.all(q.D == 0) and any("no actuator" in w for w in q.warnings)
    for model in ("linear", "nonlinear"):          # CONVERGED, nothing to solve: the flat sheet
        res = run_model(model, sc)
        assert res.converged and np.all(res.D == 0)
        assert "nothing to solve" in res.info["method"]
        assert np.allclose(res.positions_mm, LatticeGeometry(sc).X0)


def _square(c, R, a):
    pts = np.array([[a, a, 0], [-a, a, 0], [-a, -a, 0], [a, -a, 0]])
    return (pts @ R.T + c)[:, :2]


def _penetration(P, Q):
    """Separating-axis test of two convex quadrilaterals: > 0 = overlap depth (mm), < 0 = gap."""
    best = np.inf
    for poly in (P, Q):
        for k in range(4):
            e = poly[(k + 1) % 4] - poly[k]
            n = np.array([-e[1], e[0]]) / np.linalg.norm(e)
            p, q = P @ n, Q @ n
            best = min(best, min(p.max(), q.max()) - max(p.min(), q.min()))
    return best


@pytest.mark.parametrize("contact", [True, False])
def test_plates_do_not_overlap_geometrically_at_full_actuation(contact):
    """Independent geometric check of the contact model: the actual plate squares (from the nonlinear
    model's positions and rotations) of every pair of neighbouring and diagonal plates, separating-axis
    test. With contact they never overlap; without it they do (so the check has teeth)."""
    sc = scene(6, [{"name": "m", "joint": "H3,2", "value": 1.0}, {"name": "n", "joint": "V1,4", "value": 1.0}])
    geo = LatticeGeometry(sc)
    res = run_model("nonlinear", sc, contact=contact)
    assert res.converged
    a = geo.plate_side_mm / 2
    worst = -np.inf
    for i in range(geo.n):
        for j in range(i + 1, geo.n):
            if np.linalg.norm(geo.X0[i] - geo.X0[j]) < 1.5 * geo.cell_size_mm:
                worst = max(worst, _penetration(_square(res.positions_mm[i], res.rotations[i], a),
                                                _square(res.positions_mm[j], res.rotations[j], a)))
    if contact:
        assert worst <= 1e-3
    else:
        assert worst > 0.5


def test_actuator_and_clip_on_one_joint_with_equal_values_are_one_constraint():
    """A scene file may not put two items on one joint (scene-format.md; refused on loading), but the models
    still take an equal duplicate built in code as one constraint, not as a singular pair."""
    from metamaterial_wb.core.scene.items import Constraint
    acts = [{"name": "m", "joint": "H1,1", "value": 0.4}]
    with pytest.raises(SceneError, match="already carries"):
        scene(3, acts, constraints=[{"name": "c", "joint": "H1,1", "value": 0.4}])
    both = scene(3, acts)
    both.constraints.append(Constraint("c", "H1,1", 0.4))
    one = scene(3, acts)
    for model in ("linear", "nonlinear"):
        a, b = run_model(model, both), run_model(model, one)
        assert a.converged and a.info["constraints"] == 1
        assert np.allclose(a.D, b.D, atol=1e-9)
