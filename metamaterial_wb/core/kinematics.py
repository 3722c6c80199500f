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
  graph-Laplacian least-squares solve per bending direction group (``theta_B - theta_A = gamma`` on
  tilted joints, 0 elsewhere), positions from the least-squares hinge closure

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

OPENING_LIMIT_RAD = math.pi / 4       # widest pitch of the rotating-squares mechanism
MAX_TILT_DEG = 80.0                   # the scene format's tilt range (fabrication limit)
DEFAULT_HINGE_STRAIN_LIMIT = 0.5      # peak bending strain of a TPU hinge (scene.material.hinge_strain_limit)
_TILT_EPS = 1e-12


# ----------------------------------------------------------------------------------------------
# per-joint data
# ----------------------------------------------------------------------------------------------
def plate_side_mm(scene):
    return scene.cell_size_mm - scene.hinge["length_mm"]


def hinge_strain_limit(scene):
    v = scene.material.get("hinge_strain_limit", DEFAULT_HINGE_STRAIN_LIMIT) if scene.material else \
        DEFAULT_HINGE_STRAIN_LIMIT
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not (0 < v <= 5):
        raise SceneError("material.hinge_strain_limit", f"{v!r} is outside the allowed range (0, 5]")
    return float(v)


def joint_hinge_arrays(scene):
    """Per joint ``(length_mm, width_mm, thickness_mm)`` arrays with per-joint overrides applied."""
    m = scene.topology.n_joints
    lh = np.full(m, float(scene.hinge["length_mm"]))
    wh = np.full(m, float(scene.hinge["width_mm"]))
    th = np.full(m, float(scene.hinge["thickness_mm"]))
    for name, ov in scene.joint_overrides.items():
        if not any(k in ov for k in ("length_mm", "width_mm", "thickness_mm")):
            continue
        k = _joint_index(scene, name)
        lh[k] = ov.get("length_mm", lh[k])
        wh[k] = ov.get("width_mm", wh[k])
        th[k] = ov.get("thickness_mm", th[k])
    return lh, wh, th


def _joint_index(scene, name):
    from metamaterial_wb.core.scene import parse_joint
    kind, i, j = parse_joint(name)
    return scene.topology.joint_id(kind, i, j)


def joint_tilts_rad(scene):
    """Signed hinge tilt of every joint (radians): overrides, else joint_config, else computed from
    the scene's axes when it has axes but no joint_config (without changing the scene)."""
    from metamaterial_wb.core import design
    return np.radians(design.effective_tilts_deg(scene))


def joint_parity(scene):
    """+1 where the first node of the joint has even i+j, else -1."""
    ij = scene.topology.joint_ij()
    return np.where((ij[:, 0] + ij[:, 1]) % 2 == 0, 1.0, -1.0)


def joint_fold_vectors(scene):
    """Fold vector ``f = u x z`` of every joint (flat frame): -y for H joints, -x for V joints."""
    topo = scene.topology
    f = np.zeros((topo.n_joints, 3))
    f[:topo.n_h, 1] = -1.0
    f[topo.n_h:, 0] = -1.0
    return f


# ----------------------------------------------------------------------------------------------
# the tilted hinge (closed forms)
# ----------------------------------------------------------------------------------------------
def fold_from_tilt(tilt_rad, phi_a_rad):
    """Fold (rad) of a joint with tilt ``alpha`` when its first node turns in plane by ``phi_A``
    and its second by ``-phi_A``: ``tan(gamma/2) = -tan(alpha) sin(phi_A)`` (exact)."""
    return -2.0 * np.arctan(np.tan(tilt_rad) * np.sin(phi_a_rad))


def tilt_for_fold(fold_rad, phi_a_rad):
    """Inverse of :func:`fold_from_tilt`: the tilt that gives ``fold`` at ``phi_A`` (phi_A != 0)."""
    return np.arctan(-np.tan(0.5 * np.asarray(fold_rad)) / np.sin(phi_a_rad))


def hinge_rotation(fold_rad, phi_rad):
    """Total rotation ``psi`` of a hinge: ``cos(psi/2) = cos(gamma/2) cos(phi)``."""
    c = np.cos(0.5 * np.asarray(fold_rad)) * np.cos(phi_rad)
    return 2.0 * np.arccos(np.clip(c, -1.0, 1.0))


