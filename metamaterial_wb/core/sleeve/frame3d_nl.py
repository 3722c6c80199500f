"""The curved ring's 3-D frame made nonlinear (issue 18): corotational 3-D beams, large rotations, a path to
the first peak and past it.

Every element of ``frame3d.RingFrame`` keeps its linear section (stretching, bending about its two axes,
twisting) in a frame that moves with it (Crisfield's corotational formulation in 3-D): the element's axis 1
follows its chord, axes 2 and 3 the mean of its two nodes' rotated axes 2; each node's rotation relative to
that frame (the logarithm of ``R_e R_i R_e0^T``) gives the local end rotations, and the element energy is

    EA / (2 l0) (l - l0)^2 + GJ / (2 l0) (t1j - t1i)^2 + sum over a = 2, 3 of 2 EI_a / l0 (tai^2 + tai taj + taj^2)

(the 2-D model's form, ``beam.py``, in both bending planes). Large rotations and displacements are exact; the
strains small per element. Nodes carry positions and rotation matrices, updated by increments (``x + dx``,
``exp(dtheta) R``). The gradient of the energy in those increments is exact: the stretching term's
(``NonlinearFrame._axial``) and bending and twisting's through each element's axes and the left Jacobian of its
relative rotations (``_bend_gradient``). The Hessian: the stretching term's exactly, bending and twisting's by
central differences of their exact gradient over each element's nine relative increments (18 states, every
element's evaluated in one vectorised pass; differencing the energy itself took 181 states per element and 3 to 4
times as long; ``reference_gradient_hessian`` still does, as the check), assembled
sparse. The equilibrium at each prescribed rise is an energy minimum found by Newton with a line search (a
shift where the Hessian is not positive definite, its lowest mode followed down where it is indefinite) from a
secant prediction; a converged state that is a saddle (by the signs of its pivots) is left down its lowest mode,
so every state is a minimum (``stable``). Displacement control, the top plate raised without tilt or twist (the
curved solid's four-cell ring tilts by less than 0.2 degrees) or free to tilt and twist (``frame3d_plate``);
rings stacked (``RingFrame(pattern=...)``) with the plates between them free. Units as the model's.
"""
import time

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from metamaterial_wb.core.lattice.mechanics import inv_left_jacobian
from metamaterial_wb.core.sleeve.analysis import units_snapped
from metamaterial_wb.core.sleeve.frame3d import RingFrame
from metamaterial_wb.core.sleeve.frame3d_plate import RigidPlate, reduce
from metamaterial_wb.core.sleeve.rotations import expm_so3, logm_so3
from metamaterial_wb.core.sleeve.tangent import min_eig_sparse, symmetric_factor, symmetric_lu

H_FD = 1e-6          # the Hessian's difference step (positions in L, rotations in rad)


def _cross(a, b):
    """``np.cross`` on the last axis, without its axis shuffling (the stencil's batches are large)."""
    return np.stack([a[..., 1] * b[..., 2] - a[..., 2] * b[..., 1], a[..., 2] * b[..., 0] - a[..., 0] * b[..., 2],
                     a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]], -1)


def _dot(a, b):
    return np.einsum("...a,...a->...", a, b)


def _jl_inv_t(t, v):
    """``Jl(t)^-T v``: the inverse left Jacobian of SO(3) (``lattice.mechanics.inv_left_jacobian``), transposed, at
    rotation vectors ``t`` (..., 3) on ``v`` (..., 3). A turn ``phi`` on the left of ``exp(t)`` moves ``t`` by
    ``Jl(t)^-1 phi``, so a gradient ``v`` in ``t`` is ``Jl^-T v`` in ``phi``."""
    J = inv_left_jacobian(t.reshape(-1, 3)).reshape(t.shape + (3,))
    return np.einsum("...ba,...b->...a", J, v)


# An element's energy depends on its nodes' positions only through their difference r = x_j - x_i: its gradient
# is taken in the 9 relative increments (r, dtheta_i, dtheta_j); T maps them to the 12 (dx_i, dtheta_i, dx_j,
# dtheta_j), so a rigid translation lies exactly in every element's Hessian.
_T = np.zeros((9, 12))
_T[0:3, 0:3], _T[0:3, 6:9], _T[3:6, 3:6], _T[6:9, 9:12] = -np.eye(3), np.eye(3), np.eye(3), np.eye(3)


