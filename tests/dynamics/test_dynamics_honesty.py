"""Issue 18, item 5: the dynamics tell when they are not to be trusted.

Settled initial states, contact damping in the energy ledger, the summary of the accepted attempt
only, a warning when the integrator creates energy, and a dt study that flags a step-dependent
answer."""
import math

import numpy as np
import pytest

from metamaterial_wb import example_path
from metamaterial_wb.core.dynamics import PlanarSystem, Simulator
from metamaterial_wb.core.dynamics.builders import build, dynamics_config
from metamaterial_wb.core.dynamics.simulate import convergence_warnings, simulate
from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.core.scene import Scene

G = 9.81


def damped_block(m=0.1, kn=2e4):
    s = PlanarSystem([m], [m * (0.04 ** 2 + 0.02 ** 2) / 12], gravity=(0, -G))
    cn = 2 * 0.7 * math.sqrt(kn * m / 2)
    s.set_contacts([0, 0], [[-0.02, -0.01], [0.02, -0.01]], 0.5, kn, cn, kn, cn)
    return s


@pytest.mark.parametrize("method,dt,tol", [("implicit", 1e-5, 0.05), ("symplectic", None, 0.2),
                                            ("implicit", 1e-3, 0.25)])
def test_contact_damping_is_booked_and_the_ledger_closes(method, dt, tol):
    """A block dropped 5 mm onto damped contacts: the loss is the contact dampers' (no hinge, little
    slip); before, all of it landed in ``numerical_J``. At a coarse implicit step (a tenth of the
    contact period) the booking must not overshoot either (an end-of-step estimate booked 3.5x the
    loss: impacts start mid-step)."""
    sim = Simulator(damped_block(), np.array([[0.0, 0.015, 0.1]]), v0=np.array([[0.05, 0.0, 0.0]]))
    sim.run(0.15, method=method, dt=dt)
    e = sim.energy_report()
    lost = e["initial_J"] - e["final_J"]
    assert lost > 1e-3
    assert e["contact_damping_dissipated_J"] > 0.5 * lost
    assert abs(e["numerical_J"]) < tol * lost


def test_summary_reports_the_accepted_attempt_only():
    """A sabotaged explicit step blows up on landing and the run falls back; the reported
    penetration is the accepted trajectory's (below the drop's energy bound), the discarded
    attempt's is kept apart."""
    m, kn = 0.1, 2e4
    sim = Simulator(damped_block(m, kn), np.array([[0.0, 0.015, 0.0]]))
    sim.dt_limit = sim.dt_guard = 8 * sim.dt_limit
    sim.run(0.5, method="symplectic")
    assert sim.stats["fallbacks"]
    static = m * G / (2 * kn)
    bound = static + math.sqrt(static ** 2 + 2 * G * 0.005 * m / (2 * kn))
    assert sim.stats["max_penetration_mm"] * 1e-3 < bound
    assert sim.stats["discarded_max_penetration_mm"] * 1e-3 > bound


def test_energy_created_by_the_integrator_is_a_warning():
    """The ledger's residual is numerical only once every physical loss is booked: a negative one
    (energy created, e.g. the explicit integrator gaining 26 % on contacts) beyond 5 % of the energy
    turnover is a warning, a balanced ledger is not."""
    e = {"initial_J": 1.0, "final_J": 1.26, "actuator_work_J": 0.0, "damping_dissipated_J": 0.0,
         "friction_dissipated_J": 0.0, "contact_damping_dissipated_J": 0.0, "numerical_J": -0.26}
    w = convergence_warnings(e, scale_J=1.0)
    assert len(w) == 1 and "created 0.26 J" in w[0] and "26 %" in w[0]
    assert convergence_warnings(dict(e, numerical_J=-0.01), scale_J=1.0) == []
    # a real run: the damped block's ledger closes, no warning
    sim = Simulator(damped_block(), np.array([[0.0, 0.015, 0.0]]))
    sim.run(0.3, method="implicit", dt=1e-4)
    assert convergence_warnings(sim.energy_report(), 0.1 * G * 0.05) == []