def hinge_strain(psi_rad, width_mm, length_mm):
    """Peak bending strain of a flexure of in-plane width ``w`` bent by ``psi`` over length ``lh``
    (uniform curvature): ``w psi / (2 lh)``. For a tilted hinge the flexure wall turns with its axis,
    so the same width bends (docs/kinematics.md)."""
    return np.asarray(width_mm) * np.asarray(psi_rad) / (2.0 * np.asarray(length_mm))


def fold_contact_rad(length_mm, thickness_mm):
    """Fold at which the plates (thickness t, hinge at mid-thickness, gap lh) meet across a bending
    joint: ``2 atan(lh / t)``."""
    return 2.0 * np.arctan(np.asarray(length_mm) / np.asarray(thickness_mm))


def _phi_limit_strain(tilt, wh, lh, eps):
    """Largest in-plane rotation whose hinge strain stays <= eps for hinges of tilt ``tilt``."""
    psi_max = 2.0 * lh * eps / wh
    c = np.cos(0.5 * np.minimum(psi_max, math.pi))
    t2 = np.tan(tilt) ** 2
    s2 = (1.0 - c * c) / (1.0 + c * c * t2)
    out = np.arcsin(np.sqrt(np.clip(s2, 0.0, 1.0)))
    return np.where(psi_max >= math.pi, math.pi / 2, out)


def _phi_limit_fold_contact(tilt, lh, th):
    """Largest in-plane rotation before the fold of a tilted joint reaches plate contact."""
    t = np.abs(np.tan(tilt))
    with np.errstate(divide="ignore"):
        s = np.where(t > _TILT_EPS, (lh / th) / np.maximum(t, _TILT_EPS), np.inf)
    return np.where(s >= 1.0, math.pi / 2, np.arcsin(np.minimum(s, 1.0)))


# ----------------------------------------------------------------------------------------------
# rotation limits
# ----------------------------------------------------------------------------------------------
def rotation_limit_info(scene, tilts_rad=None):
    """The node rotation at D = +1 (closing) and D = -1 (opening), with what binds.

    Closing: plate contact ``asin(lh / 2s)``, hinge strain (every joint, its own sizes and tilt),
    fold contact of tilted joints. Opening: the mechanism's 45 degrees, hinge strain, fold contact.
    One limit for the whole sheet (the smallest), so that uniform D is the exact mechanism.
    """
    lh, wh, th = joint_hinge_arrays(scene)
    tilt = joint_tilts_rad(scene) if tilts_rad is None else np.asarray(tilts_rad, dtype=float)
    eps = hinge_strain_limit(scene)
    s = plate_side_mm(scene)
    lh0 = scene.hinge["length_mm"]
    contact = math.asin(min(1.0, lh0 / (2.0 * s)))
    strain = _phi_limit_strain(tilt, wh, lh, eps) if len(lh) else np.array([math.pi / 2])
    fold = _phi_limit_fold_contact(tilt, lh, th) if len(lh) else np.array([math.pi / 2])

    def jname(k):
        topo = scene.topology
        i, j = topo.joint_ij()[k]
        return f"{'H' if k < topo.n_h else 'V'}{int(i)},{int(j)}"

    def pick(cands):
        label, val = min(cands, key=lambda c: c[1])
        return val, label

    ks, kf = int(np.argmin(strain)), int(np.argmin(fold))
    closing, closing_by = pick([
        (f"plate contact asin(lh/2s) = asin({lh0:g}/(2*{s:g}))", contact),
        (f"hinge strain {eps:g} at joint {jname(ks)}", float(strain[ks])),
        (f"fold contact 2 atan(lh/t) of tilted joint {jname(kf)}", float(fold[kf]))])
    opening, opening_by = pick([
        ("mechanism (45 deg, widest pitch)", OPENING_LIMIT_RAD),
        (f"hinge strain {eps:g} at joint {jname(ks)}", float(strain[ks])),
        (f"fold contact 2 atan(lh/t) of tilted joint {jname(kf)}", float(fold[kf]))])
    return {"closing_rad": float(closing), "opening_rad": float(opening),
            "closing_deg": math.degrees(closing), "opening_deg": math.degrees(opening),
            "closing_binding": closing_by, "opening_binding": opening_by,
            "plate_contact_deg": math.degrees(contact), "hinge_strain_limit": eps}


