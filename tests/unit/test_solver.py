"""The quadratic model's solver: correctness against independent references and its stability properties.

References used here are independent of the code under test: the closed-form 1-D decay ratio, a
dense solve of the energy minimisation written from eq. (1) directly (not through the sparse
assembly), an extended-precision (mpmath) solve, and invariances that any correct solver satisfies.
"""
import math
import random

import numpy as np
import pytest

from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.core.scene import Scene
from metamaterial_wb.core.solver import (QuadraticModel, assemble_hessian, energy, model_for_scene, scene_values,
                                         solve_scene)


def grid_pairs(r, c):
    idx = np.arange(r * c).reshape(r, c)
    h = np.column_stack([idx[:, :-1].ravel(), idx[:, 1:].ravel()])
    v = np.column_stack([idx[:-1, :].ravel(), idx[1:, :].ravel()])
    return idx, np.vstack([h, v])


def reference_minimiser(n, pairs, k1, k2, fixed):
    """Minimise eq. (1)+(2) by brute force: energy gradient written term by term, dense solve."""
    free = [i for i in range(n) if i not in fixed]
    # E(D) is quadratic: build A, b of E = D^T A D by evaluating the energy on basis vectors
    def E(D):
        return sum(k2[e] * (k1[e] * (D[a] - D[b]) ** 2 + (1 - k1[e]) * (D[a] ** 2 + D[b] ** 2))
                   for e, (a, b) in enumerate(pairs))
    base = np.zeros(n)
    for i, v in fixed.items():
        base[i] = v
    m = len(free)
    # quadratic form by polarisation: E(base + x) = c + g.x + x^T Q x
    Q = np.zeros((m, m))
    g = np.zeros(m)
    e0 = E(base)
    for p, i in enumerate(free):
        d = base.copy(); d[i] += 1
        dm = base.copy(); dm[i] -= 1
        Q[p, p] = (E(d) + E(dm) - 2 * e0) / 2
        g[p] = (E(d) - E(dm)) / 2
    for p, i in enumerate(free):
        for q in range(p + 1, m):
            j = free[q]
            d = base.copy(); d[i] += 1; d[j] += 1
            Q[p, q] = Q[q, p] = (E(d) - e0 - g[p] - g[q] - Q[p, p] - Q[q, q]) / 2
    x = np.linalg.solve(2 * Q, -g)
    D = base.copy()
    D[free] = x
    return D


def random_model(seed, r=4, c=5, k1_choices=(0.0, 0.3, 0.7, 0.9, 0.99), spread=True):
    rng = np.random.default_rng(seed)
    idx, pairs = grid_pairs(r, c)
    k1 = rng.choice(k1_choices, len(pairs))
    k2 = 10 ** rng.uniform(-3, 3, len(pairs)) if spread else np.ones(len(pairs))
    groups = [("m1", [idx[0, 0], idx[0, 1]]), ("m2", [idx[r - 1, c - 2], idx[r - 1, c - 1]])]
    return idx, pairs, k1, k2, groups


@pytest.mark.parametrize("seed", range(6))
def test_matches_brute_force_minimiser(seed):
    idx, pairs, k1, k2, groups = random_model(seed)
    n = idx.size
    vals = [0.7, -0.4]
    m = QuadraticModel(n, pairs, k1, k2, groups, backend="superlu")
    D = m.solve(vals)
    fixed = {int(i): v for (name, nodes), v in zip(groups, vals) for i in nodes}
    ref = reference_minimiser(n, pairs, k1, k2, fixed)
    assert np.abs(D - ref).max() < 1e-10
    # the solution is a minimum: any perturbation of a free node raises the energy
    e = energy(D, pairs, k1, k2)
    for i in range(n):
        if i in fixed:
            continue
        for eps in (1e-3, -1e-3):
            P = D.copy(); P[i] += eps
            assert energy(P, pairs, k1, k2) > e


def test_hessian_symmetric_and_matches_energy():
    idx, pairs, k1, k2, _ = random_model(1)
    H = assemble_hessian(idx.size, pairs, k1, k2)
    assert abs(H - H.T).max() == 0
    x = np.random.default_rng(0).normal(size=idx.size)
    assert math.isclose(0.5 * x @ (H @ x), energy(x, pairs, k1, k2), rel_tol=1e-12)


