"""Dynamics core against closed-form mechanics: pendulum, free fall, energy, contact, friction cone."""
import math

import numpy as np
import pytest
from scipy.special import ellipk

from metamaterial_wb.core.dynamics import PlanarSystem, Simulator

G = 9.81


def pendulum(L=0.4, m=0.2, I=1e-3, kp=2e4, cr=0.0, cp=0.0):
    s = PlanarSystem([1.0, m], [1.0, I], fixed=[True, False], gravity=(0.0, -G))
    s.set_hinges([0], [1], [[0.0, 0.0]], [[0.0, L]], kp=kp, cp=cp, kr=0.0, cr=cr)
    return s


def start(L, th0):
    return np.array([[0, 0, 0], [L * math.sin(th0), -L * math.cos(th0), th0]])


def angle(sim):
    return math.atan2(sim.q[1, 0], -sim.q[1, 1])


def crossings(ts, xs):
    ts, xs = np.asarray(ts), np.asarray(xs)
    k = np.flatnonzero((xs[:-1] > 0) & (xs[1:] <= 0))
    return ts[k] + (ts[k + 1] - ts[k]) * xs[k] / (xs[k] - xs[k + 1])


@pytest.mark.parametrize("method,dt", [("symplectic", None), ("implicit", 5e-4)])
def test_pendulum_period_matches_elliptic_integral(method, dt):
    L, m, I, th0 = 0.4, 0.2, 1e-3, 0.6
    sim = Simulator(pendulum(L, m, I), start(L, th0))
    ts, xs = [], []
    sim.run(3.0, method=method, dt=dt, record_dt=1e-3, on_record=lambda S: (ts.append(S.t), xs.append(angle(S))))
    # compound pendulum about the pivot: I_p = m L^2 + I; exact period 4 sqrt(I_p / (m g L)) K(sin^2(th0/2))
    Ip = m * L * L + I
    T = 4 * math.sqrt(Ip / (m * G * L)) * ellipk(math.sin(th0 / 2) ** 2)
    c = crossings(ts, xs)
    assert len(c) >= 3
    T_sim = np.mean(np.diff(c))
    assert abs(T_sim - T) / T < 5e-3, (T_sim, T)


def test_free_fall_and_projectile():
    s = PlanarSystem([0.1], [1e-4], gravity=(0.0, -G))
    q0 = np.array([[0.0, 2.0, 0.3]])
    v0 = np.array([[0.5, 1.0, 2.0]])
    for method, dt in (("symplectic", 1e-4), ("implicit", 1e-4)):
        sim = Simulator(s, q0, v0)
        sim.run(0.5, method=method, dt=dt)
        t = sim.t
        assert sim.q[0, 0] == pytest.approx(0.5 * t, rel=1e-9)
        assert sim.q[0, 1] == pytest.approx(2.0 + 1.0 * t - 0.5 * G * t * t, abs=5e-4)
        assert sim.q[0, 2] == pytest.approx(0.3 + 2.0 * t, rel=1e-9)


def test_energy_conserved_without_damping_no_drift():
    # double pendulum (chaotic) with stiff pins: total energy stays within a small band, no drift
    L, m, I = 0.3, 0.1, 5e-4
    s = PlanarSystem([1.0, m, m], [1.0, I, I], fixed=[True, False, False], gravity=(0.0, -G))
    s.set_hinges([0, 1], [1, 2], [[0, 0], [0, -L / 2]], [[0, L / 2], [0, L / 2]], kp=5e4, cp=0, kr=0, cr=0)
    th = 2.0
    q0 = np.array([[0, 0, 0], [L / 2 * math.sin(th), -L / 2 * math.cos(th), th],
                   [L * math.sin(th) + L / 2 * math.sin(th), -L * math.cos(th) - L / 2 * math.cos(th), th]])
    sim = Simulator(s, q0)
    E = []
    sim.run(4.0, method="symplectic", record_dt=0.01, on_record=lambda S: E.append(s.energy(S.q, S.v, S.anchors)["total_J"]))
    E = np.array(E)
    scale = m * G * L * 3
    assert np.max(np.abs(E - E[0])) < 0.02 * scale
    n = len(E) // 10
    assert abs(E[-n:].mean() - E[:n].mean()) < 0.003 * scale
    rep = sim.energy_report()
    assert abs(rep["numerical_J"]) < 0.02 * scale


