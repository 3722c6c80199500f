"""The two lattice models: "linear" (R1, one sparse solve) and "nonlinear" (R2, Newton).

Both share :class:`~metamaterial_wb.core.lattice.geometry.LatticeGeometry` and the vectorised hinge
mechanics of :mod:`~metamaterial_wb.core.lattice.mechanics`.

* Actuators and angular constraints are exact constraints on the relative rotation of the two plates
  of their joint about the hinge's soft axis (Lagrange multipliers, a symmetric KKT system).
* Rigid motions: one node near the centre is held (all its DOFs); the result is then aligned to the
  flat sheet by a best-fit rigid motion (Kabsch), so positions are comparable across models.
* Planar scenes (no tilted hinge) keep 3 DOFs per node (x, y, rotation about z): out-of-plane DOFs
  are left out because in-plane actuation cannot excite them.
* Plate contact (nonlinear model): a one-sided penalty on the closing relative rotation of each hinge
  once it passes ``contact_fraction`` of the contact rotation ``2 asin(lh / 2s)``.
* Newton with a backtracking line search on an exact-penalty merit function, adaptive load stepping;
  dynamic relaxation (kinetic damping) as the fallback, followed by a Newton polish. A result that
  did not reach the tolerance has ``converged = False`` and a warning.
"""
import contextlib
import math
import time

import numpy as np
import scipy.sparse.linalg as spla

from metamaterial_wb.core.lattice.geometry import LatticeGeometry, fixed_items
from metamaterial_wb.core.lattice.mechanics import (ElementState, Pattern, PlanarElementState, _arc_coefficients,
                                                    _cross_e1, expm_so3, hinge_strains, log_so3)

PLANAR_DOFS = (0, 1, 5)
_ROT_DOFS = np.array([3, 4, 5, 9, 10, 11])
# symmetric KKT matrices: symmetric fill-reducing ordering, diagonal preferred, threshold pivoting only
# where the diagonal is too small (the zero multiplier block); measured 4x faster than partial pivoting
_SPLU = {"permc_spec": "MMD_AT_PLUS_A", "diag_pivot_thresh": 0.01, "options": {"SymmetricMode": True}}


# ----------------------------------------------------------------------------------------------------
# helpers
# ----------------------------------------------------------------------------------------------------
def _support_node(geo):
    X0 = geo.X0[:getattr(geo, "n_plates", geo.n)]          # a plate, never a hinge-internal node
    c = X0.mean(axis=0)
    return int(np.argmin(np.linalg.norm(X0 - c, axis=1)))


def _dofmap(geo, planar):
    n = geo.n
    keep = np.ones((n, 6), dtype=bool)
    if planar:
        keep[:, [2, 3, 4]] = False
    keep[_support_node(geo), :] = False
    dm = -np.ones(6 * n + 1, dtype=np.int64)       # last slot: "no DOF"
    flat = keep.ravel()
    dm[:6 * n][flat] = np.arange(int(flat.sum()))
    return dm, int(flat.sum())


def _kkt_solve(pat, He, A, reg, rhs):
    """Solve the KKT system; only if it is singular (redundant constraints) with the multiplier shift."""
    try:
        return spla.splu(pat.matrix(He, A, 0.0), **_SPLU).solve(rhs)
    except RuntimeError:
        return spla.splu(pat.matrix(He, A, reg), **_SPLU).solve(rhs)


try:                                     # CHOLMOD (scikit-sparse, optional: tools/pip-optional.txt)
    from sksparse.cholmod import cholesky as _cholmod
except Exception:  # pragma: no cover - depends on the machine
    _cholmod = None
# the Schur-complement KKT solve keeps the multipliers' block dense: only for a few constraints
SCHUR_MAX_CONSTRAINTS = 64
_FAST = True          # the fast paths (False inside reference_paths(): the plain reference computations)


class SchurKKT:
    """Solver of the KKT system ``[[H, A^T], [A, -reg I]] [x; y] = [f; g]`` for a positive definite ``H``
    (the material tangent ``J^T K J`` with one plate held): a sparse Cholesky factorisation of ``H``
    (CHOLMOD) and the small dense Schur complement ``S = A H^-1 A^T`` of the few actuator constraints:
    ``y = S^-1 (A H^-1 f - g)``, ``x = H^-1 (f - A^T y)`` (``reg = 0``). Same answer as a sparse LU of the KKT
    matrix (to rounding), with a cheaper factorisation and much cheaper back-substitutions (the contact
    updates need one per hinge in contact). Redundant constraints (``S`` singular): pseudo-inverse of ``S``
    (the plates' motion is unique, the multipliers are the least-norm ones). ``build`` returns None where it
    does not apply (no CHOLMOD, too many constraints, ``H`` not positive definite); the caller then factors
    the KKT matrix by LU."""

    def __init__(self, F, A, HA, S_factor, na):
        self._F, self.A, self.HA, self._S, self.na = F, A, HA, S_factor, na

    @classmethod
    def build(cls, H, A):
        if _cholmod is None or A.shape[0] > SCHUR_MAX_CONSTRAINTS or H.shape[0] == 0:
            return None
        import warnings
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("error")          # CHOLMOD warns (not raises) on a non-definite matrix
                F = _cholmod(H, mode="supernodal") if H.shape[0] > 20000 else _cholmod(H)
                Ld = F.D() if hasattr(F, "D") else None
        except Exception:
            return None
        if Ld is not None and not (np.all(Ld > 0) and np.all(np.isfinite(Ld))):
            return None                                  # indefinite tangent: the LU path pivots
        HA = F(np.ascontiguousarray(A.T)) if A.shape[0] else np.zeros((H.shape[0], 0))
        S = A @ HA
        Sinv = None
        if A.shape[0]:
            # S is symmetric positive semi-definite; redundant constraints (e.g. every joint around a cell
            # actuated) make it singular. Its null directions v have A^T v = 0 (H is definite), so they do
            # not move the plates: leave them out (pseudo-inverse) rather than amplify rounding along them.
            w, V = np.linalg.eigh(0.5 * (S + S.T))
            keep = w > 1e-10 * max(float(w.max()), 1e-300)
            Sinv = (V[:, keep] / w[keep]) @ V[:, keep].T
        return cls(F, A, HA, Sinv, H.shape[0])

    def solve(self, rhs):
        na = self.na
        f, g = rhs[:na], rhs[na:]
        u = self._F(np.ascontiguousarray(f))
        if self._S is None:
            return np.concatenate([u, g * 0.0])
        y = self._S @ (self.A @ u - g)
        return np.concatenate([u - self.HA @ y, y])


