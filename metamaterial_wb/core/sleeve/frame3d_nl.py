"""The curved ring's 3-D frame made nonlinear (issue 18): corotational 3-D beams, large rotations, a path to
the first peak and past it.

Every element of ``frame3d.RingFrame`` keeps its linear section (stretching, bending about its two axes,
twisting) in a frame that moves with it (Crisfield's corotational formulation in 3-D): the element's axis 1
follows its chord, axes 2 and 3 the mean of its two nodes' rotated axes 2; each node's rotation relative to
that frame (the logarithm of ``R_e R_i R_e0^T``) gives the local end rotations, and the element energy is

    EA / (2 l0) (l - l0)^2 + GJ / (2 l0) (t1j - t1i)^2 + sum over a = 2, 3 of 2 EI_a / l0 (tai^2 + tai taj + taj^2)

(the 2-D model's form, ``beam.py``, in both bending planes). Large rotations and displacements are exact; the
strains small per element. Nodes carry positions and rotation matrices, updated by increments (``x + dx``,
``exp(dtheta) R``); the gradient and the Hessian of the energy in those increments are taken per element by
central differences (48 and 312 vectorised energy evaluations), assembled sparse, and the equilibrium at each
prescribed rise is an energy minimum found by Newton with a line search (a shift where the Hessian is not
positive definite). Displacement control, the top plate raised without tilt or twist (the curved solid's
four-cell ring tilts by less than 0.2 degrees). Units as the model's.
"""
import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

H_FD = 1e-6          # finite-difference step (positions in L, rotations in rad)


def expm_so3(v):
    """Rotation matrices ``exp(skew(v))`` of rotation vectors ``v`` (..., 3) (Rodrigues)."""
    v = np.asarray(v, float)
    a = np.linalg.norm(v, axis=-1)[..., None, None]
    K = np.zeros(v.shape[:-1] + (3, 3))
    K[..., 0, 1], K[..., 0, 2], K[..., 1, 2] = -v[..., 2], v[..., 1], -v[..., 0]
    K[..., 1, 0], K[..., 2, 0], K[..., 2, 1] = v[..., 2], -v[..., 1], v[..., 0]
    small = a < 1e-4
    s = np.where(small, 1 - a ** 2 / 6, np.sin(a) / np.where(small, 1, a))
    c = np.where(small, 0.5 - a ** 2 / 24, (1 - np.cos(a)) / np.where(small, 1, a) ** 2)
    return np.eye(3) + s * K + c * (K @ K)


def logm_so3(R):
    """Rotation vectors (..., 3) of rotation matrices ``R`` (..., 3, 3), angles below pi."""
    c = (np.trace(R, axis1=-2, axis2=-1) - 1) / 2
    w = 0.5 * np.stack([R[..., 2, 1] - R[..., 1, 2], R[..., 0, 2] - R[..., 2, 0], R[..., 1, 0] - R[..., 0, 1]], -1)
    s = np.linalg.norm(w, axis=-1)
    a = np.arctan2(s, c)                              # precise near 0, where arccos(c) is not
    small = a < 1e-4
    f = np.where(small, 1 + a ** 2 / 6, a / np.where(small, 1, s))
    return f[..., None] * w


