"""The lattice models against independent references.

* finite differences of the energy (gradient) and of the gradient (planar tangent);
* rigid-body invariance of the hinge energy;
* the closed-form rotating-squares mechanism (pitch, D) and pure-bending energy ``EI (2 phi)^2 / 2L``;
* the linear model as the small-amplitude limit of the nonlinear one (two different solvers);
* convergence reporting: a non-converged result is flagged, never returned as converged.
"""
import json
import math
import os
import subprocess
import sys

import numpy as np
import pytest

from metamaterial_wb.core.lattice.geometry import LatticeGeometry, beam_tip_stiffness
from metamaterial_wb.core.lattice.mechanics import ElementState, expm_so3
from metamaterial_wb.core.lattice.solve import NonlinearLattice, node_twist
from metamaterial_wb.core.models import model_names, run_model
from metamaterial_wb.core.scene import Scene

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def grid(n, actuators=(), **extra):
    d = {"format": "metamaterial-scene", "version": 1, "layout": {"grid": [n, n]}, "actuators": list(actuators)}
    d.update(extra)
    return Scene.from_dict(d)


def _global_grad(geo, X, R):
    st = ElementState(geo, X, R, tangent=False)
    g = np.zeros(6 * geo.n)
    np.add.at(g, geo.dofs.ravel(), st.grad.ravel())
    return g


def _perturb(geo, X, R, dq):
    dq = dq.reshape(geo.n, 6)
    return X + dq[:, :3], expm_so3(dq[:, 3:]) @ R


def test_models_registered():
    assert {"quadratic", "linear", "nonlinear"} <= set(model_names())


def test_gradient_matches_finite_differences_with_tilted_hinges():
    sc = grid(2, joint_config={"H0,1": {"tilt_deg": 25}, "V1,1": {"tilt_deg": -15}})
    geo = LatticeGeometry(sc)
    rng = np.random.default_rng(3)
    X = geo.X0 + rng.normal(size=geo.X0.shape) * 0.3
    R = expm_so3(rng.normal(size=(geo.n, 3)) * 0.3)
    N = 6 * geo.n
    h = 1e-6

    def E(dq):
        X2, R2 = _perturb(geo, X, R, dq)
        return ElementState(geo, X2, R2, tangent=False).energy.sum()

    g_fd = np.array([(E(h * e) - E(-h * e)) / (2 * h) for e in np.eye(N)])
    g = _global_grad(geo, X, R)
    assert np.abs(g_fd - g).max() <= 1e-6 * np.abs(g).max()


def test_planar_tangent_is_the_exact_hessian():
    sc = grid(2)
    geo = LatticeGeometry(sc)
    rng = np.random.default_rng(5)
    X = geo.X0.copy()
    X[:, :2] += rng.normal(size=(geo.n, 2)) * 0.3
    R = expm_so3(np.column_stack([np.zeros((geo.n, 2)), rng.normal(size=geo.n) * 0.2]))
    N = 6 * geo.n
    h = 1e-6
    H_fd = np.array([(_global_grad(geo, *_perturb(geo, X, R, h * e)) - _global_grad(geo, *_perturb(geo, X, R, -h * e)))
                     / (2 * h) for e in np.eye(N)])
    st = ElementState(geo, X, R)
    H = np.zeros((N, N))
    for e in range(geo.m):
        H[np.ix_(geo.dofs[e], geo.dofs[e])] += st.H[e]
    idx = np.array([k for k in range(N) if k % 6 in (0, 1, 5)])
    assert np.abs(H_fd - H)[np.ix_(idx, idx)].max() <= 1e-6 * np.abs(H).max()