@contextlib.contextmanager
def reference_paths():
    """Within the block, the linear model runs its plain reference paths (sparse LU of the whole KKT
    matrix, LU for the hinge-chain positions, no CHOLMOD): for tests that the fast paths agree with it."""
    global _cholmod, _FAST
    saved = _cholmod, _FAST
    _cholmod, _FAST = None, False
    try:
        yield
    finally:
        _cholmod, _FAST = saved


class _Cholesky:
    """CHOLMOD factor of an SPD matrix with the ``solve(rhs)`` interface of SuperLU."""

    def __init__(self, M):
        self.solve = _cholmod(M)


def kkt_regularisation(geo):
    """Multiplier-block shift of the KKT matrix (1/rad units: 1e-10 of the softest hinge compliance)."""
    return 1e-10 / float(geo.K[:, 5, 5].max())


def kabsch(P, Q):
    """Rotation Rm and translation tv minimising |Rm P_i + tv - Q_i| (rows are points)."""
    pc, qc = P.mean(axis=0), Q.mean(axis=0)
    Hm = (P - pc).T @ (Q - qc)
    U, _S, Vt = np.linalg.svd(Hm)
    d = np.sign(np.linalg.det(Vt.T @ U.T)) or 1.0
    Dm = np.diag([1.0, 1.0, d])
    Rm = Vt.T @ Dm @ U.T
    return Rm, qc - Rm @ pc


def node_twist(R):
    """In-plane rotation of every plate: the twist about its own normal (swing-twist split), radians."""
    w = 0.5 * np.sqrt(np.maximum(0.0, 1.0 + np.trace(R, axis1=1, axis2=2)))
    z = np.where(w > 1e-9, (R[:, 1, 0] - R[:, 0, 1]) / np.maximum(4.0 * w, 1e-300), 1.0)
    return 2.0 * np.arctan2(z, w)


def finish(geo, X, R, align=True):
    """Align to the flat sheet (rigid, Kabsch), return positions, rotations and D."""
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
        if _cholmod is not None:                    # SPD: Cholesky when CHOLMOD is there (cheaper)
            L.sum_duplicates()
            self.lu = _Cholesky(L)
        else:
            self.lu = spla.splu(L, permc_spec="MMD_AT_PLUS_A")

    def chords(self, R, strain=None):
        """(m, 3) relations ``X_B - X_A`` for plate rotations ``R`` (``strain``: (m, 3) elastic offsets of the
        hinge ends beyond uniform bending, in A's hinge frame)."""
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
    if _FAST and not np.any(full[:, 3:5]):       # rotations about the sheet normal only: 2-D arithmetic
        c, s = np.cos(full[:, 5]), np.sin(full[:, 5])
        R2 = np.empty_like(R)
        R2[:, 0, :] = c[:, None] * R[:, 0, :] - s[:, None] * R[:, 1, :]
        R2[:, 1, :] = s[:, None] * R[:, 0, :] + c[:, None] * R[:, 1, :]
        R2[:, 2, :] = R[:, 2, :]
        return X + full[:, :3], R2
    return X + full[:, :3], expm_so3(full[:, 3:]) @ R