class NonlinearFrame:
    """Corotational 3-D frame: nodes ``P`` (n, 3), elements ``conn`` (m, 2) with the shift of node 2's image
    ``shift3``, unloaded axes ``frames0`` (m, 3, 3; rows), lengths ``l0`` and sections ``EA``, ``EI2``, ``EI3``
    (bending about axes 2 and 3), ``GJ``."""

    def __init__(self, P, conn, shift3, frames0, l0, EA, EI2, EI3, GJ):
        self.P = np.asarray(P, float)
        self.conn = np.asarray(conn, int)
        self.shift3, self.frames0, self.l0 = np.asarray(shift3, float), np.asarray(frames0, float), np.asarray(l0)
        self.EA, self.EI2, self.EI3, self.GJ = (np.asarray(v, float) for v in (EA, EI2, EI3, GJ))
        self.n = len(self.P)
        self.x = self.P.copy()
        self.R = np.tile(np.eye(3), (self.n, 1, 1))
        m = len(self.conn)
        dofs = np.concatenate([6 * self.conn[:, :1] + np.arange(6), 6 * self.conn[:, 1:] + np.arange(6)], axis=1)
        self._rows = np.repeat(dofs, 12, axis=1).ravel()
        self._cols = np.tile(dofs, (1, 12)).ravel()
        self._dofs = dofs
        self._m = m

    @classmethod
    def of_ring(cls, ring):
        """The nonlinear frame of a ``frame3d.RingFrame``."""
        return cls(ring.P, ring.conn, ring.shift3, ring.frames0, ring.l0, ring.EA, ring.EI2, ring.EI3, ring.GJ)

    # ------------------------------------------------------------------------------------------
    def element_energy(self, du=None):
        """Energy of every element (m,) at the current state, each perturbed by ``du`` (m, 12): its nodes'
        position and rotation increments ``(dx_i, dtheta_i, dx_j, dtheta_j)``."""
        i, j = self.conn[:, 0], self.conn[:, 1]
        xi, xj, Ri, Rj = self.x[i], self.x[j] + self.shift3, self.R[i], self.R[j]
        if du is not None:
            xi, xj = xi + du[:, 0:3], xj + du[:, 6:9]
            Ri, Rj = expm_so3(du[:, 3:6]) @ Ri, expm_so3(du[:, 9:12]) @ Rj
        d = xj - xi
        l = np.linalg.norm(d, axis=1)
        e1 = d / l[:, None]
        e20 = self.frames0[:, 1]
        q = 0.5 * (np.einsum("mab,mb->ma", Ri, e20) + np.einsum("mab,mb->ma", Rj, e20))
        e3 = np.cross(e1, q)
        e3 /= np.linalg.norm(e3, axis=1)[:, None]
        e2 = np.cross(e3, e1)
        Re = np.stack([e1, e2, e3], axis=1)
        R0t = np.transpose(self.frames0, (0, 2, 1))
        ti = logm_so3(Re @ Ri @ R0t)
        tj = logm_so3(Re @ Rj @ R0t)
        l0 = self.l0
        return (self.EA / (2 * l0) * (l - l0) ** 2 + self.GJ / (2 * l0) * (tj[:, 0] - ti[:, 0]) ** 2
                + 2 * self.EI2 / l0 * (ti[:, 1] ** 2 + ti[:, 1] * tj[:, 1] + tj[:, 1] ** 2)
                + 2 * self.EI3 / l0 * (ti[:, 2] ** 2 + ti[:, 2] * tj[:, 2] + tj[:, 2] ** 2))

    def energy(self):
        return float(self.element_energy().sum())

    def gradient_hessian(self, hessian=True):
        """The energy's gradient (6 n) and Hessian (sparse, 6 n x 6 n) in the nodes' increments, by central
        differences per element."""
        h, m = H_FD, self._m
        g = np.zeros((m, 12))
        du = np.zeros((m, 12))
        for a in range(12):
            c = []
            for hh in (h, 2 * h):
                du[:, a] = hh
                ep = self.element_energy(du)
                du[:, a] = -hh
                c.append((ep - self.element_energy(du)) / (2 * hh))
            g[:, a] = (4 * c[0] - c[1]) / 3                  # Richardson: the h^2 error removed
            du[:, a] = 0.0
        G = np.bincount(self._dofs.ravel(), g.ravel(), 6 * self.n)
        if not hessian:
            return G, None
        H = np.zeros((m, 12, 12))
        for a in range(12):
            for b in range(a, 12):
                e = 0.0
                for sa, sb, w in ((1, 1, 1), (1, -1, -1), (-1, 1, -1), (-1, -1, 1)):
                    du[:, a] += sa * h
                    du[:, b] += sb * h
                    e = e + w * self.element_energy(du)
                    du[:, a] = 0.0
                    du[:, b] = 0.0
                H[:, a, b] = H[:, b, a] = e / (4 * h * h)
        K = sp.csr_matrix((H.ravel(), (self._rows, self._cols)), shape=(6 * self.n, 6 * self.n))
        return G, K

    def apply(self, dq):
        """Add the increments ``dq`` (6 n): positions, and rotations composed on the left."""
        dq = dq.reshape(-1, 6)
        self.x = self.x + dq[:, :3]
        self.R = expm_so3(dq[:, 3:]) @ self.R

    def equilibrium(self, free, tol=1e-10, maxit=40):
        """Minimise the energy over the ``free`` DOFs (boolean, 6 n) from the current state (Newton, a line
        search on the energy, a diagonal shift where the step is not a descent): the iterations taken."""
        for it in range(1, maxit + 1):
            G, K = self.gradient_hessian()
            gf = G[free]
            if np.max(np.abs(gf)) < tol:
                return it - 1
            Kff = K[free][:, free].tocsc()
            shift = 0.0
            scale = float(np.abs(Kff.diagonal()).max())
            for _ in range(60):
                try:
                    step = spla.spsolve(Kff + shift * sp.identity(Kff.shape[0], format="csc"), -gf)
                except RuntimeError:
                    step = None
                if step is not None and np.all(np.isfinite(step)) and step @ gf < 0:
                    break
                shift = max(4 * shift, 1e-8 * scale)
            else:
                raise RuntimeError("no descent direction")
            e0 = self.energy()
            x0, R0 = self.x.copy(), self.R.copy()
            dq = np.zeros(6 * self.n)
            t = 1.0
            for _ in range(30):
                dq[free] = t * step
                self.apply(dq)
                if self.energy() <= e0 + 1e-4 * t * (step @ gf) or t < 1e-6:
                    break
                self.x, self.R = x0.copy(), R0.copy()
                t *= 0.5
        raise RuntimeError(f"no equilibrium in {maxit} iterations (|gradient| {np.max(np.abs(gf)):.2e})")


def trace_ring(ring, d, tol=1e-10, progress=None):
    """The ``frame3d.RingFrame`` ``ring``'s force along the rises ``d`` (d / L, increasing from 0): the bottom
    bar clamped, the top one raised without tilt or twist; ``{"d", "F", "iterations", "frame"}`` with F / (G L^2)
    (the top nodes' reaction along the axis)."""
    fr = NonlinearFrame.of_ring(ring)
    free = np.ones(6 * fr.n, bool)
    top = []
    for i, p in ring.ties:
        free[6 * i:6 * i + 6] = False
        if p == 1:
            top.append(i)
    top = np.array(top)
    F, its = [], []
    for k, dk in enumerate(np.asarray(d, float)):
        fr.x[top, 2] = fr.P[top, 2] + dk
        its.append(fr.equilibrium(free, tol))
        G, _ = fr.gradient_hessian(hessian=False)
        F.append(float(G[6 * top + 2].sum()))
        if progress:
            progress(k, dk, F[-1])
    return {"d": np.asarray(d, float), "F": np.array(F), "iterations": its, "frame": fr}