def test_rigid_motion_costs_no_energy():
    sc = grid(3, joint_config={"H1,1": {"tilt_deg": 30}})
    geo = LatticeGeometry(sc)
    Rm = expm_so3(np.array([[0.3, -0.7, 1.1]]))[0]
    X = geo.X0 @ Rm.T + np.array([5.0, -3.0, 2.0])
    R = np.broadcast_to(Rm, (geo.n, 3, 3)).copy()
    st = ElementState(geo, X, R, tangent=False)
    scale = np.abs(geo.K).max() * geo.cell_size_mm
    assert st.energy.sum() <= 1e-20 * scale
    assert np.abs(st.grad).max() <= 1e-10 * scale


def test_beam_stiffness_closed_forms():
    E, nu, L, w, t = 26.0, 0.45, 2.0, 0.8, 7.0
    K = beam_tip_stiffness(np.array([L]), np.array([w]), np.array([t]), E, nu)[0]
    # pure bending (u2 = L theta / 2, theta) stores EI theta^2 / (2 L) whatever the shear correction
    I3 = t * w ** 3 / 12
    th = 0.01
    e = np.array([0, L * th / 2, 0, 0, 0, th])
    assert 0.5 * e @ K @ e == pytest.approx(E * I3 * th ** 2 / (2 * L), rel=1e-12)
    assert K[0, 0] == pytest.approx(E * w * t / L)
    assert np.all(np.linalg.eigvalsh(K) > 0)


def _all_joints_actuated(n, value):
    sc = grid(n)
    acts = [{"name": f"a{k}", "joint": name, "value": value} for k, name in enumerate(sc.topology.joint_names)]
    return grid(n, acts)


@pytest.mark.parametrize("value", [0.5, 1.0, -0.1, -0.3, -0.6])
def test_uniform_mechanism_matches_rotating_squares_closed_form(value):
    """Every joint actuated to the same D (redundant but consistent constraints around every cell): the
    rotating-squares mechanism with every hinge in pure bending by 2 phi. Closed forms: energy
    sum EI (2 phi)^2 / (2 L); pitch = arc chord lh sin(phi)/phi + s (cos phi -+ sin phi) (core/kinematics'
    pitch with the straight hinge link replaced by the bent hinge's chord). Up to 54-degree hinge bends."""
    from metamaterial_wb.core import kinematics

    sc = _all_joints_actuated(3, value)
    res = run_model("nonlinear", sc)
    assert res.converged
    assert np.allclose(res.D, value, atol=1e-6)
    geo = LatticeGeometry(sc)
    phi = abs(value) * (geo.closing_rad if value > 0 else geo.opening_rad)
    lh = sc.hinge["length_mm"]
    I3 = sc.hinge["thickness_mm"] * sc.hinge["width_mm"] ** 3 / 12
    E_closed = geo.m * geo.E * I3 * (2 * phi) ** 2 / (2 * lh)
    assert res.info["elastic_energy_Nmm"] == pytest.approx(E_closed, rel=1e-6)
    s = geo.plate_side_mm
    pitch_closed = lh * math.sin(phi) / phi + s * (math.cos(phi) - math.copysign(1, value) * math.sin(phi))
    topo = sc.topology
    a, b = topo.node_index[(1, 0)], topo.node_index[(1, 3)]
    pitch = np.linalg.norm(res.positions_mm[b] - res.positions_mm[a]) / 3
    assert pitch == pytest.approx(pitch_closed, rel=1e-7)
    # core/kinematics' straight-link closed form differs only by the hinge's arc: lh (1 - sin(phi)/phi)
    assert abs(pitch - kinematics.uniform_pitch_mm(sc, value)) <= lh * (1 - math.sin(phi) / phi) + 1e-9


def test_linear_is_the_small_amplitude_limit_of_nonlinear():
    amp = 1e-4
    acts = [{"name": "m1", "joint": "H2,1", "value": amp}, {"name": "m2", "joint": "V1,3", "value": -0.7 * amp}]
    sc = grid(5, acts)
    lin = run_model("linear", sc)
    nl = run_model("nonlinear", sc, tol=1e-12)
    assert nl.converged
    scale = np.abs(lin.D).max()
    assert np.abs(lin.D - nl.D).max() <= 2e-3 * scale
    assert np.abs(lin.positions_mm - nl.positions_mm).max() <= 1e-3 * np.abs(lin.positions_mm - LatticeGeometry(sc).X0).max()