def quadratic_D(scene):
    """The quadratic model's D field (``core/solver.solve_scene(scene)[0]``, same energy, fixed nodes and
    islands), assembled lean for one solve: only the free-node block of the Hessian, one right-hand side,
    no response matrix. Anything the quadratic model would reject (values out of range, a node given two
    values, bad stiffness) goes through ``solve_scene`` itself, which raises its error."""
    from scipy.sparse.csgraph import connected_components
    import scipy.sparse as sp

    from metamaterial_wb.core.calibration import joint_stiffness
    from metamaterial_wb.core.solver import scene_groups, scene_values, solve_scene

    if not _FAST:
        return solve_scene(scene)[0]
    topo = scene.topology
    n = topo.n_nodes
    k1, k2 = (np.asarray(x, float) for x in joint_stiffness(scene))
    values = scene_values(scene)
    D = np.zeros(n)
    fixed = np.zeros(n, dtype=bool)
    for name, nodes in scene_groups(scene):
        v = values[name]
        nodes = np.asarray(nodes, dtype=np.int64)
        if not (np.isfinite(v) and -1.0 <= v <= 1.0) or np.any(fixed[nodes] & (D[nodes] != v)):
            return solve_scene(scene)[0]
        new = nodes[~fixed[nodes]]
        D[new] = v
        fixed[new] = True
    if not (np.all(np.isfinite(k1) & (k1 >= 0) & (k1 <= 1)) and np.all(np.isfinite(k2) & (k2 > 0))):
        return solve_scene(scene)[0]
    a, b = topo.joint_pairs[:, 0], topo.joint_pairs[:, 1]
    free = np.flatnonzero(~fixed)
    if not free.size:
        return D
    pos = -np.ones(n, dtype=np.int64)
    pos[free] = np.arange(free.size)
    ff = ~fixed[a] & ~fixed[b]
    # islands: free components with no joint to a fixed node keep D = 0 (as the quadratic model)
    adj = sp.coo_matrix((np.ones(int(ff.sum())), (pos[a[ff]], pos[b[ff]])), shape=(free.size, free.size))
    ncomp, labels = connected_components(adj, directed=False)
    touches = np.zeros(ncomp, dtype=bool)
    touches[labels[pos[a[~fixed[a] & fixed[b]]]]] = True
    touches[labels[pos[b[fixed[a] & ~fixed[b]]]]] = True
    solved = touches[labels]
    if not np.any(solved):
        return D
    # Hessian of sum k2 (k1 (Da - Db)^2 + (1 - k1)(Da^2 + Db^2)) on the solved free nodes
    keep = -np.ones(n, dtype=np.int64)
    sfree = free[solved]
    keep[sfree] = np.arange(sfree.size)
    diag = np.bincount(a, weights=2 * k2, minlength=n) + np.bincount(b, weights=2 * k2, minlength=n)
    off = -2.0 * k1 * k2
    both = (keep[a] >= 0) & (keep[b] >= 0)
    rows = np.concatenate([np.arange(sfree.size), keep[a[both]], keep[b[both]]])
    cols = np.concatenate([np.arange(sfree.size), keep[b[both]], keep[a[both]]])
    vals = np.concatenate([diag[sfree], off[both], off[both]])
    H = sp.coo_matrix((vals, (rows, cols)), shape=(sfree.size, sfree.size)).tocsc()
    H.sum_duplicates()
    # right-hand side -H_FA D_A: joints from a solved free node to a fixed one
    rhs = np.zeros(sfree.size)
    ka = (keep[a] >= 0) & fixed[b]
    kb = fixed[a] & (keep[b] >= 0)
    rhs -= np.bincount(keep[a[ka]], weights=off[ka] * D[b[ka]], minlength=sfree.size)
    rhs -= np.bincount(keep[b[kb]], weights=off[kb] * D[a[kb]], minlength=sfree.size)
    if _cholmod is not None:
        D[sfree] = _cholmod(H)(rhs)
    else:
        D[sfree] = spla.splu(H, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                             options={"SymmetricMode": True}).solve(rhs)
    return D


def quadratic_state(scene, geo, chain=None, pose="rotations", D=None):
    """The quadratic model's (R0) predicted state in lattice terms: ``(D, X, R)``.

    ``D`` from one sparse solve of the seed's energy (``core/solver``); the plate rotations from D with the
    quadratic model's own rule (``core/kinematics``: in-plane angle ``p D phi_max``, plus the folds of tilted
    hinges). Positions: ``pose="rotations"`` (default) puts the plates through the hinge chain from those
    rotations (:class:`ChainPositions`, the linear model's pose rule), ``pose="full"`` takes the quadratic
    model's own positions (``core/kinematics``, straight hinge chords). ``D``: the quadratic model's field if
    already solved.
    """
    from metamaterial_wb.core import kinematics

    if D is None:
        D = quadratic_D(scene)
    if geo.planar and pose == "rotations":
        R = kinematics.rotation_matrices(geo.phi_from_D(D))
        X = None
    else:
        kin = kinematics.Kinematics(scene, geo.tilt)
        X, R = kin.poses_from_angles(kin.angles(D))
    if pose == "rotations":
        X = (chain or ChainPositions(geo))(R, geo.X0)
    return D, X, R


