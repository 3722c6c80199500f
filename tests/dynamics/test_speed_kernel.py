"""The compiled dynamics kernel (core/dynamics/fastkernel.py + _kernel.c) against the numpy path.

The numpy code in system.py / integrators.py is the reference: forces, contact state, the Newton
matrix, the band LU and short trajectories must agree to round-off, with the same step, Jacobian,
Newton-iteration and force-evaluation counts. The fallback (no compiler, or forced) must give the
numpy path's results exactly.
"""
import os

import numpy as np
import pytest

from metamaterial_wb.core.dynamics import PlanarSystem, Simulator
from metamaterial_wb.core.dynamics import fastkernel
from metamaterial_wb.core.dynamics.builders import build, dynamics_config
from metamaterial_wb.core.dynamics.simulate import simulate
from metamaterial_wb.core.dynamics.system import DynamicsError
from metamaterial_wb.core.scene import Scene

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def scene(name):
    return Scene.load(os.path.join(ROOT, "examples", name))


def lib_or_skip():
    lib = fastkernel.load()
    if lib is None:
        pytest.skip(f"no compiled kernel here: {fastkernel.note()}")
    return lib


def pendulum_on_floor():
    """A fixed pivot (fixed dofs), a swinging body and a third one with contacts: every code path."""
    s = PlanarSystem([1.0, 0.2, 0.3], [1.0, 1e-3, 2e-3], fixed=[True, False, False], gravity=(-1.0, -9.81))
    s.set_hinges([0, 1], [1, 2], [[0.0, 0.0], [0.05, 0.01]], [[0.0, 0.4], [-0.05, 0.0]],
                 kp=[2e4, 5e3], cp=[3.0, 1.0], kr=[0.0, 2.0], cr=[0.1, 0.05], theta0=[0.0, 0.3])
    s.set_contacts([1, 2, 2, 2], [[0.0, -0.02], [0.03, -0.01], [-0.03, -0.01], [0.0, 0.02]],
                   mu=[0.5, 0.8, 0.3, 1.0], kn=1e4, cn=5.0, kt=8e3, ct=2.0)
    return s


def random_states(system, rng, count):
    """States near the floor: some contacts inside (pushing / pulling-clamped), some sticking,
    some sliding, non-zero velocities and rotations."""
    n = system.n
    for _ in range(count):
        q = np.zeros((n, 3))
        q[:, 0] = rng.uniform(-0.3, 0.3, n)
        q[:, 1] = rng.uniform(-0.004, 0.01, n)
        q[:, 2] = rng.uniform(-0.4, 0.4, n)
        v = rng.normal(0.0, 0.3, (n, 3))
        q[system.fixed] = 0.0
        v[system.fixed] = 0.0
        if system.cb.size:
            p = system.contact_points(q)
            anchors = p[:, 0] + rng.normal(0.0, 1.0, p.shape[0]) * 10 ** rng.uniform(-6, -1.5, p.shape[0])
        else:
            anchors = np.zeros(0)
        yield q, v, anchors


def systems():
    out = [("pendulum_on_floor", pendulum_on_floor())]
    for name in ("belt8.json", "worm_crawl.json"):
        sc = scene(name)
        m = build(sc, dynamics_config(sc))
        out.append((name, m.system))
    return out


