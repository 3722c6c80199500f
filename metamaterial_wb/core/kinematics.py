"""Kinematics of the rotating-squares sheet with long hinges: D field -> 3D node poses.

Full derivation and conventions: ``docs/kinematics.md``. Summary:

* Geometry. Node ``N(i,j)`` is a square plate of side ``s = cell_size - lh`` whose centre sits at
  ``x = j * cell_size``, ``y = -i * cell_size`` in the flat state (rows grow downwards, z is the
  sheet normal). A hinge of length ``lh`` joins two corners of neighbouring plates along the edge
  line; corners alternate in a checkerboard (``H(i,j)``: top corners if i+j is even, bottom if odd;
  ``V(i,j)``: right corners if i+j is even, left if odd), so that a node with even i+j turning
  counter-clockwise (D = +1, the seed's sign rule) *closes* the cells.
* In-plane rotation. ``phi = (-1)^(i+j) * D * phi_max(sign D)``: ``phi_max(+)`` is the closing limit
  (plate contact ``asin(lh / 2s)``, hinge strain, fold contact), ``phi_max(-)`` the opening limit
  (45 degrees = widest pitch of the mechanism, hinge strain, fold contact). :func:`rotation_limit_info`
  reports which one binds.
* Bending cells. A joint with tilt ``alpha`` (``scene.joint_tilt_deg``) is a revolute hinge whose axis
  leans from the plate normal by ``alpha`` towards the joint's fold vector ``f`` (``-y`` for H joints,
  ``-x`` for V joints; ``f = u x z`` with ``u`` the in-plane direction from the joint's first node to
  its second). When the two plates counter-rotate in plane by ``+-phi`` the hinge folds the second
  plate relative to the first about ``f`` by ``gamma`` with the exact relation

      tan(gamma / 2) = -tan(alpha) * sin(phi_A)      (phi_A: in-plane rotation of the first node)

  (small angles: ``|gamma| ~ 2 |phi| tan(alpha)``, the note's formula), and the hinge turns by
  ``psi`` with ``cos(psi / 2) = cos(gamma / 2) cos(phi)``.
* Poses. Every node gets ``R = F Rz(phi)``: ``F`` is the fold frame (paper-like folding of the sheet
  along its bending lines), ``Rz(phi)`` the in-plane rotation. Fold frames come from one scalar
  graph-Laplacian least-squares solve per fold group (a stretch of a bending line; ``theta_B - theta_A
  = gamma`` on its tilted joints, 0 elsewhere), composed from node 0 outwards, positions from the
  least-squares hinge closure

      sum_joints | c_B + R_B r_B - c_A - R_A r_A - M d0 |^2,   M = mid(F_A, F_B) Rz((phi_A + phi_B) / 2),

  all with one sparse factorisation per topology (:class:`Kinematics`, reuse it across frames).
  For uniform D both solves are consistent and the residual vanishes (exact mechanism); for
  non-uniform D they are the least-squares compromise.
"""
import math

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from metamaterial_wb.core.errors import SceneError
# the scalar half (per-joint data, closed forms, limits) and the rotations live in their own files;
# every name stays importable from here
from metamaterial_wb.core.limits import (DEFAULT_HINGE_STRAIN_LIMIT, MAX_TILT_DEG, OPENING_LIMIT_RAD,  # noqa: F401
                                         _TILT_EPS, _joint_index, _phi_limit_fold_contact, _phi_limit_strain,
                                         _tilts, fold_contact_rad, fold_from_tilt, hinge_rotation, hinge_strain,
                                         hinge_strain_limit, joint_fold_vectors, joint_hinge_arrays, joint_parity,
                                         node_angles, node_parity, plate_side_mm, rotation_limit_info,
                                         rotation_limits, stored_tilts_rad, tilt_for_fold, tilts_from_config_deg,
                                         uniform_fold_deg, uniform_pitch_mm)
from metamaterial_wb.core.rotations import (_matvec, axis_angle_matrices, rotation_exp, rotation_log,  # noqa: F401
                                            rotation_matrices)


