"""High level: simulate a scene for some seconds and summarise (used by the CLI, tests, benchmarks)."""
from __future__ import annotations

import time

import numpy as np

from .builders import build, dynamics_config
from .integrators import Simulator


class Trajectory:
    def __init__(self):
        self.t = []
        self.q = []
        self.extra = []

    def arrays(self):
        return np.array(self.t), np.array(self.q)


DT_CHECK_WINDOW_S = 2.0      # the dt study's window (one worm cycle; four belt control periods ...)
DT_CHECK_TOL = 0.1           # change of the window's motion at dt / 2 that is "not converged": this
DT_CHECK_CELLS = 0.05        # fraction of its travel, and at least this fraction of a cell length
ENERGY_GAIN_TOL = 0.05       # energy created by the integrator, relative to the energy turnover


MAX_FRAMES = 1_000_000   # recorded trajectory frames of one run (size budget, issue 19)
MAX_POSES = 10_000_000   # recorded body poses (frames x bodies): ~400 bytes of memory and ~35 of trajectory.json each
MAX_STEPS = 20_000_000   # time steps of one run (size budget, issue 19): ~1e-5 s of wall time each at best; the command
#                          line and the GUI's background run (core.playback.run_dynamics) both use it (simulate()'s default)


def check_step_budget(seconds, dt, field="seconds", how=None, max_steps=MAX_STEPS):
    """Refuse, before any work, a run of ``seconds`` at the time step ``dt`` that takes more than ``max_steps``
    (default ``MAX_STEPS``) steps. The integrator may still take a smaller step (the automatic step, the symplectic
    guard): :meth:`Simulator.run` checks that one before its first step.

    Parameters
    ----------
    seconds : float
        Simulated time (s).
    dt : float
        Time step (s), > 0.
    field : str, optional
        What the error names (``--dt`` on the command line).
    how : str, optional
        How the run was asked for, for the message; default ``10 s / dt 0.001 s``.
    max_steps : int, optional
        The limit.

    Raises
    ------
    SceneError
        Over the budget; the message names the steps and the limit.
    """
    from ..errors import SceneError

    how = how or f"{seconds:g} s / dt {dt:g} s"
    steps = seconds / dt
    if steps > max_steps:
        raise SceneError(field, f"{how} asks for {steps:.3g} time steps; at most {max_steps} are allowed "
                                f"(the size budget)")


def check_output_budget(seconds, fps, bodies=None, field="seconds", how=None):
    """Refuse, before any work, a run that would record more than ``MAX_FRAMES`` frames or (``bodies`` given: the
    built model's body count) more than ``MAX_POSES`` body poses (frames x bodies). The command line and the GUI's
    background run (:func:`metamaterial_wb.core.playback.run_dynamics`) both pass here (:func:`simulate` checks).

    Parameters
    ----------
    seconds : float
        Simulated time (s).
    fps : float
        Recorded frames per second.
    bodies : int, optional
        Bodies of one frame.
    field : str, optional
        What the error names (``--fps`` on the command line).
    how : str, optional
        How the run was asked for, for the message (``--seconds 10 x --fps 30``); default ``10 s at 30 frames/s``.

    Raises
    ------
    SceneError
        Over the budget; the message names the frames, the bodies and the limit.
    """
    from ..errors import SceneError

    how = how or f"{seconds:g} s at {fps:g} frames/s"
    frames = seconds * fps
    if frames > MAX_FRAMES:
        raise SceneError(field, f"{how} asks for {frames:.3g} recorded frames; at most {MAX_FRAMES} are allowed "
                                f"(the size budget)")
    if bodies is not None and frames * bodies > MAX_POSES:
        raise SceneError(field, f"{how} x {bodies} bodies asks for {frames * bodies:.3g} recorded body poses "
                                f"({frames:.6g} frames; at most {MAX_POSES // max(bodies, 1)} frames for this scene); "
                                f"at most {MAX_POSES} are allowed (the size budget): shorten the run or record fewer "
                                f"frames per second")


