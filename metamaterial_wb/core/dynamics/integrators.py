"""Time integration of a :class:`PlanarSystem`: semi-implicit Euler and linearly implicit Euler.

* ``symplectic``: semi-implicit (symplectic) Euler, ``v += dt M^-1 Q(q, v, t); q += dt v``. Its
  step is limited by the stiffest mode: the guard ``dt <= safety * 2 / (omega_K + c_max)`` is
  computed from Gershgorin bounds of the assembled stiffness and damping (``stiffness_bound``),
  every contact assumed active and sticking. A requested larger step is reduced to the guard and
  the reduction is reported in the statistics (``dt_reduced_from``).
* ``implicit``: backward Euler linearised once per step (one Newton step with the analytic sparse
  Jacobian, i.e. a Rosenbrock-Euler / Baraff-Witkin step):
  ``(M - dt dQ/dv - dt^2 dQ/dq) dv = dt (Q + dt dQ/dq v)``. A-stable for the linear part, so stiff
  hinges and contacts do not limit the step; it damps the highest modes (numerical dissipation,
  reported separately in the energy bookkeeping).

Safety: every ``check_every`` steps the state is checked (finite, speeds below ``v_limit``, energy
not growing by more than the actuators' work); on failure the run returns to the last checkpoint
and either falls back (symplectic -> implicit at the requested step, else the implicit automatic step;
implicit -> half step, up to 6 times) or raises a :class:`DynamicsError` that names the time, the
symptom and what to change. Never a silent blow-up.

Energy bookkeeping (joules, ledger.py): ``E = kinetic + gravity + elastic + contact``; actuator work is
the change of energy caused by moving rest angles / anchors, booked as each integrator applies it; friction
dissipation is the energy released when a contact anchor slips; damping dissipation is integrated
from the damper powers; ``numerical_J`` is what is left (E0 + W - D - E_end).
"""
from __future__ import annotations

import math
import time

import numpy as np
import scipy.linalg as sla
import scipy.sparse.linalg as spla
from scipy.linalg.lapack import dgbtrf as _gbtrf, dgbtrs as _gbtrs

from .autochoice import auto_method, implicit_path, implicit_step_cost
from .burst import BurstMixin
from .frames import FrameClock
from .settle import SettleMixin
from .ledger import EnergyLedger
from .system import DynamicsError, PlanarSystem

METHODS = ("auto", "symplectic", "implicit")


ROUNDOFF_STEPS = 1e-6    # a time short of a mark by less than this fraction of a step is round-off, not a step


class StepBudgetError(DynamicsError):
    """A run that would take more time steps than allowed, found before the first step."""