def rotation_limits(scene, tilts_rad=None):
    """``(closing_rad, opening_rad)``: the node rotation at D = +1 and D = -1 (magnitudes)."""
    info = rotation_limit_info(scene, tilts_rad)
    return info["closing_rad"], info["opening_rad"]


def node_parity(scene):
    ij = scene.topology.node_ij()
    return np.where((ij[:, 0] + ij[:, 1]) % 2 == 0, 1.0, -1.0)


def node_angles(scene, D, limits=None):
    """In-plane rotation (radians, counter-clockwise positive) of every node for a D field."""
    D = np.asarray(D, dtype=float)
    n = scene.topology.n_nodes
    if D.shape != (n,):
        raise SceneError("D", f"expected {n} values (one per node), got shape {D.shape}")
    bad = ~np.isfinite(D) | (np.abs(D) > 1 + 1e-12)
    if np.any(bad):
        k = int(np.flatnonzero(bad)[0])
        i, j = scene.topology.node_ij()[k]
        raise SceneError("D", f"node N{i},{j} has D = {D[k]!r}, outside the allowed range [-1, 1]")
    closing, opening = limits if limits is not None else rotation_limits(scene)
    mag = np.where(D >= 0, closing, opening)
    return node_parity(scene) * D * mag


def uniform_pitch_mm(scene, D, limits=None):
    """Closed-form node pitch for a uniform D (rotating squares with finite hinges)."""
    lh = scene.hinge["length_mm"]
    s = plate_side_mm(scene)
    closing, opening = limits if limits is not None else rotation_limits(scene)
    if D >= 0:
        phi = D * closing
        return lh + s * (math.cos(phi) - math.sin(phi))
    phi = -D * opening
    return lh + s * (math.cos(phi) + math.sin(phi))


def uniform_fold_deg(tilt_deg, phi_a_deg):
    """Fold of one joint for uniform deformation (degrees), see :func:`fold_from_tilt`."""
    return float(np.degrees(fold_from_tilt(math.radians(tilt_deg), math.radians(phi_a_deg))))


# ----------------------------------------------------------------------------------------------
# rotations (vectorised)
# ----------------------------------------------------------------------------------------------
def rotation_matrices(phi):
    """(n, 3, 3) rotations about z."""
    phi = np.asarray(phi, dtype=float)
    c, s = np.cos(phi), np.sin(phi)
    R = np.zeros((phi.size, 3, 3))
    R[:, 0, 0] = c
    R[:, 0, 1] = -s
    R[:, 1, 0] = s
    R[:, 1, 1] = c
    R[:, 2, 2] = 1.0
    return R


def axis_angle_matrices(axis, angle):
    """Rodrigues: (m, 3, 3) rotations about unit ``axis`` (m, 3) or (3,) by ``angle`` (m,)."""
    angle = np.asarray(angle, dtype=float).reshape(-1)
    axis = np.broadcast_to(np.asarray(axis, dtype=float), (angle.size, 3))
    x, y, z = axis[:, 0], axis[:, 1], axis[:, 2]
    c, s = np.cos(angle), np.sin(angle)
    C = 1.0 - c
    R = np.empty((angle.size, 3, 3))
    R[:, 0, 0] = c + x * x * C
    R[:, 0, 1] = x * y * C - z * s
    R[:, 0, 2] = x * z * C + y * s
    R[:, 1, 0] = y * x * C + z * s
    R[:, 1, 1] = c + y * y * C
    R[:, 1, 2] = y * z * C - x * s
    R[:, 2, 0] = z * x * C - y * s
    R[:, 2, 1] = z * y * C + x * s
    R[:, 2, 2] = c + z * z * C
    return R