# ----------------------------------------------------------------------------------------------
# geometry of the hinges
# ----------------------------------------------------------------------------------------------
def _hinge_geometry(scene):
    """Per joint: node indices (a, b), corner offsets r_a, r_b (flat, plate frame, 3D) and the
    chord d0 (3D), vectorised."""
    topo = scene.topology
    a_half = 0.5 * plate_side_mm(scene)
    lh = scene.hinge["length_mm"]
    m = topo.n_joints
    ij = topo.joint_ij()
    even = (ij[:, 0] + ij[:, 1]) % 2 == 0
    isH = np.arange(m) < topo.n_h
    ra = np.zeros((m, 3))
    rb = np.zeros((m, 3))
    d0 = np.zeros((m, 3))
    sgn = np.where(even, a_half, -a_half)
    # H: a's right corner, b's left corner, both top (even) or bottom (odd); chord +x
    ra[isH, 0] = a_half
    ra[isH, 1] = sgn[isH]
    rb[isH, 0] = -a_half
    rb[isH, 1] = sgn[isH]
    d0[isH, 0] = lh
    # V: a's bottom corner, b's top corner, both right (even) or left (odd); chord -y
    V = ~isH
    ra[V, 0] = sgn[V]
    ra[V, 1] = -a_half
    rb[V, 0] = sgn[V]
    rb[V, 1] = a_half
    d0[V, 1] = -lh
    lj = joint_hinge_arrays(scene)[0]
    if np.any(lj != lh):
        # a joint whose flexible length L differs from the sheet's lh (which sets the plate gap) gets
        # rigid stubs of (lh - L) / 2 on both plates: they turn with their plate, only L turns with the
        # mean rotation (inverse design, issue 17: the poses see per-joint hinge lengths)
        u = d0 / lh
        stub = 0.5 * (lh - lj)[:, None] * u
        ra, rb, d0 = ra + stub, rb - stub, lj[:, None] * u
    return topo.joint_pairs[:, 0], topo.joint_pairs[:, 1], ra, rb, d0


def flat_positions_mm(scene):
    """Node centres of the flat sheet: ``x = j * cell``, ``y = -i * cell``, ``z = 0``.

    Parameters
    ----------
    scene : Scene

    Returns
    -------
    numpy.ndarray
        Shape ``(n_nodes, 3)``.
    """
    ij = scene.topology.node_ij().astype(float)
    p = scene.cell_size_mm
    return np.column_stack([ij[:, 1] * p, -ij[:, 0] * p, np.zeros(len(ij))])


def _fold_groups(topo, a, b, tilted):
    """Fold groups ``[(direction, f, joint indices)]`` in composition order (empty for a planar sheet).

    A group is one stretch of a bending line: the tilted joints of one line (``H(., k)`` vertical,
    ``V(k, .)`` horizontal) between the same two regions (components of the sheet without its tilted
    joints), so that the stretches of one line on different branches (a U's legs, a comb's teeth) are
    folded separately. Stretches are ordered by their graph distance from node 0, which puts every
    stretch after the stretches between it and node 0: the product ``Rot(f_1, theta_1) Rot(f_2, theta_2) ...``
    then composes each node's folds along its own path from the root (for uniform D the fold field of a
    stretch off that path is exactly 0 at the node; for non-uniform D it is the least-squares compromise).
    Consecutive groups of one direction are merged (rotations about one vector commute and the fold
    fields add).
    """
    from scipy.sparse.csgraph import connected_components, shortest_path

    if not tilted.size:
        return []
    n, m = topo.n_nodes, topo.n_joints
    keep = np.ones(m, dtype=bool)
    keep[tilted] = False
    _, region = connected_components(sp.coo_matrix((np.ones(int(keep.sum())), (a[keep], b[keep])), shape=(n, n)),
                                     directed=False)
    ij = topo.joint_ij()
    keys = {}
    for k in tilted.tolist():
        line = ("vertical", int(ij[k, 1])) if k < topo.n_h else ("horizontal", int(ij[k, 0]))
        keys.setdefault(line + tuple(sorted((int(region[a[k]]), int(region[b[k]])))), []).append(k)
    dist = shortest_path(sp.coo_matrix((np.ones(m), (a, b)), shape=(n, n)).tocsr(), indices=0, unweighted=True,
                         directed=False)
    depth = {key: float(np.min(np.minimum(dist[a[js]], dist[b[js]]))) for key, js in keys.items()}
    groups = []
    for key in sorted(keys, key=lambda k: (depth[k], k)):
        if groups and groups[-1][0] == key[0]:
            groups[-1][2].extend(keys[key])
        else:
            f = np.array([0.0, -1.0, 0.0]) if key[0] == "vertical" else np.array([-1.0, 0.0, 0.0])
            groups.append((key[0], f, list(keys[key])))
    return [(d, f, np.array(sorted(js), dtype=np.int64)) for d, f, js in groups]


