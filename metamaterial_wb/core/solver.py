"""The quadratic model of the seed (eq. 1 and 2) and its sparse solver.

Per joint e joining nodes a and b, with stiffness (k1, k2):

    E_e = k2 * (k1 * (D_a - D_b)**2 + (1 - k1) * (D_a**2 + D_b**2))

so the Hessian of E = sum_e E_e is constant: ``H_aa += 2 k2``, ``H_ab = -2 k1 k2``. It is a
symmetric, weakly diagonally dominant M-matrix. An actuator (or angular constraint) on a joint fixes
D of both its nodes to the item's value. The free nodes F solve ``H_FF D_F = -H_FA D_A`` (one Newton
step on the constant Hessian is the exact minimiser).

Factor once per topology, stiffness and placement of fixed items; every new set of values then
costs one back-substitution, or (with few fixed items) a product with the precomputed response
matrix ``G = -H_FF^-1 H_FA P`` (n_free x n_items).

Stability (see docs/solver.md): k1 outside [0, 1] and k2 <= 0 are rejected; free components that
touch no fixed node ("islands") get D = 0 and a warning, never an arbitrary value (k1 = 1 included);
two different values on one node are a validation error naming both items.
"""
import time
import warnings as _warnings

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from scipy.sparse.csgraph import connected_components

from metamaterial_wb.core.errors import SceneError, range_message
from metamaterial_wb.core.scene import joint_nodes, node_name, parse_joint

try:  # optional accelerator (GPL parts in SuiteSparse; never required)
    from sksparse.cholmod import cholesky as _cholmod_cholesky  # type: ignore
except Exception:  # pragma: no cover - depends on the machine
    _cholmod_cholesky = None

BACKENDS = ("auto", "superlu", "cholmod", "dense")
RESPONSE_MATRIX_MAX_ITEMS = 32


def cholmod_available():
    """Whether scikit-sparse's CHOLMOD can be imported (the ``cholmod`` backend).

    Returns
    -------
    bool
    """
    return _cholmod_cholesky is not None


K2_MIN, K2_MAX = 1e-100, 1e100   # the solve is scale-invariant in k2; beyond this 2 k2 (and its squares)
#                                   overflow or go subnormal (a scene limits k2 to [1e-9, 1e9] itself)


def check_stiffness(k1, k2, joint_names=None):
    """Reject k1 outside [0, 1] and k2 outside [K2_MIN, K2_MAX] (or non-finite), naming the first bad joint.

    Parameters
    ----------
    k1, k2 : array_like
        Per-joint stiffness parameters (seed eq. 2).
    joint_names : sequence of str, optional
        Names for the error message (else ``#index``).

    Returns
    -------
    tuple of numpy.ndarray
        ``(k1, k2)`` as float arrays.

    Raises
    ------
    SceneError
        On the first out-of-range or non-finite value.
    """
    k1 = np.asarray(k1, dtype=float)
    k2 = np.asarray(k2, dtype=float)
    bad = np.flatnonzero(~np.isfinite(k1) | (k1 < 0) | (k1 > 1))
    if bad.size:
        j = bad[0]
        name = joint_names[j] if joint_names is not None else f"#{j}"
        raise SceneError(f"joint {name}.k1", range_message(float(k1[j]), 0, 1) + f" ({bad.size} bad joint(s))")
    bad = np.flatnonzero(~np.isfinite(k2) | (k2 < K2_MIN) | (k2 > K2_MAX))
    if bad.size:
        j = bad[0]
        name = joint_names[j] if joint_names is not None else f"#{j}"
        raise SceneError(f"joint {name}.k2", range_message(float(k2[j]), K2_MIN, K2_MAX)
                         + f" ({bad.size} bad joint(s))")
    return k1, k2