def test_energy_decreases_monotonically_with_damping():
    L = 0.4
    s = pendulum(L=L, cr=0.02, cp=20.0)
    sim = Simulator(s, start(L, 1.0))
    E = []
    sim.run(3.0, method="symplectic", record_dt=0.005, on_record=lambda S: E.append(s.energy(S.q, S.v, S.anchors)["total_J"]))
    E = np.array(E)
    assert np.all(np.diff(E) < 1e-4 * abs(E[0]))
    assert E[-1] < E[0] - 0.1 * s.mass[1] * G * L       # it really lost energy
    rep = sim.energy_report()
    assert rep["damping_dissipated_J"] > 0
    # the ledger closes: what is lost is what the damper dissipated (first-order accurate)
    assert abs(rep["numerical_J"]) < 0.05 * rep["damping_dissipated_J"]


def block(mu, incline_deg, kn=2e4, m=0.1):
    a = math.radians(incline_deg)
    s = PlanarSystem([m], [m * (0.04 ** 2 + 0.02 ** 2) / 12], gravity=(-G * math.sin(a), -G * math.cos(a)))
    cn = 2 * 0.7 * math.sqrt(kn * m / 2)
    s.set_contacts([0, 0], [[-0.02, -0.01], [0.02, -0.01]], mu, kn, cn, kn, cn)
    return s


def test_contact_rest_penetration_within_tolerance():
    m, kn = 0.1, 2e4
    s = block(0.5, 0.0, kn, m)
    sim = Simulator(s, np.array([[0.0, 0.015, 0.0]]))
    sim.run(1.0, method="symplectic")
    pen = -(sim.q[0, 1] - 0.01)
    static = m * G / (2 * kn)                # two points share the weight
    assert pen == pytest.approx(static, rel=0.02)
    assert abs(sim.v[0, 1]) < 1e-3
    # the 5 mm drop does not punch through: penetration stays below the undamped energy bound
    v_imp = math.sqrt(2 * G * 0.005)
    bound = static + math.sqrt(static ** 2 + (v_imp ** 2) * m / (2 * kn))
    assert static < sim.stats["max_penetration_mm"] * 1e-3 < bound


@pytest.mark.parametrize("method", ["symplectic", "implicit"])
def test_friction_cone_stick_and_slide(method):
    mu = 0.5                                 # atan(0.5) = 26.6 deg
    a_stick, a_slide = 20.0, 35.0
    s = block(mu, a_stick)
    q0 = np.array([[0.0, 0.01 - 0.1 * 9.81 / (2 * 2e4), 0.0]])
    sim = Simulator(s, q0)
    sim.run(1.0, method=method, dt=None if method == "symplectic" else 1e-3)
    assert abs(sim.q[0, 0]) < 1e-4           # sticks (only the elastic bristle deflection)
    s = block(mu, a_slide)
    sim = Simulator(s, q0)
    x0 = sim.q[0, 0]
    sim.run(1.0, method=method, dt=None if method == "symplectic" else 1e-3)
    a = math.radians(a_slide)
    acc = G * (math.sin(a) - mu * math.cos(a))
    assert sim.q[0, 0] - x0 == pytest.approx(-0.5 * acc * 1.0, rel=0.03)   # slides down (-x)
    assert sim.ledger["friction_J"] > 0


def test_stiff_hinges_do_not_blow_up_the_implicit_integrator():
    # a chain of 20 bodies with pins 1e9 N/m and bending 1e3 N m/rad: omega ~ 1e6 rad/s
    n = 20
    s = PlanarSystem(np.full(n, 0.01), np.full(n, 1e-6), fixed=[True] + [False] * (n - 1), gravity=(0, -G))
    s.set_hinges(np.arange(n - 1), np.arange(1, n), np.tile([0.005, 0], (n - 1, 1)),
                 np.tile([-0.005, 0], (n - 1, 1)), kp=1e9, cp=0.0, kr=1e3, cr=0.0)
    q0 = np.column_stack([np.arange(n) * 0.01, np.zeros(n), np.zeros(n)])
    sim = Simulator(s, q0)
    assert sim.dt_limit < 1e-5               # explicit would need < 10 us
    sim.run(0.5, method="implicit", dt=5e-3)
    assert np.all(np.isfinite(sim.q))
    assert not sim.stats["fallbacks"]
    rep = sim.energy_report()
    assert rep["final_J"] <= rep["initial_J"] + 1e-9       # implicit Euler only removes energy
    # an explicit step far above the stability limit is refused (reduced to the guard) ...
    sim2 = Simulator(s, q0)
    sim2.run(1e-3, method="symplectic", dt=1e-3)
    assert sim2.stats["dt_s"] <= sim2.dt_guard and "exceeds" in sim2.stats["note"]
    assert np.all(np.isfinite(sim2.q))


