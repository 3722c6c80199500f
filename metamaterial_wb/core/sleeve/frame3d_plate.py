"""The rigid plates of the nonlinear 3-D frame (``frame3d_nl``, issue 18): the ring's top plate as the curved
solid's, and the plates between stacked rings.

A plate is a rigid body carrying some of the frame's nodes (positions and rotations): its rotation ``R`` moves
each as ``x = c + R (X - c0)``, ``R_node = R``, about its centre ``c = c0 + (0, 0, rise) + shift``. The top plate
keeps its centre on the axis at the prescribed ``rise`` and is free to tilt and twist, loaded by a constant
``moment`` (the solid's bias). A plate between two stacked rings (``translate=(2,)``) also rises freely
(``shift``), as the rings below and above it push; it does not slide sideways, as the beam model's interfaces
(``model.py``: rise, tilt and twist) - the core the sleeve is wrapped around keeps it centred. (Free to slide as
well, ``translate=(0, 1, 2)``, a stack of two rings sways sideways once a ring has snapped, through states so
soft that Newton crawls.)

A plate's free DOFs join the frame's free node DOFs in ``reduce``: first its translations (if free), then its
three rotations, each plate after the last.
"""
import numpy as np
import scipy.sparse as sp

from metamaterial_wb.core.sleeve.rotations import expm_so3, logm_so3, skew


class RigidPlate:
    """A rigid plate carrying the frame's ``nodes`` (module docstring): ``moment`` (3,) the constant moment on
    it, ``translate`` the axes (0 X, 1 Y, 2 Z) along which its centre moves freely."""

    def __init__(self, frame, nodes, moment=(0.0, 0.0, 0.0), translate=()):
        self.nodes = np.asarray(nodes, int)
        self.c0 = np.array([0.0, 0.0, frame.P[self.nodes, 2].mean()])
        self.arm0 = frame.P[self.nodes] - self.c0
        self.R = np.eye(3)
        self.rise = 0.0
        self.shift = np.zeros(3)
        self.moment = np.asarray(moment, float)
        self.translate = sorted(int(a) for a in translate)
        self.ndof = len(self.translate) + 3

    def centre(self):
        return self.c0 + [0.0, 0.0, self.rise] + self.shift

    def place(self, frame, rise=None):
        """Put the carried nodes where the plate is (at ``rise``, if given)."""
        if rise is not None:
            self.rise = float(rise)
        frame.x[self.nodes] = self.centre() + self.arm0 @ self.R.T
        frame.R[self.nodes] = self.R

    def turn(self, frame, dtheta):
        """Turn the plate by the rotation vector ``dtheta`` (composed on the left), carrying its nodes."""
        self.R = expm_so3(dtheta) @ self.R
        self.place(frame)

    def move(self, frame, step):
        """Move the plate by its free DOFs' increments ``step`` (``ndof``: translations, if free, then the
        rotation vector), carrying its nodes."""
        if self.translate:
            self.shift = self.shift.copy()
            self.shift[self.translate] += step[:-3]
        self.turn(frame, step[-3:])

    def state(self):
        return self.R.copy(), self.shift.copy()

    def restore(self, state):
        self.R, self.shift = state[0].copy(), state[1].copy()

    def work(self):
        """The moment's work, ``M . log(R)``."""
        return float(self.moment @ logm_so3(self.R))

    def work_gradient(self):
        """The work's gradient in the plate's free DOFs (translations: none; a left increment of the rotation:
        ``J^-T M``, with ``J^-1`` the inverse left Jacobian of the rotation vector ``theta = log(R)``,
        ``I - K / 2 + (1 / a^2 - (1 + cos a) / (2 a sin a)) K^2``, ``K`` its skew matrix, ``a`` its angle):
        consistent with ``work``, so the line search and Newton agree when the plate has turned by degrees."""
        th = logm_so3(self.R)
        a = float(np.linalg.norm(th))
        K = skew(th)
        c = 1.0 / 12.0 + a * a / 720.0 if a < 1e-3 else 1.0 / a ** 2 - (1 + np.cos(a)) / (2 * a * np.sin(a))
        Jinv = np.eye(3) - 0.5 * K + c * (K @ K)
        return np.concatenate([np.zeros(self.ndof - 3), Jinv.T @ self.moment])

    def tilt(self):
        """The plate's rotation vector (its X and Y components are the tilt, Z the twist)."""
        return logm_so3(self.R)

    def columns(self, frame, first):
        """The plate's columns of the reduction matrix (``reduce``) from column ``first``: ``(rows, cols, vals)``;
        a carried node moves by ``dc + dtheta x arm`` and turns by ``dtheta``."""
        arm = frame.x[self.nodes] - self.centre()
        k = np.arange(3)
        dof = 6 * self.nodes[:, None] + k                                     # each carried node's positions
        rot = first + self.ndof - 3
        rows = [np.repeat(dof, 3, axis=1).ravel(), (dof + 3).ravel()]
        cols = [np.tile(rot + k, 3 * len(arm)), np.tile(rot + k, len(arm))]
        vals = [-skew(arm).ravel(), np.ones(3 * len(arm))]                   # dx = -[arm]x dtheta, and dtheta
        for j, a in enumerate(self.translate):
            rows.append(dof[:, a])
            cols.append(np.full(len(arm), first + j))
            vals.append(np.ones(len(arm)))
        return np.concatenate(rows), np.concatenate(cols), np.concatenate(vals)

    def gradient(self, frame, G):
        """The frame's gradient ``G`` (all DOFs) in the plate's free DOFs, as ``T^T G`` with its ``columns``
        (without building them): the carried nodes' forces along each translation, and about the centre their
        moments ``arm x f`` plus their own ``m`` (``dx = dtheta x arm``, so ``f . dx = dtheta . (arm x f)``)."""
        GN = G.reshape(-1, 6)[self.nodes]
        arm = frame.x[self.nodes] - self.centre()
        return np.concatenate([GN[:, self.translate].sum(axis=0),
                               (np.cross(arm, GN[:, :3]) + GN[:, 3:]).sum(axis=0)])

    def lever_hessian(self, frame, G):
        """The plate's second-order term (``ndof`` square; the translations move the nodes linearly, so only the
        rotations' block): the carried nodes' forces times the curvature of their paths, sum over nodes of
        ``f . (e_a x (e_b x arm) + e_b x (e_a x arm)) / 2``. As ``e_a x (e_b x arm) = e_b arm_a - arm delta_ab``,
        that is ``(A + A^T) / 2 - tr(A) I`` with ``A = sum arm f^T`` (one 3 x 3 product, not 36 cross products)."""
        arm = frame.x[self.nodes] - self.centre()
        f = G.reshape(-1, 6)[self.nodes, :3]
        A = arm.T @ f
        H = np.zeros((self.ndof, self.ndof))
        H[-3:, -3:] = 0.5 * (A + A.T) - np.trace(A) * np.eye(3)
        return H


