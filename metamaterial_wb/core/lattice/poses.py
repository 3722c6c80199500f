"""Poses of the lattice models: best-fit rigid alignment (Kabsch), the plates' in-plane twist and D, the
hinge-chain positions from plate rotations (:class:`ChainPositions`) and the update of a state by a DOF
increment."""
import numpy as np
import scipy.sparse.linalg as spla

from metamaterial_wb.core.lattice import linalg
from metamaterial_wb.core.lattice.linalg import _Cholesky
from metamaterial_wb.core.lattice.mechanics import _arc_coefficients, _cross_e1, expm_so3, log_so3


def kabsch(P, Q):
    """Rotation Rm and translation tv minimising |Rm P_i + tv - Q_i| (rows are points).

    Parameters
    ----------
    P, Q : numpy.ndarray
        Shape ``(n, 3)``.

    Returns
    -------
    tuple
        ``(Rm (3, 3), tv (3,))``.
    """
    pc, qc = P.mean(axis=0), Q.mean(axis=0)
    Hm = (P - pc).T @ (Q - qc)
    U, _S, Vt = np.linalg.svd(Hm)
    d = np.sign(np.linalg.det(Vt.T @ U.T)) or 1.0
    Dm = np.diag([1.0, 1.0, d])
    Rm = Vt.T @ Dm @ U.T
    return Rm, qc - Rm @ pc


def node_twist(R):
    """In-plane rotation of every plate: the twist about its own normal (swing-twist split), radians.

    Parameters
    ----------
    R : numpy.ndarray
        Shape ``(n, 3, 3)``.

    Returns
    -------
    numpy.ndarray
        Shape ``(n,)``.
    """
    w = 0.5 * np.sqrt(np.maximum(0.0, 1.0 + np.trace(R, axis1=1, axis2=2)))
    z = np.where(w > 1e-9, (R[:, 1, 0] - R[:, 0, 1]) / np.maximum(4.0 * w, 1e-300), 1.0)
    return 2.0 * np.arctan2(z, w)


def finish(geo, X, R, align=True):
    """Align to the flat sheet (rigid, Kabsch), return positions, rotations and D.

    Parameters
    ----------
    geo : LatticeGeometry
    X : numpy.ndarray
        Positions ``(n, 3)``.
    R : numpy.ndarray
        Rotations ``(n, 3, 3)``.
    align : bool
        Best-fit rigid alignment to the flat sheet first.

    Returns
    -------
    tuple
        ``(X, R, phi, D)``.
    """
    if align and geo.n > 1:
        Rm, tv = kabsch(X, geo.X0)
        X = X @ Rm.T + tv
        R = Rm[None] @ R
    phi = node_twist(R)
    D = geo.D_from_phi(phi)
    return X, R, phi, D