class Simulator(BurstMixin, SettleMixin, EnergyLedger):
    """State + integrators + energy ledger for one system.

    ``actuate(t, sim)``: optional callback that sets the system's actuation (theta0, anchors) for
    time ``t``; it may read ``sim.q``, ``sim.v`` and ``sim.contact_state()``.
    """

    def __init__(self, system: PlanarSystem, q0, v0=None, actuate=None, v_limit=50.0, safety=0.5):
        self.sys = system
        self.q = np.array(q0, float).reshape(system.n, 3)
        self.v = np.zeros_like(self.q) if v0 is None else np.array(v0, float).reshape(system.n, 3)
        self.v[system.fixed] = 0.0
        self.t = 0.0
        self.actuate = actuate
        self.v_limit = float(v_limit)
        self.safety = float(safety)
        p = system.contact_points(self.q) if system.cb.size else np.zeros((0, 2))
        self.anchors = p[:, 0].copy()
        self.inside = (p[:, 1] < 0) if p.size else np.zeros(0, bool)
        self.ledger = {"actuator_work_J": 0.0, "damping_J": 0.0, "friction_J": 0.0, "contact_damping_J": 0.0}
        self.stats = {"steps": 0, "force_evaluations": 0, "rejected_checks": 0,
                      "fallbacks": [], "max_penetration_mm": 0.0, "max_speed_m_s": 0.0}
        if actuate is not None:
            actuate(0.0, self)
        self.E0 = system.energy(self.q, self.v, self.anchors)["total_J"]
        omega_k, c_max = system.stiffness_bound()
        self.omega_max = omega_k
        self.damping_rate_max = c_max
        denom = omega_k + c_max
        self.dt_limit = 2.0 / denom if denom > 0 else math.inf     # semi-implicit Euler stability limit
        self.dt_guard = self.safety * self.dt_limit

    # -- helpers ------------------------------------------------------------------------------
    def contact_state(self):
        """Per contact point: (inside, normal force N) at the current state."""
        if not self.sys.cb.size:
            return np.zeros(0, bool), np.zeros(0)
        _, st = self.sys.forces(self.q, self.v, self.anchors)
        return st["inside"], st["fn"]

    def _update_anchors(self):
        s = self.sys
        if not s.cb.size:
            return
        k = self._compiled()
        if k is not None and self.anchors.flags.c_contiguous \
                and self.anchors.dtype == np.float64 and self.inside.dtype == bool and self.inside.flags.c_contiguous:
            # the same update in the compiled kernel (anchors and inside flags in place)
            fr, pen = k.update_anchors(self.q, self.v, self.anchors, self.inside, self.ledger["friction_J"],
                                       self.stats["max_penetration_mm"])
            self.ledger["friction_J"] = fr
            self.stats["max_penetration_mm"] = pen
            return
        p = s.contact_points(self.q)
        inside = p[:, 1] < 0
        new = inside & ~self.inside
        self.anchors = np.where(inside & ~new, self.anchors, p[:, 0])
        if np.any(inside):
            from .system import _rot
            u = _rot(self.q[s.cb, 2], s.rc)
            vpy = self.v[s.cb, 1] + self.v[s.cb, 2] * u[:, 0]
            fn = np.where(inside, np.maximum(0.0, -s.kn * p[:, 1] - s.cn * vpy), 0.0)
            spring = -s.kt * (p[:, 0] - self.anchors)
            cap = s.mu * fn
            slip = inside & (np.abs(spring) > cap)
            if np.any(slip):
                anc = np.where(slip, p[:, 0] + np.sign(spring) * cap / np.where(s.kt > 0, s.kt, 1.0),
                               self.anchors)
                # work of the (capped) friction force over the slip of the anchor
                self.ledger["friction_J"] += float(np.sum(np.where(slip, cap * np.abs(anc - self.anchors), 0.0)))
                self.anchors = anc
            pen = float(np.max(-p[:, 1])) * 1e3
            if pen > self.stats["max_penetration_mm"]:
                self.stats["max_penetration_mm"] = pen
        self.inside = inside

    def _track_com(self):
        """After a step: widen the centre of mass's x extremes (``stats["com_x_min_m"]`` / ``["com_x_max_m"]``,
        started by ``run``, with its weights ``_com_w``) to the current position (run's step by step path and the
        burst's numpy fallback step; ``mm_step`` does the same in C)."""
        x = float(self._com_w @ self.q[:, 0])
        st = self.stats
        if x < st["com_x_min_m"]:
            st["com_x_min_m"] = x
        elif x > st["com_x_max_m"]:
            st["com_x_max_m"] = x

    # -- single steps -------------------------------------------------------------------------
    def step_symplectic(self, dt):
        """One semi-implicit Euler step, ``v += dt M^-1 Q(q, v); q += dt v``, with the actuation of the step's
        start held over the step; its work is booked as this step applies it (ledger.py).

        Parameters
        ----------
        dt : float
            The step (s).
        """
        self._book_symplectic_actuation(self.t, dt)
        Q, _ = self.sys.forces(self.q, self.v, self.anchors)
        self.stats["force_evaluations"] += 1
        acc = Q / self.sys.M
        acc[self.sys.fixed] = 0.0
        v_new = self.v + dt * acc
        ph, pc = self.sys.dissipation_power(self.q, 0.5 * (self.v + v_new), self.anchors, dt)
        self.ledger["damping_J"] += dt * ph
        self.ledger["contact_damping_J"] += dt * pc
        self.v = v_new
        self.q = self.q + dt * self.v
        self.t += dt
        self._update_anchors()

    newton_max = 6
    newton_max_band = 6       # banded path (10 measured: more unconverged-step work, no gain)
    linearized_first_step = False  # accept the first Newton step when its Jacobian is fresh (measured: blew up the worm at 5 ms, no gain on the belt)
    freeze_after = None       # freeze the contact flags from this Newton iteration on (None: never)
    freeze_contacts = False   # reuse the contact flags of the first iterate within a step (off: measured worse)
    newton_tol_abs = 1e-5     # m/s (and rad/s): Newton stops when the velocity update is below
    newton_tol_rel = 1e-3     # newton_tol_abs + newton_tol_rel * max |v|
    refactor_on_contact_change = True    # also rebuild when the touching / sticking set changes
    lag_hinges = False        # banded path: keep the hinge part of the Jacobian within a step (measured: more
                              # Newton iterations on the rolling 1000-cell belt, slower overall; off)
    _newton_it = 0
    use_band = True           # chains / rings: banded LU in reverse Cuthill-McKee order (O(n))
    jacobian_max_age = 8      # steps a factored Jacobian is reused (same step, same contact/stick set)

    def _factor(self, q, v, st, h, dense, refresh=False):
        """Solver for the Newton matrix A = M - h dQ/dv - h^2 dQ/dq. The factorisation is reused while
        the step size and the set of touching / sticking contacts stay the same, for at most
        ``jacobian_max_age`` steps (a lagged Jacobian: the residual is always exact, so this changes
        only the convergence rate, never the equations being solved)."""
        s = self.sys
        key_in = st["pushing"] if st is not None else None
        key_st = st["stick"] if st is not None else None
        f = getattr(self, "_fact", None)
        same_contacts = key_in is None or (np.array_equal(f["inside"], key_in) and np.array_equal(f["stick"], key_st)) \
            if f is not None else False
        if (not refresh and f is not None and f["h"] == h and f["age"] < self.jacobian_max_age
                and (same_contacts or not self.refactor_on_contact_change)):
            f["uses"] += 1
            return f["solve"]
        band = None if dense or not self.use_band else s.band_layout()
        if band is not None or dense:
            # banded path: within one step the hinges' part of the Jacobian is lagged (from the step's
            # first build) unless convergence is slow; the touching contacts are always current.
            # Not on the small dense path: there it saves little, and servo-driven stiff pins (the
            # worm) need the current hinge Jacobian (measured: a fallback at 5 ms)
            A = s.band_system_matrix(q, v, st, h, reuse_hinges=(band is not None and self._newton_it > 0 and self.lag_hinges
                                                   and not refresh),
                                     dense=band is None)
        else:
            A, _ = s.system_matrix(q, v, self.anchors, st, h, dense=dense)
        self.stats["jacobians"] = self.stats.get("jacobians", 0) + 1
        if band is not None:
            kl, ku, perm = band["kl"], band["ku"], band["perm"]
            lu, piv, info = _gbtrf(A, kl, ku, overwrite_ab=1)
            if info > 0:      # singular: let the caller see non-finite values (handled by the checks)
                solve = lambda r: np.full(r.shape, np.nan)
            else:
                def solve(r, lu=lu, piv=piv):
                    x, _ = _gbtrs(lu, kl, ku, r[perm], piv)
                    out = np.empty_like(x)
                    out[perm] = x
                    return out
            self.stats["banded_lu"] = True
        elif dense:
            lu = sla.lu_factor(A, check_finite=False)
            solve = lambda r: sla.lu_solve(lu, r, check_finite=False)
        else:
            A = A.tocsc()
            spec = getattr(self, "_perm_spec", None)
            if spec is None:
                # chains and rings numbered along the chain factor best in their own order; keep the
                # ordering with the least fill (measured once)
                best = None
                for cand in ("NATURAL", "COLAMD"):
                    lu_c = spla.splu(A, permc_spec=cand)
                    fill = lu_c.L.nnz + lu_c.U.nnz
                    if best is None or fill < best[0]:
                        best = (fill, cand, lu_c)
                self._perm_spec = spec = best[1]
                lu = best[2]
            else:
                lu = spla.splu(A, permc_spec=spec)
            solve = lu.solve
        self._fact = {"h": h, "inside": key_in, "stick": key_st, "age": 0, "uses": 0, "solve": solve,
                      "step": self.stats["steps"]}
        return solve
    bdf2 = True
    def step_implicit(self, dt):
        """BDF2 (backward Euler on the first step, after a restart or a change of dt), solved by
        Newton's method with the analytic sparse Jacobian: one iteration per step, more while the
        set of touching contact points changes during the step (at most ``newton_max``)::

            q1 = qh + h v1,  M (v1 - vh) = h Q(q1, v1)
            BE:   h = dt,      qh = q_n,                  vh = v_n
            BDF2: h = 2/3 dt,  qh = (4 q_n - q_{n-1})/3,  vh = (4 v_n - v_{n-1})/3
        """
        self._apply_actuation(self.t + dt)
        self._implicit_solve(dt)

    def _implicit_solve(self, dt):
        """``step_implicit`` after the actuation of the step's end is set (and its first half booked)."""
        s = self.sys
        prev = getattr(self, "_prev", None)
        if self.bdf2 and prev is not None and abs(prev[2] - dt) <= 1e-12 * dt:
            h = 2.0 * dt / 3.0
            qh = (4.0 * self.q - prev[0]) / 3.0
            vh = ((4.0 * self.v - prev[1]) / 3.0).ravel()
            v1 = (2.0 * self.v - prev[1]).ravel()          # predictor: linear extrapolation
            self.stats["bdf2_steps"] = self.stats.get("bdf2_steps", 0) + 1
        else:
            h = dt
            qh = self.q
            vh = self.v.ravel()
            v1 = vh.copy()
        dense, banded = self._layout()
        Mf = s.M.ravel()
        damp_power = None
        prev = None
        st_last = None          # the last iteration's contact state (freeze_after)
        refresh = False
        converged = False
        st0 = None
        kern = self._kernel_for(dense, banded)
        self._kern_used = kern is not None
        if kern is not None:
            # the same Newton loop, compiled (fastkernel.py / _kernel.c): one call per step
            qh = np.ascontiguousarray(qh, float)
            vh = np.ascontiguousarray(vh, float)
            v1 = np.array(v1, float)
            if not (self.anchors.flags.c_contiguous and self.anchors.dtype == np.float64):
                self.anchors = np.ascontiguousarray(self.anchors, float)
            ks = kern.newton(qh, vh, v1, h, self.anchors, self.newton_max_band if banded else self.newton_max,
                             self.newton_tol_abs, self.newton_tol_rel, self.jacobian_max_age,
                             self.refactor_on_contact_change)
            st = self.stats
            st["kernel"] = "c"
            st["force_evaluations"] += int(ks[0])
            if ks[1]:
                st["jacobians"] = st.get("jacobians", 0) + int(ks[1])
            if ks[2]:
                st["newton_iterations"] = st.get("newton_iterations", 0) + int(ks[2])
            if banded:
                st["banded_lu"] = True
            self._end_implicit_step(qh, h, v1, dt, bool(ks[3]), float(ks[4]))
            return
        for it in range(self.newton_max_band if banded else self.newton_max):
            V1 = v1.reshape(-1, 3)
            q1 = qh + h * V1
            if it > 0 and self.freeze_contacts:
                frozen = st0
            elif self.freeze_after is not None and it >= self.freeze_after:
                # the active set (touching / sticking flags) cycles between iterates: keep the last
                # one, the residual becomes smooth and Newton converges
                frozen = st_last
            else:
                frozen = None
            Q1, st1 = s.forces(q1, V1, self.anchors, frozen=frozen)
            st_last = st1
            if it == 0:
                st0 = st1
            self.stats["force_evaluations"] += 1
            if damp_power is None:
                damp_power = s.last_damping_power
            R = Mf * (v1 - vh) - h * Q1.ravel()
            R[~s.free_dof] = 0.0
            self._newton_it = it
            dv = self._factor(q1, V1, st1, h, dense, refresh)(R)
            v1 = v1 - dv
            nrm = float(np.max(np.abs(dv))) if dv.size else 0.0
            if not math.isfinite(nrm):
                break
            if (it == 0 and self.linearized_first_step and self._fact["uses"] == 0
                    and (st1 is None or np.array_equal(s.contact_points(qh + h * v1.reshape(-1, 3))[:, 1] < 0,
                                                       st1["inside"]))):
                # a fresh Jacobian at this step and no contact change: one Newton step is the
                # linearly implicit BDF2 step (second order, A-stable for the linearised system)
                converged = True
                break
            if nrm <= self.newton_tol_abs + self.newton_tol_rel * float(np.max(np.abs(v1))):
                converged = True
                break
            # slow or no convergence with the lagged matrix: rebuild it at the current iterate
            refresh = prev is not None and nrm > 0.25 * prev
            prev = nrm
            self.stats["newton_iterations"] = self.stats.get("newton_iterations", 0) + 1
        if getattr(self, "_fact", None) is not None:
            self._fact["age"] += 1
        self._end_implicit_step(qh, h, v1, dt, converged, damp_power)

    def _end_implicit_step(self, qh, h, v1, dt, converged, damp_power):
        """Accept the Newton result of a BDF2 / backward-Euler step (numpy path or compiled kernel)."""
        if not converged:
            self.stats["newton_unconverged_steps"] = self.stats.get("newton_unconverged_steps", 0) + 1
        v_new = v1.reshape(-1, 3)
        v_new[self.sys.fixed] = 0.0
        self._prev = (self.q, self.v, dt)
        self.v = v_new
        self.q = qh + h * v_new
        self._book_actuation_end()
        # hinge dampers: the power of the step's first force evaluation (numpy path and compiled kernel
        # alike); contact dampers: at the step's end state (where the implicit step evaluates its
        # forces), entering / leaving points for their part of the step
        k = self._compiled()
        if k is not None:
            pc = k.contact_damping(self.q, self.v, self._prev[0], self._prev[1], self.anchors, dt)
        else:
            _, pc = self.sys.dissipation_power(self.q, self.v, self.anchors, dt, q_start=self._prev[0],
                                               v_start=self._prev[1], hinges=False)
        self.ledger["damping_J"] += dt * damp_power
        self.ledger["contact_damping_J"] += dt * pc
        self.t += dt
        self._update_anchors()

    # -- checks ------------------------------------------------------------------------------
    def _checkpoint(self):
        return (self.q.copy(), self.v.copy(), self.t, self.anchors.copy(), self.inside.copy(),
                dict(self.ledger), self.sys.theta0.copy(), self.sys.ra.copy(), self.sys.rb.copy(),
                self.actuate.state() if hasattr(self.actuate, "state") else None,
                {k: self.stats.get(k, 0) for k in self.ACCEPTED_STATS})

    # extremes that describe the motion: they come from the accepted trajectory only (a discarded
    # attempt's blow-up is reported in its fallback entry, not as the run's penetration; the Newton-unconverged
    # count of the summary's warning, likewise, counts the accepted steps only)
    ACCEPTED_STATS = ("max_penetration_mm", "max_speed_m_s", "newton_unconverged_steps", "com_x_min_m",
                      "com_x_max_m")

    def _restore(self, cp):
        (self.q, self.v, self.t, self.anchors, self.inside, ledger, th0, ra, rb, ast, acc) = cp
        self.stats["discarded_max_penetration_mm"] = max(self.stats.get("discarded_max_penetration_mm", 0.0),
                                                         self.stats["max_penetration_mm"])
        self.stats.update(acc)
        self.q, self.v, self.anchors, self.inside = self.q.copy(), self.v.copy(), self.anchors.copy(), self.inside.copy()
        self.ledger = dict(ledger)
        self.sys.theta0[:] = th0
        self.sys.ra[:] = ra
        self.sys.rb[:] = rb
        if ast is not None:
            self.actuate.restore(ast)
        self._prev = None
        self._fact = None
        if self._kern is not None:
            self._kern.invalidate()

    # -- driver ------------------------------------------------------------------------------
    def choose(self, method, dt, t_end):
        """Resolve ``method`` ("auto" picks the cheaper one for the path that will run, ``auto_method``) and the
        step size. Returns (method, dt, note); for "auto" the comparison is in ``stats["auto_choice"]``."""
        if method not in METHODS:
            raise DynamicsError(f"integrator {method!r}; allowed: {', '.join(METHODS)}")
        note = None
        if method == "auto":
            # each integrator at the step it is trusted at: the explicit one at its stability guard (stiffness,
            # damping and every contact touching and sticking), or at a requested step within its limit; the
            # implicit one at the requested step, else the scene's converged default. Never the explicit one for a
            # requested step beyond its stability limit (it would run at its guard instead of the step asked for)
            dt_imp = dt if dt is not None else self.default_implicit_dt
            if dt is not None and dt > self.dt_limit:
                method, choice = "implicit", {"reason": "requested step beyond the explicit stability limit"}
            else:
                dt_sym = self.dt_guard if dt is None else dt
                path = implicit_path(self)
                cost = implicit_step_cost(path, 3 * self.sys.n)
                method = auto_method(dt_sym, dt_imp, cost)
                choice = {"symplectic_dt_s": dt_sym, "implicit_dt_s": dt_imp, "implicit_path": path,
                          "implicit_step_cost": cost,
                          "cost_ratio_implicit_to_symplectic": cost * dt_sym / dt_imp}
            self.stats["auto_choice"] = dict(choice, chose=method)
        if method == "symplectic":
            if dt is None:
                dt = self.dt_guard
            elif dt > self.dt_limit:
                note = (f"requested dt = {dt:.3g} s exceeds the semi-implicit Euler stability limit "
                        f"2/omega = {self.dt_limit:.3g} s; reduced to the guard {self.dt_guard:.3g} s")
                self.stats["dt_reduced_from"] = dt
                dt = self.dt_guard
        else:
            if dt is None:
                dt = self.default_implicit_dt
        if not (dt > 0 and math.isfinite(dt)):
            raise DynamicsError(f"time step {dt!r} s must be a positive finite number")
        if 0 < t_end < dt:       # the whole run is one step, shortened to the run: said, never silently
            note = "; ".join(filter(None, [note, f"the step {dt:g} s is longer than the run: one step of {t_end:g} s"]))
            dt = t_end
        return method, dt, note

    default_implicit_dt = 2e-3
    energy_scale = 0.0

    def run(self, t_end, method="auto", dt=None, record_dt=None, check_every=100, on_record=None,
            max_steps=50_000_000):
        """Integrate to ``t_end`` (s). Records frames through ``on_record(sim)``: the state at the step nearest each
        instant ``k * record_dt`` (frames.py; every step when the step is longer than ``record_dt``), and always
        the final state at ``t_end`` (the last frame may follow the one before it by less than ``record_dt``);
        what was recorded is ``stats["recording"]``."""
        t0 = time.perf_counter()
        dt_requested = dt
        method, dt, note = self.choose(method, dt, t_end)
        if t_end / dt > max_steps:          # before the first step, with the step the integrator takes
            raise StepBudgetError(f"{t_end:g} s at the integrator's step {dt:.3g} s ({method}) is "
                                  f"{t_end / dt:.3g} time steps; at most {max_steps} are allowed")
        self.stats.update({"method": method, "dt_s": dt, "dt_guard_s": self.dt_guard,
                           "dt_stability_limit_s": self.dt_limit, "omega_max_rad_s": self.omega_max})
        if note:
            self.stats["note"] = note
        if method == "symplectic":
            self.stats.setdefault("kernel", "numpy")      # the explicit integrator is numpy only
        clock = None
        rec_t = None                  # the time of the last recorded frame
        eps = ROUNDOFF_STEPS * dt
        if on_record is not None:
            clock = FrameClock(record_dt)
            on_record(self)
            rec_t = self.t
            clock.recorded(self.t, dt, eps)
        # the centre of mass's extremes over every step, not only the recorded frames (the summary's travel
        # extremes must not depend on the frame rate), as Model.com_x
        w = self._com_w = np.ascontiguousarray(self.sys.com_weights(), float)
        x = float(w @ self.q[:, 0])
        self.stats["com_x_min_m"] = min(self.stats.get("com_x_min_m", x), x)
        self.stats["com_x_max_m"] = max(self.stats.get("com_x_max_m", x), x)
        cp = self._checkpoint()
        since = 0
        retries = 0
        dense, banded = self._layout()
        while self.t < t_end - eps:
            nb = 0
            if method == "implicit" and self.burst:
                k = self._compiled()
                if k is not None and self._kernel_for(dense, banded) is k:
                    # runs of steps with nothing for Python to do in between but the actuator: one C call each
                    nb = self._burst(k, dt, min(check_every - since, max_steps + 1 - self.stats["steps"]), t_end,
                                     eps, clock.rec_at(dt, eps) if clock is not None else None,
                                     self.newton_max_band if banded else self.newton_max)
            if nb:
                since += nb              # (_burst counted its steps in stats["steps"])
            else:
                # the step that reaches t_end (within round-off of a whole step) ends there exactly: time
                # accumulated by addition would otherwise leave a last step of ~1e-11 s on long runs
                last = t_end - self.t <= dt + eps
                h = t_end - self.t if last else dt
                if method == "symplectic":
                    self.step_symplectic(h)
                else:
                    self.step_implicit(h)
                if last:
                    self.t = t_end
                self._track_com()
                self.stats["steps"] += 1
                since += 1
            if self.stats["steps"] > max_steps:
                raise DynamicsError(f"more than {max_steps} steps; raise dt or use the implicit integrator")
            # the next step: dt, or the shorter one that ends the run (nearest-step rule, frames.py)
            h_next = t_end - self.t if t_end - self.t <= dt + eps else dt
            crossed = clock is not None and clock.due(self.t, h_next, eps)
            if since >= check_every or crossed or self.t >= t_end - eps:
                bad = self._health()
                if bad is not None:
                    self.stats["rejected_checks"] += 1
                    t_bad = self.t
                    self._restore(cp)
                    since = 0
                    if method == "symplectic":
                        # the implicit integrator at the step the run asked for (the scene's dt_s or --dt; the
                        # explicit step may have been reduced below it), else at its automatic step
                        method = "implicit"
                        if dt_requested is not None:
                            dt = min(dt_requested, t_end) if t_end > 0 else dt_requested
                            how = f"the requested step dt = {dt:g} s"
                        else:
                            dt = self.default_implicit_dt
                            how = f"its automatic step dt = {dt:g} s (no step was requested)"
                        eps = ROUNDOFF_STEPS * dt
                        self.stats["fallbacks"].append(
                            {"at_s": round(t_bad, 6), "reason": bad, "action": f"switched to implicit at {how}"})
                        self.stats["method"] = "symplectic->implicit"
                        continue
                    retries += 1
                    if retries > 6:
                        raise DynamicsError(
                            f"simulation unstable at t = {t_bad:.4g} s: {bad}; even the implicit integrator "
                            f"with dt = {dt:.3g} s failed. Check for very large forces (stiffness, pressure, "
                            f"servo amplitude) or set dynamics.integrator.dt_s smaller")
                    dt *= 0.5
                    eps = ROUNDOFF_STEPS * dt
                    self.stats["fallbacks"].append(
                        {"at_s": round(t_bad, 6), "reason": bad, "action": f"halved implicit dt to {dt:g} s"})
                    continue
                cp = self._checkpoint()
                since = 0
                if crossed:                   # one frame per state, however many record times it is nearest to
                    on_record(self)
                    rec_t = self.t
                    clock.recorded(self.t, h_next, eps)
        if on_record is not None and rec_t != self.t:
            # the final state is always a frame (closer than record_dt to the one before it when t_end is
            # not a multiple of record_dt): the summary's travel and energy are both taken at t_end
            on_record(self)
            clock.frames += 1
        if clock is not None:
            self.stats["recording"] = dict(clock.report(), step_s=dt)
        self.stats["dt_final_s"] = dt
        self.stats["wall_s"] = time.perf_counter() - t0
        return self
