"""The energy ledger of a :class:`~.integrators.Simulator`: the actuators' work, the safety check built on
it and the energy report (a mixin; the integrators call it).

The actuators' work is booked as each integrator applies the actuation:

* ``implicit`` (BDF2 / backward Euler): the actuation of the step's end is set before the step; the work is
  the jump of the elastic energy that moving the rest angles / anchors causes at fixed positions, averaged
  over the step's start and end positions (the trapezoidal rule for ``W = int dU/da . da``).
* ``symplectic`` (semi-implicit Euler): the actuation of the step's start is held over the step. This step
  conserves (exactly for quadratic potentials) ``E + dt/2 v . Q(q, v)``: the kinetic energy of the
  staggered velocities ``v_n . M v_n+1 / 2`` plus the potential. Moving the actuation at fixed (q, v) changes
  it by ``dU + dt/2 v . dQ_hinges``, which is the work booked. The trapezoid of the implicit step counted
  the stroke half a step late here: an error ``dt/2 int k v da/dt`` that grows with time (on stiff driven
  pins larger than the energy that moves), and the safety check's false alarms.

What the ledger does not book (``numerical_J``) is then the integrator's own error: O(dt) and shrinking
with the step for the symplectic step on smooth forces (its ``E`` differs from the conserved quantity by
``dt/2 v . Q``), the step's numerical damping for the implicit one.
"""
from __future__ import annotations

import numpy as np

from .system import _perp, _rot


