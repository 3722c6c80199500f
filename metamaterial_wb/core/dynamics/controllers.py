"""The actuators of the dynamic models built by builders.py: the callbacks ``actuate(t, sim)`` that set the
system's actuation (rest angles ``theta0``, hinge anchors ``ra`` / ``rb``) for time ``t``.

* :class:`BeltController`: the belt's pneumatic cells (gait -> pressure per cell -> rest curvature, with a fill
  time); closed loop, it reads the state (which cells touch the ground).
* :class:`SheetController`: the sheet's servos (actuator profiles -> D per cell gap -> pitch and fold); its
  actuation depends on the time only.
"""
from __future__ import annotations

import math

import numpy as np

from ..errors import SceneError
from ..gait import gait_rule_array


class BeltController:
    """Pneumatic cells: pressure command per cell from the gait -> rest curvature with a fill time."""

    def __init__(self, scene, cfg, system, h_cells, ls, theta_base, kappa_per_kpa, seg_cell):
        self.cfg = cfg
        self.b = cfg["belt"]
        self.gait = cfg["gait"]
        self.sys = system
        self.N = self.b["cells"]
        self.h_cells = h_cells
        self.ls = ls
        self.theta_base = theta_base
        self.kappa_per_kpa = kappa_per_kpa
        self.seg_cell = seg_cell
        self.p_cmd = np.zeros(self.N)
        self.p = np.zeros(self.N)            # effective pressure (filled), kPa
        self.t_last = 0.0
        self.next_control = 0.0
        self.history = []                    # (t, number of inflated cells) at control instants
        self.profiles = []
        if self.gait["type"] == "none":
            from ..scene import parse_joint
            for act in scene.actuators:
                kind, i, j = parse_joint(act.joint)
                if kind != "V" or not 0 <= j < self.N:
                    raise SceneError(f"actuators.{act.name}.joint",
                                     f"{act.joint}: a belt cell is driven through its left joint V0,j, "
                                     f"j in 0..{self.N - 1}")
                self.profiles.append((j, act))
        thr = self.b["ground_threshold_mm"] * 1e-3
        self.thr = thr

    def state(self):
        return (self.p_cmd.copy(), self.p.copy(), self.t_last, self.next_control, len(self.history))

    def restore(self, s):
        self.p_cmd, self.p, self.t_last, self.next_control, nh = s
        self.p_cmd, self.p = self.p_cmd.copy(), self.p.copy()
        del self.history[nh:]

    def prefill(self, q0):
        """Start with every cell at the pressure the gait commands at t = 0 (already filled), and the rest
        angles that go with it. For the closed loop this is its own decision for the initial contact state:
        the real controller runs while the belt is put down, so its cells are filled when it is let go."""
        self.command(0.0, q0)
        self.p = self.p_cmd.copy()
        self._set_rest_angles()

    def cell_air(self, q):
        """Seed's sensor c_i: 1 = in the air, 0 = touching the ground (any contact point within the threshold)."""
        pts = self.sys.contact_points(q)
        near = pts[:, 1] < self.thr
        seg_near = near.reshape(-1, 2).any(axis=1)
        cell_near = np.bincount(self.seg_cell, seg_near.astype(float), self.N) > 0
        return (~cell_near).astype(int)

    def command(self, t, q):
        g = self.gait
        p_on = self.b["pressure_kpa"]
        if g["type"] == "closed_loop":
            if t + 1e-12 >= self.next_control:
                act = gait_rule_array(self.cell_air(q), g["n1"], g["n2"], closed=True)
                self.p_cmd = p_on * act
                self.history.append((t, int(act.sum())))
                self.next_control += g["control_period_s"] * math.ceil(
                    (t + 1e-12 - self.next_control) / g["control_period_s"] + 1e-9) or g["control_period_s"]
        elif g["type"] == "open_loop":
            period = g["tau_on_s"] + g["tau_off_s"]
            step = int(math.floor(t / period + 1e-12))
            on = (t - step * period) < g["tau_on_s"]
            cmd = np.zeros(self.N)
            if on:
                # forward (+x) = the touch-down point moves to lower cell indices (clockwise ring)
                c = (g["start_cell"] - g["direction"] * step) % self.N
                cmd[c] = p_on
                if g["torque"] == "high":
                    cmd[(c + self.N // 2) % self.N] = p_on
            self.p_cmd = cmd
        else:
            from ..motion import profile_value
            cmd = np.zeros(self.N)
            for j, act in self.profiles:
                cmd[j] = p_on * float(profile_value(act.profile, t, act.value))
            self.p_cmd = cmd

    def __call__(self, t, sim):
        self.command(t, sim.q)
        dt = max(t - self.t_last, 0.0)
        tau = self.b["fill_time_s"]
        if tau > 0:
            self.p = self.p_cmd + (self.p - self.p_cmd) * math.exp(-dt / tau)
        else:
            self.p = self.p_cmd.copy()
        self.t_last = t
        self._set_rest_angles()

    def _set_rest_angles(self):
        kap = self.kappa_per_kpa * self.p                       # extra curvature per cell, 1/m
        kh = 0.5 * (kap[self.h_cells[:, 0]] + kap[self.h_cells[:, 1]])
        self.sys.theta0[:] = self.theta_base + kh * self.ls


class SheetController:
    """Actuator profiles -> D per cell gap -> pitch (anchors) and fold (rest angle)."""

    def __init__(self, acts, d_const, d_basis, P0, s, lh, closing, opening, tilt, system):
        self.acts = acts
        self.d_const = d_const
        self.d_basis = d_basis
        self.P0, self.s, self.lh = P0, s, lh
        self.closing, self.opening = closing, opening
        self.tilt_tan = np.tan(tilt)
        self.sys = system

    # its actuation depends on the time only: Simulator._burst (burst.py) asks for the actuation of a block of steps
    # at once (block_actuation: gap_D, then __call__'s ufuncs on the block) and lets the compiled kernel copy each
    # step's row in before the step (mm_sheet_steps)
    time_only = True

    def values(self, t):
        from ..motion import profile_value
        return np.array([float(profile_value(a.profile, t, a.value)) for a in self.acts])

    def gap_D(self, times):
        """D per cell gap at each of ``times`` (s), shape ``(len(times), gaps)``, before ``__call__``'s clip: the
        numbers ``__call__`` computes, row for row. The profiles are evaluated for all times at once (the same
        elementwise operations as for one time); the product with ``d_basis`` is taken per row, as in ``__call__``
        (a BLAS may round a matrix-matrix product differently from the matrix-vector one)."""
        from ..motion import profile_value
        times = np.asarray(times, dtype=float).reshape(-1)
        n = times.size
        D = np.empty((n, self.d_const.size))
        if not self.acts:
            D[:] = self.d_const
            return D
        V = np.empty((n, len(self.acts)))
        for k, a in enumerate(self.acts):
            V[:, k] = profile_value(a.profile, times, a.value)
        mm, basis = np.matmul, self.d_basis
        for i in range(n):
            mm(basis, V[i], out=D[i])
        D += self.d_const          # d_const + (d_basis @ values): an addition is exact either way round
        return D

    def actuation(self, D):
        """The anchors' x (``ra``, ``rb``: plus and minus half the pitch) and the rest angles for D per gap: one row
        (``__call__``) or a block of rows (:meth:`block_actuation`), the same ufuncs element for element."""
        D = np.clip(D, -1.0, 1.0)     # the quadratic model keeps |D| <= max |actuator| <= 1 already
        phi = np.where(D >= 0, D * self.closing, -D * self.opening)
        pitch = np.where(D >= 0, self.lh + self.s * (np.cos(phi) - np.sin(phi)),
                         self.lh + self.s * (np.cos(phi) + np.sin(phi)))
        # out-of-plane fold of tilted hinges: gamma = 2 phi tan(tilt), signed with D
        return pitch / 2, -pitch / 2, 2.0 * np.sign(D) * phi * self.tilt_tan

    def block_actuation(self, times):
        """:meth:`actuation` at each of ``times`` (s): three C-contiguous (len(times), gaps) arrays, the rows the
        compiled kernel copies in before each step (``mm_sheet_steps``)."""
        return tuple(np.ascontiguousarray(a, dtype=float) for a in self.actuation(self.gap_D(times)))

    def __call__(self, t, sim):
        D = self.d_const + self.d_basis @ self.values(t) if self.acts else self.d_const
        ra, rb, th = self.actuation(D)
        self.sys.ra[:, 0] = ra
        self.sys.rb[:, 0] = rb
        self.sys.theta0[:] = th
