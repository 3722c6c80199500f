"""Vectorised corotational beam-hinge mechanics (energy, gradient, tangent), no per-element Python loops.

State: node centres ``X`` (n, 3) in mm and rotations ``R`` (n, 3, 3). Increments per node are
``(dx, omega)`` (6 values): ``X <- X + dx``, ``R <- exp([omega]) R`` (spatial rotation vector).

Per hinge e = (A, B), with ``W = R_A Q0`` (A's hinge frame), ``rho = R r`` (corner offsets):

* ``u = W^T (p_B - p_A) - rest e1``   (B's hinge end in A's frame, minus the rest chord)
* ``Theta = log(W^T R_B Q0)``           (rotation of B's hinge frame relative to A's)

Energy ``E = 1/2 eps^T K eps``. The Jacobian of ``u`` and its second derivatives are exact
(``exp([omega])`` to second order); ``Theta``'s Jacobian is exact (inverse left Jacobian of SO(3)); the
curvature of the rotation logarithm (zero for in-plane motion) enters the tangent by central differences
of its exact gradient, so the tangent is the symmetric Hessian (checked against finite differences of the
energy in tests/fidelity/test_lattice_models.py).
"""
import numpy as np
import scipy.sparse as sp


def skew(v):
    """(..., 3) -> (..., 3, 3) cross-product matrices: ``skew(v) @ x == cross(v, x)``."""
    v = np.asarray(v, dtype=float)
    S = np.zeros(v.shape[:-1] + (3, 3))
    S[..., 0, 1] = -v[..., 2]
    S[..., 0, 2] = v[..., 1]
    S[..., 1, 0] = v[..., 2]
    S[..., 1, 2] = -v[..., 0]
    S[..., 2, 0] = -v[..., 1]
    S[..., 2, 1] = v[..., 0]
    return S


def expm_so3(w):
    """Rodrigues: (n, 3) rotation vectors -> (n, 3, 3)."""
    th = np.linalg.norm(w, axis=1)
    small = th < 1e-8
    ths = np.where(small, 1.0, th)
    A = np.where(small, 1.0 - th ** 2 / 6.0, np.sin(ths) / ths)
    B = np.where(small, 0.5 - th ** 2 / 24.0, (1.0 - np.cos(ths)) / ths ** 2)
    K = skew(w)
    I = np.broadcast_to(np.eye(3), K.shape)
    return I + A[:, None, None] * K + B[:, None, None] * (K @ K)


def log_so3(C):
    """(m, 3, 3) rotations -> (m, 3) rotation vectors (angles below pi)."""
    ax = 0.5 * np.stack([C[:, 2, 1] - C[:, 1, 2], C[:, 0, 2] - C[:, 2, 0], C[:, 1, 0] - C[:, 0, 1]], axis=1)
    s = np.linalg.norm(ax, axis=1)
    c = 0.5 * (np.trace(C, axis1=1, axis2=2) - 1.0)
    th = np.arctan2(s, c)
    small = s < 1e-8
    f = np.where(small, 1.0 + th ** 2 / 6.0, th / np.where(small, 1.0, s))
    return f[:, None] * ax


def inv_left_jacobian(T):
    """(m, 3) -> (m, 3, 3) inverse left Jacobian of SO(3)."""
    th = np.linalg.norm(T, axis=1)
    small = th < 1e-5
    ths = np.where(small, 1.0, th)
    c = np.where(small, 1.0 / 12.0 + th ** 2 / 720.0,
                 1.0 / ths ** 2 - (1.0 + np.cos(ths)) / (2.0 * ths * np.sin(ths)))
    S = skew(T)
    I = np.broadcast_to(np.eye(3), S.shape)
    return I - 0.5 * S + c[:, None, None] * (S @ S)


def _cross_e1(T):
    """T x e1 for (m, 3) arrays."""
    out = np.zeros_like(T)
    out[:, 1] = T[:, 2]
    out[:, 2] = -T[:, 1]
    return out