# ----------------------------------------------------------------------------------------------
# the factored kinematics
# ----------------------------------------------------------------------------------------------
class Kinematics:
    """Factored pose solver for one scene topology and joint configuration (reuse across frames).

    ``poses(D) -> (positions_mm (n,3), rotations (n,3,3), phi (n,))``. Build cost: one sparse LU of
    the node graph Laplacian; per frame: a few vectorised passes and one multi-right-hand-side
    back-substitution.

    Parameters
    ----------
    scene : Scene
    tilts_rad : array_like, optional
        Signed hinge tilt (rad) of every joint. Pass ``core.design.joint_tilts_rad(scene)`` (or use
        ``core.design.kinematics_for``) for a scene that may have axes but no joint configuration; the default,
        the scene's stored tilts, raises a SceneError for such a scene.
    """

    def __init__(self, scene, tilts_rad=None):
        self.scene = scene
        topo = scene.topology
        self.n = n = topo.n_nodes
        self.m = m = topo.n_joints
        self.a, self.b, self.ra, self.rb, self.d0 = _hinge_geometry(scene)
        self.tilt = _tilts(scene, tilts_rad)
        self.limits = rotation_limits(scene, self.tilt)
        self.parity = node_parity(scene)
        inc = sp.csr_matrix((np.concatenate([-np.ones(m), np.ones(m)]),
                             (np.concatenate([np.arange(m), np.arange(m)]), np.concatenate([self.a, self.b]))),
                            shape=(m, n))
        self.inc = inc
        self.incT = inc.T.tocsr()
        self.flat = flat_positions_mm(scene)
        self._lu = None
        if n > 1:
            L = (inc.T @ inc).tocsc()
            self._lu = spla.splu(L[1:, 1:].tocsc(), permc_spec="MMD_AT_PLUS_A")
        self.tilted = np.flatnonzero(np.abs(self.tilt) > _TILT_EPS)
        self.groups = _fold_groups(topo, self.a, self.b, self.tilted)
        self.planar = not self.groups

    # -- linear algebra ----------------------------------------------------------------------
    def _solve_edges(self, e):
        """Least-squares node values x (n, k) with x_b - x_a ~ e (m, k), x[0] = 0."""
        e = np.asarray(e, dtype=float)
        x = np.zeros((self.n, e.shape[1]))
        if self._lu is not None:
            rhs = (self.incT @ e)[1:]
            x[1:] = self._lu.solve(np.ascontiguousarray(rhs))
        return x

    # -- pieces --------------------------------------------------------------------------------
    def angles(self, D):
        return node_angles(self.scene, D, self.limits)

    def joint_folds(self, phi):
        """Fold (rad) of every joint for in-plane rotations ``phi`` (0 on untilted joints)."""
        gamma = np.zeros(self.m)
        if self.tilted.size:
            t = self.tilted
            phi_a = 0.5 * (phi[self.a[t]] - phi[self.b[t]])
            gamma[t] = fold_from_tilt(self.tilt[t], phi_a)
        return gamma

    def fold_frames(self, phi):
        """(n, 3, 3) fold frames F (identity for a planar scene)."""
        return self._fold_state(phi)[0]

    def _fold_state(self, phi):
        """``(F, theta)``: fold frames and the per-group fold fields (n, groups)."""
        if self.planar:
            return np.broadcast_to(np.eye(3), (self.n, 3, 3)).copy(), None
        gamma = self.joint_folds(phi)
        E = np.zeros((self.m, len(self.groups)))
        for g, (_d, _f, js) in enumerate(self.groups):
            E[js, g] = gamma[js]
        theta = self._solve_edges(E)
        F = None
        for g, (_d, f, _js) in enumerate(self.groups):
            Rg = axis_angle_matrices(f, theta[:, g])
            F = Rg if F is None else F @ Rg
        return F, theta

    def _chords(self, phi, F, R, theta=None):
        a, b = self.a, self.b
        mean = 0.5 * (phi[a] + phi[b])
        c, s = np.cos(mean), np.sin(mean)
        d = self.d0
        chord = np.column_stack([c * d[:, 0] - s * d[:, 1], s * d[:, 0] + c * d[:, 1], np.zeros(self.m)])
        if not self.planar:
            if theta is not None and len(self.groups) == 1:
                # one fold direction: mid(F_A, F_B) = Rot(f, (theta_A + theta_B) / 2) exactly
                M = axis_angle_matrices(self.groups[0][1], 0.5 * (theta[a, 0] + theta[b, 0]))
            else:
                Fa = F[a]
                M = Fa @ rotation_exp(0.5 * rotation_log(np.swapaxes(Fa, 1, 2) @ F[b]))
            chord = _matvec(M, chord)
        return chord + _matvec(R[a], self.ra) - _matvec(R[b], self.rb)

    def rotations(self, phi, F=None):
        F = self.fold_frames(phi) if F is None else F
        Rz = rotation_matrices(phi)
        return Rz if self.planar else F @ Rz

    # -- public --------------------------------------------------------------------------------
    def poses(self, D):
        """``(positions_mm (n,3), rotations (n,3,3), phi (n,))`` for a D field."""
        phi = self.angles(D)
        pos, R = self.poses_from_angles(phi)
        return pos, R, phi

    def poses_from_angles(self, phi):
        phi = np.asarray(phi, dtype=float)
        F, theta = self._fold_state(phi)
        R = self.rotations(phi, F)
        e = self._chords(phi, F, R, theta)
        pos = self._solve_edges(e)
        pos += self.flat.mean(axis=0) - pos.mean(axis=0)
        return pos, R

    def positions(self, phi):
        """Node centres (n, 3) in mm for in-plane node rotations ``phi`` (radians)."""
        return self.poses_from_angles(phi)[0]

    def closure_residual(self, phi, pos):
        """Max hinge-closure error (mm) of positions ``pos`` for rotations ``phi``."""
        phi = np.asarray(phi, dtype=float)
        F = self.fold_frames(phi)
        R = self.rotations(phi, F)
        e = self._chords(phi, F, R)
        r = pos[self.b] - pos[self.a] - e
        return float(np.abs(r).max()) if len(r) else 0.0

    def rotation_closure_residual(self, phi):
        """Max deviation (rad) of the fold frames from ``F_B = F_A Rot(f, gamma)`` over all joints."""
        phi = np.asarray(phi, dtype=float)
        F = self.fold_frames(phi)
        gamma = self.joint_folds(phi)
        f = joint_fold_vectors(self.scene)
        want = F[self.a] @ axis_angle_matrices(f, gamma)
        err = rotation_log(np.swapaxes(want, 1, 2) @ F[self.b])
        return float(np.linalg.norm(err, axis=1).max()) if self.m else 0.0