def test_maximum_principle_random_scenes():
    rng = np.random.default_rng(42)
    for trial in range(60):
        r, c = rng.integers(1, 6), rng.integers(2, 7)
        idx, pairs = grid_pairs(r, c)
        k1 = rng.choice([0.0, 0.5, 0.9, 0.999, 1.0], len(pairs))
        k2 = 10 ** rng.uniform(-6, 6, len(pairs))
        n = idx.size
        nodes = rng.choice(n, size=min(n, 4), replace=False)
        groups = [("a", [nodes[0]]), ("b", [nodes[1]])] if n >= 2 else [("a", [0])]
        vals = rng.uniform(-1, 1, len(groups))
        m = QuadraticModel(n, pairs, k1, k2, groups, backend="superlu")
        D = m.solve(vals)
        lo, hi = min(0.0, vals.min()), max(0.0, vals.max())
        assert D.min() >= lo - 1e-7 and D.max() <= hi + 1e-7, (trial, D.min(), D.max(), vals)
        assert np.all(np.isfinite(D))


def test_decay_ratio_on_long_chain():
    # a chain of nodes (1-D), actuator at one end: D_i ~ r^i with r = (1 - sqrt(1 - k1^2)) / k1
    for k1v in (0.3, 0.5, 0.9, 0.99):
        n = 400
        pairs = np.column_stack([np.arange(n - 1), np.arange(1, n)])
        m = QuadraticModel(n, pairs, np.full(n - 1, k1v), np.ones(n - 1), [("m", [0])])
        D = m.solve([1.0])
        r = (1 - math.sqrt(1 - k1v ** 2)) / k1v
        # far from the free end the ratio is the infinite-chain one
        for i in (5, 10, 20):
            if D[i] > 1e-250:
                assert abs(D[i + 1] / D[i] - r) < 1e-12


def test_decay_on_scene_chain_of_cells():
    """On a 1 x N chain of cells the two node rows move together: the ratio per cell solves
    k1 (r + 1/r) = 2 - ... ; checked against a transfer-matrix solution of the same equations."""
    s = Scene.from_dict({"layout": {"chain": 60}, "joints": [],
                         "actuators": [{"name": "m", "joint": "V0,0", "value": 1.0}]})
    k1v = 0.9
    s2 = Scene.from_dict({"layout": {"chain": 60}, "hinge": {"length_mm": 2.0},
                          "joints": [{"joint": n, "k1": k1v, "k2": 1.0} for n in s.topology.joint_names],
                          "actuators": [{"name": "m", "joint": "V0,0", "value": 1.0}]})
    D, *_ = solve_scene(s2)
    topo = s2.topology
    top = np.array([D[topo.node_index[(0, j)]] for j in range(61)])
    bot = np.array([D[topo.node_index[(1, j)]] for j in range(61)])
    assert np.allclose(top, bot)  # symmetry of the two rows
    # each node: 3 joints (left, right, vertical) with the vertical partner equal:
    # 3 D_j - k1 (D_{j-1} + D_{j+1} + D_j) = 0  ->  r + 1/r = (3 - k1) / k1
    q = (3 - k1v) / k1v
    r = (q - math.sqrt(q * q - 4)) / 2
    for j in (5, 10, 15):
        assert abs(top[j + 1] / top[j] - r) < 1e-10


def test_limits_k1_zero_and_one():
    idx, pairs = grid_pairs(5, 6)
    n = idx.size
    groups = [("m", [idx[2, 2], idx[2, 3]])]
    m0 = QuadraticModel(n, pairs, np.zeros(len(pairs)), np.ones(len(pairs)), groups)
    D0 = m0.solve([0.8])
    free = np.setdiff1d(np.arange(n), [idx[2, 2], idx[2, 3]])
    assert np.all(D0[free] == 0.0)  # diagonal Hessian: exactly zero
    m1 = QuadraticModel(n, pairs, np.ones(len(pairs)), 10 ** np.linspace(-3, 3, len(pairs)), groups)
    D1 = m1.solve([0.8])
    assert np.abs(D1 - 0.8).max() < 1e-9  # perfect propagation regardless of k2


def test_island_gets_zero_and_warning_even_at_k1_one():
    # two separate components: one with an actuator, one without (k1 = 1 makes it singular)
    n = 8
    pairs = np.array([[0, 1], [1, 2], [2, 3], [4, 5], [5, 6], [6, 7]])
    m = QuadraticModel(n, pairs, np.ones(6), np.ones(6), [("m", [0])])
    D = m.solve([0.6])
    assert np.allclose(D[:4], 0.6)
    assert np.all(D[4:] == 0.0)
    assert m.warnings and "D = 0" in m.warnings[0]
    # no actuator at all on a scene: warning, all zero
    s = Scene.from_dict({"layout": {"grid": [2, 2]}, "joints": []})
    D, _m, warns, _t = solve_scene(s)
    assert np.all(D == 0) and warns