# ----------------------------------------------------------------------------------------------------
# linear model (R1)
# ----------------------------------------------------------------------------------------------------
class LinearLattice:
    """Linearised lattice: tangent stiffness of the flat sheet, exact linearised actuator constraints.

    Factor once per scene structure and placement, re-solve per set of values (the response without
    contact is linear in the actuator values). Plate contact (``contact=True``): hinges whose linearised
    closing rotation passes ``contact_fraction`` of the contact rotation get the nonlinear model's stiff
    one-sided spring; the set of such hinges is found by re-solving until it stops changing (semismooth
    Newton on a piecewise-quadratic energy), so the answer is piecewise linear. When no hinge reaches
    contact (small amplitudes) this costs nothing extra.

    Poses: the plate rotations are ``exp`` of the solved rotation increments; the positions come from those
    rotations through the hinge chain (:class:`ChainPositions`, ``poses="chain"``, the default) rather than
    from adding the solved displacements to the flat sheet (``poses="linear"``), which stretches every hinge
    by the second-order motion of the plate corners. Both agree to first order; ``q`` is the same.

    ``base=(X, R)`` linearises about that state instead of the flat sheet (the ``about=quadratic`` option:
    the quadratic model's predicted state, :func:`quadratic_state`): the corotational strains and hinge
    forces of the state enter the right-hand side, the actuator constraints and the contact onset are
    measured from it, and ``q`` is the increment from it. ``tangent="material"`` keeps only ``J^T K J``
    (positive semi-definite; the state's non-equilibrium stress terms mislead the step,
    docs/fidelity-models.md); ``"full"`` is the exact tangent. :meth:`line_search` then picks the step
    length along ``q`` from the nonlinear energy.
    """

    def __init__(self, scene, geo=None, contact=True, contact_fraction=0.98, contact_stiffness=1e4, poses="chain",
                 base=None, tangent="full", chain=None):
        t0 = time.perf_counter()
        if poses not in ("chain", "linear"):
            from metamaterial_wb.core.errors import SceneError
            raise SceneError("--option poses", f"{poses!r}; allowed: chain, linear")
        self.poses = poses
        self._chain = chain          # the hinge-chain position rule of geo (built on first use if None)
        self.geo = geo or LatticeGeometry(scene)
        geo = self.geo
        self.joints, self.values, self.psi, self.names = fixed_items(scene, geo)
        self.dofmap, self.na = _dofmap(geo, geo.planar)
        self.pattern = Pattern(geo.dofs, self.dofmap, self.na, self.joints, None)
        if base is None:
            # at the flat sheet the arc correction and its first derivative vanish: leave it out
            self.base = (geo.X0, np.broadcast_to(np.eye(3), (geo.n, 3, 3)).copy())
            if _FAST and PlanarElementState.applies(geo, self.base[1]):
                st = PlanarElementState(geo, self.base[0], self.base[1], arc=False)
            else:
                st = ElementState(geo, self.base[0], self.base[1], tangent=True, arc=False)
            self.g0 = None                  # no force, no strain at the flat sheet
            self.eps0 = None
        else:
            # linearised about a deformed state (X, R): corotational strains, forces and tangent there
            self.base = (np.asarray(base[0], float), np.asarray(base[1], float))
            if _FAST and tangent != "full" and PlanarElementState.applies(geo, self.base[1]):
                st = PlanarElementState(geo, self.base[0], self.base[1])      # material tangent included
            else:
                st = ElementState(geo, self.base[0], self.base[1], tangent=(tangent == "full"))
                if tangent != "full":        # material (Gauss-Newton) part J^T K J only: no stress terms
                    st.H = np.transpose(st.J, (0, 2, 1)) @ (geo.K @ st.J)
            self.g0 = self.pattern.vector(st.grad)
            self.eps0 = st.eps
        self.He = st.H
        self.J5 = st.J[:, 5, :].copy()
        self.J6 = st.J                      # strains (u, Theta) of the flat sheet per element DOF
        Acon = self.J5[self.joints] if self.joints.size else None
        self._Acon = Acon
        self.reg = kkt_regularisation(geo)
        self._KKT = None
        self._schur_ok = base is None or tangent != "full"      # positive definite tangents only
        self.contact = bool(contact)
        self.close_sign = -geo.parity[geo.a]
        self.kappa_c = contact_fraction * 2.0 * geo.contact_rad / np.cos(geo.tilt)
        self.kappa_onset = self.kappa_c
        if self.eps0 is not None:        # closing rotation measured from the base state
            self.kappa_c = self.kappa_c - self.close_sign * self.eps0[:, 5]
        self.kc = contact_stiffness * geo.K[:, 5, 5]
        self.contact_info = {"contact_hinges": 0, "active_set_iterations": 0}
        self._zcol = None            # column of each hinge's cached back-substitution in self._Z (-1: none yet)
        self._Z = None
        self._nz = 0
        self._Jc = None
        self.timings = {"assemble_s": time.perf_counter() - t0}
        t1 = time.perf_counter()
        self.lu = None
        self.H = self.pattern.stiffness(st.H)        # (na, na) CSC stiffness block
        if self.joints.size:
            if self._schur_ok:
                self.lu = SchurKKT.build(self.H, self.pattern.rows(Acon, self.joints))
            if self.lu is None:
                try:
                    self.lu = spla.splu(self.KKT, **_SPLU)
                except RuntimeError:     # redundant constraints (e.g. clips on every joint around a cell)
                    self._KKT = self.pattern.matrix(st.H, Acon, self.reg)
                    self.lu = spla.splu(self._KKT, **_SPLU)
        self.timings["factor_s"] = time.perf_counter() - t1

    @property
    def KKT(self):
        """The KKT matrix ``[[H, A^T], [A, 0]]`` (sparse; built on first use: the factorisation does not
        need it when the Schur-complement solver applies)."""
        if self._KKT is None:
            if _FAST:           # from the assembled stiffness block and the constraint rows (no pattern sort)
                import scipy.sparse as sp
                H = self.H.tocoo()
                na = self.na
                Ad = self.pattern.rows(self._Acon, self.joints) if self.joints.size else np.zeros((0, na))
                nc = Ad.shape[0]
                r, c = np.nonzero(Ad)
                v = Ad[r, c]
                d = na + np.arange(nc)
                rows = np.concatenate([H.row, na + r, c, d])
                cols = np.concatenate([H.col, c, na + r, d])
                self._KKT = sp.csc_matrix((np.concatenate([H.data, v, v, np.zeros(nc)]), (rows, cols)),
                                          shape=(na + nc, na + nc))
            else:
                self._KKT = self.pattern.matrix(self.He, self._Acon, 0.0)
        return self._KKT

    def _energy(self, q):
        """Elastic energy ``q.H q / 2`` (H = the factored KKT matrix's stiffness block) plus the contact
        penalty; sparse products (this is evaluated in every active-set line search)."""
        e = 0.5 * float(q @ (self.H @ q))
        if self.g0 is not None:
            e += float(self.g0 @ q)
        over = self._closing(q) - self.kappa_c
        return float(e + 0.5 * np.sum(self.kc * np.maximum(over, 0.0) ** 2))

    def _closing(self, q):
        """Closing rotation of every hinge (linearised): a sparse (m, na) matrix built on first use."""
        if self._Jc is None:
            import scipy.sparse as sp
            ed = self.pattern.ed
            J = self.close_sign[:, None] * self.J5
            keep = (ed >= 0) & (J != 0.0)
            rows = np.broadcast_to(np.arange(ed.shape[0])[:, None], ed.shape)[keep]
            self._Jc = sp.csr_matrix((J[keep], (rows, ed[keep])), shape=(ed.shape[0], self.na))
        return self._Jc @ q

    def _U(self, active):
        """Sparse (k, N) rows: the closing-rotation gradient of each active hinge on the KKT unknowns."""
        import scipy.sparse as sp
        ed = self.pattern.ed[active]                                  # (k, 12) active DOF indices or -1
        Jr = self.close_sign[active, None] * self.J5[active]
        keep = ed >= 0
        rows = np.repeat(np.arange(active.size), 12).reshape(-1, 12)[keep]
        return sp.csr_matrix((Jr[keep], (rows, ed[keep])), shape=(active.size, self.pattern.N))

    def _rows(self, active, V):
        """``U @ V`` for the active hinges' closing-gradient rows U, V of shape (N,) or (N, c)."""
        ed = self.pattern.ed[active]                                   # (k, 12), -1 = no DOF
        Vp = np.concatenate([V[:self.na], np.zeros((1,) + V.shape[1:])])
        Jr = self.close_sign[active, None] * self.J5[active]
        if V.ndim == 1:
            return np.einsum("ki,ki->k", Jr, Vp[ed])
        return np.einsum("ki,kic->kc", Jr, Vp[ed])

    def _solve_with_contacts(self, y_free, active):
        """KKT solve with stiff one-sided springs (the nonlinear model's contact penalty) on ``active``:
        a low-rank (Woodbury) update of the cached base factorisation, no new factorisation:
        ``x = y - Z (C^-1 + U Z)^-1 U y`` with ``Z = M^-1 U^T`` (one cached back-substitution per hinge)
        and ``y = y_free + Z C kappa_c`` (the springs' preload)."""
        if active.size == 0:
            return y_free[:self.na], y_free[self.na:]
        kc = self.kc[active]
        if self._zcol is None:
            self._zcol = -np.ones(self.geo.m, dtype=np.int64)
            self._Z = np.zeros((self.pattern.N, 0))
            self._nz = 0
        missing = active[self._zcol[active] < 0]
        if missing.size:
            Ut = np.zeros((self.pattern.N, missing.size))
            Jm = self.close_sign[missing, None] * self.J5[missing]
            edm = self.pattern.ed[missing]
            cols = np.broadcast_to(np.arange(missing.size)[:, None], edm.shape)
            ok = edm >= 0
            Ut[edm[ok], cols[ok]] = Jm[ok]        # one hinge per column, its DOFs distinct: no repeats
            used = self._nz
            self._zcol[missing] = used + np.arange(missing.size)
            if not _FAST:
                self._Z = np.hstack([self._Z[:, :used], self.lu.solve(Ut)])
            else:                   # column-major buffer with spare room: no copy per update, contiguous columns
                if used + missing.size > self._Z.shape[1]:
                    Zn = np.empty((self.pattern.N, max(2 * (used + missing.size), 16)), order="F")
                    Zn[:, :used] = self._Z[:, :used]
                    self._Z = Zn
                self._Z[:, used:used + missing.size] = self.lu.solve(Ut)
            self._nz = used + missing.size
        Z = self._Z[:, self._zcol[active]]
        y = y_free + Z @ (kc * self.kappa_c[active])
        S = np.diag(1.0 / kc) + self._rows(active, Z)
        x = y - Z @ np.linalg.solve(S, self._rows(active, y))
        return x[:self.na], x[self.na:]

    def solve(self, psi=None):
        geo = self.geo
        psi = self.psi if psi is None else psi
        I3 = np.broadcast_to(np.eye(3), (geo.n, 3, 3)).copy()
        self.contact_info = {"contact_hinges": 0, "active_set_iterations": 0}
        if self.lu is None or not np.any(psi):
            return geo.X0.copy(), I3, np.zeros(self.na), np.zeros(self.joints.size)
        rhs = np.zeros(self.pattern.N)
        rhs[self.na:] = psi
        if self.eps0 is not None:        # residual forces and constraint offsets of the base state
            rhs[:self.na] = -self.g0
            rhs[self.na:] -= self.eps0[self.joints, 5]
        sol = self.lu.solve(rhs)
        q = sol[:self.na]
        mu = sol[self.na:]
        if self.contact:
            # semismooth Newton on the penalised piecewise-quadratic (convex) energy: solve with the hinges
            # past the contact onset penalised, then a backtracking line search on the energy (both
            # iterates satisfy the linear actuator constraints, so every point between them does too)
            active = None
            e_old = self._energy(q)
            for it in range(100):
                new = np.flatnonzero(self._closing(q) > self.kappa_c)
                if (active is None and new.size == 0) or (active is not None and np.array_equal(new, active)):
                    break
                active = new
                q_new, mu_new = self._solve_with_contacts(sol, active)
                alpha = 1.0
                for _ in range(30):
                    q_try = q + alpha * (q_new - q)
                    e_try = self._energy(q_try)
                    if e_try <= e_old + 1e-14 * abs(e_old):
                        break
                    alpha *= 0.5
                q, e_old = q_try, e_try
                mu = mu + alpha * (mu_new - mu)
                self.contact_info = {"contact_hinges": int(active.size), "active_set_iterations": it + 1}
                if alpha < 1e-8:
                    break
            else:
                self.contact_info["active_set_converged"] = False
        X, R = self.pose(q)
        return X, R, q, mu

    def pose(self, q, alpha=1.0):
        """Positions and rotations of the step ``alpha q`` from the base state: rotations ``exp`` of the
        rotation increments, positions by the pose rule (``chain``: through the hinge chain)."""
        geo = self.geo
        X, R = _apply(self.base[0], self.base[1], alpha * q, self.dofmap, geo.n)
        if self.poses == "chain":        # positions through the hinge chain from the plate rotations
            if self._chain is None:
                self._chain = ChainPositions(geo)
            if getattr(self, "_step", (None,))[0] is not q:       # linearised strains of the step (once per q)
                self._step = (q, (self.J6 @ self.pattern.gather(q)[:, :, None])[:, :, 0])
            eps = alpha * self._step[1]
            if self.eps0 is not None:
                eps = eps + self.eps0
            strain = eps[:, 0:3] - 0.5 * geo.rest * _cross_e1(eps[:, 3:6])    # beyond uniform bending
            X = self._chain(R, X, strain)
        return X, R

    def merit(self, eps, nu):
        """The nonlinear model's energy at hinge strains ``eps`` (hinges and, with contact, its penalty on the
        closing rotation past the onset) plus the exact penalty ``nu |c|_1`` of the actuator constraints."""
        e = 0.5 * float(np.einsum("mi,mij,mj->", eps, self.geo.K, eps))
        if self.contact:
            over = np.maximum(self.close_sign * eps[:, 5] - self.kappa_onset, 0.0)
            e += 0.5 * float(np.sum(self.kc * over * over))
        if self.joints.size:
            e += nu * float(np.abs(eps[self.joints, 5] - self.psi).sum())
        return e

    def merit_slope(self, q, nu):
        """d merit / d alpha at alpha = 0 along the step ``alpha q`` from the base state (analytic: hinge
        forces of the state, contact springs already past the onset, and the constraint penalty)."""
        if getattr(self, "_step", (None,))[0] is not q:
            self._step = (q, (self.J6 @ self.pattern.gather(q)[:, :, None])[:, :, 0])
        deps = self._step[1]
        slope = float(self.g0 @ q)
        if self.contact:
            over = self.close_sign * self.eps0[:, 5] - self.kappa_onset
            on = over > 0
            slope += float(np.sum(self.kc[on] * over[on] * self.close_sign[on] * deps[on, 5]))
        if self.joints.size:
            c0 = self.eps0[self.joints, 5] - self.psi
            slope += nu * float(np.sum(np.sign(c0) * deps[self.joints, 5]))
        return slope

    def line_search(self, q, mu, X1, R1):
        """Step length along the solved step that minimises the merit (the nonlinear energy plus the constraint
        penalty, at the poses the model returns): the parabola through the merit and its slope at the base
        state and the merit of the full step; its minimum is taken only if its merit is below the full
        step's. Returns ``(alpha, X, R)``. The slope at the base is exact: to first order the returned poses
        move along the solved increments (the hinge-chain positions satisfy the same linearised relations)."""
        if self.eps0 is None or not q.size:
            return 1.0, X1, R1
        nu = 2.0 * float(np.abs(mu).max(initial=0.0))
        m0 = self.merit(self.eps0, nu)
        m1 = self.merit(hinge_strains(self.geo, X1, R1), nu)
        slope = self.merit_slope(q, nu)
        curv = m1 - m0 - slope
        if not (slope < 0 and curv > 0):
            return 1.0, X1, R1
        a = min(2.0, max(1.0 / 64, -slope / (2.0 * curv)))
        if a == 1.0:
            return 1.0, X1, R1
        Xa, Ra = self.pose(q, a)
        if self.merit(hinge_strains(self.geo, Xa, Ra), nu) < m1:
            return a, Xa, Ra
        return 1.0, X1, R1


