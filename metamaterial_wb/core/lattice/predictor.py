"""The quadratic model as the lattice models' predictor: its D field assembled lean for one solve
(:func:`quadratic_D`) and its state in lattice terms (:func:`quadratic_state`, the ``about=quadratic``
linearisation point)."""
import numpy as np
import scipy.sparse.linalg as spla

from metamaterial_wb.core.lattice import linalg
from metamaterial_wb.core.lattice.poses import ChainPositions


def quadratic_D(scene):
    """The quadratic model's D field (``core/solver.solve_scene(scene)[0]``, same energy, fixed nodes and
    islands), assembled lean for one solve: only the free-node block of the Hessian, one right-hand side,
    no response matrix. Anything the quadratic model would reject (values out of range, a node given two
    values, bad stiffness) goes through ``solve_scene`` itself, which raises its error.

    Parameters
    ----------
    scene : Scene

    Returns
    -------
    numpy.ndarray
        Shape ``(n_nodes,)``.
    """
    from scipy.sparse.csgraph import connected_components
    import scipy.sparse as sp

    from metamaterial_wb.core.calibration import joint_stiffness
    from metamaterial_wb.core.solver import scene_groups, scene_values, solve_scene

    if not linalg._FAST:
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
    if linalg._cholmod is not None:
        D[sfree] = linalg._cholmod(H)(rhs)
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

    Parameters
    ----------
    scene : Scene
    geo : LatticeGeometry
    chain : ChainPositions, optional
        Reused hinge-chain solver.
    pose : {"rotations", "full"}
    D : numpy.ndarray, optional

    Returns
    -------
    tuple
        ``(D, X, R)``.
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
