"""Force-displacement models of one unit cell, one ring of cells and a sleeve of rings.

Mechanics (see ``docs/sleeves.md``):

* every free part of the two curved beams (left and right of the central pillar, lower and upper
  beam: four segments per cell) is a chain of corotational beam elements (``beam.py``) along the
  cosine centre line; the edge pillars and the bottom bar are clamped; the central pillar and the
  top bar form one rigid body (stiff link elements from a reference node to the four inner beam
  ends);
* units: lengths / L, forces / (G L^2): the material enters only through ``E = 4 G`` (incompressible
  neo-Hookean, small-strain plane-strain modulus, out-of-plane motion restricted as in the seed) or
  ``E = 3 G`` (``plane="stress"``); section ``A = t T``, ``I = T t^3 / 12``;
* unit cell: the top body's vertical displacement ``d`` is prescribed, its horizontal displacement
  and rotation are free (the seed's kinematic coupling); neighbours enter through the clamped,
  shared edge pillars (periodicity);
* ring of N cells (angles ``phi_k = 2 pi k / N`` on the mid radius ``R``) and M rings in series:
  every ring interface is a rigid plate with axial displacement ``w`` and tilt ``(psi_x, psi_y)``;
  cell k of ring r sees ``v = dw + R (dpsi_x sin phi_k - dpsi_y cos phi_k)`` and the in-plane
  rotation of its top bar ``theta = dpsi_x cos phi_k + dpsi_y sin phi_k`` (the tilt component about
  its radial axis); the top plate's ``w = d`` is prescribed, all tilts are free;
* path following: displacement control with a secant predictor; at every step the total energy is
  *minimised* (Newton with Cholesky; a negative-curvature direction from the smallest eigenvector
  when the tangent is indefinite), so the traced path is the stable one a slow, quasi-static
  displacement-controlled test follows: through negative stiffness continuously, and with a jump
  (recorded as an event) where the stable branch ends (snap-back).
"""
import math
import time
from dataclasses import dataclass, field

import numpy as np
import scipy.linalg as sla

from metamaterial_wb.core.errors import MetamaterialError
from metamaterial_wb.core.sleeve.beam import BeamMesh
from metamaterial_wb.core.sleeve.cell import CellGeometry

LINK_FACTOR = 1.0e3     # stiffness of the rigid-body links relative to the beam's axial stiffness


def modulus(plane="strain"):
    """Young's modulus in units of G for an incompressible neo-Hookean material."""
    if plane == "strain":
        return 4.0
    if plane == "stress":
        return 3.0
    raise MetamaterialError(f"plane: {plane!r}; allowed: 'strain', 'stress'")


@dataclass
class CellMesh:
    """Nodes (in units of L) of one cell; node 0 is the top body's reference node."""
    X0: np.ndarray
    conn: np.ndarray
    EA: np.ndarray
    EI: np.ndarray
    fixed_nodes: list
    top: int = 0
    segments: list = field(default_factory=list)    # node index lists, centre side first


def build_cell_mesh(geom: CellGeometry, n_el=10, plane="strain", t_scale=1.0):
    """Beam mesh of one unit cell, normalised by L. ``t_scale`` scales the beam thickness."""
    L = geom.L
    E = modulus(plane)
    t, T = geom.t * t_scale / L, geom.T / L
    EA_b, EI_b = E * t * T, E * T * t ** 3 / 12.0
    c = geom.c / L
    ref = np.array([0.0, (geom.y_lower + 0.5 * geom.spacing) / L])
    X = [ref]
    conn, EA, EI, fixed, segs = [], [], [], [], []
    for which in (0, 1):
        for side in (-1, 1):
            # graded towards both ends (clamps): cosine spacing
            s = 0.5 * (1 - np.cos(np.linspace(0, np.pi, n_el + 1)))
            xs = side * (c / 2 + (0.5 - c / 2) * s)
            ys = geom.centre_line(xs * L, which) / L
            first = len(X)
            for x, y in zip(xs, ys):
                X.append(np.array([x, y]))
            idx = list(range(first, first + n_el + 1))
            segs.append(idx)
            for a, b in zip(idx[:-1], idx[1:]):
                conn.append((a, b)); EA.append(EA_b); EI.append(EI_b)
            fixed.append(idx[-1])                  # outer end on the edge pillar: clamped
            # rigid link: reference node -> inner end (on the central pillar)
            ell = np.hypot(*(X[idx[0]] - ref))
            conn.append((0, idx[0])); EA.append(LINK_FACTOR * EA_b)
            EI.append(LINK_FACTOR * EA_b * ell ** 2 / 12.0)
    return CellMesh(np.array(X), np.array(conn), np.array(EA), np.array(EI), fixed, 0, segs)


