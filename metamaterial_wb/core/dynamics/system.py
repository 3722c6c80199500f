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
        self.last_damping_power = 0.0

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

    def set_contacts(self, body, rc, mu, kn, cn, kt, ct):
        p = len(body)
        self.cb = np.asarray(body, np.int64)
        self.rc = np.asarray(rc, float).reshape(p, 2).copy()
        f = lambda x: np.broadcast_to(np.asarray(x, float), (p,)).copy()
        self.mu, self.kn, self.cn, self.kt, self.ct = f(mu), f(kn), f(cn), f(kt), f(ct)
        if np.any(self.mu < 0):
            raise DynamicsError("friction coefficients must be >= 0")
        self._pattern = None

    # -- geometry -----------------------------------------------------------------------------
    def contact_points(self, q):
        return q[self.cb, :2] + _rot(q[self.cb, 2], self.rc)

    # -- forces -------------------------------------------------------------------------------
    def forces(self, q, v, anchors, frozen=None):
        """Generalised forces Q (n, 3) and the contact state used (dict).

        ``frozen``: a contact state from an earlier call; its touching / sticking / slip-direction
        flags are reused (a smooth residual for Newton's method within one implicit step)."""
        n = self.n
        Q = np.zeros((n, 3))
        Q[:, 0] = self.mass * self.gravity[0]
        Q[:, 1] = self.mass * self.gravity[1]
        a, b = self.ha, self.hb
        if a.size:
            Ra = _rot(q[a, 2], self.ra)
            Rb = _rot(q[b, 2], self.rb)
            d = q[b, :2] + Rb - q[a, :2] - Ra
            wa, wb = v[a, 2], v[b, 2]
            vd = v[b, :2] + wb[:, None] * _perp(Rb) - v[a, :2] - wa[:, None] * _perp(Ra)
            f = -self.kp[:, None] * d - self.cp[:, None] * vd
            tr = -self.kr * (q[b, 2] - q[a, 2] - self.theta0) - self.cr * (wb - wa)
            self.last_damping_power = float(np.sum(self.cp * np.sum(vd * vd, axis=1))
                                            + np.sum(self.cr * (wb - wa) ** 2))
            tb = _cross(Rb, f) + tr
            ta = -_cross(Ra, f) - tr
            Q[:, 0] += np.bincount(b, f[:, 0], n) - np.bincount(a, f[:, 0], n)
            Q[:, 1] += np.bincount(b, f[:, 1], n) - np.bincount(a, f[:, 1], n)
            Q[:, 2] += np.bincount(b, tb, n) + np.bincount(a, ta, n)
        st = None
        if self.cb.size:
            c = self.cb
            u = _rot(q[c, 2], self.rc)
            p = q[c, :2] + u
            vp = v[c, :2] + v[c, 2][:, None] * _perp(u)
            pen = -p[:, 1]
            inside = pen > 0 if frozen is None else frozen["inside"]
            fn = np.where(inside, np.maximum(0.0, self.kn * pen - self.cn * vp[:, 1]), 0.0)
            trial = -self.kt * (p[:, 0] - anchors) - self.ct * vp[:, 0]
            cap = self.mu * fn
            if frozen is None:
                stick = np.abs(trial) <= cap
                sgn = np.sign(trial)
            else:
                stick, sgn = frozen["stick"], frozen["sgn"]
            ft = np.where(inside, np.where(stick, trial, sgn * cap), 0.0)
            fc = np.column_stack([ft, fn])
            Q[:, 0] += np.bincount(c, ft, n)
            Q[:, 1] += np.bincount(c, fn, n)
            Q[:, 2] += np.bincount(c, _cross(u, fc), n)
            st = {"u": u, "p": p, "vp": vp, "inside": inside, "fn": fn, "stick": stick, "sgn": sgn,
                  "fc": fc, "pushing": inside & (fn > 0)}
        return Q, st

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
            JdT = Jd.transpose(0, 2, 1)
            JtJ = np.matmul(JdT, Jd)
            G = np.zeros((m, 2, 6))
            G[:, :, 2] = wa[:, None] * Ra
            G[:, :, 5] = -wb[:, None] * Rb
            Kh = -self.kp[:, None, None] * JtJ - self.cp[:, None, None] * np.matmul(JdT, G)
            Kh[:, 2, 2] += (Ra * f).sum(axis=1)
            Kh[:, 5, 5] -= (Rb * f).sum(axis=1)
            Ch = -self.cp[:, None, None] * JtJ
            for (i, j, s) in ((5, 5, -1), (5, 2, 1), (2, 5, 1), (2, 2, -1)):
                Kh[:, i, j] += s * self.kr
                Ch[:, i, j] += s * self.cr
        p = self.cb.size
        Kc = np.zeros((p, 3, 3))
        Cc = np.zeros((p, 3, 3))
        if p:
            u, pushing, stick = st["u"], st["pushing"], st["stick"]
            w = v[self.cb, 2]
            Jp = np.zeros((p, 2, 3))
            Jp[:, 0, 0] = 1.0
            Jp[:, 1, 1] = 1.0
            Jp[:, :, 2] = _perp(u)
            K = np.zeros((p, 2, 2))
            C = np.zeros((p, 2, 2))
            on = pushing.astype(float)
            st_ = (pushing & stick).astype(float)
            sl = (pushing & ~stick).astype(float)
            K[:, 1, 1] = on * self.kn
            C[:, 1, 1] = on * self.cn
            K[:, 0, 0] = st_ * self.kt
            C[:, 0, 0] = st_ * self.ct
            # sliding: ft = sgn * mu * fn, fn = -kn py - cn vy  ->  dft/dpy = -sgn mu kn  (K = -df/dp)
            K[:, 0, 1] = sl * self.mu * st["sgn"] * self.kn
            C[:, 0, 1] = sl * self.mu * st["sgn"] * self.cn
            dvdq = np.zeros((p, 2, 3))
            dvdq[:, :, 2] = -w[:, None] * u
            JpT = Jp.transpose(0, 2, 1)
            Kc = -np.matmul(JpT, np.matmul(K, Jp) + np.matmul(C, dvdq))
            Kc[:, 2, 2] -= (u * st["fc"]).sum(axis=1)
            Cc = -np.matmul(JpT, np.matmul(C, Jp))
        return Kh, Ch, Kc, Cc

    def system_matrix(self, q, v, anchors, st, dt, dense=False):
        """A = M - dt dQ/dv - dt^2 dQ/dq on the free dofs (identity on fixed dofs), and dQ/dq."""
        if self._pattern is None:
            self._build_pattern()
        P = self._pattern
        Kh, Ch, Kc, Cc = self.jacobian_blocks(q, v, anchors, st)
        N = P["N"]
        Mdiag = np.where(self.free_dof, self.M.ravel(), 1.0)
        kq = np.concatenate([Kh.ravel(), Kc.ravel(), np.zeros(N)])[P["keep"]]
        cv = np.concatenate([Ch.ravel(), Cc.ravel(), np.zeros(N)])[P["keep"]]
        md = np.concatenate([np.zeros(P["nh"] + P["nc"]), Mdiag])[P["keep"]]
        vals_A = md - dt * cv - dt * dt * kq
        A_data = np.bincount(P["inv"], vals_A, P["nnz"])
        K_data = np.bincount(P["inv"], kq, P["nnz"])
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

    def stiffness_bound(self):
        """(omega_K, omega_C): the stiffest mode (rad/s) and the strongest damping rate (1/s) of the
        mass-scaled symmetric parts (Lanczos / dense eigenvalues, +5 %), else upper bounds from Gershgorin row sums of M^-1/2 dQ/dq M^-1/2 and M^-1/2 dQ/dv M^-1/2 with every contact pushing and sticking."""
        q = np.zeros((self.n, 3))
        v = np.zeros((self.n, 3))
        if self._pattern is None:
            self._build_pattern()
        p = self.cb.size
        st = {"u": _rot(np.zeros(p), self.rc), "pushing": np.ones(p, bool), "stick": np.ones(p, bool),
              "sgn": np.zeros(p), "fc": np.zeros((p, 2))}
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