def _start(scene, cfg, model, settle):
    sim = Simulator(model.system, model.q0, actuate=model.actuate)
    sim.default_implicit_dt = getattr(model, "default_dt", None) or sim.default_implicit_dt
    sim.energy_scale = float(model.system.mass.sum() * 9.81 * 0.05)
    info = None
    if settle and cfg["initial_state"] == "settled":
        info = sim.settle()
    return sim, info


def dt_study(scene, cfg, method, dt, window, settle=True):
    """The same run on a short window at ``dt`` and at ``dt / 2``: centre-of-mass travel of both and
    the largest body position difference at the window's end (mm)."""
    out = []
    for h in (dt, 0.5 * dt):
        model = build(scene, cfg)
        sim, _ = _start(scene, cfg, model, settle)
        c0 = model.com_x(sim.q)
        sim.run(window, method=method, dt=h)
        out.append((model.com_x(sim.q) - c0, sim.q.copy(), sim.stats["dt_s"]))
    (d1, q1, h1), (d2, q2, h2) = out
    diff = float(np.max(np.linalg.norm(q1[:, :2] - q2[:, :2], axis=1))) * 1e3
    travel = max(abs(d1), abs(d2)) * 1e3
    cell = cfg["belt"]["cell_length_mm"] if cfg["model"] == "belt" else scene.cell_size_mm
    tol = max(DT_CHECK_TOL * travel, DT_CHECK_CELLS * cell)
    return {"window_s": window, "dt_s": [h1, h2], "com_displacement_mm": [d1 * 1e3, d2 * 1e3],
            "com_difference_mm": abs(d1 - d2) * 1e3, "max_position_difference_mm": diff, "tolerance_mm": tol,
            "converged": bool(abs(d1 - d2) * 1e3 <= tol)}


def convergence_warnings(energy, scale_J, study=None, stats=None):
    """Sentences for the summary's ``warnings``: an energy ledger that does not close (energy created or
    lost by the integrator beyond ``ENERGY_GAIN_TOL`` of the energy turnover), implicit steps accepted
    with Newton's method unconverged (``stats``: the integrator statistics), a dt study that changed the
    answer."""
    out = []
    turnover = max(abs(energy["actuator_work_J"]), energy["damping_dissipated_J"] + energy["friction_dissipated_J"]
                   + energy.get("contact_damping_dissipated_J", 0.0), scale_J, 1e-12)
    num = energy["numerical_J"]
    implicit = stats is not None and str(stats.get("method", "")).split("->")[-1] == "implicit"
    if num < -ENERGY_GAIN_TOL * turnover:
        out.append(f"the energy ledger does not close: the integrator created {-num:.3g} J of "
                   f"energy ({-100 * num / turnover:.0f} % of the energy turnover {turnover:.3g} J; "
                   f"or the contacts' stick / slip is not resolved at this step): check with a smaller dt"
                   + ("" if implicit else " or the implicit integrator"))
    elif num > ENERGY_GAIN_TOL * turnover:
        out.append(f"the energy ledger does not close: the integrator dissipated {num:.3g} J that no damper or "
                   f"friction took ({100 * num / turnover:.0f} % of the energy turnover {turnover:.3g} J): the step "
                   f"damps motion the physics keeps; check with a smaller dt")
    if stats is not None and stats.get("newton_unconverged_steps", 0):
        n, steps = int(stats["newton_unconverged_steps"]), max(int(stats.get("steps", 0)), 1)
        out.append(f"{n} of {steps} implicit steps ({100.0 * n / steps:.2g} %) were accepted with Newton's method "
                   f"unconverged (the contacts' touching / sticking set kept changing between iterates): those "
                   f"steps do not solve their equations; a run at a smaller step tells whether that matters")
    if study is not None and not study["converged"]:
        a, b = study["com_displacement_mm"]
        out.append(f"dt study: over the first {study['window_s']:g} s the centre of mass travels {a:+.2f} mm at "
                   f"dt = {study['dt_s'][0]:.3g} s and {b:+.2f} mm at dt / 2: the answer depends on the step; "
                   f"use a smaller dt")
    return out