@dataclass
class Path:
    """A traced FD path. ``d`` and ``F`` normalised (d / L, F / (G L^2))."""
    d: np.ndarray
    F: np.ndarray
    states: np.ndarray            # (n, ncells) top-body displacement of every cell, / L
    tilt: np.ndarray              # (n, 2) tilt (psi_x, psi_y) of the top plate, rad (zeros for a cell)
    theta: np.ndarray             # (n, ncells) in-plane rotation of every cell's top bar, rad
    jumps: list                   # indices i where the state jumped between i-1 and i
    iterations: int = 0
    seconds: float = 0.0


class SleeveModel:
    """M rings of N cells (or one bare unit cell when ``ring is None``).

    ``cells``: list of CellGeometry, one per cell type; ``pattern``: list of rings, each a list of
    type indices around the circumference (ring 0 at the bottom). ``radius_L``: mid radius / L
    (default: the circumference is N cell widths).
    """

    def __init__(self, cells, pattern=None, n_el=10, plane="strain", radius_L=None,
                 imperfection=0.0, top_rotation="free"):
        self.cells = list(cells)
        self.unit = pattern is None
        self.pattern = [[0]] if pattern is None else [list(r) for r in pattern]
        self.M = len(self.pattern)
        self.N = len(self.pattern[0])
        L = self.cells[0].L
        if any(abs(g.L - L) > 1e-12 for g in self.cells):
            raise MetamaterialError("cell_types: every type must have the same L (cells share the ring)")
        W = self.cells[0].width / L
        self.radius = radius_L if radius_L is not None else self.N * W / (2 * np.pi)
        meshes, offsets = [], []
        X, conn, EA, EI, fixed = [], [], [], [], []
        self.cell_index = []
        nn = 0
        for r, row in enumerate(self.pattern):
            for k, typ in enumerate(row):
                cm = build_cell_mesh(self.cells[typ], n_el, plane)
                meshes.append(cm)
                offsets.append(nn)
                X.append(cm.X0); conn.append(cm.conn + nn); EA.append(cm.EA); EI.append(cm.EI)
                fixed.extend(np.array(cm.fixed_nodes) + nn)
                self.cell_index.append((r, k, typ))
                nn += len(cm.X0)
        self.meshes = meshes
        self.mesh = BeamMesh(np.vstack(X), np.vstack(conn), np.concatenate(EA), np.concatenate(EI))
        self.tops = np.array(offsets)
        nfull = self.mesh.ndof
        fixed_dofs = set()
        for n in fixed:
            fixed_dofs.update((3 * n, 3 * n + 1, 3 * n + 2))
        slaved = set()
        for o in offsets:
            slaved.update((3 * o + 1, 3 * o + 2))
            if not self.unit:
                slaved.add(3 * o)                   # tangential: ring twist
        free = [i for i in range(nfull) if i not in fixed_dofs and i not in slaved]
        # reduced unknowns: free nodal DOFs, then plate DOFs
        self.nfree = len(free)
        if top_rotation not in ("free", "fixed"):
            raise MetamaterialError(f"top_rotation: {top_rotation!r}; allowed: 'free', 'fixed'")
        self.rot_free = top_rotation == "free"
        if self.unit:
            nplate = 1 if self.rot_free else 0      # the cell's top rotation
        else:
            nplate = 4 * (self.M - 1) + 3           # interfaces (w, psi_x, psi_y, twist); top: no w
        nred = self.nfree + nplate
        T = np.zeros((nfull, nred))
        P = np.zeros(nfull)
        T[free, np.arange(self.nfree)] = 1.0
        if self.unit:
            o = offsets[0]
            P[3 * o + 1] = 1.0
            if self.rot_free:
                T[3 * o + 2, self.nfree] = 1.0
        else:
            def plate(p):
                """Columns (w, psi_x, psi_y, twist) of plate p (0 = fixed bottom, M = top)."""
                if p == 0:
                    return (None, None, None, None)
                if p == self.M:
                    b = self.nfree + 4 * (self.M - 1)
                    return ("d", b, b + 1, b + 2)
                b = self.nfree + 4 * (p - 1)
                return (b, b + 1, b + 2, b + 3)
            for ci, (r, k, typ) in enumerate(self.cell_index):
                o = offsets[ci]
                phi = 2 * np.pi * k / self.N
                sn, cs = np.sin(phi), np.cos(phi)
                for p, sgn in ((r + 1, 1.0), (r, -1.0)):
                    w, px, py, tw = plate(p)
                    if tw is not None:
                        T[3 * o, tw] += sgn * self.radius
                    if w == "d":
                        P[3 * o + 1] += sgn
                    elif w is not None:
                        T[3 * o + 1, w] += sgn
                    if px is not None:
                        T[3 * o + 1, px] += sgn * self.radius * sn
                        T[3 * o + 1, py] += -sgn * self.radius * cs
                        T[3 * o + 2, px] += sgn * cs
                        T[3 * o + 2, py] += sgn * sn
        import scipy.sparse as sp
        self.T, self.P = sp.csr_matrix(T), P
        # imperfection: a tiny constant moment on the top plate (about the axis at -45 deg, which
        # lengthens cells 0 and 1 of a four-cell ring) so that a uniform ring tilts the same way on
        # loading and unloading, like the seed's mesh imperfections; zero by default
        self.bias = np.zeros(nred)
        if imperfection and not self.unit:
            b = self.nfree + 4 * (self.M - 1)
            mag = imperfection * float(np.max(self.mesh.EA)) / LINK_FACTOR * self.radius
            self.bias[b] = mag / np.sqrt(2)
            self.bias[b + 1] = -mag / np.sqrt(2)
        self.TT = self.T.T.tocsr()
        # sparse LDL^T-like factorisation (SuperLU, symmetric mode, diagonal pivots) for larger systems
        self.sparse = nred > 200
        self.nred = nred
        self.phi = np.array([2 * np.pi * k / self.N for (_, k, _) in self.cell_index])

    # ------------------------------------------------------------------------------------------
    def full(self, q, d):
        return self.T @ q + self.P * d

    def evaluate(self, q, d, need_hessian=True):
        e, g, K = self.mesh.evaluate(self.full(q, d), need_hessian, self.sparse)
        e -= float(self.bias @ q)
        gr = self.TT @ g - self.bias
        if K is None:
            Kr = None
        elif self.sparse:
            Kr = (self.TT @ K @ self.T).tocsc()
        else:
            Kr = np.asarray(self.TT @ np.asarray(self.TT @ K).T)
        return e, gr, Kr, float(self.P @ g)

    def tilt_of(self, q):
        if self.unit:
            return np.zeros(2)
        b = self.nfree + 4 * (self.M - 1)
        return np.array([q[b], q[b + 1]])

    def cell_states(self, q, d):
        qf = self.full(q, d)
        return qf[3 * self.tops + 1].copy(), qf[3 * self.tops + 2].copy()

    # ------------------------------------------------------------------------------------------
    def minimise(self, q, d, tol, maxit=60):
        """Local energy minimum at prescribed ``d`` starting from ``q``. Returns (q, F, iterations)."""
        it = 0
        kicked = 0
        while it < maxit:
            it += 1
            e, g, K, F = self.evaluate(q, d)
            gn = np.linalg.norm(g)
            solve, pd = self._factor(K)
            if pd and gn < tol:
                return q, F, it
            if pd:
                step = -solve(g)
                if np.abs(step).max() < 1e-12:    # converged to round-off (fine meshes)
                    return q + step, F, it
            else:
                if self.sparse:
                    lam, vec = self._min_eig_sparse(K)
                else:
                    lam, vec = sla.eigh(K, subset_by_index=[0, 0], check_finite=False)
                v = vec[:, 0] / max(np.abs(vec[:, 0]).max(), 1e-300)
                gv = float(g @ v)
                if gv > 0 or (abs(gv) <= 1e-12 * max(gn, 1e-300) and v[np.argmax(np.abs(v))] < 0):
                    v = -v
                # negative curvature: expanding search along the descent direction v
                best_a, best_e, a = 0.0, e, 1e-3
                while a <= 0.5:
                    ea = self._energy(q + a * v, d)
                    if ea < best_e:
                        best_a, best_e = a, ea
                        a *= 2.0
                    else:
                        break
                if best_a > 0:
                    q = q + best_a * v
                    continue
                if gn < tol:
                    kicked += 1
                    if kicked > 20:
                        break
                    q = q + 1e-3 * v
                    continue
                shift = -lam[0] * 1.5 + 1e-8 * np.mean(np.abs(K.diagonal()))
                if self.sparse:
                    import scipy.sparse as sp
                    import scipy.sparse.linalg as spla
                    step = -spla.spsolve((K + shift * sp.identity(K.shape[0], format="csc")).tocsc(), g)
                else:
                    step = -np.linalg.solve(K + shift * np.eye(len(K)), g)
            # backtracking on the energy (full step accepted when it does not raise the energy)
            a = 1.0
            smax = np.abs(step).max()
            if smax > 0.05:
                a = 0.05 / smax
            for _ in range(30):
                e2 = self._energy(q + a * step, d)
                if e2 <= e + 1e-14 * max(1.0, abs(e)):
                    break
                a *= 0.5
            q = q + a * step
        raise _NoConvergence()

    def _energy(self, q, d):
        return self.mesh.evaluate(self.full(q, d), False)[0] - float(self.bias @ q)

    def _factor(self, K):
        """``(solve, positive_definite)`` for the reduced tangent ``K``."""
        if not self.sparse:
            try:
                C = sla.cho_factor(K, check_finite=False)
            except np.linalg.LinAlgError:
                return None, False
            return (lambda b: sla.cho_solve(C, b, check_finite=False)), True
        import scipy.sparse.linalg as spla
        try:
            lu = spla.splu(K, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                           options={"SymmetricMode": True})
        except RuntimeError:                  # exactly singular
            return None, False
        if not np.array_equal(lu.perm_r, lu.perm_c):
            # off-diagonal pivoting happened: inertia unknown from U; decide densely
            return self._factor_dense(K.toarray())
        # symmetric permutation P K P^T = L D L^T (Sylvester): positive definite <=> all pivots > 0
        return lu.solve, bool(np.all(lu.U.diagonal() > 0))

    def _min_eig_sparse(self, K):
        """Smallest eigenpair of a sparse symmetric indefinite ``K``: bracket the eigenvalue by
        inertia (signs of the symmetric-mode LU pivots of K - s I, Sylvester), then shift-invert."""
        import scipy.sparse as sp
        import scipy.sparse.linalg as spla
        n = K.shape[0]
        I = sp.identity(n, format="csc")
        absK = abs(K)
        gersh = float(np.min(2 * K.diagonal() - np.asarray(absK.sum(axis=1)).ravel()))
        lo = min(gersh, -1e-300) * 1.01          # below every eigenvalue

        def below(sv):
            """True when some eigenvalue lies below sv (None if the inertia is unknown)."""
            try:
                lu = spla.splu((K - sv * I).tocsc(), permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                               options={"SymmetricMode": True})
            except RuntimeError:
                return True
            if not np.array_equal(lu.perm_r, lu.perm_c):
                return None
            return bool(np.any(lu.U.diagonal() < 0))

        hi = -abs(lo) * 1e-15
        ok = True
        for _ in range(60):                      # geometric bisection on the magnitude
            if abs(lo) / abs(hi) < 4:
                break
            mid = -np.sqrt(abs(lo) * abs(hi))
            b = below(mid)
            if b is None:
                ok = False
                break
            if b:
                hi = mid
            else:
                lo = mid
        try:
            if not ok:
                raise RuntimeError
            lam, vec = spla.eigsh(K, k=1, sigma=lo, which="LM", tol=1e-8)
            return lam, vec
        except Exception:
            return sla.eigh(K.toarray(), subset_by_index=[0, 0], check_finite=False)

    def _factor_dense(self, K):
        try:
            C = sla.cho_factor(K, check_finite=False)
        except np.linalg.LinAlgError:
            return None, False
        return (lambda b: sla.cho_solve(C, b, check_finite=False)), True

    def trace(self, d_values, q0=None, tol=None, progress=None):
        """Follow the stable equilibrium path through the prescribed displacements ``d_values``."""
        t0 = time.perf_counter()
        if tol is None:
            tol = 1e-9 * float(np.max(self.mesh.EA)) / LINK_FACTOR
        q = np.zeros(self.nred) if q0 is None else q0.copy()
        d_prev = None
        q_prev = None
        ds, Fs, states, tilts, thetas, jumps = [], [], [], [], [], []
        total_it = 0
        dv = list(d_values)
        for i, d in enumerate(dv):
            # secant predictor along the previous step
            if q_prev is not None and d_prev is not None and abs(d - d_prev) > 0 and not (jumps and jumps[-1] == i - 1):
                pass
            guess = q
            if len(ds) >= 2 and (not jumps or jumps[-1] < len(ds) - 1):
                dd0 = ds[-1] - ds[-2]
                if abs(dd0) > 0:
                    guess = q + (q - q_prev) * (d - ds[-1]) / dd0
            qn, F, it = self._solve_step(guess, q, d, ds[-1] if ds else 0.0, tol)
            total_it += it
            if ds:
                v_old = states[-1]
                v_new, _ = self.cell_states(qn, d)
                dl = abs(d - ds[-1])
                if np.max(np.abs(v_new - v_old)) > 5 * dl + 0.02:
                    jumps.append(len(ds))
            q_prev = q
            q = qn
            ds.append(d)
            Fs.append(F)
            v, th = self.cell_states(q, d)
            states.append(v)
            thetas.append(th)
            tilts.append(self.tilt_of(q))
            if progress:
                progress(i + 1, len(dv))
        self.last_q = q
        return Path(np.array(ds), np.array(Fs), np.array(states), np.array(tilts), np.array(thetas),
                    jumps, total_it, time.perf_counter() - t0)

    def _solve_step(self, guess, q, d, d_old, tol, depth=0):
        try:
            return self.minimise(guess, d, tol)
        except _NoConvergence:
            pass
        try:
            return self.minimise(q, d, tol, maxit=200)
        except _NoConvergence:
            pass
        if depth < 6:
            dm = 0.5 * (d + d_old)
            qm, _, it1 = self._solve_step(q, q, dm, d_old, tol, depth + 1)
            qn, F, it2 = self._solve_step(qm, qm, d, dm, tol, depth + 1)
            return qn, F, it1 + it2
        raise MetamaterialError(f"sleeve model: no equilibrium found at d/L = {d:.4g}")