def test_conflicting_fixed_values_rejected_naming_both():
    with pytest.raises(SceneError) as e:
        Scene.from_dict({"layout": {"grid": [2, 3]},
                         "actuators": [{"name": "m1", "joint": "H0,0", "value": 0.5},
                                       {"name": "m2", "joint": "V0,1", "value": -0.5}]})
    msg = str(e.value)
    assert "m1" in msg and "m2" in msg and "N0,1" in msg
    # same value on a shared node is fine; changing one of them later is rejected
    s = Scene.from_dict({"layout": {"grid": [2, 3]},
                         "actuators": [{"name": "m1", "joint": "H0,0", "value": 0.5},
                                       {"name": "m2", "joint": "V0,1", "value": 0.5}]})
    m = model_for_scene(s)
    with pytest.raises(SceneError, match="m1"):
        m.solve({"m1": 0.5, "m2": 0.2})
    with pytest.raises(SceneError, match="m1"):
        s.set_value("m2", 0.1)


def test_invalid_stiffness_rejected():
    idx, pairs = grid_pairs(2, 2)
    for k1, k2, what in ((1.2, 1.0, "k1"), (-0.1, 1.0, "k1"), (0.5, 0.0, "k2"), (0.5, -1.0, "k2"),
                         (np.nan, 1.0, "k1"), (0.5, np.inf, "k2")):
        with pytest.raises(SceneError, match=what):
            QuadraticModel(4, pairs, np.full(len(pairs), k1), np.full(len(pairs), k2), [("m", [0])])


def test_scale_invariance_of_k2():
    idx, pairs, k1, k2, groups = random_model(3, 6, 7)
    vals = [0.9, -0.3]
    D = QuadraticModel(idx.size, pairs, k1, k2, groups).solve(vals)
    for f in (2.0 ** 20, 2.0 ** -20):
        assert np.array_equal(QuadraticModel(idx.size, pairs, k1, k2 * f, groups).solve(vals), D)
    for f in (1e6, 1e-6):
        assert np.abs(QuadraticModel(idx.size, pairs, k1, k2 * f, groups).solve(vals) - D).max() < 1e-12


def test_renumbering_invariance():
    idx, pairs, k1, k2, groups = random_model(5, 6, 7)
    n = idx.size
    vals = [0.5, 0.25]
    D = QuadraticModel(n, pairs, k1, k2, groups).solve(vals)
    perm = np.random.default_rng(9).permutation(n)   # old index -> new index
    new_pairs = perm[pairs]
    new_groups = [(name, [int(perm[i]) for i in nodes]) for name, nodes in groups]
    order = np.random.default_rng(10).permutation(len(pairs))  # joint order too
    Dn = QuadraticModel(n, new_pairs[order], k1[order], k2[order], new_groups).solve(vals)
    assert np.abs(Dn[perm] - D).max() < 1e-13


def test_extended_precision_agreement():
    mpmath = pytest.importorskip("mpmath")
    mpmath.mp.dps = 50
    for seed, k1s in ((0, (0.5, 0.9, 0.99)), (1, (0.999999,))):
        idx, pairs, k1, k2, groups = random_model(seed, 4, 4, k1_choices=k1s)
        n = idx.size
        vals = [0.8, -0.6]
        D = QuadraticModel(n, pairs, k1, k2, groups).solve(vals)
        fixed = {int(i): v for (name, nodes), v in zip(groups, vals) for i in nodes}
        free = [i for i in range(n) if i not in fixed]
        pos = {i: p for p, i in enumerate(free)}
        A = mpmath.zeros(len(free), len(free))
        b = mpmath.zeros(len(free), 1)
        for (a, c), kk1, kk2 in zip(pairs, k1, k2):
            kk1 = mpmath.mpf(float(kk1)); kk2 = mpmath.mpf(float(kk2))
            for x, y in ((a, c), (c, a)):
                if x in pos:
                    A[pos[x], pos[x]] += 2 * kk2
                    if y in pos:
                        A[pos[x], pos[y]] -= 2 * kk1 * kk2
                    else:
                        b[pos[x]] += 2 * kk1 * kk2 * mpmath.mpf(fixed[y])
        x = mpmath.lu_solve(A, b)
        err = max(abs(float(x[pos[i]]) - D[i]) for i in free)
        assert err < (1e-12 if max(k1s) <= 0.99 else 1e-9), err