def reduce(frame, free, plates, G, K):
    """The gradient ``G`` and Hessian ``K`` of the frame's energy (all DOFs) in the ``free`` node DOFs and the
    ``plates``' free DOFs (after them, in order), the plates' moments' work subtracted: ``(g, K)``, K sparse
    CSC (``None`` for ``K`` None: the gradient alone)."""
    n6, nf = 6 * frame.n, int(free.sum())
    if K is None:
        return np.concatenate([G[free]] + [p.gradient(frame, G) - p.work_gradient() for p in plates]), None
    rows, cols, vals = [np.flatnonzero(free)], [np.arange(nf)], [np.ones(nf)]
    first, blocks = nf, []
    for p in plates:
        r, c, v = p.columns(frame, first)
        rows.append(r); cols.append(c); vals.append(v)
        blocks.append((first, p))
        first += p.ndof
    T = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(n6, first))
    g = T.T @ G
    lr, lc, lv = [], [], []
    for f0, p in blocks:
        g[f0:f0 + p.ndof] -= p.work_gradient()
        a, b = np.divmod(np.arange(p.ndof ** 2), p.ndof)
        lr.append(f0 + a); lc.append(f0 + b); lv.append(p.lever_hessian(frame, G).ravel())
    Kr = (T.T @ K @ T).tocsc()
    if blocks:
        Kr = Kr + sp.csc_matrix((np.concatenate(lv), (np.concatenate(lr), np.concatenate(lc))), shape=Kr.shape)
    return g, Kr