@pytest.mark.parametrize("label,system", systems(), ids=lambda x: x if isinstance(x, str) else "")
@pytest.mark.parametrize("full_band", [False, True], ids=["rcm-band", "full-band"])
def test_forces_and_newton_matrix_match_numpy(label, system, full_band):
    """full_band: the layout of small systems that are not narrow-banded (natural order, kl = ku = N - 1)."""
    lib = lib_or_skip()
    layout = fastkernel.layout_for(system, band_max=-1 if full_band else 64)
    if full_band:
        assert layout[1] == layout[2] == 3 * system.n - 1
    k = fastkernel.Kernel(lib, system, layout)
    rng = np.random.default_rng(7)
    seen = {"inside": 0, "stick": 0, "slide": 0}
    for q, v, anchors in random_states(system, rng, 12):
        Qn, stn = system.forces(q, v, anchors)
        dpn = system.last_damping_power
        Qc, stc, dpc = k.forces(q, v, anchors)
        scale = np.max(np.abs(Qn))
        assert np.max(np.abs(Qc - Qn)) <= 1e-10 * scale
        assert dpc == pytest.approx(dpn, rel=1e-10, abs=1e-300)
        if stn is not None:
            for key in ("inside", "stick", "pushing"):
                assert np.array_equal(stc[key], stn[key]), key
            for key in ("fn", "ft", "ux", "uy"):
                assert np.allclose(stc[key], stn[key], rtol=1e-10, atol=1e-12 * (1 + np.max(np.abs(stn[key])))), key
            seen["inside"] += int(stn["pushing"].sum())
            seen["stick"] += int((stn["pushing"] & stn["stick"]).sum())
            seen["slide"] += int((stn["pushing"] & ~stn["stick"]).sum())
        for h in (2e-3, 1.3e-3):
            An = system.band_system_matrix(q, v, stn, h, dense=True)
            Ac = k.matrix(q, v, anchors, h)
            assert np.max(np.abs(Ac - An)) <= 1e-10 * np.max(np.abs(An))
            # and the band LU solves it like LAPACK's dense LU
            b = rng.normal(size=An.shape[0])
            x, info = k.solve(An, b)
            assert info == 0
            xr = np.linalg.solve(An, b)
            assert np.max(np.abs(x - xr)) <= 1e-9 * np.max(np.abs(xr))
    if system.cb.size:
        # the random states exercised touching, sticking and sliding contacts
        assert seen["inside"] > 0 and seen["stick"] > 0 and seen["slide"] > 0, seen


@pytest.mark.parametrize("label,system", systems(), ids=lambda x: x if isinstance(x, str) else "")
def test_ledger_terms_match_numpy(label, system):
    """The energy ledger's per-step terms in the kernel (``Kernel.actuation_jump``, ``Kernel.contact_damping``)
    against the numpy code they replace on the compiled path (``Simulator._actuation_jump`` on the numpy path,
    ``PlanarSystem.dissipation_power``'s contact part over a step): points staying in, entering and leaving the
    floor, sticking and sliding; an actuation that turns the rest angles and, separately, moves the pins."""
    lib = lib_or_skip()
    k = fastkernel.Kernel(lib, system, fastkernel.layout_for(system, band_max=64))
    rng = np.random.default_rng(11)
    sim = Simulator(system, np.zeros((system.n, 3)))
    sim.kernel = "numpy"
    cases = {"stay": 0, "enter": 0, "leave": 0}
    states = list(random_states(system, rng, 24))
    for (q0, v0, _), (q, v, anchors) in zip(states[:-1], states[1:]):
        for dt in (1e-3, 2.5e-4):
            _, pn = system.dissipation_power(q, v, anchors, dt, q_start=q0, v_start=v0, hinges=False)
            pk = k.contact_damping(q, v, q0, v0, anchors, dt)
            assert pk == pytest.approx(pn, rel=1e-12, abs=1e-14 * (1 + abs(pn)))
        if system.cb.size:
            py0, py = system.contact_points(q0)[:, 1], system.contact_points(q)[:, 1]
            cases["stay"] += int(np.sum((py0 < 0) & (py < 0)))
            cases["enter"] += int(np.sum((py0 >= 0) & (py < 0)))
            cases["leave"] += int(np.sum((py0 < 0) & (py >= 0)))
        old = (system.theta0.copy(), system.ra.copy(), system.rb.copy())
        for moved in ("theta0", "pins"):
            if moved == "theta0":
                system.theta0[:] = old[0] + rng.normal(0, 0.1, old[0].shape)
            else:
                system.ra[:] = old[1] * (1 + rng.normal(0, 0.05, old[1].shape))
                system.rb[:] = old[2] + rng.normal(0, 1e-3, old[2].shape)
            wn, wk = sim._actuation_jump(q, old), k.actuation_jump(q, old)
            assert wk == pytest.approx(wn, rel=1e-10, abs=1e-14)
            system.theta0[:], system.ra[:], system.rb[:] = old
        assert k.actuation_jump(q, old) == 0.0            # nothing moved: nothing booked
    if system.cb.size:
        assert all(cases.values()), cases