def _arc_coefficients(t2):
    """A = (1 - cos t)/t^2, B = (t - sin t)/t^3 and their derivatives with respect to t^2 (series near 0)."""
    small = t2 < 1e-2          # Taylor series below 0.1 rad (truncation < 1e-14), closed forms above
    t2s = np.where(small, 1.0, t2)
    th = np.sqrt(t2s)
    c, sn = np.cos(th), np.sin(th)
    t = t2
    A = np.where(small, 0.5 - t / 24.0 + t * t / 720.0 - t ** 3 / 40320.0, (1.0 - c) / t2s)
    B = np.where(small, 1.0 / 6.0 - t / 120.0 + t * t / 5040.0 - t ** 3 / 362880.0, (th - sn) / (t2s * th))
    dA = np.where(small, -1.0 / 24.0 + t / 360.0 - t * t / 13440.0, (th * sn - 2.0 + 2.0 * c) / (2.0 * t2s * t2s))
    dB = np.where(small, -1.0 / 120.0 + t / 2520.0 - t * t / 120960.0,
                  ((1.0 - c) * th - 3.0 * (th - sn)) / (2.0 * t2s * t2s * th))
    return A, B, dA, dB


def arc_offset(T, rest):
    """Offset of the far end of a hinge bent and twisted uniformly by the rotation vector ``T``, relative
    to where the linear beam law puts it: ``rest (V(T) e1 - e1) - rest/2 (T x e1)``, with ``V`` the left
    Jacobian of SO(3) (``rest V(T) e1`` is the chord of a constant-curvature arc). O(|T|^2)."""
    return _arc(T, rest, derivative=False)[0]


def _arc(T, rest, derivative=True):
    rest = np.asarray(rest, float)
    if rest.ndim:                                      # per-element rest chords (refined hinges)
        rest = rest[:, None]
    t2 = np.sum(T * T, axis=1)
    A, B, dA, dB = _arc_coefficients(t2)
    x = _cross_e1(T)                                   # T x e1
    y = T * T[:, 0:1]                                  # T x (T x e1) = T (T.e1) - e1 (T.T)
    y[:, 0] -= t2
    c = rest * ((A - 0.5)[:, None] * x + B[:, None] * y)
    if not derivative:
        return c, None
    m = T.shape[0]
    E1 = np.zeros((3, 3))                              # d(T x e1)/dT
    E1[1, 2] = 1.0
    E1[2, 1] = -1.0
    dy = T[:, :, None] * np.array([1.0, 0.0, 0.0])[None, None, :]     # T e1^T
    dy = dy + T[:, 0][:, None, None] * np.eye(3)[None]              # + (T.e1) I
    dy[:, 0, :] -= 2.0 * T                                            # - 2 e1 T^T
    dc = ((A - 0.5)[:, None, None] * E1[None] + 2.0 * dA[:, None, None] * x[:, :, None] * T[:, None, :]
          + B[:, None, None] * dy + 2.0 * dB[:, None, None] * y[:, :, None] * T[:, None, :])
    return c, (rest[:, :, None] if rest.ndim else rest) * dc


def arc_offset_derivatives(T, rest, second=True):
    """``(c, dc/dT (m,3,3), d2c/dT2 (m,3,3,3))``: first derivatives in closed form, second by central
    differences of the first (only used in the tangent)."""
    c, dc = _arc(T, rest)
    if not second:
        return c, dc, None
    d2 = np.empty(T.shape + (3, 3))
    hs = 1e-6
    for l in range(3):
        Tp = T.copy()
        Tp[:, l] += hs
        Tm = T.copy()
        Tm[:, l] -= hs
        d2[:, :, :, l] = (_arc(Tp, rest)[1] - _arc(Tm, rest)[1]) / (2 * hs)
    return c, dc, 0.5 * (d2 + np.swapaxes(d2, 2, 3))


_ROT = np.array([3, 4, 5, 9, 10, 11])


def _log_curvature(W, WB, sigma, h=1e-6):
    """(m, 6, 6) symmetric second derivative of ``sigma . log(W_A^T W_B)`` with respect to the two plates'
    rotation increments (A then B), by central differences of its exact gradient."""
    m = W.shape[0]

    def grad(dA, dB):
        WA2 = expm_so3(dA) @ W
        WB2 = expm_so3(dB) @ WB
        C = np.einsum("mji,mjk->mik", WA2, WB2)
        T = log_so3(C)
        JLi = inv_left_jacobian(T) @ np.transpose(WA2, (0, 2, 1))
        gB = (sigma[:, None, :] @ JLi)[:, 0, :]
        return np.concatenate([-gB, gB], axis=1)

    Hr = np.empty((m, 6, 6))
    z = np.zeros((m, 3))
    for k in range(6):
        e = np.zeros((m, 3))
        e[:, k % 3] = h
        if k < 3:
            gp, gm = grad(e, z), grad(-e, z)
        else:
            gp, gm = grad(z, e), grad(z, -e)
        Hr[:, :, k] = (gp - gm) / (2 * h)
    return 0.5 * (Hr + np.transpose(Hr, (0, 2, 1)))