class EnergyLedger:
    """Actuator work, safety check and energy report of a simulator (``self.sys``, ``self.q``, ``self.v``,
    ``self.anchors``, ``self.ledger``, ``self.E0``, ``self.energy_scale``, ``self.actuate``)."""

    _work_peak = 0.0          # the largest |actuators' work| at the checks passed so far

    def _set_actuation(self, t):
        """Set the actuation for time ``t``; the former (theta0, ra, rb) when it changed, else None."""
        if self.actuate is None:
            return None
        s = self.sys
        old = (s.theta0.copy(), s.ra.copy(), s.rb.copy())
        self.actuate(t, self)
        if np.array_equal(old[0], s.theta0) and np.array_equal(old[1], s.ra) and np.array_equal(old[2], s.rb):
            return None
        return old

    def _apply_actuation(self, t):
        """Implicit step: set the actuation for time ``t`` (the step's end) and book the actuators' work of the
        step: the change of elastic
        energy that moving the rest angles / anchors from their old to their new values causes, averaged
        over the positions at the step's start (here) and at its end (``_book_actuation_end``). The average
        is the trapezoidal rule for ``W = int dE/da . da``; the jump at the start positions alone (the former
        ledger) also counts ``k (da)^2 / 2`` per step, which the integrator then dissipates again: an O(dt)
        error that landed in both "actuator work" and "numerical" (most of both on the worm's stiff pins
        at 1 ms)."""
        self._book_actuation(self._set_actuation(t))

    def _book_actuation(self, old):
        """Implicit step whose actuation of the step's end is set: keep ``old`` (the former (theta0, ra, rb), or
        None when unchanged) for ``_book_actuation_end`` and book the first half of the trapezoid, at the step's
        start positions (``_apply_actuation``; the compiled burst's numpy fallback step, burst.py)."""
        self._act_old = old
        if old is not None:
            self.ledger["actuator_work_J"] += 0.5 * self._actuation_jump(self.q, old)

    def _actuation_jump(self, q, old):
        """Elastic energy at positions ``q`` with the current actuation minus that with ``old``
        (theta0, ra, rb); by the compiled kernel where the steps run on it (``_compiled``)."""
        s = self.sys
        k = self._compiled()
        if k is not None:
            return k.actuation_jump(q, old)
        th_old, ra_old, rb_old = old
        rel = q[s.hb, 2] - q[s.ha, 2]
        W = 0.5 * float(np.sum(s.kr * ((rel - s.theta0) ** 2 - (rel - th_old) ** 2)))
        if not (np.array_equal(ra_old, s.ra) and np.array_equal(rb_old, s.rb)):
            qa, qb = q[s.ha], q[s.hb]
            d_new = qb[:, :2] + _rot(qb[:, 2], s.rb) - qa[:, :2] - _rot(qa[:, 2], s.ra)
            d_old = qb[:, :2] + _rot(qb[:, 2], rb_old) - qa[:, :2] - _rot(qa[:, 2], ra_old)
            W += 0.5 * float(np.sum(s.kp * (np.sum(d_new * d_new, 1) - np.sum(d_old * d_old, 1))))
        return W

    def _book_actuation_end(self):
        """Implicit step: the other half of ``_apply_actuation``'s trapezoid, at the step's end positions."""
        old = getattr(self, "_act_old", None)
        if old is not None:
            self.ledger["actuator_work_J"] += 0.5 * self._actuation_jump(self.q, old)
            self._act_old = None

    def _book_symplectic_actuation(self, t, dt):
        """Set the actuation for time ``t`` (a semi-implicit Euler step of ``dt`` starts) and book its work
        ``dU + dt/2 (v . Q_hinges(new) - v . Q_hinges(old))`` at the current (q, v) (module docstring)."""
        old = self._set_actuation(t)
        if old is None:
            return
        s, q, v = self.sys, self.q, self.v
        a, b = s.ha, s.hb
        th_old, ra_old, rb_old = old
        dw = v[b, 2] - v[a, 2]
        rel = q[b, 2] - q[a, 2]
        # rotational springs: the energy's jump; the power -kr (rel - theta0) dw changes by kr dtheta0 dw
        # (dot products: these arrays are short, numpy's per-call overhead dominates)
        dU = 0.5 * float(s.kr @ ((rel - s.theta0) ** 2 - (rel - th_old) ** 2))
        dP = float(s.kr @ ((s.theta0 - th_old) * dw))
        if not (np.array_equal(ra_old, s.ra) and np.array_equal(rb_old, s.rb)):
            # pins: energy kp |d|^2 / 2 and power -(kp d + cp d') . d', d' = the pin points' relative velocity;
            # both depend on the attachment points ra, rb the actuators move
            ca, sa, cb, sb = np.cos(q[a, 2]), np.sin(q[a, 2]), np.cos(q[b, 2]), np.sin(q[b, 2])
            bx, by = q[b, 0] - q[a, 0], q[b, 1] - q[a, 1]
            vx, vy = v[b, 0] - v[a, 0], v[b, 1] - v[a, 1]
            wa, wb = v[a, 2], v[b, 2]
            for ra, rb, sign in ((s.ra, s.rb, 1.0), (ra_old, rb_old, -1.0)):
                Rax, Ray = ca * ra[:, 0] - sa * ra[:, 1], sa * ra[:, 0] + ca * ra[:, 1]
                Rbx, Rby = cb * rb[:, 0] - sb * rb[:, 1], sb * rb[:, 0] + cb * rb[:, 1]
                dx, dy = bx + Rbx - Rax, by + Rby - Ray
                ddx, ddy = vx - wb * Rby + wa * Ray, vy + wb * Rbx - wa * Rax
                dU += sign * 0.5 * float(s.kp @ (dx * dx + dy * dy))
                dP -= sign * float(s.kp @ (dx * ddx + dy * ddy) + s.cp @ (ddx * ddx + ddy * ddy))
        self.ledger["actuator_work_J"] += dU + 0.5 * dt * dP

    def _hinge_power(self, q, v, act=None):
        """Power ``v . F_hinge`` (W) of the hinges' springs and dampers at (q, v), with the actuation ``act``
        (theta0, ra, rb; default the current one). (The reference for ``_book_symplectic_actuation``'s
        difference, which computes it in one pass.)"""
        s = self.sys
        if not s.ha.size:
            return 0.0
        th0, ra, rb = act if act is not None else (s.theta0, s.ra, s.rb)
        a, b = s.ha, s.hb
        Ra, Rb = _rot(q[a, 2], ra), _rot(q[b, 2], rb)
        d = q[b, :2] + Rb - q[a, :2] - Ra
        dd = v[b, :2] + v[b, 2:3] * _perp(Rb) - v[a, :2] - v[a, 2:3] * _perp(Ra)
        dw = v[b, 2] - v[a, 2]
        rel = q[b, 2] - q[a, 2] - th0
        return -float(np.sum(s.kp * np.sum(d * dd, 1)) + np.sum(s.cp * np.sum(dd * dd, 1))
                      + np.sum(s.kr * rel * dw) + np.sum(s.cr * dw * dw))

    def _health(self):
        """None if fine, else a sentence describing the symptom."""
        if not (np.all(np.isfinite(self.q)) and np.all(np.isfinite(self.v))):
            return "the state became non-finite (NaN/inf)"
        vmax = float(np.max(np.abs(self.v[:, :2]))) if self.v.size else 0.0
        self.stats["max_speed_m_s"] = max(self.stats["max_speed_m_s"], vmax)
        if vmax > self.v_limit:
            return f"a body reached {vmax:.3g} m/s (limit {self.v_limit:g} m/s)"
        E = self.sys.energy(self.q, self.v, self.anchors)["total_J"]
        # dissipation only removes energy: the energy can never exceed the initial energy plus the
        # actuators' work (the dissipation estimates are not used here, so they cannot raise false alarms).
        # The margin is half the energy in play: the initial energy, the weight over 5 cm and the largest
        # actuators' work booked at the checks passed so far; not the work booked now, which swings through
        # zero when a drive takes back what it put in (a margin that then collapsed to 1 uJ flagged converged
        # driven runs). Without actuators the margin is what it was.
        W = self.ledger["actuator_work_J"]
        budget = self.E0 + W
        peak = max(self._work_peak, abs(W))
        scale = abs(self.E0) + peak + 1e-6 + self.energy_scale
        if E - budget > 0.5 * scale:
            return (f"the energy grew to {E:.4g} J, {E - budget:.3g} J more than the initial energy plus the "
                    f"actuators' work allows")
        self._work_peak = peak
        return None

    def energy_report(self):
        """The energy ledger at the current state (joules).

        Returns
        -------
        dict
            ``initial_J``, ``final_J``, ``final_parts_J`` (kinetic, gravity, elastic, contact, total),
            ``actuator_work_J``, ``damping_dissipated_J``, ``friction_dissipated_J``,
            ``contact_damping_dissipated_J`` and ``numerical_J`` = initial + work - dissipated - final (what
            the integrator itself created (< 0) or lost (> 0)).
        """
        e = self.sys.energy(self.q, self.v, self.anchors)
        W = self.ledger["actuator_work_J"]
        out = {"initial_J": self.E0, "final_J": e["total_J"], "final_parts_J": e,
               "actuator_work_J": W, "damping_dissipated_J": self.ledger["damping_J"],
               "friction_dissipated_J": self.ledger["friction_J"],
               "contact_damping_dissipated_J": self.ledger["contact_damping_J"]}
        out["numerical_J"] = (self.E0 + W - self.ledger["damping_J"] - self.ledger["friction_J"]
                              - self.ledger["contact_damping_J"] - e["total_J"])
        return out