def _run(sc, seconds, kernel, dt=None, perturb=0.0):
    cfg = dynamics_config(sc)
    model = build(sc, cfg)
    sim = Simulator(model.system, model.q0 * (1.0 + perturb), actuate=model.actuate)
    sim.energy_scale = float(model.system.mass.sum() * 9.81 * 0.05)
    sim.kernel = kernel
    sim.run(seconds, method="implicit", dt=dt or cfg["integrator"]["dt_s"])
    return sim


COUNTS = ("steps", "force_evaluations", "jacobians", "newton_iterations", "newton_unconverged_steps")


@pytest.mark.parametrize("name,seconds", [("belt8.json", 0.6), ("worm_crawl.json", 0.3), ("belt1000.json", 0.04)])
def test_short_trajectory_matches_numpy_path(name, seconds):
    """Same counts; states equal to round-off. Stick-slip friction amplifies round-off (the numpy
    path itself, started 1e-15 relative away, drifts by 1e-7 m on the worm within 0.2 s), so the
    bound is 1e-9 of the model size or, where that amplification dominates, the numpy path's own
    spread under a 1e-15 relative perturbation of the start."""
    lib_or_skip()
    sc = scene(name)
    a = _run(sc, seconds, "numpy")
    b = _run(sc, seconds, "c")
    assert a.stats["kernel"] == "numpy" and b.stats["kernel"] == "c"
    for key in COUNTS:
        assert a.stats.get(key, 0) == b.stats.get(key, 0), key
    L = max(float(np.max(np.ptp(a.q[:, :2], axis=0))), 1e-3)
    c = _run(sc, seconds, "numpy", perturb=1e-15)
    dq = float(np.max(np.abs(b.q - a.q)))
    assert dq <= max(1e-9 * L, 10 * float(np.max(np.abs(c.q - a.q)))), dq
    assert np.array_equal(a.inside, b.inside)
    assert np.allclose(b.anchors, a.anchors, rtol=0, atol=max(10 * dq, 1e-12))
    for key in ("actuator_work_J", "damping_J", "contact_damping_J", "friction_J"):
        spread = abs(c.ledger[key] - a.ledger[key])
        assert abs(b.ledger[key] - a.ledger[key]) <= max(1e-9 * abs(a.ledger[key]), 10 * spread, 1e-15), key
    pa, pb, pc = (x.stats["max_penetration_mm"] for x in (a, b, c))
    assert abs(pb - pa) <= max(1e-9 * pa, 10 * abs(pc - pa))


@pytest.mark.parametrize("band_max", [64, -1], ids=["rcm-band", "full-band"])
def test_fixed_dofs_and_restart_match_numpy(band_max):
    """A pivot (fixed body), contacts and a change of dt (backward Euler restart)."""
    lib_or_skip()
    out = []
    for kernel in ("numpy", "c"):
        s = pendulum_on_floor()
        s.band_max = band_max
        q0 = np.array([[0, 0, 0], [0.2, -0.35, 0.5], [0.3, 0.005, 0.1]])
        sim = Simulator(s, q0)
        sim.kernel = kernel
        sim.run(0.3, method="implicit", dt=2e-3)
        sim.run(0.5, method="implicit", dt=1e-3)
        out.append(sim)
    a, b = out
    assert b.stats["kernel"] == "c"
    for key in COUNTS:
        assert a.stats.get(key, 0) == b.stats.get(key, 0), key
    assert np.max(np.abs(a.q - b.q)) < 1e-10
    assert np.all(b.q[0] == 0.0) and np.all(b.v[0] == 0.0)


def test_fallback_without_compiler_gives_the_numpy_results(monkeypatch, tmp_path):
    sc = scene("belt8.json")
    ref = _run(sc, 0.3, "numpy")
    monkeypatch.setenv("PATH", str(tmp_path))          # no cc / gcc on PATH
    monkeypatch.delenv("CC", raising=False)
    monkeypatch.setenv("METAMATERIAL_CACHE_DIR", str(tmp_path))
    fastkernel.reset()
    try:
        assert fastkernel.load() is None
        assert "no C compiler" in fastkernel.note()
        sim = _run(sc, 0.3, "auto")
        assert sim.stats["kernel"] == "numpy"
        assert "no C compiler" in sim.stats["kernel_note"]
        # the numpy path (a process's first run can differ from later ones in the last bit)
        assert np.allclose(sim.q, ref.q, rtol=0, atol=1e-12) and np.allclose(sim.v, ref.v, rtol=0, atol=1e-9)
        for key in COUNTS:
            assert sim.stats.get(key, 0) == ref.stats.get(key, 0)
        with pytest.raises(DynamicsError, match="compiled dynamics kernel requested"):
            _run(sc, 0.01, "c")
        # the simulate() summary reports the fallback
        summary, *_ = simulate(sc, 0.05)
        assert summary["integrator"]["kernel"] == "numpy"
    finally:
        fastkernel.reset()