def test_linear_is_linear_and_reuses_its_factorisation():
    from metamaterial_wb.core.lattice.solve import LinearLattice

    acts = [{"name": "m1", "joint": "H1,1", "value": 0.2}, {"name": "m2", "joint": "V2,3", "value": -0.1}]
    sc = grid(4, acts)
    lin = LinearLattice(sc, contact=False)     # without contact the response is exactly linear
    q1 = lin.solve(np.array([1.0, 0.0]) * lin.psi)[2]
    q2 = lin.solve(np.array([0.0, 1.0]) * lin.psi)[2]
    q = lin.solve()[2]
    assert np.allclose(q, q1 + q2, atol=1e-12 * np.abs(q).max())


def test_tilted_hinges_fold_the_sheet_out_of_plane():
    """A strip with tilted H joints on one column line folds about that line; without tilt it stays flat."""
    tilted = {f"H{i},2": {"tilt_deg": 30.0} for i in range(3)}
    acts = [{"name": "m1", "joint": "H1,2", "value": 0.8}]
    flat = Scene.from_dict({"layout": {"grid": [2, 5]}, "actuators": acts})
    bent = Scene.from_dict({"layout": {"grid": [2, 5]}, "actuators": acts, "joint_config": tilted})
    for model in ("linear", "nonlinear"):
        r0 = run_model(model, flat)
        r1 = run_model(model, bent)
        assert r1.converged and r0.converged
        assert np.abs(r0.positions_mm[:, 2]).max() < 1e-9
        z = r1.positions_mm[:, 2]
        assert np.ptp(z) > 0.05, model            # folded: the plates leave the plane
        assert r1.info["dofs"] == 2 * r0.info["dofs"]   # 6 instead of 3 DOF per node


def test_contact_penalty_keeps_plates_from_overlapping():
    acts = [{"name": "m1", "joint": "H3,2", "value": 1.0}]
    sc = grid(6, acts)
    geo = LatticeGeometry(sc)
    out = {}
    for contact in (True, False):
        m = NonlinearLattice(sc, geo, contact=contact)
        X, R, ok = m.solve()
        assert ok
        st = ElementState(geo, X, R, tangent=False)
        closing = m.close_sign * st.eps[:, 5] / (2 * geo.contact_rad)
        out[contact] = closing.max()
    assert out[True] <= 1.0 + 1e-3           # no hinge closes past plate contact
    assert out[False] > 1.2                  # ... which it would without the contact penalty


def test_non_converged_result_is_flagged_and_cli_exits_nonzero(tmp_path):
    acts = [{"name": "m1", "joint": "H2,2", "value": 1.0}, {"name": "m2", "joint": "H3,2", "value": -1.0}]
    sc = grid(5, acts)
    res = run_model("nonlinear", sc, max_iter=1, fallback=False)
    assert res.converged is False
    assert any("did NOT converge" in w for w in res.warnings)
    p = tmp_path / "s.json"
    p.write_text(sc.to_json())
    out = tmp_path / "r.json"
    r = subprocess.run([sys.executable, "-m", "metamaterial_wb", "solve", str(p), "--out", str(out), "--model",
                        "nonlinear", "--option", "max_iter=1", "--option", "fallback=false"],
                       cwd=REPO, capture_output=True, text=True)
    assert r.returncode == 1
    assert "did not converge" in r.stderr
    assert json.loads(out.read_text())["converged"] is False


