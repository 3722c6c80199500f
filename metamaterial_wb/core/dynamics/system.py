"""Planar rigid-body network: rigid nodes, elastic hinges, gravity, floor contact with Coulomb friction.

Everything lives in the *floor frame* (SI units: m, kg, s, rad): x runs along the floor (up the
incline), y is the floor normal, the floor is the line ``y = 0``. An incline of angle ``alpha``
is modelled by tilting gravity: ``g = (-g sin alpha, -g cos alpha)``, so a positive incline rises
towards +x.

Bodies (rigid nodes): state ``q = (x, y, theta)`` and ``v = (vx, vy, omega)`` per body; mass and
inertia per body; bodies can be fixed (infinite mass, e.g. a pendulum pivot).

Hinges join body ``a`` and body ``b``:

* a *pin spring* between the anchor ``ra`` (in a's frame) and ``rb`` (in b's frame), isotropic,
  zero rest length, stiffness ``kp`` and damping ``cp`` (the axial / shear stiffness of the hinge);
* a *torsional spring* on the relative angle ``theta_b - theta_a - theta0`` with stiffness ``kr``
  and damping ``cr``. ``theta0`` (rest angle) and the anchors are what actuators change over time
  (servo position sources, pneumatic rest curvature, contracting cells).

Contacts are points ``rc`` fixed on bodies. Normal force: penalty ``kn * pen - cn * v_n`` (never
pulling). Tangential force: an elastic-plastic "bristle": a spring ``kt`` to an anchor on the floor
plus damping ``ct``, capped at ``mu * fn`` (Coulomb cone); when the cap is reached the anchor slides
(the contact slips) and the energy it loses is booked as friction dissipation. This gives true
sticking on an incline shallower than ``atan(mu)``, unlike a velocity-regularised friction law.

``forces`` is fully vectorised (no per-body Python loop); ``jacobians`` returns the analytic
``dQ/dq`` and ``dQ/dv`` blocks that the implicit integrator assembles into one sparse matrix with a
sparsity pattern fixed at construction.
"""
from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from ..errors import MetamaterialError


class DynamicsError(MetamaterialError):
    """The simulation cannot continue (unstable, non-finite, impossible parameters)."""


def _rot(th, r):
    c, s = np.cos(th), np.sin(th)
    out = np.empty(r.shape)
    out[:, 0] = c * r[:, 0] - s * r[:, 1]
    out[:, 1] = s * r[:, 0] + c * r[:, 1]
    return out


def _perp(u):
    out = np.empty(u.shape)
    out[:, 0] = -u[:, 1]
    out[:, 1] = u[:, 0]
    return out


def _cross(u, f):
    return u[:, 0] * f[:, 1] - u[:, 1] * f[:, 0]