def test_environment_switch_forces_numpy(monkeypatch):
    monkeypatch.setenv(fastkernel.ENV_SWITCH, "numpy")
    fastkernel.reset()
    try:
        sim = _run(scene("worm_crawl.json"), 0.05, "auto")
        assert sim.stats["kernel"] == "numpy"
        assert fastkernel.ENV_SWITCH in sim.stats["kernel_note"]
    finally:
        monkeypatch.delenv(fastkernel.ENV_SWITCH)
        fastkernel.reset()


def test_kernel_builds_into_an_empty_cache_dir(monkeypatch, tmp_path):
    """The first use compiles the C source into the per-user cache (what CI does on a fresh machine)."""
    if fastkernel._compiler() is None:
        pytest.skip("no C compiler")
    monkeypatch.setenv("METAMATERIAL_CACHE_DIR", str(tmp_path))
    fastkernel.reset()
    try:
        assert fastkernel.load() is not None, fastkernel.note()
        built = [f for f in os.listdir(tmp_path) if f.startswith("dynkernel-") and f.endswith(".so")]
        assert len(built) == 1
        sim = _run(scene("belt8.json"), 0.05, "auto")
        assert sim.stats["kernel"] == "c"
    finally:
        fastkernel.reset()


def test_singular_matrix_is_reported_not_hidden():
    """A zero pivot gives non-finite values (as the numpy path), which the run's checks catch."""
    lib = lib_or_skip()
    s = pendulum_on_floor()
    k = fastkernel.Kernel(lib, s, fastkernel.layout_for(s))
    A = np.eye(9)
    A[4, 4] = 0.0
    A[4, 3] = 0.0
    x, info = k.solve(A, np.ones(9))
    assert info > 0                            # LAPACK's convention: the (1-based) zero pivot
    assert not np.all(np.isfinite(x)), x       # and the solution says so, as numpy's would
    with np.errstate(divide="ignore", invalid="ignore"):
        try:
            ref = np.linalg.solve(A, np.ones(9))
        except np.linalg.LinAlgError:          # numpy refuses outright: no finite answer exists either
            ref = None
    assert ref is None or not np.all(np.isfinite(ref))


def test_contact_flags_frozen_from_the_first_iteration_run():
    """``Simulator.freeze_after = 0`` (an experimental Newton option, numpy path): the first iteration has no
    earlier contact state to keep, so it evaluates its own (it raised UnboundLocalError on ``st_last`` before)."""
    sc = scene("worm_crawl.json")
    cfg = dynamics_config(sc)
    model = build(sc, cfg)
    sim = Simulator(model.system, model.q0, actuate=model.actuate)
    sim.freeze_after = 0
    sim.run(0.01, method="implicit", dt=cfg["integrator"]["dt_s"])
    assert sim.stats["kernel"] == "numpy" and sim.stats["steps"] == 40 and np.all(np.isfinite(sim.q))


def _run_burst(name, seconds, burst, actuate=None, **kw):
    sc = scene(name)
    cfg = dynamics_config(sc)
    model = build(sc, cfg)
    sim = Simulator(model.system, model.q0, actuate=actuate(model) if actuate else model.actuate)
    sim.energy_scale = float(model.system.mass.sum() * 9.81 * 0.05)
    sim.kernel = "c"
    sim.burst = burst
    frames = []
    sim.run(seconds, method="implicit", dt=cfg["integrator"]["dt_s"], record_dt=seconds / 7,
            on_record=lambda S: frames.append((S.t, S.q.copy(), S.v.copy(), S.anchors.copy(), S.inside.copy(),
                                               dict(S.ledger))), **kw)
    return sim, frames