def assemble_hessian(n_nodes, pairs, k1, k2):
    """Sparse Hessian (CSR) of the quadratic energy.

    Parameters
    ----------
    n_nodes : int
        Number of nodes.
    pairs : numpy.ndarray
        (m, 2) node indices of the joints.
    k1, k2 : numpy.ndarray
        (m,) per-joint stiffness parameters.

    Returns
    -------
    scipy.sparse.csr_matrix
        (n_nodes, n_nodes).
    """
    pairs = np.asarray(pairs, dtype=np.int64).reshape(-1, 2)
    a, b = pairs[:, 0], pairs[:, 1]
    diag = np.bincount(a, weights=2 * k2, minlength=n_nodes) + np.bincount(b, weights=2 * k2, minlength=n_nodes)
    off = -2.0 * k1 * k2
    rows = np.concatenate([np.arange(n_nodes), a, b])
    cols = np.concatenate([np.arange(n_nodes), b, a])
    vals = np.concatenate([diag, off, off])
    return sp.csr_matrix((vals, (rows, cols)), shape=(n_nodes, n_nodes))


def energy(D, pairs, k1, k2):
    """Total energy (seed eq. 2) of a D field.

    Parameters
    ----------
    D : numpy.ndarray
        (n,) deformation per node.
    pairs : numpy.ndarray
        (m, 2) node indices of the joints.
    k1, k2 : numpy.ndarray
        (m,) per-joint stiffness parameters.

    Returns
    -------
    float
    """
    D = np.asarray(D, dtype=float)
    a, b = np.asarray(pairs).T
    return float(np.sum(k2 * (k1 * (D[a] - D[b]) ** 2 + (1 - k1) * (D[a] ** 2 + D[b] ** 2))))


class _Factor:
    """A factorisation of the SPD matrix H_FF with ``solve(rhs)``."""

    def __init__(self, A, backend):
        self.backend = backend
        n = A.shape[0]
        if n == 0:
            self.solve = lambda b: np.zeros_like(b)
            return
        if backend == "cholmod":
            f = _cholmod_cholesky(A.tocsc())
            self.solve = f
        elif backend == "dense":
            import scipy.linalg as sla
            c = sla.cho_factor(A.toarray())
            self.solve = lambda b: sla.cho_solve(c, b)
        else:
            lu = spla.splu(A.tocsc(), permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                           options={"SymmetricMode": True})
            self.solve = lu.solve