# the planar solver of the skeleton, now the general one (name kept for callers)
PlanarKinematics = Kinematics


def node_poses(scene, D, kin=None):
    """``(positions_mm (n,3), rotations (n,3,3), phi (n,))`` for a D field.

    Parameters
    ----------
    scene : Scene
    D : array_like
        Shape ``(n_nodes,)``.
    kin : Kinematics, optional
        A factored solver to reuse (default: a new one with the scene's stored tilts).

    Returns
    -------
    tuple of numpy.ndarray
    """
    kin = kin or Kinematics(scene)
    return kin.poses(D)


# ----------------------------------------------------------------------------------------------
# measured angles of a pose (model-independent: works on any model's rotations)
# ----------------------------------------------------------------------------------------------
def joint_angles(scene, rotations):
    """Per joint, from node rotations: signed fold (deg; angle between the plate normals, positive
    when the second node's side rises towards the first node's +z about the fold vector) and total
    hinge rotation (deg).

    Parameters
    ----------
    scene : Scene
    rotations : array_like
        Shape ``(n_nodes, 3, 3)``.

    Returns
    -------
    tuple of numpy.ndarray
        ``(fold_deg, psi_deg)``, each of shape ``(n_joints,)``.
    """
    topo = scene.topology
    R = np.asarray(rotations, dtype=float)
    a, b = topo.joint_pairs[:, 0], topo.joint_pairs[:, 1]
    na, nb = R[a][:, :, 2], R[b][:, :, 2]
    f = joint_fold_vectors(scene)
    # fold vector carried by the first node's frame (its in-plane turn is below 90 deg: sign only)
    fa = _matvec(R[a], f)
    cross = np.cross(na, nb)
    sign = np.where(np.einsum("mi,mi->m", cross, fa) < 0, -1.0, 1.0)
    fold = sign * np.degrees(np.arctan2(np.linalg.norm(cross, axis=1), np.einsum("mi,mi->m", na, nb)))
    rel = np.swapaxes(R[a], 1, 2) @ R[b]
    psi = np.degrees(np.linalg.norm(rotation_log(rel), axis=1))
    return fold, psi