def _assert_same_run(a, b):
    """Bitwise the same trajectory, ledger and counts; the centre of mass's extremes (summed in C in the burst, by
    numpy's dot product step by step) to round-off."""
    (sa, fa), (sb, fb) = a, b
    assert sa.stats["kernel"] == sb.stats["kernel"] == "c"
    for key in COUNTS + ("bdf2_steps", "max_penetration_mm", "rejected_checks"):
        assert sa.stats.get(key, 0) == sb.stats.get(key, 0), key
    for key in ("com_x_min_m", "com_x_max_m"):
        assert sb.stats[key] == pytest.approx(sa.stats[key], rel=1e-13, abs=1e-15), key
    assert sa.t == sb.t
    for x, y in ((sa.q, sb.q), (sa.v, sb.v), (sa.anchors, sb.anchors), (sa.inside, sb.inside)):
        assert np.array_equal(x, y)
    assert sa.ledger == sb.ledger
    assert len(fa) == len(fb)
    for x, y in zip(fa, fb):
        assert x[0] == y[0] and x[5] == y[5]
        assert all(np.array_equal(p, r) for p, r in zip(x[1:5], y[1:5]))


@pytest.mark.parametrize("name,seconds", [("worm_crawl.json", 0.3), ("belt8.json", 0.6), ("belt1000.json", 0.04)])
def test_one_call_per_step_matches_step_implicit(name, seconds):
    """``Simulator._burst`` (mm_step: the whole implicit step in one C call, run's default) against the same run
    through ``step_implicit`` step by step (``Simulator.burst = False``): the same states at every recorded frame,
    ledger and counts, bit for bit."""
    lib_or_skip()
    _assert_same_run(_run_burst(name, seconds, False), _run_burst(name, seconds, True))


def test_one_call_per_step_with_an_actuator_that_replaces_arrays():
    """An actuator that, now and then, replaces an array the kernel reads (``theta0``) instead of writing into it:
    that step falls back to the numpy path and the next one rebinds the kernel, as step by step."""
    lib_or_skip()

    def replacing(model):
        inner = model.actuate

        def act(t, sim):
            inner(t, sim)
            if int(round(t / 2.5e-4)) % 37 == 0:
                sim.sys.theta0 = sim.sys.theta0.copy()
        return act
    a = _run_burst("worm_crawl.json", 0.1, False, actuate=replacing)
    b = _run_burst("worm_crawl.json", 0.1, True, actuate=replacing)
    _assert_same_run(a, b)
    assert b[0].stats["steps"] == 400


def test_one_call_per_step_keeps_the_step_limit():
    """The step limit counts the steps of earlier runs too; the burst stops at the same step as step by step."""
    lib_or_skip()
    out = []
    for burst in (False, True):
        sim, _ = _run_burst("belt8.json", 0.0, burst)
        sim.run(0.1, method="implicit", dt=1e-3)                                  # 100 steps
        with pytest.raises(DynamicsError, match="more than 130 steps"):
            sim.run(0.26, method="implicit", dt=2e-3, max_steps=130)              # 0.26 s / 2 ms = 130: allowed
        out.append(sim)
    assert out[0].stats["steps"] == out[1].stats["steps"] == 131
    assert np.array_equal(out[0].q, out[1].q) and out[0].ledger == out[1].ledger


def test_one_call_per_step_books_the_steps_before_an_actuator_error():
    """An actuator that raises mid-burst: the steps taken before it are counted and booked, as step by step."""
    lib_or_skip()

    def failing(model):
        inner = model.actuate

        def act(t, sim):
            if t > 0.0301:
                raise RuntimeError("sensor lost")
            inner(t, sim)
        return act
    out = []
    for burst in (False, True):
        sc = scene("worm_crawl.json")
        model = build(sc, dynamics_config(sc))
        sim = Simulator(model.system, model.q0, actuate=failing(model))
        sim.kernel, sim.burst = "c", burst
        with pytest.raises(RuntimeError, match="sensor lost"):
            sim.run(0.1, method="implicit", dt=2.5e-4)
        out.append(sim)
    a, b = out
    assert a.stats["steps"] == b.stats["steps"] == 120
    assert a.ledger == b.ledger and np.array_equal(a.q, b.q)
    assert a.stats["force_evaluations"] == b.stats["force_evaluations"]