class QuadraticModel:
    """Factor once, re-solve per value change.

    Parameters
    ----------
    n_nodes, pairs, k1, k2: the structure (pairs index nodes).
    groups: list of ``(name, [node indices])``; every node of a group is fixed to the group's value.
    names: optional node names for messages.
    backend: "auto" (CHOLMOD if installed, else SuperLU), "superlu", "cholmod" or "dense".
    """

    def __init__(self, n_nodes, pairs, k1, k2, groups, node_names=None, joint_names=None, backend="auto"):
        t0 = time.perf_counter()
        if backend not in BACKENDS:
            raise SceneError("backend", f"{backend!r}; allowed: {', '.join(BACKENDS)}")
        if backend == "cholmod" and not cholmod_available():
            raise SceneError("backend", "'cholmod' needs scikit-sparse, which is not installed; use 'superlu'")
        if backend == "auto":
            backend = "cholmod" if cholmod_available() else "superlu"
        self.backend = backend
        self.n_nodes = int(n_nodes)
        self.pairs = np.asarray(pairs, dtype=np.int64).reshape(-1, 2)
        self.k1, self.k2 = check_stiffness(k1, k2, joint_names)
        self.node_names = node_names
        self.groups = [(str(name), np.asarray(nodes, dtype=np.int64)) for name, nodes in groups]
        self.group_names = [g[0] for g in self.groups]
        self.warnings = []
        self.timings = {}

        # fixed nodes: the first group that names a node defines it; others must agree at solve time
        node_group = {}
        shared = []
        for gi, (_, nodes) in enumerate(self.groups):
            for n in nodes:
                n = int(n)
                if n in node_group:
                    shared.append((n, node_group[n], gi))
                else:
                    node_group[n] = gi
        self._shared = shared
        fixed = np.array(sorted(node_group), dtype=np.int64)
        self.fixed = fixed
        self.fixed_group = np.array([node_group[int(n)] for n in fixed], dtype=np.int64)
        is_fixed = np.zeros(self.n_nodes, dtype=bool)
        is_fixed[fixed] = True
        free = np.flatnonzero(~is_fixed)

        # islands: free components with no joint to a fixed node
        a, b = self.pairs[:, 0], self.pairs[:, 1]
        ff = ~is_fixed[a] & ~is_fixed[b]
        pos = -np.ones(self.n_nodes, dtype=np.int64)
        pos[free] = np.arange(free.size)
        adj = sp.coo_matrix((np.ones(int(ff.sum())), (pos[a[ff]], pos[b[ff]])), shape=(free.size, free.size))
        ncomp, labels = connected_components(adj, directed=False)
        touches = np.zeros(ncomp, dtype=bool)
        fa = ~is_fixed[a] & is_fixed[b]
        fb = is_fixed[a] & ~is_fixed[b]
        touches[labels[pos[a[fa]]]] = True
        touches[labels[pos[b[fb]]]] = True
        island_mask = ~touches[labels] if free.size else np.zeros(0, dtype=bool)
        self.island_nodes = free[island_mask]
        if self.island_nodes.size:
            n_isl = int(np.unique(labels[island_mask]).size)
            first = self._node_label(int(self.island_nodes[0]))
            self.warnings.append(
                f"{n_isl} part(s) of the structure ({self.island_nodes.size} nodes, e.g. {first}) have no actuator "
                f"or constraint; their deformation is set to D = 0")
        self.free = free[~island_mask]
        self.timings["setup_s"] = time.perf_counter() - t0

        t1 = time.perf_counter()
        H = assemble_hessian(self.n_nodes, self.pairs, self.k1, self.k2)
        self.H = H
        H_F = H[self.free]
        self.H_FF = H_F[:, self.free].tocsc()
        self.H_FA = H_F[:, fixed].tocsc()
        self.timings["assemble_s"] = time.perf_counter() - t1

        t2 = time.perf_counter()
        self._factor = _Factor(self.H_FF, backend)
        self.timings["factor_s"] = time.perf_counter() - t2

        # response matrix for few items: D_F = G @ values
        t3 = time.perf_counter()
        self.G = None
        ng = len(self.groups)
        if 0 < ng <= RESPONSE_MATRIX_MAX_ITEMS and self.free.size:
            P = sp.csr_matrix((np.ones(fixed.size), (np.arange(fixed.size), self.fixed_group)),
                              shape=(fixed.size, ng))
            rhs = -(self.H_FA @ P).toarray()
            self.G = np.asarray(self._factor.solve(rhs)).reshape(self.free.size, ng)
        self.timings["response_s"] = time.perf_counter() - t3
        self.timings["total_prepare_s"] = time.perf_counter() - t0

    # -- helpers ----------------------------------------------------------------------------
    def _node_label(self, n):
        return self.node_names[n] if self.node_names is not None else f"node #{n}"

    def _values_array(self, values):
        ng = len(self.groups)
        if isinstance(values, dict):
            arr = np.zeros(ng)
            for k, name in enumerate(self.group_names):
                if name not in values:
                    raise SceneError(f"values.{name}", "no value given for this actuator/constraint")
                arr[k] = values[name]
            extra = set(values) - set(self.group_names)
            if extra:
                raise SceneError(f"values.{sorted(extra)[0]}", f"unknown item; known: {self.group_names}")
        else:
            arr = np.asarray(values, dtype=float).reshape(-1)
            if arr.size != ng:
                raise SceneError("values", f"expected {ng} values ({self.group_names}), got {arr.size}")
        for k, v in enumerate(arr):
            if not np.isfinite(v) or v < -1 or v > 1:
                raise SceneError(f"values.{self.group_names[k]}", range_message(float(v), -1, 1))
        for n, g1, g2 in self._shared:
            if arr[g1] != arr[g2]:
                raise SceneError(f"values.{self.group_names[g2]}",
                                 f"{self.group_names[g2]!r} sets {self._node_label(n)} to {arr[g2]}, but "
                                 f"{self.group_names[g1]!r} sets it to {arr[g1]}; a node takes one fixed value")
        return arr

    # -- solving ----------------------------------------------------------------------------
    def solve(self, values, use_response=True):
        """D for every node given the items' values.

        Parameters
        ----------
        values : dict or array_like
            By item name, or an array in group order.
        use_response : bool, optional
            Use the precomputed response matrix (fast path) instead of a fresh back-substitution.

        Returns
        -------
        numpy.ndarray
            (n_nodes,) D.

        Raises
        ------
        SceneError
            If a value is missing or out of range.
        """
        arr = self._values_array(values)
        D = np.zeros(self.n_nodes)
        D[self.fixed] = arr[self.fixed_group]
        if self.free.size:
            if use_response and self.G is not None:
                D[self.free] = self.G @ arr
            else:
                rhs = -(self.H_FA @ D[self.fixed])
                D[self.free] = self._factor.solve(rhs)
        return D

    def residual(self, D):
        """Relative residual of the free-node equations (a health check).

        Parameters
        ----------
        D : numpy.ndarray
            (n_nodes,) a solution.

        Returns
        -------
        float
        """
        if not self.free.size:
            return 0.0
        x = D[self.free]
        b = -(self.H_FA @ D[self.fixed])
        r = self.H_FF @ x - b
        scale = abs(self.H_FF).sum(axis=0).max() * np.abs(x).sum() + np.abs(b).sum()
        return float(np.abs(r).sum() / scale) if scale > 0 else float(np.abs(r).sum())


