"""Hinges of n corotational Timoshenko elements (nonlinear model option ``hinge_elements``, issue 18 item 1).

* A cantilever of n elements (the lattice's own element mechanics) under a tip force converges to the
  geometrically exact (Reissner) beam with the same axial, shear and bending stiffness, solved here
  independently as a boundary-value problem (scipy solve_bvp); the error falls with n, at second order
  for few elements and first order asymptotically.
* On a grid the change of D between n and 2n falls geometrically (the Richardson study of
  docs/fidelity.md rests on that), and at a tiny amplitude every n gives the one-element answer (the chain
  of Timoshenko tip stiffnesses is exact in linear theory).
"""
import math
import types

import numpy as np
import pytest
from scipy.integrate import solve_bvp

from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.core.lattice.geometry import SHEAR_COEFFICIENT, beam_tip_stiffness
from metamaterial_wb.core.lattice.mechanics import ElementState
from metamaterial_wb.core.models import run_model
from metamaterial_wb.core.scene import Scene

L, W, T, E, NU = 2.0, 0.8, 7.0, 26.0, 0.45          # the default hinge (mm, MPa)


def _cantilever(n, F):
    """Tip position and rotation of an n-element corotational cantilever (clamped at x = 0, in-plane tip
    force F = (Fx, Fy) in N, no tip moment), by Newton on the total potential energy."""
    geo = types.SimpleNamespace(
        a=np.arange(n), b=np.arange(1, n + 1), rA=np.zeros((n, 3)), rB=np.zeros((n, 3)),
        Q0=np.broadcast_to(np.eye(3), (n, 3, 3)).copy(), rest=L / n, arc_correction=True, planar=True,
        K=beam_tip_stiffness(np.full(n, L / n), np.full(n, W), np.full(n, T), E, NU))
    X = np.column_stack([np.linspace(0.0, L, n + 1), np.zeros(n + 1), np.zeros(n + 1)])
    R = np.broadcast_to(np.eye(3), (n + 1, 3, 3)).copy()
    dofs = (0, 1, 5)
    loc = [k for k in range(12) if k % 6 in dofs]
    for lam in np.linspace(0.1, 1.0, 10):
        for _ in range(30):
            st = ElementState(geo, X, R, tangent=True)
            g = np.zeros(3 * (n + 1))
            H = np.zeros((3 * (n + 1),) * 2)
            for e in range(n):
                idx = [3 * e, 3 * e + 1, 3 * e + 2, 3 * e + 3, 3 * e + 4, 3 * e + 5]
                g[idx] += st.grad[e, loc]
                H[np.ix_(idx, idx)] += st.H[e][np.ix_(loc, loc)]
            g[3 * n:3 * n + 2] -= lam * np.asarray(F)
            free = np.arange(3, 3 * (n + 1))
            if np.abs(g[free]).max() < 1e-12 * max(1.0, abs(F[1])):
                break
            dq = np.linalg.solve(H[np.ix_(free, free)], -g[free]).reshape(n, 3)
            X[1:, :2] += dq[:, :2]
            c, s = np.cos(dq[:, 2]), np.sin(dq[:, 2])
            Rz = np.zeros((n, 3, 3))
            Rz[:, 0, 0], Rz[:, 0, 1], Rz[:, 1, 0], Rz[:, 1, 1], Rz[:, 2, 2] = c, -s, s, c, 1.0
            R[1:] = Rz @ R[1:]
        else:
            raise AssertionError("cantilever Newton did not converge")
    return X[-1, :2], math.atan2(R[-1, 1, 0], R[-1, 0, 0])


def _reissner(F):
    """The planar geometrically exact beam (extensible, shearable) under the tip force F: solve_bvp on
    x' = (1 + N/EA) cos th - (V/kGA) sin th, y' = (1 + N/EA) sin th + (V/kGA) cos th, th' = m/EI,
    m' = -(x' Fy - y' Fx); x = y = th = 0 at the root, m = 0 at the tip."""
    G = E / (2 * (1 + NU))
    EA, GA, EI = E * W * T, SHEAR_COEFFICIENT * G * W * T, E * T * W ** 3 / 12.0
    Fx, Fy = F

    def rhs(s, z):
        x, y, th, m = z
        c, sn = np.cos(th), np.sin(th)
        N = Fx * c + Fy * sn
        V = -Fx * sn + Fy * c
        dx = (1 + N / EA) * c - (V / GA) * sn
        dy = (1 + N / EA) * sn + (V / GA) * c
        return np.vstack([dx, dy, m / EI, -(dx * Fy - dy * Fx)])

    s = np.linspace(0, L, 201)
    z0 = np.vstack([s, np.zeros_like(s), np.zeros_like(s), Fy * (L - s)])
    sol = solve_bvp(rhs, lambda za, zb: np.array([za[0], za[1], za[2], zb[3]]), s, z0, tol=1e-10, max_nodes=100000)
    assert sol.success
    zL = sol.sol(L)
    return zL[:2], zL[2]