def _solve(K, b):
    """``K^-1 b`` for the sparse symmetric ``K`` (CSC): by ``tangent.symmetric_factor`` (minimum degree on
    K + K^T, diagonal pivots; about twice as fast as ``spsolve``'s column ordering here), or by ``spsolve``
    (partial pivoting) where that LU fails or its residual is above round-off (an indefinite ``K`` that needs
    pivoting off the diagonal). ``spsolve``'s RuntimeError for a singular ``K`` passes through."""
    try:
        lu = symmetric_factor(K)
        x = lu.solve(b)
        if np.all(np.isfinite(x)) and np.linalg.norm(K @ x - b) <= 1e-10 * np.linalg.norm(b):
            return x, lu.solve
    except RuntimeError:
        pass
    return spla.spsolve(K, b), None


def _csr_pattern(rows, cols, n):
    """The CSR structure of the COO triplets' positions ``rows``, ``cols`` (n x n, duplicates summed): the slot of
    each triplet in the data array, the column indices (sorted within each row) and the row pointer."""
    order = np.lexsort((cols, rows))
    r, c = rows[order], cols[order]
    first = np.r_[True, (r[1:] != r[:-1]) | (c[1:] != c[:-1])]
    slot = np.empty(len(rows), np.int64)
    slot[order] = np.cumsum(first) - 1
    return slot, c[first], np.searchsorted(r[first], np.arange(n + 1))


def _moves():
    """The Hessian's stencil: each of an element's 9 relative increments by +H_FD (rows 0-8) and -H_FD (rows
    9-17), r applied to node j, as ``(dxi, dxj, turn_i, turn_j)``: the moves (18, 1, 3) to broadcast over the
    elements, each turn the distinct rotation matrices of its rows and each row's index into them."""
    steps = np.concatenate([np.eye(9), -np.eye(9)]) @ _T.clip(0)
    h = steps[:, None, :] * H_FD
    turns = []
    for cols in (slice(3, 6), slice(9, 12)):
        distinct, index = np.unique(steps[:, cols], axis=0, return_inverse=True)
        turns.append((expm_so3(distinct * H_FD), index.ravel()))
    return h[..., 0:3], h[..., 6:9], turns[0], turns[1]