def test_explicit_integrator_on_undamped_contacts_closes_the_ledger_at_its_guard():
    """Issue 18's "symplectic integrator gains 26 % energy with contacts, unflagged", in a run we can afford:
    a block bouncing on undamped penalty contacts (nothing dissipates but slip). At the guard step (contacts
    included in the guard) the explicit integrator creates no energy: it ends below its initial energy, the
    residual is a loss and nothing is flagged. (Beyond the guard the outcome of this bouncing is chaotic, see
    docs/dynamics.md "Honesty": energy created in 10 of 24 runs at 1.5-1.9x the guard, flagged where it exceeds
    5 % of the turnover; the 26 % case itself was not reproduced.)"""
    s = damped_block()
    s.set_contacts([0, 0], [[-0.02, -0.01], [0.02, -0.01]], 0.5, 2e4, 0.0, 2e4, 0.0)   # undamped
    sim = Simulator(s, np.array([[0.0, 0.015, 0.1]]), v0=np.array([[0.05, 0.0, 0.0]]))
    sim.run(1.0, method="symplectic")
    assert not sim.stats["fallbacks"] and sim.stats["dt_s"] == pytest.approx(sim.dt_guard)
    e = sim.energy_report()
    assert e["final_J"] < e["initial_J"] and e["numerical_J"] > 0
    assert e["friction_dissipated_J"] > 0 and e["contact_damping_dissipated_J"] == 0.0
    assert convergence_warnings(e, 0.1 * G * 0.05) == []


def test_reverse_worm_starts_from_a_static_equilibrium():
    """The profile starts at -0.8 while the bodies are built at D = 0: as built the worm starts with
    9.7 J of elastic energy; settled it starts at rest in equilibrium (forces balance)."""
    scene = Scene.load(example_path("worm_crawl_reverse"))
    cfg = dynamics_config(scene)
    assert cfg["initial_state"] == "settled"
    model = build(scene, cfg)
    sim = Simulator(model.system, model.q0, actuate=model.actuate)
    assert sim.E0 > 1.0                                   # the as-built jump
    info = sim.settle()
    assert sim.E0 < 0.05 and info["residual_m"] < 1e-8
    Q, _ = model.system.forces(sim.q, np.zeros_like(sim.q), sim.anchors)
    weight = float(model.system.mass.sum()) * G
    assert np.max(np.abs(Q[:, :2])) < 1e-4 * weight
    s, *_ = simulate(scene, 0.2)
    assert s["initial_state"]["kind"] == "settled" and s["energy"]["initial_J"] < 0.05
    assert abs(s["energy"]["numerical_J"]) < 1.0          # was 10 J: the jump landed in "numerical"


def test_dt_study_flags_the_coarse_worm():
    """At 10 ms the worm crawls about half as far as at 5 ms; the dt study says so (at its default step,
    0.25 ms since issue 18, it does not)."""
    scene = Scene.load(example_path("worm_crawl"))
    coarse, *_ = simulate(scene, 2.0, dt=0.01, dt_check=True)
    assert coarse["dt_study"]["converged"] is False
    assert any("dt study" in w for w in coarse["warnings"])
    fine, *_ = simulate(scene, 1.0, dt_check=True)       # 1 s: the default step is small since issue 18
    assert fine["dt_study"]["converged"] is True and not any("dt study" in w for w in fine["warnings"])


def test_bad_initial_state_is_named():
    scene = Scene.load(example_path("worm_crawl"))
    scene.extra["dynamics"] = dict(scene.extra.get("dynamics", {}), initial_state="resting")
    with pytest.raises(SceneError, match="initial_state"):
        dynamics_config(scene)


def test_belt1000_starts_settled_and_stays_at_rest():
    """``examples/belt1000.json`` starts from its static equilibrium under gravity (a tank-tread shape
    well below the 318 mm circle) and, with the gait off, stays at rest; released as a circle it
    is still moving after the same time (it sloshes for more than 12 s, docs/dynamics.md)."""
    import copy
    import json

    with open(example_path("belt1000")) as fh:
        base = json.load(fh)
    assert base["dynamics"]["initial_state"] == "settled"
    ke = {}
    for init in ("settled", "as_built"):
        d = copy.deepcopy(base)
        d["dynamics"]["gait"] = {"type": "none"}
        d["dynamics"]["initial_state"] = init
        scene = Scene.from_dict(d)
        cfg = dynamics_config(scene)
        model = build(scene, cfg)
        sim = Simulator(model.system, model.q0, actuate=model.actuate)
        if init == "settled":
            info = sim.settle()
            assert info["residual_m"] < 1e-8
            assert 0.10 < sim.q[:, 1].max() < 0.2         # flattened (the circle is 0.318 m high)
        sim.run(0.2, method="implicit", dt=2e-3)
        ke[init] = 0.5 * float(np.sum(model.system.M * sim.v * sim.v))
    assert ke["settled"] < 1e-12
    assert ke["as_built"] > 1e-4