def test_cantilever_converges_to_the_geometrically_exact_beam():
    EI = E * T * W ** 3 / 12.0
    F = (0.0, 2.0 * EI / L ** 2)               # linear theory: tip rotation F L^2 / 2 EI = 1 rad
    ref_p, ref_th = _reissner(F)
    assert 0.6 < ref_th < 1.0                   # a large rotation: the nonlinear regime
    errs = []
    for n in (1, 2, 4, 8, 16):
        p, th = _cantilever(n, F)
        errs.append(np.linalg.norm(p - ref_p) / L + abs(th - ref_th))
    errs = np.array(errs)
    # measured: 0.187, 0.040, 0.014, 0.0064, 0.0031 (tip position / L + tip rotation in rad)
    assert errs[-1] < 5e-3, errs                # 16 elements: the exact beam to 0.5 %
    assert np.all(errs[1:] < errs[:-1]), errs   # monotone convergence
    order = np.log2(errs[:-1] / errs[1:])
    # second order while bending dominates, first order asymptotically: each element measures its shear
    # and stretch in its start frame, off the mid frame by half its rotation (docs/fidelity.md)
    assert order[0] > 1.8 and np.all(order > 0.9), (errs, order)
    assert errs[0] > 30 * errs[-1]              # one element is measurably off: the reason for the option


REF = {"tol": 1e-11, "load_steps": 4, "max_iter": 60}     # the fidelity reference's Newton settings


def _grid(amp, n=6):
    q = n // 4                                  # the fidelity benchmark's four actuators
    acts = [{"name": "m1", "joint": f"H{q},{q}", "value": amp},
            {"name": "m2", "joint": f"V{q},{n - q}", "value": -0.6 * amp},
            {"name": "m3", "joint": f"H{n - q},{n - q - 1}", "value": 0.8 * amp},
            {"name": "m4", "joint": f"V{n - q - 1},{q}", "value": -amp}]
    return Scene.from_dict({"format": "metamaterial-scene", "version": 1, "name": "g", "layout": {"grid": [n, n]},
                            "actuators": acts})


def test_grid_D_converges_geometrically_with_hinge_elements():
    scene = _grid(0.5)
    D = {k: run_model("nonlinear", scene, hinge_elements=k, **REF).D for k in (1, 2, 4, 8)}
    d = [float(np.sqrt(np.mean((D[2 * k] - D[k]) ** 2))) for k in (1, 2, 4)]
    # measured: 0.242, 0.039, 0.0052 RMS D
    assert d[0] > 0.05                          # refining matters at the working amplitude
    assert d[1] < 0.3 * d[0] and d[2] < 0.3 * d[1], d
    r = run_model("nonlinear", scene, hinge_elements=4)
    assert r.converged and r.info["hinge_elements"] == 4
    lo, hi = r.info["hinge_chord_stretch_range"]
    assert -0.5 < lo <= hi < 0.5


def test_tiny_amplitude_every_n_gives_the_one_element_answer():
    scene = _grid(1e-3)
    D1 = run_model("nonlinear", scene, tol=1e-12).D
    for k in (2, 5):
        Dk = run_model("nonlinear", scene, hinge_elements=k, tol=1e-12).D
        assert np.abs(Dk - D1).max() < 2e-3 * np.abs(D1).max()


@pytest.mark.parametrize("bad", [0, -1, 2.5, "x", 1000])
def test_bad_hinge_elements_is_a_scene_error(bad):
    with pytest.raises(SceneError, match="hinge_elements"):
        run_model("nonlinear", _grid(0.1), hinge_elements=bad)


def test_fe_hinge_law_scales_the_beam_to_the_calculix_table():
    from metamaterial_wb.core.lattice.geometry import LatticeGeometry, apply_hinge_law, fe_hinge_factors

    scene = _grid(0.05)
    beam = LatticeGeometry(scene)
    fe = apply_hinge_law(LatticeGeometry(scene), "fe")
    ratio = np.einsum("mii->mi", fe.K) / np.einsum("mii->mi", beam.K)
    # the default hinge (2 x 0.8 mm, aspect 2.5) is a row of the table: in-plane bending 1.25, torsion 8.2
    assert np.allclose(ratio[:, 5], 1.2484, atol=1e-4) and np.allclose(ratio[:, 3], 8.1754, atol=1e-4)
    assert np.all(np.linalg.eigvalsh(fe.K) > 0)
    # a uniform stiffening barely moves the plates but raises the energy (the servo's work) by ~25 %
    a = run_model("nonlinear", scene)
    b = run_model("nonlinear", scene, hinge_law="fe")
    assert np.sqrt(np.mean((a.D - b.D) ** 2)) < 1e-3
    assert 1.2 < b.info["elastic_energy_Nmm"] / a.info["elastic_energy_Nmm"] < 1.3
    assert b.info["hinge_law"] == "fe"
    assert run_model("nonlinear", scene, hinge_law="fe", hinge_elements=2).converged
    assert run_model("linear", scene, hinge_law="fe").converged
    with pytest.raises(SceneError, match="outside the FE-calibrated range"):
        fe_hinge_factors([20.0], [0.8], [7.0])
    with pytest.raises(SceneError, match="hinge_law"):
        run_model("nonlinear", scene, hinge_law="abaqus")