def scene_groups(scene):
    """``[(name, [node indices])]`` for the scene's actuators and constraints (file order).

    Parameters
    ----------
    scene : Scene

    Returns
    -------
    list of tuple
    """
    topo = scene.topology
    groups = []
    for _, item in scene.fixed_items():
        kind, i, j = parse_joint(item.joint)
        groups.append((item.name, [topo.node_id(*n) for n in joint_nodes(kind, i, j)]))
    return groups


def model_for_scene(scene, calibration=None, backend="auto"):
    """A factored :class:`QuadraticModel` of a scene.

    Parameters
    ----------
    scene : Scene
    calibration : Calibration, optional
        k1 / k2 from hinge sizes (default: the package calibration).
    backend : str, optional
        ``"auto"``, ``"superlu"``, ``"cholmod"`` or ``"dense"``.

    Returns
    -------
    QuadraticModel
    """
    from metamaterial_wb.core.calibration import joint_stiffness

    topo = scene.topology
    k1, k2 = joint_stiffness(scene, calibration)
    return QuadraticModel(topo.n_nodes, topo.joint_pairs, k1, k2, scene_groups(scene),
                          node_names=_LazyNames(topo, "node"), joint_names=_LazyNames(topo, "joint"),
                          backend=backend)


class _LazyNames:
    """Node / joint names for messages, built only when a message needs one."""

    def __init__(self, topo, what):
        self.topo, self.what = topo, what

    def __getitem__(self, k):
        if self.what == "node":
            i, j = self.topo.node_ij()[k]
            return node_name(int(i), int(j))
        return self.topo.joint_names[k]


def scene_values(scene):
    """``{name: value}`` of every actuator and constraint.

    Parameters
    ----------
    scene : Scene

    Returns
    -------
    dict
    """
    return {item.name: item.value for _, item in scene.fixed_items()}


def solve_scene(scene, global_deformation=None, model=None, backend="auto"):
    """Solve a scene.

    With ``global_deformation`` g (the seed's "Global Deformation" slider) every D = g: perfect
    propagation, no solve.

    Parameters
    ----------
    scene : Scene
    global_deformation : float, optional
        If given, D = g everywhere.
    model : QuadraticModel, optional
        A factored model of the same scene to reuse.
    backend : str, optional
        Linear-solver backend (see :func:`model_for_scene`).

    Returns
    -------
    tuple
        ``(D, model_or_None, warnings, timings)``.
    """
    if global_deformation is not None:
        from metamaterial_wb.core.errors import check_number
        g = check_number("global_deformation", global_deformation, -1.0, 1.0)
        return np.full(scene.topology.n_nodes, g), None, [], {"solve_s": 0.0}
    if model is None:
        model = model_for_scene(scene, backend=backend)
    t = time.perf_counter()
    D = model.solve(scene_values(scene))
    timings = dict(model.timings)
    timings["solve_s"] = time.perf_counter() - t
    return D, model, list(model.warnings), timings