def test_factor_reuse_equals_refactoring():
    s = Scene.from_dict({"layout": {"grid": [8, 9]},
                         "joints": [{"joint": "H3,3", "k1": 0.5, "k2": 3.0}],
                         "actuators": [{"name": "a", "joint": "V0,0", "value": 0.1},
                                       {"name": "b", "joint": "H7,4", "value": 0.2}],
                         "constraints": [{"name": "c", "joint": "V4,9", "value": -0.3}]})
    m = model_for_scene(s)
    rng = np.random.default_rng(0)
    for _ in range(20):
        vals = dict(zip(["a", "b", "c"], rng.uniform(-1, 1, 3)))
        D_reuse = m.solve(vals)
        D_backsub = m.solve(vals, use_response=False)
        for k, v in vals.items():
            s.set_value(k, float(v))
        D_new = model_for_scene(s).solve(scene_values(s))
        D_dense = model_for_scene(s, backend="dense").solve(scene_values(s))
        assert np.abs(D_reuse - D_new).max() < 1e-15
        assert np.abs(D_backsub - D_new).max() < 1e-15
        assert np.abs(D_dense - D_new).max() < 1e-13
        assert m.residual(D_reuse) < 1e-14


def test_global_deformation_sets_every_node():
    s = Scene.from_dict({"layout": {"grid": [2, 6]},
                         "actuators": [{"name": "m", "joint": "V0,0", "value": 0.1}]})
    D, *_ = solve_scene(s, global_deformation=-0.4)
    assert np.all(D == -0.4)
    with pytest.raises(SceneError, match="global_deformation"):
        solve_scene(s, global_deformation=1.5)


def test_values_out_of_range_rejected_by_name():
    s = Scene.from_dict({"layout": {"grid": [2, 2]},
                         "actuators": [{"name": "m", "joint": "V0,0", "value": 0.1}]})
    m = model_for_scene(s)
    with pytest.raises(SceneError, match=r"values\.m.*1\.5"):
        m.solve({"m": 1.5})
    with pytest.raises(SceneError, match="zzz"):
        m.solve({"m": 0.1, "zzz": 0.2})


def test_constraint_fixes_nodes_like_actuator():
    base = {"layout": {"grid": [3, 4]}}
    a = Scene.from_dict(dict(base, actuators=[{"name": "x", "joint": "H1,1", "value": 0.5}]))
    c = Scene.from_dict(dict(base, constraints=[{"name": "x", "joint": "H1,1", "value": 0.5}]))
    Da, *_ = solve_scene(a)
    Dc, *_ = solve_scene(c)
    assert np.array_equal(Da, Dc)
    t = a.topology
    assert Da[t.node_index[(1, 1)]] == 0.5 and Da[t.node_index[(1, 2)]] == 0.5


def test_large_grid_smoke():
    idx, pairs = grid_pairs(300, 300)
    m = QuadraticModel(idx.size, pairs, np.full(len(pairs), 0.95), np.ones(len(pairs)),
                       [("a", [idx[10, 10], idx[10, 11]]), ("b", [idx[250, 250], idx[251, 250]])])
    D = m.solve([1.0, -1.0])
    assert D[idx[10, 10]] == 1.0 and D[idx[250, 250]] == -1.0
    assert m.residual(D) < 1e-13
    assert -1 - 1e-12 <= D.min() and D.max() <= 1 + 1e-12


@pytest.mark.parametrize("backend", ["superlu", "cholmod", "dense"])
def test_backends_agree(backend):
    from metamaterial_wb.core import solver
    if backend == "cholmod" and not solver.cholmod_available():
        pytest.skip("scikit-sparse (CHOLMOD) not installed: optional accelerator")
    idx, pairs, k1, k2, groups = random_model(7, 9, 11)
    ref = QuadraticModel(idx.size, pairs, k1, k2, groups, backend="superlu").solve([0.3, -0.9])
    m = QuadraticModel(idx.size, pairs, k1, k2, groups, backend=backend)
    assert m.backend == backend
    assert np.abs(m.solve([0.3, -0.9]) - ref).max() < 1e-13
    assert np.abs(m.solve([0.3, -0.9], use_response=False) - ref).max() < 1e-13