def hinge_strains(geo, X, R):
    """(m, 6) strains ``eps = (u, Theta)`` of every hinge at the state ``(X, R)``: the same as
    :class:`ElementState` ``.eps`` without the Jacobians (for energy evaluations, e.g. line searches)."""
    a, b = geo.a, geo.b
    if getattr(geo, "planar", False) and np.abs(R[:, 2, 2] - 1.0).max(initial=0.0) <= 1e-14:
        # rotations about the sheet normal only (planar scenes): 2-D arithmetic, same values
        phi = np.arctan2(R[:, 1, 0], R[:, 0, 0])
        ca, sa, cb, sb = np.cos(phi[a]), np.sin(phi[a]), np.cos(phi[b]), np.sin(phi[b])
        rA, rB = geo.rA, geo.rB
        dx = X[b, 0] - X[a, 0] + cb * rB[:, 0] - sb * rB[:, 1] - ca * rA[:, 0] + sa * rA[:, 1]
        dy = X[b, 1] - X[a, 1] + sb * rB[:, 0] + cb * rB[:, 1] - sa * rA[:, 0] - ca * rA[:, 1]
        lx, ly = ca * dx + sa * dy, -sa * dx + ca * dy              # in plate A's axes
        Q = geo.Q0
        u = np.column_stack([Q[:, 0, 0] * lx + Q[:, 1, 0] * ly, Q[:, 0, 1] * lx + Q[:, 1, 1] * ly,
                             X[b, 2] - X[a, 2]])
        u[:, 0] -= geo.rest
        t = phi[b] - phi[a]
        Th = np.zeros((a.size, 3))
        Th[:, 2] = t - 2.0 * np.pi * np.round(t / (2.0 * np.pi))
    else:
        W = R[a] @ geo.Q0
        d = (X[b] - X[a] + np.einsum("mij,mj->mi", R[b], geo.rB) - np.einsum("mij,mj->mi", R[a], geo.rA))
        u = np.einsum("mji,mj->mi", W, d)
        u[:, 0] -= geo.rest
        Th = log_so3(np.einsum("mji,mjk->mik", W, R[b] @ geo.Q0))
    if getattr(geo, "arc_correction", False):
        u -= _arc(Th, geo.rest, derivative=False)[0]
    return np.concatenate([u, Th], axis=1)