@pytest.mark.filterwarnings("ignore::RuntimeWarning")     # the sabotaged explicit run overflows on purpose
def test_explicit_instability_is_caught_and_falls_back():
    n = 10
    s = PlanarSystem(np.full(n, 0.01), np.full(n, 1e-6), fixed=[True] + [False] * (n - 1), gravity=(0, -G))
    s.set_hinges(np.arange(n - 1), np.arange(1, n), np.tile([0.005, 0], (n - 1, 1)),
                 np.tile([-0.005, 0], (n - 1, 1)), kp=1e6, cp=0.0, kr=10.0, cr=0.0)
    q0 = np.column_stack([np.arange(n) * 0.01, np.zeros(n), np.zeros(n)])
    sim = Simulator(s, q0)
    sim.dt_limit = sim.dt_guard = 10 * sim.dt_limit    # sabotage the guard: 5x above the real limit
    sim.run(0.3, method="symplectic")
    assert sim.stats["fallbacks"], "the blow-up went unnoticed"
    assert sim.stats["method"] == "symplectic->implicit"
    assert np.all(np.isfinite(sim.q)) and np.max(np.abs(sim.v)) < 10


def test_analytic_jacobian_matches_finite_differences():
    # hinges with offsets and rest angles, one contact sticking, one slipping, one in the air
    rng = np.random.default_rng(0)
    n = 4
    s = PlanarSystem(rng.uniform(0.1, 1, n), rng.uniform(0.01, 0.1, n), gravity=(0.3, -9.8))
    s.set_hinges([0, 1, 2], [1, 2, 3], rng.normal(size=(3, 2)) * 0.1, rng.normal(size=(3, 2)) * 0.1,
                 kp=rng.uniform(10, 100, 3), cp=rng.uniform(0.1, 1, 3), kr=rng.uniform(1, 5, 3),
                 cr=rng.uniform(0.1, 1, 3), theta0=rng.normal(size=3))
    s.set_contacts([0, 1, 2, 3], [[0, -0.05], [0.02, -0.05], [0, -0.05], [0, -0.05]], 0.5, 1e3, 5.0, 1e3, 5.0)
    q = np.column_stack([rng.normal(size=n) * 0.1, [-0.01, -0.02, 0.2, -0.03], rng.normal(size=n) * 0.3])
    v = rng.normal(size=(n, 3))
    anc = s.contact_points(q)[:, 0] + np.array([0.001, -0.5, 0.0, 0.0])
    Q, st = s.forces(q, v, anc)
    assert st["stick"][0] and not st["stick"][1] and not st["inside"][2]
    A, K = s.system_matrix(q, v, anc, st, 1.0, dense=True)
    C = np.diag(s.M.ravel()) - A - K            # A = M - dt C - dt^2 K with dt = 1
    eps = 1e-7
    Kfd = np.zeros((3 * n, 3 * n))
    Cfd = np.zeros((3 * n, 3 * n))
    for j in range(3 * n):
        d = np.zeros(3 * n)
        d[j] = eps
        d = d.reshape(n, 3)
        Kfd[:, j] = (s.forces(q + d, v, anc)[0] - s.forces(q - d, v, anc)[0]).ravel() / (2 * eps)
        Cfd[:, j] = (s.forces(q, v + d, anc)[0] - s.forces(q, v - d, anc)[0]).ravel() / (2 * eps)
    assert np.abs(K - Kfd).max() < 1e-5 * np.abs(Kfd).max()
    assert np.abs(C - Cfd).max() < 1e-5 * np.abs(Cfd).max()



@pytest.mark.parametrize("method,dt,t_end,steps", [("symplectic", 1e-4, 30.0, 300000), ("implicit", 2e-3, 100.0, 50000),
                                                   ("symplectic", 7e-5, 10.0, 142858)])
def test_a_run_takes_exactly_its_steps_and_ends_at_t_end(method, dt, t_end, steps):
    """Time was accumulated by addition: after 300 000 steps of 0.1 ms (or 50 000 of 2 ms) the round-off left t short
    of t_end by ~1e-11 s and the run took one more step of that size (a force evaluation, a Newton solve and a frame
    for nothing). The step that reaches t_end within round-off now ends there: t_end / dt steps (rounded up when
    dt does not divide t_end: 10 s at 70 us is 142 857 steps and a shorter last one), ending at t_end exactly."""
    s = PlanarSystem([0.1], [1e-4], gravity=(0.0, 0.0))
    sim = Simulator(s, np.array([[0.0, 2.0, 0.0]]), np.array([[0.01, 0.0, 0.0]]))
    times = []
    sim.run(t_end, method=method, dt=dt, record_dt=0.5, on_record=lambda sm: times.append(sm.t))
    assert sim.stats["steps"] == steps
    assert sim.t == t_end
    assert times[-1] == t_end and len(times) == round(t_end / 0.5) + 1
    assert sim.q[0, 0] == pytest.approx(0.01 * t_end, rel=1e-9)