# ----------------------------------------------------------------------------------------------------
# nonlinear model (R2)
# ----------------------------------------------------------------------------------------------------
class NonlinearLattice:
    """Nonlinear corotational lattice: ``solve()`` returns ``(X, R, converged)``; ``stats`` says how.

    Options are those of the "nonlinear" model (core/lattice/__init__.py, docs/fidelity-models.md).
    """

    def __init__(self, scene, geo=None, contact=True, contact_fraction=0.98, contact_stiffness=1e4,
                 tol=1e-8, max_iter=40, load_steps=1, min_step=1.0 / 64, fallback=True, dr_max_iter=5000,
                 predictor=False, planar=None, method="newton"):
        from metamaterial_wb.core.errors import SceneError
        if method not in ("newton", "dynamic_relaxation"):
            raise SceneError("--option method", f"{method!r}; allowed: newton, dynamic_relaxation")
        self.method = method
        self.geo = geo or LatticeGeometry(scene)
        geo = self.geo
        self.joints, self.values, self.psi, self.names = fixed_items(scene, geo)
        self.planar = geo.planar if planar is None else bool(planar)
        self.dofmap, self.na = _dofmap(geo, self.planar)
        self.pattern = Pattern(geo.dofs, self.dofmap, self.na, self.joints, None)
        self.reg = kkt_regularisation(geo)
        # rounding floor of the force residual: forces are differences of positions ~ the cell size
        self.force_floor = 100.0 * np.finfo(float).eps * float(geo.K[:, 0, 0].max()) * geo.cell_size_mm
        self.contact = contact
        self.contact_fraction = contact_fraction
        # contact penalty per hinge: a multiple of its soft bending stiffness, acting on the closing rotation
        # refined hinges (core/lattice/refine): contact on the whole-hinge elements only
        self.kc = contact_stiffness * getattr(geo, "contact_k", geo.K[:, 5, 5])
        self.kappa0 = np.where(getattr(geo, "contact_mask", True),
                               contact_fraction * 2.0 * geo.contact_rad / np.cos(geo.tilt), np.inf)
        self.close_sign = -geo.parity[geo.a]                 # closing measure = close_sign * Theta_3
        self.tol = float(tol)
        self.max_iter = int(max_iter)
        self.load_steps = max(1, int(load_steps))
        self.min_step = float(min_step)
        self.fallback = fallback
        self.dr_max_iter = int(dr_max_iter)
        self.predictor = predictor
        self.stats = {"newton_iterations": 0, "load_steps": 0, "line_search_backtracks": 0,
                      "dr_iterations": 0, "method": "newton"}

    # -- energy pieces ------------------------------------------------------------------------------
    def _state(self, X, R, tangent=True):
        """``(element state, energy incl. contact, element gradients, element tangents or None)``."""
        st = ElementState(self.geo, X, R, tangent=False)
        E, ge = self._energy_grad(st)
        return st, E, ge, (self._tangent(st) if tangent else None)

    def _contact_terms(self, st):
        if not self.contact:
            return None
        over = self.close_sign * st.eps[:, 5] - self.kappa0
        idx = np.flatnonzero(over > 0)
        if not idx.size:
            return None
        return idx, over[idx], st.J[idx, 5, :] * self.close_sign[idx, None]

    def _energy_grad(self, st):
        E = float(st.energy.sum())
        ge = st.grad
        ct = self._contact_terms(st)
        if ct is not None:
            idx, over, Jr = ct
            f = self.kc[idx] * over
            E += 0.5 * float(np.sum(f * over))
            ge = ge.copy()
            ge[idx] += f[:, None] * Jr
        return E, ge

    def _tangent(self, st, mu=None):
        """Element tangents of the Lagrangian: hinges, contact springs and, away from the plane, the
        curvature of the soft-axis rotation weighted by the contact forces and actuator multipliers."""
        He = st.tangent()
        ct = self._contact_terms(st)
        spatial = not self.geo.planar and getattr(self.geo, "exact_tangent", True)
        if ct is not None:
            idx, over, Jr = ct
            He = He.copy()
            He[idx] += self.kc[idx, None, None] * Jr[:, :, None] * Jr[:, None, :]
            if spatial:
                He[np.ix_(idx, _ROT_DOFS, _ROT_DOFS)] += st.soft_axis_curvature(idx, self.kc[idx] * over *
                                                                                 self.close_sign[idx])
        if spatial and mu is not None and mu.size and np.any(mu):
            He = He.copy() if ct is None else He
            # constraints share joints only once (fixed_items), so the fancy-index update is safe
            He[np.ix_(self.joints, _ROT_DOFS, _ROT_DOFS)] += st.soft_axis_curvature(self.joints, mu)
        return He

    def _kkt_norm(self, r_f, c, scale_f):
        """Scaled KKT residual: forces relative to the actuator load, constraints relative to the rotations."""
        rc = np.abs(c).max(initial=0.0) / max(1e-3, np.abs(self.psi).max(initial=0.0))
        return max(np.abs(r_f).max(initial=0.0) / scale_f, rc)

    def _constraint(self, st, lam):
        return st.eps[self.joints, 5] - lam * self.psi

    # -- Newton on one load level -------------------------------------------------------------------
    def _newton(self, X, R, lam, mu, scale_f):
        pat = self.pattern
        nu = None
        carried = None
        for it in range(self.max_iter):
            if carried is None:
                st, E, ge, _ = self._state(X, R, tangent=False)
            else:
                st, E, ge = carried
            g = pat.vector(ge)
            c = self._constraint(st, lam)
            A = st.J[self.joints, 5, :]
            Ag = pat.vector(A * mu[:, None], self.joints) if mu.size else 0.0
            r_f = np.abs(g + Ag).max() if g.size else 0.0
            r_c = np.abs(c).max() if c.size else 0.0
            self.last_residual = (r_f / scale_f, r_c)
            if r_f <= max(self.tol * scale_f, self.force_floor) and \
                    r_c <= self.tol * max(1e-3, np.abs(self.psi).max(initial=0.0)):
                return X, R, mu, True, it
            He = self._tangent(st, mu)
            rhs = np.concatenate([-(g + Ag), -c])      # increments of the state and of the multipliers
            try:
                sol = _kkt_solve(pat, He, A, self.reg, rhs)
            except RuntimeError:
                return X, R, mu, False, it
            if not np.all(np.isfinite(sol)):
                return X, R, mu, False, it
            dq = sol[:self.na]
            mu_new = mu + sol[self.na:]
            nu = max(nu or 0.0, 2.0 * (np.abs(mu_new).max(initial=0.0)) + 1e-30)
            merit0 = E + nu * np.abs(c).sum()
            slope = float(g @ dq) - nu * np.abs(c).sum()
            alpha = 1.0
            ok = False
            res0 = self._kkt_norm(g + Ag, c, scale_f)
            for _ in range(12):
                X2, R2 = _apply(X, R, alpha * dq, self.dofmap, self.geo.n)
                st2, E2, g2, _H2 = self._state(X2, R2, tangent=False)
                c2 = self._constraint(st2, lam)
                merit = E2 + nu * np.abs(c2).sum()
                if merit <= merit0 + 1e-4 * alpha * min(slope, 0.0) + 1e-13 * abs(merit0):
                    ok = True
                    break
                # close to the solution the energy changes drown in rounding: there, accept a step that
                # reduces the KKT residual instead (far from it, the energy decides: it keeps Newton on the
                # branch it started on)
                if res0 > 1e-5:
                    alpha *= 0.5
                    self.stats["line_search_backtracks"] += 1
                    continue
                mu_t = mu + alpha * (mu_new - mu)
                A2 = st2.J[self.joints, 5, :]
                Ag2 = pat.vector(A2 * mu_t[:, None], self.joints) if mu.size else 0.0
                if self._kkt_norm(pat.vector(g2) + Ag2, c2, scale_f) <= (1.0 - 1e-4 * alpha) * res0:
                    ok = True
                    break
                alpha *= 0.5
                self.stats["line_search_backtracks"] += 1
            self.stats["newton_iterations"] += 1
            if not ok:
                return X, R, mu, False, it
            X, R = X2, R2
            carried = (st2, E2, g2)
            mu = mu + alpha * (mu_new - mu)
        st, E, ge, He = self._state(X, R, tangent=False)
        g = pat.vector(ge)
        c = self._constraint(st, lam)
        Ag = pat.vector(st.J[self.joints, 5, :] * mu[:, None], self.joints) if mu.size else 0.0
        self.last_residual = ((np.abs(g + Ag).max() if g.size else 0.0) / scale_f,
                              np.abs(c).max() if c.size else 0.0)
        return X, R, mu, False, self.max_iter

    # -- dynamic relaxation fallback -----------------------------------------------------------------
    def _dr_masses(self, X, R, kp):
        """Fictitious masses: Gershgorin row sums of the penalised tangent, contact penalties included
        whether active or not (so that a contact that closes cannot destabilise the explicit steps)."""
        pat = self.pattern
        st = ElementState(self.geo, X, R, tangent=True)
        He = np.abs(st.H)
        Jr = np.abs(st.J[:, 5, :])
        if self.contact:
            He = He + self.kc[:, None, None] * Jr[:, :, None] * Jr[:, None, :]
        gersh = pat.vector(He.sum(axis=2))
        if self.joints.size:
            A = np.abs(st.J[self.joints, 5, :])
            gersh = gersh + kp * pat.vector(A * A.sum(axis=1, keepdims=True), self.joints)
        return np.maximum(gersh, 1e-12 * max(gersh.max(initial=0.0), 1e-300))

    def _dynamic_relaxation(self, X, R, tol_f, scale_f):
        """Kinetic-damping dynamic relaxation on the penalised energy (constraints as stiff springs).

        Explicit pseudo-dynamics with unit time step and Gershgorin masses (refreshed every 100 steps);
        the velocities restart from zero at every kinetic-energy peak. No linear solves: it gets through
        states where Newton's tangent is singular or the line search stalls, and Newton then polishes.
        """
        pat = self.pattern
        st = ElementState(self.geo, X, R, tangent=True)
        kp = 10.0 * float(np.abs(st.H[:, :, :]).max())
        psi_scale = max(np.abs(self.psi).max(initial=0.0), 1e-12)
        v = np.zeros(self.na)
        ke_old = 0.0
        mass = None
        for it in range(self.dr_max_iter):
            if it % 100 == 0:
                mass = self._dr_masses(X, R, kp)
            st, E, ge, _ = self._state(X, R, tangent=False)
            c = self._constraint(st, 1.0)
            if self.joints.size:
                ge = ge.copy()
                np.add.at(ge, self.joints, (kp * c)[:, None] * st.J[self.joints, 5, :])
            f = -pat.vector(ge)
            if np.abs(f).max() <= tol_f * scale_f and (not c.size or np.abs(c).max() <= 1e-3 * psi_scale):
                self.stats["dr_iterations"] += it
                return X, R, True
            v = v + f / mass
            ke = float(v @ (mass * v))
            if ke < ke_old:          # kinetic damping: restart from rest at a kinetic-energy peak
                v = np.zeros_like(v)
                ke = 0.0
            ke_old = ke
            X, R = _apply(X, R, v, self.dofmap, self.geo.n)
        self.stats["dr_iterations"] += self.dr_max_iter
        return X, R, False

    # -- driver ---------------------------------------------------------------------------------------
    def solve(self, linear=None):
        geo = self.geo
        I3 = np.broadcast_to(np.eye(3), (geo.n, 3, 3)).copy()
        X, R = geo.X0.copy(), I3
        if not self.joints.size or not np.any(self.psi):
            self.stats["method"] = "no load (nothing to solve)"
            return X, R, True
        # refined hinges: the force scale from the one-element lattice (the same loads on the plates)
        lin = linear or LinearLattice(self.geo.scene, getattr(geo, "base", geo), contact=False)
        q0 = lin.solve(self.psi)[2]
        # force scale: the largest generalised force the actuators apply in the linear solution
        Klin_q = lin.H @ q0
        scale_f = max(float(np.abs(Klin_q).max()), 1e-30)
        q_lin = None
        if self.predictor and lin.na == self.na:
            # predictor: the linearised lattice with plate contact (piecewise linear)
            lin.contact = self.contact
            lin.kappa_c, lin.kc = self.kappa0, self.kc
            q_lin = lin.solve(self.psi)[2]
        self.scale_f = scale_f
        if self.method == "dynamic_relaxation":
            # dynamic relaxation alone (for comparison; the default uses it only as Newton's fallback)
            self.stats["method"] = "dynamic relaxation"
            X, R, ok = self._dynamic_relaxation(X, R, self.tol, scale_f)
            st = ElementState(geo, X, R, tangent=False)
            g = self.pattern.vector(self._energy_grad(st)[1])
            self.last_residual = (float(np.abs(g).max()) / scale_f, float(np.abs(self._constraint(st, 1.0)).max()))
            self.mu = np.zeros(self.joints.size)
            return X, R, ok
        mu = np.zeros(self.joints.size)
        lam = 0.0
        dl = 1.0 / self.load_steps
        converged = False
        while lam < 1.0 - 1e-15:
            step = min(dl, 1.0 - lam)
            target = lam + step
            X1, R1 = X, R
            if q_lin is not None and lam == 0.0:
                X1, R1 = _apply(X, R, step * q_lin, self.dofmap, geo.n)
            X2, R2, mu2, ok, _ = self._newton(X1, R1, target, mu.copy(), scale_f)
            if not ok and (X1 is not X):
                X2, R2, mu2, ok, _ = self._newton(X, R, target, mu.copy(), scale_f)
            if ok:
                X, R, mu, lam = X2, R2, mu2, target
                self.stats["load_steps"] += 1
                if step == dl and dl < 1.0:
                    dl = min(1.0, 2.0 * dl)
                continue
            if step / 2 >= self.min_step:
                dl = step / 2
                continue
            break
        converged = lam >= 1.0 - 1e-15
        if not converged and self.fallback:
            self.stats["method"] = "dynamic relaxation + Newton"
            Xd, Rd, ok = self._dynamic_relaxation(X, R, 1e-2, scale_f)
            X3, R3, mu3, ok2, _ = self._newton(Xd, Rd, 1.0, np.zeros(self.joints.size), scale_f)
            if ok2:
                X, R, converged = X3, R3, True
            else:
                X, R = (X3, R3) if np.all(np.isfinite(X3)) else (Xd, Rd)
        self.mu = mu
        return X, R, converged