class ElementState:
    """Strains, Jacobians and (optionally) element tangents of every hinge at one state."""

    def __init__(self, geo, X, R, tangent=True, Kmat=None, arc=None):
        a, b = geo.a, geo.b
        K = geo.K if Kmat is None else Kmat
        RA = R[a]
        RB = R[b]
        W = RA @ geo.Q0
        WB = RB @ geo.Q0
        rhoA = (RA @ geo.rA[:, :, None])[:, :, 0]
        rhoB = (RB @ geo.rB[:, :, None])[:, :, 0]
        D0 = X[b] - X[a] + rhoB            # p_B - x_A
        d = D0 - rhoA                      # p_B - p_A
        u = np.einsum("mji,mj->mi", W, d)
        u[:, 0] -= geo.rest
        C = np.einsum("mji,mjk->mik", W, WB)
        Th = log_so3(C)
        eps = np.concatenate([u, Th], axis=1)
        m = eps.shape[0]
        J = np.zeros((m, 6, 12))
        Wt = np.transpose(W, (0, 2, 1))    # rows = hinge axes
        J[:, 0:3, 0:3] = -Wt
        J[:, 0:3, 6:9] = Wt
        J[:, 0:3, 3:6] = np.cross(Wt, D0[:, None, :])
        J[:, 0:3, 9:12] = np.cross(rhoB[:, None, :], Wt)
        JL = inv_left_jacobian(Th) @ Wt
        J[:, 3:6, 3:6] = -JL
        J[:, 3:6, 9:12] = JL
        arc = getattr(geo, "arc_correction", False) if arc is None else arc
        if arc:
            # measure u from the chord of a uniformly bent/twisted hinge (exact pure bending, see arc_offset)
            c, dc, _ = arc_offset_derivatives(Th, geo.rest, second=False)
            eps[:, 0:3] -= c
            J[:, 0:3, :] -= dc @ J[:, 3:6, :]
        s = (K @ eps[:, :, None])[:, :, 0]
        self.eps, self.J, self.s, self.W = eps, J, s, W
        self.energy = 0.5 * np.einsum("mi,mi->m", eps, s)
        self.grad = (s[:, None, :] @ J)[:, 0, :]
        self.H = None
        # geo.exact_tangent (default True) includes the curvature of the rotation logarithm (3-D only)
        self._keep = (K, D0, rhoB, Th, arc, geo.rest, WB, dc if arc else None,
                      bool(getattr(geo, "exact_tangent", True)) and not getattr(geo, "planar", False))
        if tangent:
            self.tangent()

    def soft_axis_curvature(self, idx, weight):
        """``sum weight * d2(Theta_3)/dq2`` for the elements ``idx`` on their rotational DOFs (k, 6, 6): the
        curvature of the soft-axis rotation (actuator constraints, contact); zero for in-plane motion."""
        sigma = np.zeros((len(idx), 3))
        sigma[:, 2] = weight
        WB = self._keep[6]
        return _log_curvature(self.W[idx], WB[idx], sigma)

    def tangent(self):
        """Element tangents (m, 12, 12), computed once on demand."""
        if self.H is not None:
            return self.H
        K, D0, rhoB, Th, arc, rest, WB, dc, spatial = self._keep
        J, s, W = self.J, self.s, self.W
        if True:
            Jt = np.transpose(J, (0, 2, 1))
            H = Jt @ (K @ J)
            v = (W @ s[:, 0:3, None])[:, :, 0]           # spatial force conjugate to u
            I = np.eye(3)
            vD = np.einsum("mi,mi->m", v, D0)[:, None, None]
            vr = np.einsum("mi,mi->m", v, rhoB)[:, None, None]
            H[:, 3:6, 3:6] += 0.5 * (v[:, :, None] * D0[:, None, :] + D0[:, :, None] * v[:, None, :]) - vD * I
            H[:, 9:12, 9:12] += 0.5 * (v[:, :, None] * rhoB[:, None, :] + rhoB[:, :, None] * v[:, None, :]) - vr * I
            Sv = skew(v)
            H[:, 3:6, 6:9] += Sv
            H[:, 6:9, 3:6] += np.transpose(Sv, (0, 2, 1))
            H[:, 3:6, 0:3] -= Sv
            H[:, 0:3, 3:6] -= np.transpose(Sv, (0, 2, 1))
            X_ = -rhoB[:, :, None] * v[:, None, :] + vr * I
            H[:, 3:6, 9:12] += X_
            H[:, 9:12, 3:6] += np.transpose(X_, (0, 2, 1))
            if arc:
                d2c = arc_offset_derivatives(Th, rest, second=True)[2]
                JT = J[:, 3:6, :]
                Hc = np.einsum("mi,mikl->mkl", s[:, 0:3], d2c)
                H -= np.transpose(JT, (0, 2, 1)) @ Hc @ JT
            if spatial:
                # curvature of the rotation logarithm (zero for in-plane motion): symmetric part of the
                # finite-difference derivative of the exact gradient of sigma . Theta
                sigma = s[:, 3:6].copy()
                if arc:
                    sigma -= np.einsum("mij,mi->mj", dc, s[:, 0:3])
                Hr = _log_curvature(W, WB, sigma)
                H[np.ix_(np.arange(H.shape[0]), _ROT, _ROT)] += Hr
            self.H = H
        return self.H