def simulate(scene, seconds, method=None, dt=None, record_dt=None, cfg=None, model=None, dt_check=False,
             max_steps=MAX_STEPS):
    """Run the scene's dynamics. Returns ``(summary dict, Trajectory, model, simulator)``.

    The bodies start at a static equilibrium under gravity and the actuators' values at t = 0 when
    ``dynamics.initial_state`` is ``"settled"`` (the default for sheets). ``dt_check``: also run the
    first ``DT_CHECK_WINDOW_S`` at dt / 2 and warn when the motion changes (``summary["dt_study"]``).
    ``max_steps``: the most time steps the run may take (default ``MAX_STEPS``, as the command line; a given
    ``dt`` or the scene's ``dt_s`` is checked before settling (:func:`check_step_budget`), the step the integrator
    chooses by ``StepBudgetError`` before the first step); more than
    ``MAX_FRAMES`` recorded frames or ``MAX_POSES`` recorded body poses are refused before any work
    (:func:`check_output_budget`)."""
    t_wall = time.perf_counter()
    cfg = cfg or dynamics_config(scene)
    model = model or build(scene, cfg)
    method = method or cfg["integrator"]["method"]
    if dt is None:
        dt = cfg["integrator"]["dt_s"]
    if record_dt is None:
        record_dt = max(seconds / 200.0, 1e-3)
    check_output_budget(seconds, 1.0 / record_dt, int(model.system.n))    # before settling / integrating
    if dt is not None and dt > 0:                                          # (a bad dt: the integrator says why)
        check_step_budget(seconds, dt, max_steps=max_steps)
    sim, settled = _start(scene, cfg, model, True)
    traj = Trajectory()

    def rec(S):
        traj.t.append(S.t)
        traj.q.append(S.q.copy())
        if model.kind == "belt":
            traj.extra.append(model.actuate.p.copy())

    t_build = time.perf_counter() - t_wall
    sim.run(seconds, method=method, dt=dt, record_dt=record_dt, on_record=rec, max_steps=max_steps)
    t, q = traj.arrays()
    com = np.array([model.com_x(qq) for qq in q])
    disp_mm = (com[-1] - com[0]) * 1e3
    summary = {
        "format": "metamaterial-simulation", "version": 1, "scene": scene.name, "model": model.kind,
        "seconds": seconds, "displacement_mm": disp_mm,
        "mean_speed_mm_s": disp_mm / seconds if seconds > 0 else 0.0,
        # over every step (the integrator's extremes), not only the recorded frames
        "min_com_displacement_mm": float((min(com.min(), sim.stats.get("com_x_min_m", com.min())) - com[0]) * 1e3),
        "max_com_displacement_mm": float((max(com.max(), sim.stats.get("com_x_max_m", com.max())) - com[0]) * 1e3),
        "energy": sim.energy_report(),
        "integrator": dict(sim.stats, build_s=t_build, realtime_factor=seconds / max(sim.stats["wall_s"], 1e-9)),
        "incline_deg": cfg["incline_deg"],
        "model_info": model.info,
    }
    summary["initial_state"] = dict(kind=cfg["initial_state"], **(settled or {}))
    study = None
    if dt_check and seconds > 0:
        # the integrator and step the accepted run ended with (after a fallback: the implicit one)
        study = dt_study(scene, cfg, sim.stats["method"].split("->")[-1],
                         sim.stats.get("dt_final_s", sim.stats["dt_s"]), min(seconds, DT_CHECK_WINDOW_S))
        summary["dt_study"] = study
    summary["warnings"] = convergence_warnings(summary["energy"], sim.energy_scale, study, sim.stats)
    if model.kind == "belt":
        # "rolls back": the centre of mass ends more than one cell length against the commanded direction
        # (an open-loop gait's direction, -1 rolls towards -x; every other gait rolls towards +x)
        d = cfg["gait"].get("direction", 1) if isinstance(cfg.get("gait"), dict) else 1
        summary["rolled_back"] = bool(d * disp_mm < -cfg["belt"]["cell_length_mm"])
    return summary, traj, model, sim