class _NoConvergence(Exception):
    pass


def default_stroke(cells):
    """Default maximum displacement / L: past the full inversion of the tallest cell type."""
    h = max(g.h / g.L for g in cells)
    return 2.0 * h + 0.12


def cell_curve(geom, n_el=10, steps=200, d_max=None, plane="strain", unload=True, top_rotation="free"):
    """Loading (and unloading) FD path of one unit cell. Returns (load, unload_or_None)."""
    m = SleeveModel([geom], None, n_el, plane, top_rotation=top_rotation)
    d_max = default_stroke([geom]) if d_max is None else d_max
    d = np.linspace(0, d_max, steps + 1)
    up = m.trace(d)
    down = m.trace(d[::-1], q0=m.last_q) if unload else None
    return up, down


def ring_curve(cells, pattern, n_el=8, steps=200, d_max=None, plane="strain", unload=True,
               imperfection=0.0, progress=None):
    m = SleeveModel(cells, pattern, n_el, plane, imperfection=imperfection)
    d_max = default_stroke(cells) * len(pattern) if d_max is None else d_max
    d = np.linspace(0, d_max, steps + 1)
    up = m.trace(d, progress=progress)
    down = m.trace(d[::-1], q0=m.last_q, progress=progress) if unload else None
    return m, up, down