class Pattern:
    """Fixed sparsity pattern: element matrices (m, 12, 12) on active DOFs + constraint rows -> CSC.

    ``dofmap`` maps the 6 n full DOFs to active indices (-1 = left out: supported or out-of-plane).
    """

    def __init__(self, elem_dofs, dofmap, n_active, con_elems=None, con_dofs_local=None):
        self.dofmap = dofmap
        self.n_active = n_active
        ed = dofmap[elem_dofs]                       # (m, 12)
        self.ed = ed
        self.nc = 0 if con_elems is None else len(con_elems)
        self.N = n_active + self.nc
        self._con_elems = con_elems
        self._ready = False          # the KKT pattern (a sort) is built on the first matrix() call
        self._stiff = None

    def _build(self):
        """Pattern of the KKT matrix (repeated assemblies, e.g. Newton, reuse it)."""
        self._ready = True
        ed = self.ed
        n_active = self.n_active
        con_elems = self._con_elems
        m = ed.shape[0]
        r = np.repeat(ed, 12, axis=1)                # (m, 144)
        c = np.tile(ed, (1, 12))
        keep = (r >= 0) & (c >= 0)
        self.keep_elem = keep.ravel()
        rows = [r.ravel()[self.keep_elem]]
        cols = [c.ravel()[self.keep_elem]]
        nc = 0 if con_elems is None else len(con_elems)
        self.nc = nc
        if nc:
            cd = ed[con_elems]                        # (nc, 12)
            ck = cd >= 0
            self.con_keep = ck.ravel()
            crow = np.repeat(n_active + np.arange(nc), 12).reshape(nc, 12)
            rows += [crow.ravel()[self.con_keep], cd.ravel()[self.con_keep], n_active + np.arange(nc)]
            cols += [cd.ravel()[self.con_keep], crow.ravel()[self.con_keep], n_active + np.arange(nc)]
        rows = np.concatenate(rows)
        cols = np.concatenate(cols)
        N = n_active + nc
        self.N = N
        lin = cols.astype(np.int64) * N + rows      # column-major order for CSC
        uniq, inv = np.unique(lin, return_inverse=True)
        self.inv = inv
        self.nnz = uniq.size
        self.indices = (uniq % N).astype(np.int32)
        colidx = uniq // N
        self.indptr = np.concatenate([[0], np.cumsum(np.bincount(colidx, minlength=N))]).astype(np.int32)

    def stiffness(self, He):
        """The assembled stiffness block alone, (n_active, n_active) CSC, for a single assembly (duplicates
        summed by scipy's compressed-format conversion: no sort of the whole pattern)."""
        if self._stiff is None:
            # only the element DOFs that are active somewhere (planar scenes: 6 of 12)
            loc = np.flatnonzero((self.ed >= 0).any(axis=0))
            ed = self.ed[:, loc]
            k = loc.size
            r = np.repeat(ed, k, axis=1).ravel()
            c = np.tile(ed, (1, k)).ravel()
            keep = (r >= 0) & (c >= 0)
            full = (loc[:, None] * 12 + loc[None, :]).ravel()          # (k*k,) positions in a 12 x 12 block
            idx = (np.arange(ed.shape[0])[:, None] * 144 + full[None, :]).ravel()[keep]
            self._stiff = (idx, r[keep], c[keep])
        idx, r, c = self._stiff
        n = self.n_active
        M = sp.coo_matrix((He.reshape(-1)[idx], (r, c)), shape=(n, n)).tocsc()
        M.sum_duplicates()
        return M

    def rows(self, Ae, elems):
        """Element rows ``Ae`` (k, 12) of the elements ``elems`` -> dense (k, n_active) rows."""
        out = np.zeros((len(elems), self.n_active))
        if len(elems):
            ed = self.ed[elems]
            k = ed >= 0
            rr = np.broadcast_to(np.arange(len(elems))[:, None], ed.shape)
            np.add.at(out, (rr[k], ed[k]), Ae[k])
        return out

    def matrix(self, He, Acon=None, reg=0.0):
        """KKT matrix ``[[H, A^T], [A, -reg I]]``. A tiny ``reg`` keeps it regular when constraints are
        redundant (e.g. clips on every joint around a cell: their relative rotations are dependent)."""
        if not self._ready:
            self._build()
        parts = [He.reshape(He.shape[0], -1).ravel()[self.keep_elem]]
        if self.nc:
            a = Acon.ravel()[self.con_keep]
            parts += [a, a, np.full(self.nc, -float(reg))]
        data = np.bincount(self.inv, weights=np.concatenate(parts), minlength=self.nnz)
        M = sp.csc_matrix((data, self.indices, self.indptr), shape=(self.N, self.N))
        return M

    def vector(self, ge, elems=None):
        """Element vectors (m, 12) (or rows for the elements ``elems``) -> active global vector."""
        ed = (self.ed if elems is None else self.ed[elems]).ravel()
        k = ed >= 0
        return np.bincount(ed[k], weights=ge.ravel()[k], minlength=self.n_active)

    def gather(self, q):
        """Active global vector -> (m, 12) element values (0 for left-out DOFs)."""
        full = np.concatenate([q, [0.0]])
        return full[self.ed]