def test_settle_does_not_run_away_on_the_eight_cell_belt():
    """Regression: a relaxation with a fixed growing step diverged on belt8 (bodies thrown by 6e9 mm);
    accepted steps must converge and lower the potential energy, so it ends in an equilibrium."""
    scene = Scene.load(example_path("belt8"))
    cfg = dynamics_config(scene)
    model = build(scene, cfg)
    sim = Simulator(model.system, model.q0, actuate=model.actuate)
    E_built = sim.E0
    info = sim.settle()
    assert info["residual_m"] < 1e-8 and sim.E0 < E_built
    Q, _ = model.system.forces(sim.q, np.zeros_like(sim.q), sim.anchors)
    assert np.max(np.abs(Q[:, :2])) < 1e-4 * float(model.system.mass.sum()) * G
    assert -1e-3 < model.system.contact_points(sim.q)[:, 1].min()      # resting on the floor, not through it


def test_actuator_work_does_not_depend_on_the_step_and_the_worm_ledger_closes():
    """Issue 18: at 1 ms 76 % of the worm's actuator work landed in "numerical". The ledger booked the
    servos' work as the elastic-energy jump at the step's start positions, which also counts
    ``kp (da)^2 / 2`` per step on the stiff pins (an O(dt) error, dissipated again by the integrator). With
    the trapezoidal booking the work is the same at 2 and 1 ms and the residual is below 5 % of it."""
    scene = Scene.load(example_path("worm_crawl"))
    W = {}
    for dt in (2e-3, 1e-3):
        s, *_ = simulate(scene, 2.0, dt=dt)
        e = s["energy"]
        W[dt] = e["actuator_work_J"]
        assert abs(e["numerical_J"]) < 0.05 * e["actuator_work_J"]
        assert not any("ledger" in w for w in s["warnings"])
    assert W[1e-3] == pytest.approx(W[2e-3], rel=0.01)     # was 0.70 vs 1.23 J over 10 s


def test_energy_lost_by_the_integrator_and_unconverged_newton_steps_are_warnings():
    """The residual is flagged in either sign (numerical dissipation too, not only energy created), and
    implicit steps accepted with Newton unconverged are reported."""
    e = {"initial_J": 1.0, "final_J": 0.5, "actuator_work_J": 1.0, "damping_dissipated_J": 0.4,
         "friction_dissipated_J": 0.0, "contact_damping_dissipated_J": 0.0, "numerical_J": 0.3}
    w = convergence_warnings(e, scale_J=0.01)
    assert len(w) == 1 and "dissipated 0.3 J" in w[0] and "30 %" in w[0]
    assert convergence_warnings(dict(e, numerical_J=0.04), scale_J=0.01) == []
    w = convergence_warnings(dict(e, numerical_J=0.0), 0.01, stats={"steps": 400, "newton_unconverged_steps": 3})
    assert len(w) == 1 and "3 of 400 implicit steps" in w[0]
    assert convergence_warnings(dict(e, numerical_J=0.0), 0.01, stats={"steps": 400}) == []


def test_dt_study_flags_the_worm_at_1ms():
    """The worm's regime change (docs/dynamics-fidelity.md, "worm"): at 1 ms the pads' chatter is damped
    out by the integrator and the worm crawls about 21 mm in 1.25 s, at 0.5 ms about 3 mm. The energy ledger
    closes in both (the chatter is a motion, not an energy error), so only the dt study can tell: it must."""
    scene = Scene.load(example_path("worm_crawl"))
    s, *_ = simulate(scene, 1.25, dt=1e-3, dt_check=True)
    a, b = s["dt_study"]["com_displacement_mm"]
    assert a > 15 and b < 8 and s["dt_study"]["converged"] is False
    assert any("dt study" in w for w in s["warnings"])
