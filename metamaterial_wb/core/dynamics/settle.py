"""``Simulator.settle`` (integrators.py): the bodies moved to a static equilibrium under gravity, contacts and the
actuation at the start, at rest, before a run (``dynamics.initial_state: "settled"``). A mixin: it steps the
simulator's own implicit integrator and restores its time, ledger and statistics."""
from __future__ import annotations

import math

import numpy as np

from .system import DynamicsError


class SettleMixin:
    """``Simulator``'s static-equilibrium relaxation (reads and writes its state; uses ``step_implicit``)."""

    def settle(self, max_iter=300, tol=1e-9, h_max=0.1):
        """Move the bodies to a static equilibrium under gravity, contacts and the actuation at the
        current time (the profiles' first values), at rest: backward-Euler steps with the velocities
        zeroed after each one (a proximal-point iteration on the static forces: each accepted step
        lowers the potential energy) and a step growing from 1 ms to ``h_max`` while Newton converges
        and the energy falls (a step that fails either is undone and retried 4x shorter). Time,
        ledger and step statistics are left as they were; the initial energy is taken at the settled
        state. Returns ``{"iterations", "moved_mm", "residual_m"}``; a :class:`DynamicsError` when
        no equilibrium is found."""
        act, self.actuate = self.actuate, None
        ledger, stats = dict(self.ledger), dict(self.stats)
        t, q_start = self.t, self.q.copy()
        v0 = np.zeros_like(self.v)
        h, step_max = 1e-3, math.inf
        E = self.sys.energy(self.q, v0, self.anchors)["total_J"]
        it = 0
        try:
            for it in range(1, max_iter + 1):
                q_old, anc_old, ins_old = self.q.copy(), self.anchors.copy(), self.inside.copy()
                bad_before = self.stats.get("newton_unconverged_steps", 0)
                self._prev = None
                self._fact = None
                self.step_implicit(h)
                self.t = t
                self.v[:] = 0.0
                E_new = self.sys.energy(self.q, v0, self.anchors)["total_J"] if np.all(np.isfinite(self.q)) else math.inf
                unconverged = self.stats.get("newton_unconverged_steps", 0) > bad_before
                if not math.isfinite(E_new) or E_new > E + 1e-9 * max(abs(E), 1e-6) or unconverged:
                    self.q, self.anchors, self.inside = q_old, anc_old, ins_old
                    h *= 0.25
                    if h < 1e-7:
                        break
                    continue
                E = E_new
                step_max = float(np.max(np.abs(self.q - q_old))) if self.q.size else 0.0
                if step_max < tol:
                    break
                h = min(h_max, 2.0 * h)
        finally:
            self._prev = None
            self._fact = None
            if self._kern is not None:
                self._kern.invalidate()
            self.actuate = act
            self.ledger, self.stats = ledger, stats
        if not step_max < tol:
            raise DynamicsError(f"no static equilibrium found for the initial state after {it} relaxation steps "
                                f"(last change {step_max:.3g} m); set dynamics.initial_state to \"as_built\"")
        p = self.sys.contact_points(self.q) if self.sys.cb.size else np.zeros((0, 2))
        self.inside = (p[:, 1] < 0) if p.size else np.zeros(0, bool)
        self.E0 = self.sys.energy(self.q, self.v, self.anchors)["total_J"]
        moved = float(np.max(np.linalg.norm(self.q[:, :2] - q_start[:, :2], axis=1))) * 1e3 if self.q.size else 0.0
        return {"iterations": it, "moved_mm": moved, "residual_m": step_max}