class PlanarSystem:
    def __init__(self, mass, inertia, fixed=None, gravity=(0.0, -9.81)):
        self.mass = np.asarray(mass, float).copy()
        self.inertia = np.asarray(inertia, float).copy()
        self.n = self.mass.size
        if np.any(~np.isfinite(self.mass)) or np.any(self.mass <= 0):
            raise DynamicsError("every body needs a positive finite mass")
        if np.any(~np.isfinite(self.inertia)) or np.any(self.inertia <= 0):
            raise DynamicsError("every body needs a positive finite moment of inertia")
        self.fixed = np.zeros(self.n, bool) if fixed is None else np.asarray(fixed, bool).copy()
        self.gravity = np.asarray(gravity, float)
        self.M = np.column_stack([self.mass, self.mass, self.inertia])      # (n, 3)
        self.free_dof = np.repeat(~self.fixed, 3)
        # hinges
        self.ha = np.zeros(0, np.int64)
        self.hb = np.zeros(0, np.int64)
        self.ra = np.zeros((0, 2))
        self.rb = np.zeros((0, 2))
        self.kp = self.cp = self.kr = self.cr = self.theta0 = np.zeros(0)
        # contacts
        self.cb = np.zeros(0, np.int64)
        self.rc = np.zeros((0, 2))
        self.mu = self.kn = self.cn = self.kt = self.ct = np.zeros(0)
        self._pattern = None
        self._band = None
        self._fsc = None
        self.last_damping_power = 0.0

    def com_weights(self):
        """Mass fractions of the free bodies: the centre of mass whose travel the summaries report is
        ``com_weights() @ q[:, 0]`` (fixed bodies, a belt's frame or a ground, do not travel)."""
        m = self.mass * ~self.fixed
        return m / m.sum() if m.sum() > 0 else m

    # -- construction -----------------------------------------------------------------------
    def set_hinges(self, a, b, ra, rb, kp, cp, kr, cr, theta0=0.0):
        m = len(a)
        self.ha = np.asarray(a, np.int64)
        self.hb = np.asarray(b, np.int64)
        self.ra = np.asarray(ra, float).reshape(m, 2).copy()
        self.rb = np.asarray(rb, float).reshape(m, 2).copy()
        f = lambda x: np.broadcast_to(np.asarray(x, float), (m,)).copy()
        self.kp, self.cp, self.kr, self.cr, self.theta0 = f(kp), f(cp), f(kr), f(cr), f(theta0)
        self._pattern = None
        self._band = None
        self._fsc = None

    def set_contacts(self, body, rc, mu, kn, cn, kt, ct):
        p = len(body)
        self.cb = np.asarray(body, np.int64)
        self.rc = np.asarray(rc, float).reshape(p, 2).copy()
        f = lambda x: np.broadcast_to(np.asarray(x, float), (p,)).copy()
        self.mu, self.kn, self.cn, self.kt, self.ct = f(mu), f(kn), f(cn), f(kt), f(ct)
        if np.any(self.mu < 0):
            raise DynamicsError("friction coefficients must be >= 0")
        self._pattern = None
        self._band = None
        self._fsc = None

    # -- geometry -----------------------------------------------------------------------------
    def contact_points(self, q):
        return q[self.cb, :2] + _rot(q[self.cb, 2], self.rc)

    # -- forces -------------------------------------------------------------------------------
    def forces(self, q, v, anchors, frozen=None):
        """Generalised forces Q (n, 3) and the contact state used (dict).

        ``frozen``: a contact state from an earlier call; its touching / sticking / slip-direction
        flags are reused (a smooth residual for Newton's method within one implicit step)."""
        n = self.n
        if getattr(self, "_fsc", None) is None:
            self._build_force_scatter()
        th = q[:, 2]
        cth, sth = np.cos(th), np.sin(th)
        parts = []
        a, b = self.ha, self.hb
        if a.size:
            rax, ray, rbx, rby = self.ra[:, 0], self.ra[:, 1], self.rb[:, 0], self.rb[:, 1]   # actuators move them
            ca, sa, cb, sb = cth[a], sth[a], cth[b], sth[b]
            Rax = ca * rax - sa * ray
            Ray = sa * rax + ca * ray
            Rbx = cb * rbx - sb * rby
            Rby = sb * rbx + cb * rby
            qa, qb, va, vb = q[a], q[b], v[a], v[b]
            wa, wb = va[:, 2], vb[:, 2]
            dx = qb[:, 0] + Rbx - qa[:, 0] - Rax
            dy = qb[:, 1] + Rby - qa[:, 1] - Ray
            vdx = vb[:, 0] - wb * Rby - va[:, 0] + wa * Ray
            vdy = vb[:, 1] + wb * Rbx - va[:, 1] - wa * Rax
            fx = -self.kp * dx - self.cp * vdx
            fy = -self.kp * dy - self.cp * vdy
            dw = wb - wa
            tr = -self.kr * (qb[:, 2] - qa[:, 2] - self.theta0) - self.cr * dw
            self.last_damping_power = float(self.cp @ (vdx * vdx + vdy * vdy) + self.cr @ (dw * dw))
            parts += [fx, fy, Rbx * fy - Rby * fx + tr, Ray * fx - Rax * fy - tr]
        st = None
        if self.cb.size:
            c = self.cb
            rcx, rcy = self.rc[:, 0], self.rc[:, 1]
            cc, sc = cth[c], sth[c]
            ux = cc * rcx - sc * rcy
            uy = sc * rcx + cc * rcy
            qc, vc = q[c], v[c]
            w = vc[:, 2]
            px = qc[:, 0] + ux
            py = qc[:, 1] + uy
            vpx = vc[:, 0] - w * uy
            vpy = vc[:, 1] + w * ux
            inside = py < 0 if frozen is None else frozen["inside"]
            fn = np.where(inside, np.maximum(0.0, -self.kn * py - self.cn * vpy), 0.0)
            trial = -self.kt * (px - anchors) - self.ct * vpx
            cap = self.mu * fn
            if frozen is None:
                stick = np.abs(trial) <= cap
                sgn = np.sign(trial)
            else:
                stick, sgn = frozen["stick"], frozen["sgn"]
            ft = np.where(inside, np.where(stick, trial, sgn * cap), 0.0)
            parts += [ft, fn, ux * fn - uy * ft]
            st = {"ux": ux, "uy": uy, "inside": inside, "fn": fn, "ft": ft, "stick": stick, "sgn": sgn,
                  "pushing": inside & (fn > 0)}
        Q = np.empty((n, 3))
        Q[:, 0] = self.mass * self.gravity[0]
        Q[:, 1] = self.mass * self.gravity[1]
        Q[:, 2] = 0.0
        Q = Q.ravel()
        if parts:
            Q += self._fsc @ np.concatenate(parts)
        return Q.reshape(n, 3), st

    def dissipation_power(self, q, v, anchors, dt=None, q_start=None, v_start=None, hinges=True):
        """``(hinge dampers, contact dampers)`` power in W at the state (q, v): what the dampers take
        out of the mechanical energy. Contacts: the normal force's non-elastic part,
        ``-(fn - kn pen) v_n`` (the damper ``cn v_n``, and the penalty energy a separating point
        loses while ``fn`` is clamped at 0), and the tangential damper ``ct v_t^2`` of sticking points
        (slip losses are booked as friction when the anchors move). ``dt``: the step over which the
        power is applied; a clamped point's loss is capped at its penalty energy per step (it cannot
        lose more than it holds). ``q_start, v_start``: the state at the step's start; a point that
        enters the floor during the step counts for the part of its motion spent in the floor, and
        one that leaves it counts, at the start state's power, for the part spent before leaving."""
        ph = 0.0
        a, b = self.ha, self.hb
        if a.size and hinges:
            Ra, Rb = _rot(q[a, 2], self.ra), _rot(q[b, 2], self.rb)
            wa, wb = v[a, 2], v[b, 2]
            vdx = v[b, 0] - wb * Rb[:, 1] - v[a, 0] + wa * Ra[:, 1]
            vdy = v[b, 1] + wb * Rb[:, 0] - v[a, 1] - wa * Ra[:, 0]
            dw = wb - wa
            ph = float(self.cp @ (vdx * vdx + vdy * vdy) + self.cr @ (dw * dw))
        if not self.cb.size:
            return ph, 0.0
        py_end, p_end = self._contact_damper_power(q, v, anchors, dt)
        if q_start is None:
            return ph, float(np.sum(p_end))
        c = self.cb
        py0 = q_start[c, 1] + _rot(q_start[c, 2], self.rc)[:, 1]
        pc = 0.0
        enter = (py0 >= 0) & (py_end < 0)
        stay = (py0 < 0) & (py_end < 0)
        pc += float(np.sum(p_end[stay]))
        if np.any(enter):
            pc += float(np.sum(p_end[enter] * (-py_end[enter]) / (py0[enter] - py_end[enter])))
        leave = (py0 < 0) & (py_end >= 0)
        if np.any(leave) and v_start is not None:
            _, p0 = self._contact_damper_power(q_start, v_start, anchors, dt)
            pc += float(np.sum(p0[leave] * (-py0[leave]) / (py_end[leave] - py0[leave])))
        return ph, pc

    def _contact_damper_power(self, q, v, anchors, dt=None):
        """Per contact point: height ``py`` and the contact dampers' power (0 in the air)."""
        c = self.cb
        u = _rot(q[c, 2], self.rc)
        py = q[c, 1] + u[:, 1]
        out = np.zeros(len(c))
        k = np.nonzero(py < 0)[0]
        if k.size:
            ck, uk = c[k], u[k]
            vpx = v[ck, 0] - v[ck, 2] * uk[:, 1]
            vpy = v[ck, 1] + v[ck, 2] * uk[:, 0]
            pen = -py[k]
            kn, cn = self.kn[k], self.cn[k]
            fn = np.maximum(0.0, kn * pen - cn * vpy)
            dn = -(fn - kn * pen) * vpy
            if dt is not None:
                dn = np.where(fn > 0, dn, np.minimum(dn, 0.5 * kn * pen * pen / dt))
            ct = self.ct[k]
            trial = -self.kt[k] * (q[ck, 0] + uk[:, 0] - anchors[k]) - ct * vpx
            stick = np.abs(trial) <= self.mu[k] * fn
            out[k] = dn + np.where(stick, ct * vpx * vpx, 0.0)
        return py, out

    def _build_force_scatter(self):
        """A constant sparse matrix that sums the hinge and contact forces into Q (one product
        instead of many scatter-adds)."""
        n, m, p = self.n, self.ha.size, self.cb.size
        a, b, c = self.ha, self.hb, self.cb
        ar_m, ar_p = np.arange(m), np.arange(p)
        rows = [3 * b, 3 * a, 3 * b + 1, 3 * a + 1, 3 * b + 2, 3 * a + 2, 3 * c, 3 * c + 1, 3 * c + 2]
        cols = [ar_m, ar_m, m + ar_m, m + ar_m, 2 * m + ar_m, 3 * m + ar_m,
                4 * m + ar_p, 4 * m + p + ar_p, 4 * m + 2 * p + ar_p]
        vals = [np.ones(m), -np.ones(m), np.ones(m), -np.ones(m), np.ones(m), np.ones(m),
                np.ones(p), np.ones(p), np.ones(p)]
        if not m:
            rows, cols, vals = rows[6:], [x - 4 * m for x in cols[6:]], vals[6:]
        self._fsc = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                                  shape=(3 * n, (4 * m if m else 0) + 3 * p))

    # -- Jacobians ---------------------------------------------------------------------------
    def _build_pattern(self):
        """COO index pattern of all blocks, reduced to the free dofs; map to CSR data."""
        dofs_h = np.column_stack([3 * self.ha, 3 * self.ha + 1, 3 * self.ha + 2,
                                  3 * self.hb, 3 * self.hb + 1, 3 * self.hb + 2])       # (m, 6)
        rows_h = np.repeat(dofs_h, 6, axis=1).ravel()
        cols_h = np.tile(dofs_h, (1, 6)).ravel()
        dofs_c = np.column_stack([3 * self.cb, 3 * self.cb + 1, 3 * self.cb + 2])       # (p, 3)
        rows_c = np.repeat(dofs_c, 3, axis=1).ravel()
        cols_c = np.tile(dofs_c, (1, 3)).ravel()
        N = 3 * self.n
        diag = np.arange(N)
        rows = np.concatenate([rows_h, rows_c, diag])
        cols = np.concatenate([cols_h, cols_c, diag])
        free = self.free_dof
        keep = free[rows] & free[cols]
        # fixed dofs: identity rows (their velocity never changes)
        lin = rows * N + cols
        uniq, inv = np.unique(lin[keep], return_inverse=True)
        self._pattern = {
            "keep": keep, "inv": inv, "nnz": uniq.size,
            "rows": uniq // N, "cols": uniq % N, "N": N,
            "nh": rows_h.size, "nc": rows_c.size,
        }
        csr = sp.csr_matrix((np.arange(1, uniq.size + 1, dtype=float), (uniq // N, uniq % N)), shape=(N, N))
        # order of csr.data relative to uniq
        self._pattern["csr_indices"] = csr.indices.copy()
        self._pattern["csr_indptr"] = csr.indptr.copy()
        self._pattern["csr_perm"] = (csr.data - 1).astype(np.int64)   # data[k] = uniq value #perm[k]

    def jacobian_blocks(self, q, v, anchors, st):
        """Flattened dQ/dq and dQ/dv entries in pattern order (hinge blocks, contact blocks)."""
        Kh, Ch = self._hinge_blocks(q, v)
        p = self.cb.size
        Kc = np.zeros((p, 3, 3))
        Cc = np.zeros((p, 3, 3))
        if p:
            # only touching contacts contribute: compute their blocks and scatter them
            idx = self._active_contacts(st)
            Kc[idx], Cc[idx] = self._contact_blocks(idx, v, st)
        return Kh, Ch, Kc, Cc

    @staticmethod
    def _active_contacts(st):
        return np.flatnonzero(st["pushing"] | (st["ft"] != 0.0) | (st["fn"] != 0.0))

    def _hinge_blocks(self, q, v):
        a, b = self.ha, self.hb
        m = a.size
        Kh = np.zeros((m, 6, 6))
        Ch = np.zeros((m, 6, 6))
        if m:
            Ra = _rot(q[a, 2], self.ra)
            Rb = _rot(q[b, 2], self.rb)
            Jd = np.zeros((m, 2, 6))
            Jd[:, 0, 0] = -1.0
            Jd[:, 1, 1] = -1.0
            Jd[:, :, 2] = -_perp(Ra)
            Jd[:, 0, 3] = 1.0
            Jd[:, 1, 4] = 1.0
            Jd[:, :, 5] = _perp(Rb)
            d = q[b, :2] + Rb - q[a, :2] - Ra
            wa, wb = v[a, 2], v[b, 2]
            vd = v[b, :2] + wb[:, None] * _perp(Rb) - v[a, :2] - wa[:, None] * _perp(Ra)
            f = -self.kp[:, None] * d - self.cp[:, None] * vd
            # small per-hinge products as broadcast sums (much faster than stacked matmul)
            JtJ = (Jd[:, :, :, None] * Jd[:, :, None, :]).sum(axis=1)
            G = np.zeros((m, 2, 6))
            G[:, :, 2] = wa[:, None] * Ra
            G[:, :, 5] = -wb[:, None] * Rb
            Kh = -self.kp[:, None, None] * JtJ - self.cp[:, None, None] * (Jd[:, :, :, None] * G[:, :, None, :]).sum(axis=1)
            Kh[:, 2, 2] += (Ra * f).sum(axis=1)
            Kh[:, 5, 5] -= (Rb * f).sum(axis=1)
            Ch = -self.cp[:, None, None] * JtJ
            for (i, j, s) in ((5, 5, -1), (5, 2, 1), (2, 5, 1), (2, 2, -1)):
                Kh[:, i, j] += s * self.kr
                Ch[:, i, j] += s * self.cr
        return Kh, Ch

    def _contact_blocks(self, idx, v, st):
        p = idx.size
        if not p:
            return np.zeros((0, 3, 3)), np.zeros((0, 3, 3))
        u = np.column_stack([st["ux"][idx], st["uy"][idx]])
        pushing, stick = st["pushing"][idx], st["stick"][idx]
        kn, cn, kt, ct, mu = self.kn[idx], self.cn[idx], self.kt[idx], self.ct[idx], self.mu[idx]
        w = v[self.cb[idx], 2]
        Jp = np.zeros((p, 2, 3))
        Jp[:, 0, 0] = 1.0
        Jp[:, 1, 1] = 1.0
        Jp[:, :, 2] = _perp(u)
        K = np.zeros((p, 2, 2))
        C = np.zeros((p, 2, 2))
        on = pushing.astype(float)
        st_ = (pushing & stick).astype(float)
        sl = (pushing & ~stick).astype(float)
        K[:, 1, 1] = on * kn
        C[:, 1, 1] = on * cn
        K[:, 0, 0] = st_ * kt
        C[:, 0, 0] = st_ * ct
        # sliding: ft = sgn * mu * fn, fn = -kn py - cn vy  ->  dft/dpy = -sgn mu kn  (K = -df/dp)
        K[:, 0, 1] = sl * mu * st["sgn"][idx] * kn
        C[:, 0, 1] = sl * mu * st["sgn"][idx] * cn
        dvdq = np.zeros((p, 2, 3))
        dvdq[:, :, 2] = -w[:, None] * u
        JpT = Jp.transpose(0, 2, 1)
        Kc = -np.matmul(JpT, np.matmul(K, Jp) + np.matmul(C, dvdq))
        Kc[:, 2, 2] -= u[:, 0] * st["ft"][idx] + u[:, 1] * st["fn"][idx]
        Cc = -np.matmul(JpT, np.matmul(C, Jp))
        return Kc, Cc

    def band_system_matrix(self, q, v, st, dt, reuse_hinges=False, dense=False):
        """A = M - dt dQ/dv - dt^2 dQ/dq in LAPACK band storage (``band_layout`` order), or dense
        (``dense=True``, natural order). With
        ``reuse_hinges`` the hinge part of the last call (same dt) is kept and only the touching
        contacts are re-evaluated: within one Newton solve the hinges' Jacobian is lagged (the
        residual stays exact, so only the convergence rate can change) while the contact set,
        which is what changes between iterates, is always current."""
        self._ensure_scatter()
        P = self._pattern
        c = getattr(self, "_hcache", None)
        if not (reuse_hinges and c is not None and c[0] == dt):
            Kh, Ch = self._hinge_blocks(q, v)
            base = P["Mdata"] - P["Sh"] @ (dt * Ch.ravel() + (dt * dt) * Kh.ravel())
            self._hcache = c = (dt, base)
        A_data = c[1].copy()
        if self.cb.size and st is not None:
            idx = self._active_contacts(st)
            if idx.size:
                Kc, Cc = self._contact_blocks(idx, v, st)
                cols = P["cmap"][idx].ravel()
                vals = (dt * Cc + (dt * dt) * Kc).ravel()
                ok = cols >= 0
                A_data -= np.bincount(cols[ok], vals[ok], P["nnz"])
        if dense:
            N = P["N"]
            A = np.zeros((N, N))
            A[P["rows"], P["cols"]] = A_data
            fx = ~self.free_dof
            A[fx, fx] = 1.0
            return A
        return self._band_matrix(A_data)

    def _ensure_scatter(self):
        if self._pattern is None:
            self._build_pattern()
        P = self._pattern
        if "S" in P:
            return
        # scatter matrix: block entries (hinges, contacts) -> unique pattern entries; the mass
        # diagonal is a constant part
        nb = P["nh"] + P["nc"]
        keep = P["keep"][:nb]
        nk = int(keep.sum())
        P["S"] = sp.csr_matrix((np.ones(nk), (P["inv"][:nk], np.flatnonzero(keep))), shape=(P["nnz"], nb))
        P["Sh"] = P["S"][:, :P["nh"]].tocsr()
        full = np.full(nb, -1, np.int64)
        full[np.flatnonzero(keep)] = P["inv"][:nk]
        P["cmap"] = full[P["nh"]:].reshape(-1, 9)
        Mdiag = np.where(self.free_dof, self.M.ravel(), 1.0)
        md = np.concatenate([np.zeros(nb), Mdiag])[P["keep"]]
        P["Mdata"] = np.bincount(P["inv"], md, P["nnz"])

    def system_matrix(self, q, v, anchors, st, dt, dense=False):
        """A = M - dt dQ/dv - dt^2 dQ/dq on the free dofs (identity on fixed dofs), and dQ/dq."""
        if self._pattern is None:
            self._build_pattern()
        P = self._pattern
        Kh, Ch, Kc, Cc = self.jacobian_blocks(q, v, anchors, st)
        N = P["N"]
        self._ensure_scatter()
        S = P["S"]
        kq_all = np.concatenate([Kh.ravel(), Kc.ravel()])
        cv_all = np.concatenate([Ch.ravel(), Cc.ravel()])
        A_data = P["Mdata"] - S @ (dt * cv_all + (dt * dt) * kq_all)
        if dense == "band":
            return self._band_matrix(A_data), None
        K_data = S @ kq_all
        # fixed dofs: identity
        if dense:
            A = np.zeros((N, N))
            A[P["rows"], P["cols"]] = A_data
            K = np.zeros((N, N))
            K[P["rows"], P["cols"]] = K_data
            fx = ~self.free_dof
            A[fx, fx] = 1.0
            return A, K
        A = sp.csr_matrix((A_data[P["csr_perm"]], P["csr_indices"], P["csr_indptr"]), shape=(N, N))
        K = sp.csr_matrix((K_data[P["csr_perm"]], P["csr_indices"], P["csr_indptr"]), shape=(N, N))
        if np.any(~self.free_dof):
            fx = np.flatnonzero(~self.free_dof)
            A = A + sp.csr_matrix((np.ones(fx.size), (fx, fx)), shape=(N, N))
        return A, K

    # -- banded form (chains and rings) --------------------------------------------------------
    band_max = 64     # use the banded LU when the reordered half-bandwidth is at most this

    def rcm_order(self):
        """Reverse Cuthill-McKee order of the dofs on the Jacobian's pattern: ``(perm, pos, rows, cols, kl,
        ku)`` with ``pos`` the inverse permutation, ``rows``/``cols`` the pattern's entries in that order
        and ``kl``/``ku`` the lower/upper half-bandwidths there."""
        if self._pattern is None:
            self._build_pattern()
        P = self._pattern
        N = P["N"]
        from scipy.sparse.csgraph import reverse_cuthill_mckee
        G = sp.csr_matrix((np.ones(P["nnz"]), (P["rows"], P["cols"])), shape=(N, N))
        G = (G + G.T + sp.identity(N, format="csr")).tocsr()
        perm = np.asarray(reverse_cuthill_mckee(G, symmetric_mode=True), np.int64)
        pos = np.empty(N, np.int64)
        pos[perm] = np.arange(N)
        r, c = pos[P["rows"]], pos[P["cols"]]
        kl = int(max(0, np.max(r - c))) if r.size else 0
        ku = int(max(0, np.max(c - r))) if r.size else 0
        return perm, pos, r, c, kl, ku

    def band_layout(self):
        """A reverse Cuthill-McKee ordering of the dofs and its half-bandwidth, or None when the
        matrix is not narrow-banded. A chain numbered along itself is banded as it is; a ring
        (a closed chain) becomes banded with half-bandwidth ~ 3 * 2 + 2 after the reordering
        (the zig-zag 0, n-1, 1, n-2, ...), so one LAPACK band LU (dgbtrf) costs O(n) instead of a
        general sparse LU."""
        if getattr(self, "_band", None) is not None:
            return self._band or None
        perm, pos, r, c, kl, ku = self.rcm_order()
        N = perm.size
        if max(kl, ku) > self.band_max or N < 60:
            self._band = False
            return None
        fx = np.flatnonzero(~self.free_dof)
        self._band = {"perm": perm, "pos": pos, "kl": kl, "ku": ku, "N": N,
                      "brow": kl + ku + r - c, "bcol": c, "fx_row": np.full(fx.size, kl + ku), "fx_col": pos[fx]}
        return self._band

    def _band_matrix(self, A_data):
        B = self._band
        ab = np.zeros((2 * B["kl"] + B["ku"] + 1, B["N"]))
        ab[B["brow"], B["bcol"]] = A_data
        if B["fx_col"].size:
            ab[B["fx_row"], B["fx_col"]] = 1.0
        return ab

    def stiffness_bound(self):
        """(omega_K, omega_C): the stiffest mode (rad/s) and the strongest damping rate (1/s) of the
        mass-scaled symmetric parts (Lanczos / dense eigenvalues, +5 %), else upper bounds from Gershgorin row sums of M^-1/2 dQ/dq M^-1/2 and M^-1/2 dQ/dv M^-1/2 with every contact pushing and sticking."""
        q = np.zeros((self.n, 3))
        v = np.zeros((self.n, 3))
        if self._pattern is None:
            self._build_pattern()
        p = self.cb.size
        u0 = _rot(np.zeros(p), self.rc)
        st = {"ux": u0[:, 0], "uy": u0[:, 1], "pushing": np.ones(p, bool), "stick": np.ones(p, bool),
              "sgn": np.zeros(p), "ft": np.zeros(p), "fn": np.zeros(p)}
        Kh, Ch, Kc, Cc = self.jacobian_blocks(q, v, None, st)
        # friction while sliding couples the normal stiffness into the tangent direction
        P = self._pattern
        N = P["N"]
        try:   # the stiffest mode itself (Lanczos), every contact touching and sticking
            import scipy.sparse.linalg as spla
            sq = np.sqrt(self.M.ravel())
            out = []
            for blocks in ((Kh, Kc), (Ch, Cc)):
                vals = np.concatenate([blocks[0].ravel(), blocks[1].ravel(), np.zeros(N)])[P["keep"]]
                data = np.bincount(P["inv"], vals, P["nnz"]) / (sq[P["rows"]] * sq[P["cols"]])
                A = sp.csr_matrix((data, (P["rows"], P["cols"])), shape=(N, N))
                A = 0.5 * (A + A.T)
                fr = np.flatnonzero(self.free_dof)
                A = A[fr][:, fr]
                if A.shape[0] <= 400:
                    lam = float(np.max(np.abs(np.linalg.eigvalsh(A.toarray())))) if A.shape[0] else 0.0
                else:
                    lam = float(abs(spla.eigsh(A, k=1, which="LM", return_eigenvectors=False, tol=1e-3,
                                               maxiter=5000)[0]))
                out.append(lam * 1.05)
            return float(np.sqrt(out[0])), float(out[1])
        except Exception:      # fall back to the Gershgorin bound below
            pass
        out = []
        for blocks in ((Kh, Kc), (Ch, Cc)):
            vals = np.abs(np.concatenate([blocks[0].ravel(), blocks[1].ravel(), np.zeros(N)]))[P["keep"]]
            data = np.bincount(P["inv"], vals, P["nnz"])
            sq = np.sqrt(self.M.ravel())
            rowsum = np.bincount(P["rows"], data / (sq[P["rows"]] * sq[P["cols"]]), N)
            r = np.where(self.free_dof, rowsum, 0.0)
            out.append(float(r.max()) if r.size else 0.0)
        return float(np.sqrt(out[0])), float(out[1])

    # -- energy -------------------------------------------------------------------------------
    def elastic_energy(self, q):
        a, b = self.ha, self.hb
        if not a.size:
            return 0.0
        d = q[b, :2] + _rot(q[b, 2], self.rb) - q[a, :2] - _rot(q[a, 2], self.ra)
        rel = q[b, 2] - q[a, 2] - self.theta0
        return float(0.5 * np.sum(self.kp * np.sum(d * d, axis=1)) + 0.5 * np.sum(self.kr * rel * rel))

    def energy(self, q, v, anchors):
        """Kinetic, gravity, elastic (hinges) and contact (penalty + bristle) energy in J."""
        kin = 0.5 * float(np.sum(self.M * v * v * (~self.fixed)[:, None]))
        grav = -float(np.sum(self.mass[~self.fixed, None] * q[~self.fixed, :2] * self.gravity))
        el = self.elastic_energy(q)
        con = 0.0
        if self.cb.size:
            p = self.contact_points(q)
            pen = np.maximum(-p[:, 1], 0.0)
            inside = pen > 0
            con = float(0.5 * np.sum(self.kn * pen * pen)
                        + 0.5 * np.sum(np.where(inside, self.kt * (p[:, 0] - anchors) ** 2, 0.0)))
        return {"kinetic_J": kin, "gravity_J": grav, "elastic_J": el, "contact_J": con,
                "total_J": kin + grav + el + con}
