"""2-D corotational Euler-Bernoulli beam elements (Crisfield's formulation), vectorised with numpy.

Every node carries three degrees of freedom ``(u, v, theta)``: displacements from the reference
position and the rotation from the reference orientation. An element between nodes ``i`` and ``j``
has the reference length ``L0`` and angle ``beta0``; in the current configuration its chord has the
length ``ln`` and angle ``beta``. The rigid rotation ``alpha = beta - beta0`` is removed so that the
local (small-strain) quantities are

    ul = ln - L0,        th1 = theta_i - alpha,        th2 = theta_j - alpha

and the strain energy is ``EA/(2 L0) ul^2 + 2 EI/L0 (th1^2 + th1 th2 + th2^2)``. Large rotations and
displacements are exact (geometric nonlinearity); strains are assumed small per element.
Gradient and tangent are the exact derivatives of that energy (checked against finite
differences in ``tests/sleeve/test_beam_model.py``).
"""
import numpy as np


class BeamMesh:
    """Nodes (reference positions), element connectivity and section stiffnesses."""

    def __init__(self, X0, conn, EA, EI, shift=None):
        """``shift`` (m, 2), optional: added to an element's reference chord ``X0[j] - X0[i]``, so
        that an element can join a node to the periodic image of another (a ring closing on
        itself, a periodic unit cell); the displacements are shared, the geometry is shifted."""
        self.X0 = np.asarray(X0, dtype=float).reshape(-1, 2)
        self.conn = np.asarray(conn, dtype=int).reshape(-1, 2)
        m = len(self.conn)
        self.EA = np.broadcast_to(np.asarray(EA, dtype=float), (m,)).copy()
        self.EI = np.broadcast_to(np.asarray(EI, dtype=float), (m,)).copy()
        i, j = self.conn[:, 0], self.conn[:, 1]
        d0 = self.X0[j] - self.X0[i]
        if shift is not None:
            d0 = d0 + np.asarray(shift, dtype=float).reshape(-1, 2)
        self.L0 = np.hypot(d0[:, 0], d0[:, 1])
        if np.any(self.L0 <= 0):
            raise ValueError("zero-length beam element")
        self.d0 = d0
        self.dofs = np.stack([3 * i, 3 * i + 1, 3 * i + 2, 3 * j, 3 * j + 1, 3 * j + 2], axis=1)

    @property
    def ndof(self):
        return 3 * len(self.X0)

    def evaluate(self, q, need_hessian=True, sparse=False):
        """Energy, gradient (ndof,) and tangent (ndof, ndof) at nodal DOFs ``q``; the tangent is a
        dense array, or a scipy CSR matrix with ``sparse=True``."""
        q = np.asarray(q, dtype=float)
        ue = q[self.dofs]                                   # (m, 6)
        dx = self.d0[:, 0] + ue[:, 3] - ue[:, 0]
        dy = self.d0[:, 1] + ue[:, 4] - ue[:, 1]
        ln = np.hypot(dx, dy)
        c, s = dx / ln, dy / ln
        # rigid rotation relative to the reference chord, robust for any angle below pi
        alpha = np.arctan2(self.d0[:, 0] * dy - self.d0[:, 1] * dx,
                           self.d0[:, 0] * dx + self.d0[:, 1] * dy)
        th1 = ue[:, 2] - alpha
        th2 = ue[:, 5] - alpha
        L0, EA, EI = self.L0, self.EA, self.EI
        ul = ln - L0
        N = EA / L0 * ul
        k = 2.0 * EI / L0
        M1 = k * (2 * th1 + th2)
        M2 = k * (th1 + 2 * th2)
        energy = float(np.sum(0.5 * EA / L0 * ul ** 2 + k * (th1 ** 2 + th1 * th2 + th2 ** 2)))
        m = len(L0)
        zero = np.zeros(m)
        r = np.stack([-c, -s, zero, c, s, zero], axis=1)
        z = np.stack([s, -c, zero, -s, c, zero], axis=1)
        b1 = -z / ln[:, None]
        b1[:, 2] += 1.0
        b2 = -z / ln[:, None]
        b2[:, 5] += 1.0
        fe = N[:, None] * r + M1[:, None] * b1 + M2[:, None] * b2
        g = np.zeros(self.ndof)
        np.add.at(g, self.dofs, fe)
        if not need_hessian:
            return energy, g, None
        EAL = (EA / L0)[:, None, None]
        Ke = (EAL * r[:, :, None] * r[:, None, :]
              + (2 * k)[:, None, None] * (b1[:, :, None] * b1[:, None, :] + b2[:, :, None] * b2[:, None, :])
              + k[:, None, None] * (b1[:, :, None] * b2[:, None, :] + b2[:, :, None] * b1[:, None, :])
              + (N / ln)[:, None, None] * z[:, :, None] * z[:, None, :]
              + ((M1 + M2) / ln ** 2)[:, None, None] * (r[:, :, None] * z[:, None, :] + z[:, :, None] * r[:, None, :]))
        I = np.broadcast_to(self.dofs[:, :, None], Ke.shape)
        J = np.broadcast_to(self.dofs[:, None, :], Ke.shape)
        if sparse:
            import scipy.sparse as sp
            K = sp.csr_matrix((Ke.ravel(), (I.ravel(), J.ravel())), shape=(self.ndof, self.ndof))
            return energy, g, K
        K = np.zeros((self.ndof, self.ndof))
        np.add.at(K, (I, J), Ke)
        return energy, g, K