def test_dynamic_relaxation_reaches_the_newton_equilibrium():
    acts = [{"name": "m1", "joint": "H1,1", "value": 0.4}]
    sc = grid(3, acts)
    geo = LatticeGeometry(sc)
    m = NonlinearLattice(sc, geo)
    Xn, Rn, ok = m.solve()
    assert ok and m.stats["method"] == "newton"
    m2 = NonlinearLattice(sc, geo, dr_max_iter=6000)
    I3 = np.broadcast_to(np.eye(3), (geo.n, 3, 3)).copy()
    Xd, Rd, _ = m2._dynamic_relaxation(geo.X0.copy(), I3, 1e-6, m.scale_f)
    span = np.abs(Xn - geo.X0).max()
    assert np.abs(Xd - Xn).max() < 0.05 * span
    # the fallback path end to end: DR then a Newton polish converges to the same state
    Xp, Rp, mu, ok2, _ = m2._newton(Xd, Rd, 1.0, np.zeros(1), m.scale_f)
    assert ok2 and np.abs(Xp - Xn).max() < 1e-6 * span


@pytest.mark.parametrize("model", ["quadratic", "linear", "nonlinear"])
def test_solve_cli_same_format_for_every_model(tmp_path, model):
    sc = grid(3, [{"name": "m1", "joint": "H1,1", "value": 0.3}])
    p = tmp_path / "s.json"
    p.write_text(sc.to_json())
    out = tmp_path / "r.json"
    r = subprocess.run([sys.executable, "-m", "metamaterial_wb", "solve", str(p), "--out", str(out), "--model", model],
                       cwd=REPO, capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    doc = json.loads(out.read_text())
    assert doc["model"] == model and doc["converged"] is True
    assert len(doc["nodes"]) == sc.topology.n_nodes
    assert {"D", "position_mm", "rotation", "rotation_deg"} <= set(doc["nodes"][0])


def test_D_is_derived_from_the_plate_rotation_with_the_sign_rule():
    sc = grid(3, [{"name": "m1", "joint": "H1,1", "value": 0.3}])
    res = run_model("nonlinear", sc)
    geo = LatticeGeometry(sc)
    phi = node_twist(res.rotations)
    assert np.allclose(res.D, geo.D_from_phi(phi))
    # the actuated pair turns in opposite senses and their D add up to twice the actuator value
    k = sc.topology.joint_index["H1,1"]
    a, b = sc.topology.joint_pairs[k]
    assert np.sign(phi[a]) == -np.sign(phi[b])
    assert res.D[a] + res.D[b] == pytest.approx(0.6, abs=1e-6)


def test_fallback_dynamic_relaxation_then_newton_end_to_end():
    """Newton starved (3 iterations, no load stepping) fails; dynamic relaxation takes over and a Newton
    polish converges to the same equilibrium as the normal path."""
    sc = grid(3, [{"name": "m", "joint": "H1,1", "value": 0.6}])
    ref = run_model("nonlinear", sc)
    res = run_model("nonlinear", sc, max_iter=3, min_step=1.0)
    assert res.converged and res.info["method"] == "dynamic relaxation + Newton"
    assert res.info["dr_iterations"] > 0
    assert np.abs(res.D - ref.D).max() < 1e-8


def test_scene_with_axes_but_no_joint_configuration_folds_like_a_configured_one():
    from metamaterial_wb.core.design import ensure_configured

    d = {"format": "metamaterial-scene", "version": 1, "layout": {"chain": 6},
         "hinge": {"length_mm": 5, "width_mm": 0.8, "thickness_mm": 7},
         "axes": [{"direction": "vertical", "line": 3, "fold_deg": 40}],
         "actuators": [{"name": "m", "joint": "V0,3", "value": 0.8}]}
    raw = Scene.from_dict(d)
    configured = Scene.from_dict(d)
    ensure_configured(configured)
    assert configured.joint_config and not raw.joint_config
    a = run_model("linear", raw)
    b = run_model("linear", configured)
    assert np.ptp(a.positions_mm[:, 2]) > 1e-3
    assert np.allclose(a.positions_mm, b.positions_mm, atol=1e-9)


def test_dynamic_relaxation_alone_is_reported_as_such_and_bad_options_rejected():
    from metamaterial_wb.core.errors import SceneError

    sc = Scene.from_dict({"layout": {"chain": 4}, "actuators": [{"name": "m", "joint": "V0,1", "value": 0.05}]})
    ref = run_model("nonlinear", sc)
    res = run_model("nonlinear", sc, method="dynamic_relaxation", tol=1e-2, dr_max_iter=20000)
    assert res.info["method"] == "dynamic relaxation"
    if res.converged:
        assert np.abs(res.D - ref.D).max() < 0.1 * np.abs(ref.D).max()     # tol 1e-2 on forces
    else:
        assert any("did NOT converge" in w for w in res.warnings)
    with pytest.raises(SceneError, match="method"):
        run_model("nonlinear", sc, method="magic")
    with pytest.raises(SceneError, match="unknown option"):
        run_model("linear", sc, tol=1e-3)


def test_tangent_is_the_exact_hessian_with_tilted_hinges():
    """3-D: the element tangent (hinge law, arc correction, curvature of the rotation logarithm) equals the
    symmetric second derivative of the energy, by finite differences of the energy itself."""
    sc = Scene.from_dict({"layout": {"grid": [1, 2]}, "joint_config": {"H0,1": {"tilt_deg": 25},
                                                                        "V0,1": {"tilt_deg": -15}}})
    geo = LatticeGeometry(sc)
    rng = np.random.default_rng(1)
    X = geo.X0 + rng.normal(size=geo.X0.shape) * 0.3
    R = expm_so3(rng.normal(size=(geo.n, 3)) * 0.3)
    N = 6 * geo.n
    h = 1e-4
    I = np.eye(N)

    def E(dq):
        X2, R2 = _perturb(geo, X, R, dq)
        return ElementState(geo, X2, R2, tangent=False).energy.sum()

    H_fd = np.zeros((N, N))
    for i in range(N):
        for j in range(i, N):
            H_fd[i, j] = H_fd[j, i] = (E(h * (I[i] + I[j])) - E(h * (I[i] - I[j])) - E(h * (I[j] - I[i]))
                                       + E(-h * (I[i] + I[j]))) / (4 * h * h)
    st = ElementState(geo, X, R)
    H = np.zeros((N, N))
    for e in range(geo.m):
        H[np.ix_(geo.dofs[e], geo.dofs[e])] += st.H[e]
    assert np.abs(H_fd - H).max() <= 1e-6 * np.abs(H).max()


def test_random_folded_scenes_converge():
    """Robustness: random layouts, hinge sizes, tilted joints (not along axes) and actuators up to +-1;
    Newton (with the curvature of the actuator constraints) converges on every one."""
    rng = np.random.default_rng(7)
    done = 0
    while done < 8:
        r, c = (int(x) for x in rng.integers(1, 5, 2))
        names = Scene.grid(r, c).topology.joint_names
        joints = rng.choice(names, size=min(int(rng.integers(1, 4)), len(names)), replace=False)
        acts = [{"name": f"a{i}", "joint": str(j), "value": float(np.round(rng.uniform(-1, 1), 2))}
                for i, j in enumerate(joints)]
        tilted = rng.choice(names, size=min(3, len(names)), replace=False)
        d = {"layout": {"grid": [r, c]}, "actuators": acts,
             "hinge": {"length_mm": float(rng.uniform(0.5, 8)), "width_mm": float(rng.uniform(0.3, 1.5)),
                       "thickness_mm": 7},
             "joint_config": {str(j): {"tilt_deg": float(rng.uniform(-50, 50))} for j in tilted}}
        try:
            sc = Scene.from_dict(d)
        except Exception:
            continue
        res = run_model("nonlinear", sc)
        assert res.converged, (d, res.info)
        assert res.info["method"] == "newton"
        done += 1
