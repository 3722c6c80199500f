"""Vectorised corotational beam-hinge mechanics (energy, gradient, tangent), no per-element Python loops.

State: node centres ``X`` (n, 3) in mm and rotations ``R`` (n, 3, 3). Increments per node are
``(dx, omega)`` (6 values): ``X <- X + dx``, ``R <- exp([omega]) R`` (spatial rotation vector).

Per hinge e = (A, B), with ``W = R_A Q0`` (A's hinge frame), ``rho = R r`` (corner offsets):

* ``u = W^T (p_B - p_A) - rest e1``   (B's hinge end in A's frame, minus the rest chord)
* ``Theta = log(W^T R_B Q0)``           (rotation of B's hinge frame relative to A's)

Energy ``E = 1/2 eps^T K eps``. The Jacobian of ``u`` and its second derivatives are exact
(``exp([omega])`` to second order); ``Theta``'s Jacobian is exact (inverse left Jacobian of SO(3)),
its second derivatives are left out of the tangent (they vanish for in-plane motion, so Newton is
exactly quadratic for planar scenes and nearly so with tilted hinges).
"""
import numpy as np
import scipy.sparse as sp


def skew(v):
    """(m, 3) -> (m, 3, 3) cross-product matrices."""
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


class ElementState:
    """Strains, Jacobians and (optionally) element tangents of every hinge at one state."""

    def __init__(self, geo, X, R, tangent=True, Kmat=None):
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
        s = (K @ eps[:, :, None])[:, :, 0]
        self.eps, self.J, self.s, self.W = eps, J, s, W
        self.energy = 0.5 * np.einsum("mi,mi->m", eps, s)
        self.grad = (s[:, None, :] @ J)[:, 0, :]
        self.H = None
        if tangent:
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
            self.H = H


class Pattern:
    """Fixed sparsity pattern: element matrices (m, 12, 12) on active DOFs + constraint rows -> CSC.

    ``dofmap`` maps the 6 n full DOFs to active indices (-1 = left out: supported or out-of-plane).
    """

    def __init__(self, elem_dofs, dofmap, n_active, con_elems=None, con_dofs_local=None):
        self.dofmap = dofmap
        self.n_active = n_active
        ed = dofmap[elem_dofs]                       # (m, 12)
        self.ed = ed
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

    def matrix(self, He, Acon=None, reg=0.0):
        """KKT matrix ``[[H, A^T], [A, -reg I]]``. A tiny ``reg`` keeps it regular when constraints are
        redundant (e.g. clips on every joint around a cell: their relative rotations are dependent)."""
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
