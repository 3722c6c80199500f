"""Runs of implicit steps on the compiled kernel, one C call per step (``Simulator._burst``, used by
``Simulator.run`` in integrators.py between its health checks and records).

``mm_step`` (_kernel.c) does what ``step_implicit``'s compiled branch, ``_end_implicit_step``, the ledger's
actuation halves and ``_update_anchors`` do, in the same order with the same operations; between two steps only
the actuator callback runs in Python. ``Simulator.burst = False`` runs every step through ``step_implicit`` (the
reference of the tests).
"""
from __future__ import annotations

import numpy as np

from . import fastkernel
from .system import DynamicsError


class BurstMixin:
    """``Simulator``'s compiled-kernel selection and its one-call-per-step path (a mixin: it reads and writes the
    simulator's state, ledger and statistics, and falls back to its ``_implicit_solve``)."""

    kernel = "auto"           # "auto": the compiled kernel (fastkernel.py) when available, else numpy;
                              # "numpy": always the numpy path; "c": the compiled kernel or a DynamicsError
    _kern = None
    _kern_used = False

    def _layout(self):
        """``(dense, banded)``: how the implicit step solves its Newton systems: dense LU up to 300 degrees of
        freedom, else the band solver when it is on and the system has a band layout (else sparse SuperLU)."""
        dense = 3 * self.sys.n <= 300
        return dense, (not dense and self.use_band and self.sys.band_layout() is not None)

    def _kernel_for(self, dense, banded):
        """The compiled kernel for this step, or None (numpy path). Only the default Newton options
        are compiled; the experimental ones (freezing, lagging, linearised first step) and the
        general sparse (SuperLU) path stay in numpy."""
        s = self.sys
        k = self._kern
        if self.kernel == "numpy":
            self.stats["kernel"] = "numpy"
            return None
        if (self.freeze_contacts or self.freeze_after is not None or self.linearized_first_step or self.lag_hinges
                or not (dense or banded)):
            why = "a non-default Newton option or a layout without band structure"
        elif k is not None and k.matches(s):
            return k
        else:
            why = getattr(self, "_kern_fail", None)
            if why is None:
                lib = fastkernel.load()
                if lib is None:
                    why = fastkernel.note()
                else:
                    try:
                        layout = fastkernel.layout_for(s, band_max=s.band_max)
                        if layout is None:
                            why = "the system matrix is neither narrow-banded nor small"
                        else:
                            self._kern = k = fastkernel.Kernel(lib, s, layout)
                            return k
                    except ValueError as e:
                        why = str(e)
                self._kern_fail = why
        if self.kernel == "c":
            raise DynamicsError(f"compiled dynamics kernel requested but not usable: {why}")
        self.stats["kernel"] = "numpy"
        self.stats["kernel_note"] = why
        return None

    def _compiled(self):
        """The compiled kernel when the last step ran on it and it still matches the system, else None."""
        k = self._kern
        return k if k is not None and self._kern_used and k.matches(self.sys) else None

    burst = True              # run(): implicit steps on the compiled kernel, one C call each (_burst);
                              # False: every step through step_implicit (the reference for the tests)
    _BURST_BYTES = 65536      # output block of _burst (q and v of its steps, views handed out as self.q / self.v)

    def _burst(self, k, dt, n_max, t_end, eps, rec_at, max_it):
        """Up to ``n_max`` implicit steps of ``dt`` on the compiled kernel ``k``, each one ``mm_step`` call (the
        actuation, the BDF2 / backward-Euler Newton solve, the step's end, the ledger's terms, the anchors and the
        centre of mass's extremes of ``step_implicit`` + ``run``, in the same order with the same operations).
        Stops before the step that would be run()'s last one (``t_end - t <= dt + eps``: run() takes it) and
        after a step that reaches ``t_end - eps`` or the next record time ``rec_at``. The ledger and the statistics
        (and the steps counted in ``stats["steps"]``) are written back when it returns, also on an exception (during
        a burst only ``q``, ``v``, ``t``, ``anchors`` and ``inside`` are current). An actuator that replaces one of
        the system's arrays, or binds a new array to ``self.anchors`` / ``self.inside`` (which the kernel updates in
        place), ends the burst with that step on the numpy path (as ``step_implicit``; the next burst reads the new
        arrays). Returns the number of steps taken."""
        s = self.sys
        n = 0
        t = self.t
        if n_max <= 0 or t_end - t <= dt + eps:
            return 0
        lib, Sp, T, Tp, N = k.lib, k.Sp, k.T, k.Tp, k.N
        q = self.q = np.ascontiguousarray(self.q, float)
        v = self.v = np.ascontiguousarray(self.v, float)
        prev = getattr(self, "_prev", None)
        bdf2 = bool(self.bdf2 and prev is not None and abs(prev[2] - dt) <= 1e-12 * dt)
        if bdf2:
            qp, vp = np.ascontiguousarray(prev[0], float), np.ascontiguousarray(prev[1], float)
            self._prev = (qp, vp, prev[2])
            T.qp, T.vp = qp.ctypes.data, vp.ctypes.data
        T.q, T.v = q.ctypes.data, v.ctypes.data
        if not (self.anchors.flags.c_contiguous and self.anchors.dtype == np.float64):
            self.anchors = np.ascontiguousarray(self.anchors, float)
        if not (self.inside.flags.c_contiguous and self.inside.dtype == bool):
            self.inside = np.ascontiguousarray(self.inside, bool)
        anc, ins = self.anchors, self.inside       # the arrays the kernel updates in place (mm_step)
        T.anchors, T.inside = anc.ctypes.data, ins.ctypes.data
        w = self._com_w
        T.w = w.ctypes.data
        led, st = self.ledger, self.stats
        T.aw, T.damp, T.cdamp, T.fric = (led["actuator_work_J"], led["damping_J"], led["contact_damping_J"],
                                         led["friction_J"])
        T.pen, T.com_min, T.com_max = st["max_penetration_mm"], st["com_x_min_m"], st["com_x_max_m"]
        T.fe = T.jac = T.nit = T.unconv = T.bdf2_steps = 0
        T.dt, T.tol_abs, T.tol_rel = dt, self.newton_tol_abs, self.newton_tol_rel
        T.bdf2, T.use_bdf2 = int(bdf2), int(bool(self.bdf2))
        T.max_it, T.max_age, T.refactor = max_it, self.jacobian_max_age, int(bool(self.refactor_on_contact_change))
        lib.mm_save_actuation(Sp, Tp)
        step = lib.mm_step
        act = self.actuate
        get, ids = k._get, k._ids
        B = max(1, min(n_max, self._BURST_BYTES // (16 * N)))
        slot = B
        qs = vs = ()
        off_rec = rec_at is None
        fallback = False
        sheet = getattr(act, "block_actuation", None) if getattr(act, "time_only", False) else None
        if sheet is not None and not (getattr(act, "sys", None) is s and act.d_const.shape == (s.ha.size,)):
            sheet = None
        try:
            if sheet is not None:
                # an actuation that depends on the time only: the D of the whole run of steps in one evaluation,
                # the actuation from it (numpy, __call__'s ufuncs) and the steps in one C call (mm_sheet_steps)
                times = []
                tt = t
                while len(times) < n_max:
                    if t_end - tt <= dt + eps:
                        break
                    tt += dt
                    times.append(tt)
                    if tt >= t_end - eps or not (off_rec or tt < rec_at):
                        break
                if times:
                    acts = sheet(times)
                    nb = len(times)
                    block = np.empty((nb, 2) + q.shape)
                    T.out = block.ctypes.data
                    k.sheet_steps(nb, acts)
                    n = nb
                    self._prev = (block[nb - 2, 0], block[nb - 2, 1], dt) if nb > 1 else (q, v, dt)
                    self.q, self.v = block[nb - 1, 0], block[nb - 1, 1]
                    self.t = t = tt
            while sheet is None and n < n_max:
                if t_end - t <= dt + eps:
                    break
                if act is not None:
                    act(t + dt, self)
                    if tuple(map(id, get(s))) != ids or self.anchors is not anc or self.inside is not ins:
                        fallback = True
                        break
                if slot == B:
                    block = np.empty((B, 2) + q.shape)
                    qs, vs = list(block[:, 0]), list(block[:, 1])
                    T.out = block.ctypes.data
                    slot = 0
                step(Sp, Tp)
                self._prev = (self.q, self.v, dt)
                self.q = qs[slot]
                self.v = vs[slot]
                slot += 1
                t += dt
                self.t = t
                n += 1
                if t >= t_end - eps or not (off_rec or t < rec_at):
                    break
        finally:      # the steps taken are booked also when the actuator raises
            led["actuator_work_J"], led["damping_J"], led["contact_damping_J"], led["friction_J"] = (
                T.aw, T.damp, T.cdamp, T.fric)
            st["max_penetration_mm"], st["com_x_min_m"], st["com_x_max_m"] = T.pen, T.com_min, T.com_max
            st["force_evaluations"] += T.fe
            st["steps"] += n
            for key, c in (("jacobians", T.jac), ("newton_iterations", T.nit), ("newton_unconverged_steps", T.unconv),
                           ("bdf2_steps", T.bdf2_steps)):
                if c:
                    st[key] = st.get(key, 0) + c
        if fallback:
            # the actuator replaced an array the kernel reads or writes: this step on the numpy path, as
            # step_implicit (its actuation is set: _apply_actuation's booking, with the kernel's saved old one)
            old = (k.th_old.copy(), k.ra_old.reshape(-1, 2).copy(), k.rb_old.reshape(-1, 2).copy())
            same = (np.array_equal(old[0], s.theta0) and np.array_equal(old[1], s.ra)
                    and np.array_equal(old[2], s.rb))
            self._book_actuation(None if same else old)
            self._implicit_solve(dt)
            n += 1
            st["steps"] += 1
            self._track_com()
        return n