class PlanarElementState:
    """:class:`ElementState`'s strains, Jacobians and hinge forces for a planar scene at a planar state
    (every plate turned about the sheet normal only), in 2-D arithmetic: the same values (to rounding) on the
    in-plane DOFs (x, y and the rotation about z of both plates), which are the only ones a planar scene
    keeps; the out-of-plane entries of ``J`` are left zero. ``H`` is the material tangent ``J^T K J`` (at the
    flat sheet, where the forces vanish, the full tangent). Used by the linear model (tests:
    tests/fidelity/test_linear_fast_paths.py)."""

    def __init__(self, geo, X, R, arc=True):
        a, b = geo.a, geo.b
        K = geo.K
        m = a.size
        RA, RB = R[a], R[b]
        Q = geo.Q0
        # hinge axes of plate A in space (in-plane: the third components vanish), rows of W^T
        w1x = RA[:, 0, 0] * Q[:, 0, 0] + RA[:, 0, 1] * Q[:, 1, 0]
        w1y = RA[:, 1, 0] * Q[:, 0, 0] + RA[:, 1, 1] * Q[:, 1, 0]
        w2x = RA[:, 0, 0] * Q[:, 0, 1] + RA[:, 0, 1] * Q[:, 1, 1]
        w2y = RA[:, 1, 0] * Q[:, 0, 1] + RA[:, 1, 1] * Q[:, 1, 1]
        rA, rB = geo.rA, geo.rB
        rhoAx = RA[:, 0, 0] * rA[:, 0] + RA[:, 0, 1] * rA[:, 1]
        rhoAy = RA[:, 1, 0] * rA[:, 0] + RA[:, 1, 1] * rA[:, 1]
        rhoBx = RB[:, 0, 0] * rB[:, 0] + RB[:, 0, 1] * rB[:, 1]
        rhoBy = RB[:, 1, 0] * rB[:, 0] + RB[:, 1, 1] * rB[:, 1]
        D0x = X[b, 0] - X[a, 0] + rhoBx
        D0y = X[b, 1] - X[a, 1] + rhoBy
        dx, dy = D0x - rhoAx, D0y - rhoAy
        eps = np.zeros((m, 6))
        eps[:, 0] = w1x * dx + w1y * dy - geo.rest
        eps[:, 1] = w2x * dx + w2y * dy
        eps[:, 2] = X[b, 2] - X[a, 2]
        phi = np.arctan2(R[:, 1, 0], R[:, 0, 0])
        t = phi[b] - phi[a]
        t = t - 2.0 * np.pi * np.round(t / (2.0 * np.pi))
        eps[:, 5] = t
        J = np.zeros((m, 6, 12))
        J[:, 0, 0], J[:, 0, 1], J[:, 0, 6], J[:, 0, 7] = -w1x, -w1y, w1x, w1y
        J[:, 1, 0], J[:, 1, 1], J[:, 1, 6], J[:, 1, 7] = -w2x, -w2y, w2x, w2y
        J[:, 0, 5] = w1x * D0y - w1y * D0x                 # (w x D0)_z
        J[:, 1, 5] = w2x * D0y - w2y * D0x
        J[:, 0, 11] = rhoBx * w1y - rhoBy * w1x            # (rhoB x w)_z
        J[:, 1, 11] = rhoBx * w2y - rhoBy * w2x
        J[:, 5, 5] = -1.0
        J[:, 5, 11] = 1.0
        if arc:
            # measure u from the chord of the uniformly bent hinge (ElementState with Theta = (0, 0, t))
            t2 = t * t
            A_, B_, dA, dB = _arc_coefficients(t2)
            rest = geo.rest
            eps[:, 0] -= rest * (-B_ * t2)
            eps[:, 1] -= rest * ((A_ - 0.5) * t)
            dc0 = rest * (-2.0 * B_ * t - 2.0 * dB * t2 * t)
            dc1 = rest * ((A_ - 0.5) + 2.0 * dA * t2)
            J[:, 0, 5] += dc0
            J[:, 0, 11] -= dc0
            J[:, 1, 5] += dc1
            J[:, 1, 11] -= dc1
        s = (K @ eps[:, :, None])[:, :, 0]
        self.eps, self.J, self.s = eps, J, s
        self.grad = (s[:, None, :] @ J)[:, 0, :]
        self.H = np.transpose(J, (0, 2, 1)) @ (K @ J)

    @staticmethod
    def applies(geo, R):
        """A planar scene at a state turned about the sheet normal only (as ``hinge_strains``' shortcut)."""
        return bool(getattr(geo, "planar", False) and np.abs(R[:, 2, 2] - 1.0).max(initial=0.0) <= 1e-14)