class ChainPositions:
    """Node positions from the plate rotations through the hinge chain (the linear model's poses).

    Every hinge, force-free and bent uniformly by its relative rotation ``Theta = log(W_A^T W_B)``, puts its
    far end at the arc chord ``rest V(Theta) e1`` in plate A's hinge frame (the nonlinear model's zero-strain
    state, ``core/lattice/mechanics``). Each hinge thus gives a relation
    ``X_B - X_A = R_A r_A + W_A rest V(Theta) e1 - R_B r_B`` between its two node centres; the positions are
    their least-squares solution over the hinge graph (one factorisation of the graph Laplacian per
    structure, one back-substitution per call). The linear model adds each hinge's elastic offset beyond
    uniform bending (``u - rest/2 Theta x e1`` of its solution), so that both pose rules agree to first
    order. A rigid rotation keeps every plate square and every hinge chord exact, which adding linear
    displacements does not (a plate corner turned by ``phi`` moves by ``2 sin(phi/2)`` times its radius, not
    ``phi``). The result keeps the mean of the positions it is given (the gauge; results are aligned
    afterwards anyway).

    Parameters
    ----------
    geo : LatticeGeometry
    """

    def __init__(self, geo):
        import scipy.sparse as sp

        self.geo = geo
        n, m = geo.n, geo.m
        self.lu = None
        if n < 2 or m == 0:
            return
        # graph Laplacian of the hinges (layouts are connected: scene validation), node 0 held (the gauge)
        a, b = geo.a, geo.b
        deg = np.bincount(np.concatenate([a, b]), minlength=n).astype(float)
        r = np.concatenate([a, b, np.arange(n)]) - 1
        c = np.concatenate([b, a, np.arange(n)]) - 1
        v = np.concatenate([-np.ones(2 * m), deg])
        k = (r >= 0) & (c >= 0)
        L = sp.coo_matrix((v[k], (r[k], c[k])), shape=(n - 1, n - 1)).tocsc()
        if linalg._cholmod is not None:             # SPD: Cholesky when CHOLMOD is there (cheaper)
            L.sum_duplicates()
            self.lu = _Cholesky(L)
        else:
            self.lu = spla.splu(L, permc_spec="MMD_AT_PLUS_A")

    def chords(self, R, strain=None):
        """(m, 3) relations ``X_B - X_A`` for plate rotations ``R`` (``strain``: (m, 3) elastic offsets of the
        hinge ends beyond uniform bending, in A's hinge frame).

        Parameters
        ----------
        R : numpy.ndarray
            Plate rotations ``(n, 3, 3)``.
        strain : numpy.ndarray, optional
            ``(m, 3)``.

        Returns
        -------
        numpy.ndarray
            ``(m, 3)``.
        """
        geo = self.geo
        if geo.planar:
            return self._planar_chords(R, strain)
        W = R[geo.a] @ geo.Q0
        T = log_so3(np.einsum("mji,mjk->mik", W, R[geo.b] @ geo.Q0))
        t2 = np.einsum("mi,mi->m", T, T)
        A, B = _arc_coefficients(t2)[:2]
        y = T * T[:, 0:1]                                       # T x (T x e1)
        y[:, 0] -= t2
        loc = geo.rest * (A[:, None] * _cross_e1(T) + B[:, None] * y)
        loc[:, 0] += geo.rest                                   # rest V(Theta) e1
        if strain is not None:
            loc += strain
        return (np.einsum("mij,mj->mi", W, loc) + np.einsum("mij,mj->mi", R[geo.a], geo.rA)
                - np.einsum("mij,mj->mi", R[geo.b], geo.rB))

    def _planar_chords(self, R, strain):
        """Same as :meth:`chords` for rotations about the sheet normal (Theta = (0, 0, phi_B - phi_A))."""
        geo = self.geo
        phi = np.arctan2(R[:, 1, 0], R[:, 0, 0])
        a, b = geo.a, geo.b
        t = phi[b] - phi[a]
        t = t - 2.0 * np.pi * np.round(t / (2.0 * np.pi))
        A, B = _arc_coefficients(t * t)[:2]
        loc = np.zeros((geo.m, 3))
        loc[:, 0] = geo.rest * (1.0 - B * t * t)               # rest V(Theta) e1 in the hinge frame
        loc[:, 1] = geo.rest * A * t
        if strain is not None:
            loc += strain
        v = np.einsum("mij,mj->mi", geo.Q0, loc)               # in the flat sheet's axes
        ca, sa, cb, sb = np.cos(phi[a]), np.sin(phi[a]), np.cos(phi[b]), np.sin(phi[b])
        out = np.zeros((geo.m, 3))
        out[:, 0] = ca * (v[:, 0] + geo.rA[:, 0]) - sa * (v[:, 1] + geo.rA[:, 1]) - (cb * geo.rB[:, 0] - sb * geo.rB[:, 1])
        out[:, 1] = sa * (v[:, 0] + geo.rA[:, 0]) + ca * (v[:, 1] + geo.rA[:, 1]) - (sb * geo.rB[:, 0] + cb * geo.rB[:, 1])
        out[:, 2] = v[:, 2]
        return out

    def __call__(self, R, X_gauge, strain=None):
        if self.lu is None:
            return X_gauge.copy()
        geo = self.geo
        e = self.chords(R, strain)
        rhs = np.empty((geo.n, 3))
        for d in range(3):                                      # incidence^T e: +e at B, -e at A
            rhs[:, d] = np.bincount(geo.b, e[:, d], geo.n) - np.bincount(geo.a, e[:, d], geo.n)
        X = np.zeros_like(X_gauge)
        X[1:] = self.lu.solve(np.ascontiguousarray(rhs[1:]))
        return X + (X_gauge.mean(axis=0) - X.mean(axis=0))     # keeps the mean position it is given


def _apply(X, R, q, dofmap, n):
    full = np.zeros(6 * n)
    k = dofmap[:6 * n] >= 0
    full[k] = q[dofmap[:6 * n][k]]
    full = full.reshape(n, 6)
    if linalg._FAST and not np.any(full[:, 3:5]):       # rotations about the sheet normal only: 2-D arithmetic
        c, s = np.cos(full[:, 5]), np.sin(full[:, 5])
        R2 = np.empty_like(R)
        R2[:, 0, :] = c[:, None] * R[:, 0, :] - s[:, None] * R[:, 1, :]
        R2[:, 1, :] = s[:, None] * R[:, 0, :] + c[:, None] * R[:, 1, :]
        R2[:, 2, :] = R[:, 2, :]
        return X + full[:, :3], R2
    return X + full[:, :3], expm_so3(full[:, 3:]) @ R