_MOVES = _moves()
BATCH = 60000        # element states evaluated per pass (memory about 200 * BATCH doubles)
CHORD_RATE = 0.3     # equilibrium: chord steps go on while each cuts the gradient at least this much,
CHORD_FLOOR = 1e-2   # and to this fraction of the tolerance (cheap; Newton's last step overshoots as far)


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
        self._pattern = _csr_pattern(self._rows, self._cols, 6 * self.n)

    def assemble(self, blocks):
        """The element blocks ``blocks`` (m, 12, 12) summed into the sparse 6 n x 6 n matrix (CSR) on the pattern
        found once (``_csr_pattern``): the same matrix as from the COO triplets, without sorting them each time."""
        slot, indices, indptr = self._pattern
        data = np.bincount(slot, np.asarray(blocks).ravel(), len(indices))
        K = sp.csr_matrix((data, indices, indptr), shape=(6 * self.n, 6 * self.n))
        K.has_sorted_indices = True
        return K

    @classmethod
    def of_ring(cls, ring):
        """The nonlinear frame of a ``frame3d.RingFrame``."""
        return cls(ring.P, ring.conn, ring.shift3, ring.frames0, ring.l0, ring.EA, ring.EI2, ring.EI3, ring.GJ)

    # ------------------------------------------------------------------------------------------
    def element_energy(self, du=None, elements=slice(None)):
        """Energy of the ``elements`` (all by default) at the current state, each perturbed by ``du`` (..., m, 12):
        its nodes' position and rotation increments ``(dx_i, dtheta_i, dx_j, dtheta_j)``, any leading axes a
        batch of perturbations."""
        if du is None:
            return self._energy(elements, 0.0, 0.0, np.eye(3), np.eye(3))
        return self._energy(elements, du[..., 0:3], du[..., 6:9], expm_so3(du[..., 3:6]), expm_so3(du[..., 9:12]))

    def _local(self, elements, dxi, dxj, turn_i, turn_j):
        """The ``elements``' corotational state with the nodes moved by ``dxi``, ``dxj`` and turned by ``turn_i``,
        ``turn_j`` (each broadcast against the ``elements``): rotation matrices (..., 3, 3), or a pair (U, 3, 3) of
        distinct ones and the index (S,) into them, which turns every element only U times and gathers (the
        stencil's batched 3 x 3 products cost about 100 ns each). ``(l, Re, qi, qj, s, ti, tj)``: the chord's
        length, the element's axes (rows e1, e2, e3), its nodes' turned axes 2 and ``|e1 x (qi + qj) / 2|``, and
        the nodes' rotations relative to the element's axes."""
        c = self.conn[elements]
        i, j = c[:, 0], c[:, 1]
        xi, xj = self.x[i] + dxi, self.x[j] + self.shift3[elements] + dxj
        R0t = np.transpose(self.frames0[elements], (0, 2, 1))
        e20 = self.frames0[elements, 1]
        d = xj - xi
        l = np.linalg.norm(d, axis=-1)
        e1 = d / l[..., None]
        qs, Ms = [], []
        for n, turn in ((i, turn_i), (j, turn_j)):
            Rn = self.R[n]
            Rne = np.concatenate([Rn @ R0t, np.einsum("mab,mb->ma", Rn, e20)[..., None]], axis=-1)   # (m, 3, 4)
            if isinstance(turn, tuple):
                Rne = (turn[0][:, None] @ Rne)[turn[1]]
            else:
                Rne = turn @ Rne
            Ms.append(Rne[..., :3])
            qs.append(Rne[..., 3])
        e3 = _cross(e1, 0.5 * (qs[0] + qs[1]))
        s = np.linalg.norm(e3, axis=-1)
        e3 /= s[..., None]
        e2 = _cross(e3, e1)
        Re = np.stack([e1, e2, e3], axis=-2)
        return l, Re, qs[0], qs[1], s, logm_so3(Re @ Ms[0]), logm_so3(Re @ Ms[1])

    def _energy(self, elements, dxi, dxj, turn_i, turn_j):
        """The element energies with the nodes moved and turned (``_local``)."""
        l, _, _, _, _, ti, tj = self._local(elements, dxi, dxj, turn_i, turn_j)
        l0, EA, GJ = self.l0[elements], self.EA[elements], self.GJ[elements]
        EI2, EI3 = self.EI2[elements], self.EI3[elements]
        return (EA / (2 * l0) * (l - l0) ** 2 + GJ / (2 * l0) * (tj[..., 0] - ti[..., 0]) ** 2
                + 2 * EI2 / l0 * (ti[..., 1] ** 2 + ti[..., 1] * tj[..., 1] + tj[..., 1] ** 2)
                + 2 * EI3 / l0 * (ti[..., 2] ** 2 + ti[..., 2] * tj[..., 2] + tj[..., 2] ** 2))

    def _bend_gradient(self, elements, dxi, dxj, turn_i, turn_j):
        """The exact gradient (..., m, 9) of the bending and twisting energy in each element's relative
        increments (r, dtheta_i, dtheta_j) at the moved and turned state (``_local``). A turn dtheta_n of node n
        and the element axes' own turn w (r and the mean axis 2 q moving) turn its relative rotation t_n by
        ``phi_n = Re (dtheta_n - w)`` on the left, so t_n moves by ``Jl(t_n)^-1 phi_n``; w in the element's
        axes: ``(dq . e3 - (q . e1) dr . e3 / l) / s``, ``-dr . e3 / l``, ``dr . e2 / l``, with
        ``dq = (dtheta_i x qi + dtheta_j x qj) / 2``."""
        l, Re, qi, qj, s, ti, tj = self._local(elements, dxi, dxj, turn_i, turn_j)
        l0, GJ = self.l0[elements], self.GJ[elements]
        b2, b3 = 2 * self.EI2[elements] / l0, 2 * self.EI3[elements] / l0
        tw = GJ / l0 * (tj[..., 0] - ti[..., 0])
        wi = _jl_inv_t(ti, np.stack([-tw, b2 * (2 * ti[..., 1] + tj[..., 1]), b3 * (2 * ti[..., 2] + tj[..., 2])], -1))
        wj = _jl_inv_t(tj, np.stack([tw, b2 * (ti[..., 1] + 2 * tj[..., 1]), b3 * (ti[..., 2] + 2 * tj[..., 2])], -1))
        w = wi + wj
        e1, e2, e3 = Re[..., 0, :], Re[..., 1, :], Re[..., 2, :]
        q1 = 0.5 * _dot(qi + qj, e1)
        g = np.empty(l.shape + (9,))
        g[..., 0:3] = ((w[..., 0] * q1 / s + w[..., 1]) / l)[..., None] * e3 - (w[..., 2] / l)[..., None] * e2
        half = (0.5 * w[..., 0] / s)[..., None]
        g[..., 3:6] = np.einsum("...ba,...b->...a", Re, wi) - half * _cross(qi, e3)
        g[..., 6:9] = np.einsum("...ba,...b->...a", Re, wj) - half * _cross(qj, e3)
        return g

    def energy(self):
        return float(self.element_energy().sum())

    def gradient_hessian(self, hessian=True):
        """The energy's gradient (6 n) and Hessian (sparse, 6 n x 6 n) in the nodes' increments, both exact but
        the Hessian's bending and twisting: stretching, by far the stiffest term, exactly (``_axial``); bending
        and twisting's gradient exactly (``_bend_gradient``), their Hessian by central differences of it over
        each element's 9 relative increments (``_MOVES``: 18 states, every element's in one vectorised pass, the
        elements in chunks that keep the batch near ``BATCH``), made symmetric (the differenced gradient is the
        Hessian plus half the skew matrix of the rotational gradient, the exponential map's own term, which the
        symmetric part drops)."""
        m = self._m
        g, Ha = self._axial(hessian)
        g9 = self._bend_gradient(slice(None), 0.0, 0.0, np.eye(3), np.eye(3))
        G = np.bincount(self._dofs.ravel(), (g + g9 @ _T).ravel(), 6 * self.n)
        if not hessian:
            return G, None
        H9 = np.empty((m, 9, 9))
        chunk = max(1, BATCH // 18)
        for a in range(0, m, chunk):
            el = slice(a, min(m, a + chunk))
            gs = self._bend_gradient(el, *_MOVES)                   # (18, elements, 9)
            D = np.transpose(gs[:9] - gs[9:], (1, 2, 0)) / (2 * H_FD)    # D[e, a, b] = d g_a / d u_b
            H9[el] = 0.5 * (D + np.transpose(D, (0, 2, 1)))
        return G, self.assemble(Ha + _T.T @ H9 @ _T)

    def _axial(self, hessian=True):
        """The stretching energy's exact gradient (m, 12) and Hessian (m, 12, 12): with k = EA / l0,
        f = k (l - l0) and e the chord's direction, the force f e on node j and its
        tangent k e e^T + f / l (I - e e^T) in the relative position."""
        i, j = self.conn[:, 0], self.conn[:, 1]
        d = self.x[j] + self.shift3 - self.x[i]
        l = np.linalg.norm(d, axis=1)
        e = d / l[:, None]
        k = self.EA / self.l0
        f = k * (l - self.l0)
        g = np.zeros((self._m, 12))
        g[:, 0:3], g[:, 6:9] = -f[:, None] * e, f[:, None] * e
        if not hessian:
            return g, None
        ee = e[:, :, None] * e[:, None, :]
        Kx = k[:, None, None] * ee + (f / l)[:, None, None] * (np.eye(3) - ee)
        H = np.zeros((self._m, 12, 12))
        H[:, 0:3, 0:3] = H[:, 6:9, 6:9] = Kx
        H[:, 0:3, 6:9] = H[:, 6:9, 0:3] = -Kx
        return g, H

    def apply(self, dq):
        """Add the increments ``dq`` (6 n): positions, and rotations composed on the left."""
        dq = dq.reshape(-1, 6)
        self.x = self.x + dq[:, :3]
        self.R = expm_so3(dq[:, 3:]) @ self.R

    def reduced(self, free, plate=None, hessian=True):
        """The total energy's gradient and Hessian (sparse CSC; ``None`` without ``hessian``) in the ``free`` DOFs
        and, with a ``RigidPlate`` or a list of them, their free DOFs (last; ``frame3d_plate.reduce``)."""
        G, K = self.gradient_hessian(hessian)
        plates = _plates(plate)
        if not plates:
            return G[free], K[free][:, free].tocsc() if hessian else None
        return reduce(self, free, plates, G, K)

    def lowest_modes(self, free, plate=None, k=4):
        """The ``k`` lowest eigenvalues of the reduced Hessian (``reduced``) and the plates' rotations' share of
        each mode (their part of the unit eigenvector; 0 without a plate): a tilt mode that reaches zero is where
        the untilted path stops being a minimum."""
        _, K = self.reduced(free, plate)
        w, v = spla.eigsh(K, k=k, sigma=-1e-9 * float(abs(K).max()), which="LM")
        order = np.argsort(w)
        rot, first = [], int(free.sum())
        for p in _plates(plate):
            first += p.ndof
            rot += [first - 3, first - 2, first - 1]
        share = (np.linalg.norm(v[rot], axis=0) if rot else np.zeros(k))[order]
        return w[order], share

    def equilibrium(self, free, tol=1e-10, maxit=40, plate=None, stable=True):
        """Minimise the energy over the ``free`` DOFs (boolean, 6 n) and, with a ``RigidPlate`` or a list of
        them, their free DOFs, from the current state (Newton, a line search on the energy, a diagonal shift where
        the step is not a descent; the full step once the decrease it predicts is below the energy's round-off;
        after a Newton step, chord steps on its LU while each cuts the gradient to ``CHORD_RATE`` of the last, down
        to ``CHORD_FLOOR`` of ``tol``, and the converged state's own Hessian for the check below): the iterations
        taken, Newton and chord. With ``stable`` a state where the gradient vanishes but the reduced Hessian has a
        negative eigenvalue (below -1e-10 of its largest diagonal entry; by its pivots' signs, Sylvester) is a
        saddle, left down its lowest eigenvector (``_negative_curvature``, at most ten times) - the symmetric
        state a symmetric structure keeps by itself, e.g. two equal rings in series past their shared peak."""
        nf = int(free.sum())
        plates = _plates(plate)
        escapes = 0

        def total():
            return self.energy() - sum(p.work() for p in plates)

        def move(v):
            dq = np.zeros(6 * self.n)
            dq[free] = v[:nf]
            self.apply(dq)
            f0 = nf
            for p in plates:
                p.move(self, v[f0:f0 + p.ndof])
                f0 += p.ndof

        def keep():
            x0, R0, saved = self.x.copy(), self.R.copy(), [p.state() for p in plates]

            def back():
                self.x, self.R = x0.copy(), R0.copy()
                for p, st in zip(plates, saved):
                    p.restore(st)
            return back

        def search(step, gf, e0, back):
            """The step, halved until the energy falls enough (Armijo); the full step once the decrease it
            predicts is below the energy's round-off."""
            t = 1.0
            exact = abs(step @ gf) < 1e-12 * abs(e0)
            for _ in range(30):
                move(t * step)
                if exact or total() <= e0 + 1e-4 * t * (step @ gf) or t < 1e-6:
                    return
                back()
                t *= 0.5

        chord, g_last = None, None
        for it in range(1, maxit + 1):
            if chord is not None:
                # a chord step: the last Newton step's factor again while it cuts the gradient by CHORD_RATE a
                # step (a Hessian and its LU cost about ten gradients); the converged state's own Hessian below
                gf = self.reduced(free, plate, hessian=False)[0]
                g_now = float(np.max(np.abs(gf)))
                if CHORD_FLOOR * tol <= g_now < CHORD_RATE * g_last:
                    step = chord(-gf)
                    if np.all(np.isfinite(step)) and step @ gf < 0:
                        e0 = total()
                        search(step, gf, e0, keep())
                        g_last = g_now
                        continue
                chord = None
            gf, Kff = self.reduced(free, plate)
            saddle = False
            if np.max(np.abs(gf)) < tol:
                if not stable or escapes >= 10 or symmetric_lu(Kff)[1] == 0:
                    return it - 1
                saddle = True
            shift = 0.0
            scale = float(np.abs(Kff.diagonal()).max())
            for _ in range(0 if saddle else 60):
                try:
                    step, chord = _solve(Kff + shift * sp.identity(Kff.shape[0], format="csc") if shift else Kff,
                                         -gf)
                except RuntimeError:
                    step = None
                if step is not None and np.all(np.isfinite(step)) and step @ gf < 0:
                    break
                shift = max(4 * shift, 1e-8 * scale)
            else:
                if not saddle:
                    raise RuntimeError("no descent direction")
            if saddle or shift > 0:
                chord = None
            g_last = float(np.max(np.abs(gf)))
            e0 = total()
            back = keep()
            if saddle or shift > 0:
                # a converged state counts as a saddle below -1e-10 of the scale (the differenced Hessian's
                # soft modes stay above that); before that, any way down helps
                moved = self._negative_curvature(Kff, gf, 1e-10 * scale if saddle else 0.0, move, back, total, e0)
                if saddle:
                    if not moved:
                        return it - 1
                    escapes += 1
                if moved:
                    continue
            search(step, gf, e0, back)
        raise RuntimeError(f"no equilibrium in {maxit} iterations (|gradient| {np.max(np.abs(gf)):.2e})")

    @staticmethod
    def _negative_curvature(K, g, floor, move, back, total, e0):
        """Where the reduced Hessian ``K`` has an eigenvalue below ``-floor``, the way down from the saddle: its
        lowest eigenvector (``tangent.min_eig_sparse``), turned against the gradient ``g`` (where ``g`` does not
        tell, towards the lower energy 1e-3 either way), followed by an expanding search (1e-3 to 0.5; the first
        length that does not lower the energy ends it) - as the beam model's ``minimise``; the shifted Newton step
        alone crawls off a saddle, and at a symmetric one it stays. True when it moved (the state left there)."""
        w, v = min_eig_sparse(K, k=1)
        if w[0] >= -floor:
            return False
        v = v[:, 0]
        gv = float(v @ g)
        if abs(gv) <= 1e-6 * float(np.linalg.norm(g)) or not np.any(g):
            side = []
            for sgn in (1.0, -1.0):
                move(sgn * 1e-3 * v)
                side.append(total())
                back()
            v = -v if side[1] < side[0] else v
        elif gv > 0:
            v = -v
        best, best_e, a = 0.0, e0, 1e-3
        while a <= 0.5:
            move(a * v)
            e = total()
            back()
            if e >= best_e:
                break
            best, best_e, a = a, e, 2 * a
        if best:
            move(best * v)
        return best > 0


def _plates(plate):
    """``None``, one ``RigidPlate`` or a list of them, as a list."""
    return [] if plate is None else list(plate) if isinstance(plate, (list, tuple)) else [plate]


def first_peak(geom, n_cells, root_extension, n_el, d, beam_model_P1=None, beam_model_plane=None):
    """The uniform curved ring's first peak from the nonlinear frame, for the ``sleeve`` command
    (``model.frame_nonlinear``): the ring of ``n_cells`` cells ``geom`` (``frame3d.RingFrame``, plane stress,
    ``root_extension``, ``n_el`` elements per beam half) traced along ``d`` (d / L) until its force has fallen
    past a maximum. ``{"P1", "P1_displacement", "beam_model_P1", "beam_model_plane", "ratio", "root_extension",
    "elements", "steps", "seconds"}``
    (P1 None when the force still rises at the end of ``d``; ratio the beam model's P1 over the frame's), or
    ``{"error", "elements", "seconds"}`` when Newton finds no equilibrium."""
    t0 = time.perf_counter()
    ring = RingFrame(geom, n_cells, plane="stress", root_extension=root_extension, n_el=n_el)
    try:
        r = trace_ring(ring, d, stop_after_peak=True)
    except RuntimeError as e:
        return {"error": str(e), "elements": n_el, "seconds": time.perf_counter() - t0}
    F = r["F"]
    k = int(np.argmax(F))
    peaked = 0 < k < len(F) - 1
    P1 = float(F[k]) if peaked else None
    return {"P1": P1, "P1_displacement": float(r["d"][k]) if peaked else None,
            "beam_model_P1": beam_model_P1, "beam_model_plane": beam_model_plane, "root_extension": root_extension,
            "ratio": beam_model_P1 / P1 if (P1 and beam_model_P1 is not None) else None,
            "elements": n_el, "steps": len(F), "seconds": time.perf_counter() - t0}


def reference_gradient_hessian(frame, h=H_FD):
    """The slow, plain route to ``frame.gradient_hessian()`` (the one this module used first): the whole element
    energy, stretching included, differenced one increment and one pair at a time over all 12 (fourth-order
    gradient, four-corner Hessian with 2 h on its diagonal), 360 vectorised energy evaluations. A check on the
    batched stencil and the exact stretching, and the speed baseline (benchmarks/bench_sleeve_frame3d.py)."""
    m = frame._m
    du = np.zeros((m, 12))
    g, H = np.zeros((m, 12)), np.zeros((m, 12, 12))
    for a in range(12):
        c = []
        for hh in (h, 2 * h):
            du[:, a] = hh
            ep = frame.element_energy(du)
            du[:, a] = -hh
            c.append((ep - frame.element_energy(du)) / (2 * hh))
        g[:, a] = (4 * c[0] - c[1]) / 3
        du[:, a] = 0.0
        for b in range(a, 12):
            e = 0.0
            for sa, sb in ((1, 1), (1, -1), (-1, 1), (-1, -1)):
                du[:, a] += sa * h
                du[:, b] += sb * h
                e = e + sa * sb * frame.element_energy(du)
                du[:, a] = du[:, b] = 0.0
            H[:, a, b] = H[:, b, a] = e / (4 * h * h)
    n6 = 6 * frame.n
    G = np.bincount(frame._dofs.ravel(), g.ravel(), n6)
    return G, sp.csr_matrix((H.ravel(), (frame._rows, frame._cols)), shape=(n6, n6))


def trace_ring(ring, d, tol=1e-10, progress=None, predict=True, stop_after_peak=False, plate="fixed", bias=1e-5,
               bias_angle=0.5, modes=0, bias_ramp=None, start=None, stable=True):
    """The ``frame3d.RingFrame`` ``ring``'s force along the rises ``d`` (d / L, increasing from 0): the bottom
    bar clamped, the top one raised; ``{"d", "F", "iterations", "tilt", "frame"}`` with F / (G L^2) (the top
    nodes' reaction along the axis) and the top plate's rotation vectors (k, 3). ``plate``: ``"fixed"``, raised
    without tilt or twist, or ``"free"``, the curved solid's rigid plate (``RigidPlate``: tilting and twisting
    freely under a bias moment ``bias R`` towards ``bias_angle * pi / N``, ``fe/sleeve3d.py``'s; with
    ``bias_ramp`` the moment grows with the rise, reaching its full size at ``d = bias_ramp``, as a ccx
    ``*STATIC`` step ramps it to the step's end). Each state is
    predicted from the last two (secant, if ``predict``). With ``stop_after_peak`` the trace ends two falling
    steps after its first maximum (``d`` cut there). With ``modes`` > 0 also ``"modes"`` and ``"plate_share"``
    (k, modes): the lowest eigenvalues of each state's reduced Hessian and the plate's share of their modes
    (``NonlinearFrame.lowest_modes``). ``"snapped"`` (k, units): which of the ring's hysterons (the edge
    pillars, each with its two beam halves) have snapped at each state, by the beam model's rule: the mean of
    their halves' outer ends' rises over their inner ends' beyond h / L (``RingFrame.states``), and ``"rises"``
    (k, states): those rises, per beam half. A sleeve of stacked rings (``RingFrame`` of a ``pattern``): the
    plates between them rise, tilt and twist freely (``RigidPlate(translate=(2,))``, as the beam model's
    interfaces), ``"ring_rises"`` (k, rings) each ring's own rise (its upper plate's centre's over its lower one's) and
    ``"plates"`` every plate that moves freely (those between the rings, then the top one if free; ``"plate"``
    the top one or None). ``start``: a result of this function to go on from (its frame and plates; e.g.
    unloading along ``d`` falling from its last rise). ``stable``: every state a minimum (``equilibrium``: a
    saddle is left down its lowest mode); False keeps a symmetric path through its bifurcations, as the unbiased
    solid's (``bench/fe_frame3d_plate.py``'s untilted runs, which read the tilt pair's zero off it)."""
    if plate not in ("fixed", "free"):
        raise ValueError(f"plate: {plate!r}; allowed: 'fixed', 'free'")
    fr = NonlinearFrame.of_ring(ring) if start is None else start["frame"]
    M = ring.rings
    free = np.ones(6 * fr.n, bool)
    on = [[] for _ in range(M + 1)]                      # the nodes tied to each plate, 0 the clamped bottom
    for i, p in ring.ties:
        free[6 * i:6 * i + 6] = False
        on[p].append(i)
    top = np.array(on[M])
    if start is None:                                     # the plates between stacked rings: free bodies
        plates = [RigidPlate(fr, on[p], translate=(2,)) for p in range(1, M)]
        rp = None
        if plate == "free":
            phi = bias_angle * np.pi / ring.n_cells
            m = bias * ring.radius
            rp = RigidPlate(fr, top, (m * np.sin(phi), -m * np.cos(phi), 0.0))
            plates.append(rp)
    else:
        plates, rp = start["plates"], start["plate"]
    full = rp.moment.copy() if rp is not None else None
    F, its, tilt, lows, shares, snapped, rises, ring_rise = [], [], [], [], [], [], [], []
    a_, b_ = np.array(ring.states).T
    unit_ids = sorted(set(ring.units), key=ring.units.index)
    unit_of = np.array([unit_ids.index(u) for u in ring.units])
    d = np.asarray(d, float)
    def state():
        return fr.x.copy(), fr.R.copy(), [p.state() for p in plates]

    def restore(st):
        fr.x, fr.R = st[0].copy(), st[1].copy()
        for p, ps in zip(plates, st[2]):
            p.restore(ps)
            p.place(fr)

    def raise_to(dk):
        if rp is None:
            fr.x[top, 2] = fr.P[top, 2] + dk
        else:
            rp.place(fr, dk)
            if bias_ramp:
                rp.moment = full * min(1.0, dk / bias_ramp)

    last = None
    for k, dk in enumerate(d):
        now = state()
        # secant predictor from the last two states
        if predict and last is not None and k >= 2 and d[k - 1] != d[k - 2]:
            s = (dk - d[k - 1]) / (d[k - 1] - d[k - 2])
            fr.x = now[0] + s * (now[0] - last[0])
            fr.R = expm_so3(s * logm_so3(now[1] @ np.transpose(last[1], (0, 2, 1)))) @ now[1]
            for p, (R1, c1), (R0, c0) in zip(plates, now[2], last[2]):
                p.restore((expm_so3(s * logm_so3(R1 @ R0.T)) @ R1, c1 + s * (c1 - c0)))
                p.place(fr)
        last = now
        raise_to(dk)
        try:
            its.append(fr.equilibrium(free, tol, plate=plates, stable=stable))
        except RuntimeError:
            # a jump (the secant extrapolates the last one, or the state leaves its branch here): from the last
            # state without the prediction, in quarter steps, with more iterations each
            restore(now)
            n = 0
            for dj in np.linspace(d[k - 1] if k else 0.0, dk, 5)[1:]:
                raise_to(dj)
                n += fr.equilibrium(free, tol, maxit=200, plate=plates, stable=stable)
            its.append(n)
        G, _ = fr.gradient_hessian(hessian=False)
        F.append(float(G[6 * top + 2].sum()))
        tilt.append(rp.tilt() if rp is not None else np.zeros(3))
        levels = np.array([0.0] + [p.shift[2] for p in plates if p.translate] + [dk])
        ring_rise.append(np.diff(levels))
        rise = (fr.x - fr.P)[a_, 2] - (fr.x - fr.P)[b_, 2]
        rises.append(rise)
        snapped.append(units_snapped(rise, ring.snap_height, unit_of)[0])
        if modes:
            w, sh = fr.lowest_modes(free, plates, modes)
            lows.append(w)
            shares.append(sh)
        if progress:
            progress(k, dk, F[-1])
        if stop_after_peak and k >= 3 and F[-1] < F[-2] < F[-3]:
            d = d[:k + 1]
            break
    out = {"d": d, "F": np.array(F), "iterations": its, "tilt": np.array(tilt), "snapped": np.array(snapped),
           "rises": np.array(rises), "ring_rises": np.array(ring_rise), "frame": fr, "plate": rp,
           "plates": plates}
    if modes:
        out.update(modes=np.array(lows), plate_share=np.array(shares))
    return out