def rotation_log(R):
    """Rotation vectors (m, 3) of rotations (m, 3, 3) with angles below pi."""
    tr = np.einsum("mii->m", R)
    ang = np.arccos(np.clip(0.5 * (tr - 1.0), -1.0, 1.0))
    v = 0.5 * np.column_stack([R[:, 2, 1] - R[:, 1, 2], R[:, 0, 2] - R[:, 2, 0], R[:, 1, 0] - R[:, 0, 1]])
    s = np.sin(ang)
    small = s < 1e-8
    fac = np.where(small, 1.0 + ang * ang / 6.0, ang / np.where(small, 1.0, s))
    return v * fac[:, None]


def rotation_exp(w):
    """Rotations (m, 3, 3) from rotation vectors (m, 3)."""
    w = np.asarray(w, dtype=float).reshape(-1, 3)
    ang = np.linalg.norm(w, axis=1)
    axis = np.where(ang[:, None] > 1e-15, w / np.where(ang > 1e-15, ang, 1.0)[:, None], [0.0, 0.0, 1.0])
    return axis_angle_matrices(axis, ang)


def _matvec(R, v):
    return np.einsum("mij,mj->mi", R, v)


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
    ij = scene.topology.node_ij().astype(float)
    p = scene.cell_size_mm
    return np.column_stack([ij[:, 1] * p, -ij[:, 0] * p, np.zeros(len(ij))])


# ----------------------------------------------------------------------------------------------
# the factored kinematics
# ----------------------------------------------------------------------------------------------
class Kinematics:
    """Factored pose solver for one scene topology and joint configuration (reuse across frames).

    ``poses(D) -> (positions_mm (n,3), rotations (n,3,3), phi (n,))``. Build cost: one sparse LU of
    the node graph Laplacian; per frame: a few vectorised passes and one multi-right-hand-side
    back-substitution.
    """

    def __init__(self, scene, tilts_rad=None):
        from scipy.sparse.csgraph import shortest_path

        self.scene = scene
        topo = scene.topology
        self.n = n = topo.n_nodes
        self.m = m = topo.n_joints
        self.a, self.b, self.ra, self.rb, self.d0 = _hinge_geometry(scene)
        self.tilt = joint_tilts_rad(scene) if tilts_rad is None else np.asarray(tilts_rad, dtype=float)
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
        # bending lines: tilted H joints group by column (vertical lines), tilted V joints by row
        tilted = np.flatnonzero(np.abs(self.tilt) > _TILT_EPS)
        self.tilted = tilted
        self.groups = []       # list of (fold vector (3,), joint indices) in composition order
        if tilted.size:
            ij = topo.joint_ij()
            isH = tilted < topo.n_h
            keys = {}
            for k, h in zip(tilted.tolist(), isH.tolist()):
                key = ("vertical", int(ij[k, 1])) if h else ("horizontal", int(ij[k, 0]))
                keys.setdefault(key, []).append(k)
            adj = sp.coo_matrix((np.ones(m), (self.a, self.b)), shape=(n, n)).tocsr()
            dist = shortest_path(adj, indices=0, unweighted=True, directed=False)
            depth = {key: float(np.min(np.minimum(dist[self.a[js]], dist[self.b[js]])))
                     for key, js in keys.items()}
            order = sorted(keys, key=lambda k: (depth[k], k))
            for key in order:      # merge consecutive lines of the same direction (they commute)
                f = np.array([0.0, -1.0, 0.0]) if key[0] == "vertical" else np.array([-1.0, 0.0, 0.0])
                if self.groups and self.groups[-1][0] == key[0]:
                    self.groups[-1][2].extend(keys[key])
                else:
                    self.groups.append((key[0], f, list(keys[key])))
            self.groups = [(d, f, np.array(js, dtype=np.int64)) for d, f, js in self.groups]
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
    """``(positions_mm (n,3), rotations (n,3,3), phi (n,))`` for a D field."""
    kin = kin or Kinematics(scene)
    return kin.poses(D)


# ----------------------------------------------------------------------------------------------
# measured angles of a pose (model-independent: works on any model's rotations)
# ----------------------------------------------------------------------------------------------
def joint_angles(scene, rotations):
    """Per joint, from node rotations: signed fold (deg; angle between the plate normals, positive
    when the second node's side rises towards the first node's +z about the fold vector) and total
    hinge rotation (deg)."""
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
