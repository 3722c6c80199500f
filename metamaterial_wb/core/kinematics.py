"""Kinematics of the rotating-squares sheet with long hinges: D field -> node poses.

Geometry (docs/kinematics.md): node ``N(i,j)`` is a square plate of side ``s = cell_size - lh``
whose centre sits at ``x = j * cell_size``, ``y = -i * cell_size`` in the flat state (rows grow
downwards, z is the sheet normal). A hinge of length ``lh`` joins two corners of neighbouring plates
along the edge line. Corners alternate in a checkerboard so that every plate uses four distinct
corners:

* ``H(i,j)``: top corners if i+j is even, bottom corners if odd;
* ``V(i,j)``: right corners if i+j is even, left corners if odd.

With this connectivity a node with even i+j turning counter-clockwise (D = +1, the seed's sign
rule) *closes* the cells. Node rotation: ``phi = (-1)^(i+j) * D * phi_max(sign D)`` with
``phi_max(+) = closing limit`` (plate contact, ``asin(lh / 2s)``) and ``phi_max(-) = opening limit``
(45 degrees, where the mechanism reaches its widest pitch).

Positions: exact for uniform D (pitch ``P = lh + s (cos phi - sin phi)`` when closing,
``lh + s (cos phi + sin phi)`` when opening); for non-uniform D a sparse least-squares hinge
closure (one graph-Laplacian solve, factored once per topology).
"""
import math

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from metamaterial_wb.core.errors import SceneError

OPENING_LIMIT_RAD = math.pi / 4


def plate_side_mm(scene):
    return scene.cell_size_mm - scene.hinge["length_mm"]


def rotation_limits(scene):
    """``(closing_rad, opening_rad)``: the node rotation at D = +1 and D = -1 (magnitudes)."""
    lh = scene.hinge["length_mm"]
    s = plate_side_mm(scene)
    closing = math.asin(min(1.0, lh / (2.0 * s)))
    return closing, OPENING_LIMIT_RAD


def node_angles(scene, D):
    """In-plane rotation (radians, counter-clockwise positive) of every node for a D field."""
    D = np.asarray(D, dtype=float)
    if np.any(~np.isfinite(D)) or np.any(np.abs(D) > 1 + 1e-12):
        bad = int(np.flatnonzero(~np.isfinite(D) | (np.abs(D) > 1 + 1e-12))[0])
        raise SceneError("D", f"node {scene.topology.nodes[bad]} has D = {D[bad]!r}, outside [-1, 1]")
    closing, opening = rotation_limits(scene)
    ij = scene.topology.node_ij()
    parity = np.where((ij[:, 0] + ij[:, 1]) % 2 == 0, 1.0, -1.0)
    mag = np.where(D >= 0, closing, opening)
    return parity * D * mag


def uniform_pitch_mm(scene, D):
    """Closed-form node pitch for a uniform D (rotating squares with finite hinges)."""
    lh = scene.hinge["length_mm"]
    s = plate_side_mm(scene)
    closing, opening = rotation_limits(scene)
    if D >= 0:
        phi = D * closing
        return lh + s * (math.cos(phi) - math.sin(phi))
    phi = -D * opening
    return lh + s * (math.cos(phi) + math.sin(phi))


def _hinge_geometry(scene):
    """Per joint: node indices (a, b), corner offsets r_a, r_b (flat, plate frame) and d0 (chord)."""
    topo = scene.topology
    a_half = 0.5 * plate_side_mm(scene)
    lh = scene.hinge["length_mm"]
    n = topo.n_joints
    ra = np.zeros((n, 2))
    rb = np.zeros((n, 2))
    d0 = np.zeros((n, 2))
    for k, (kind, i, j) in enumerate(topo.joints):
        even = (i + j) % 2 == 0
        if kind == "H":
            y = a_half if even else -a_half
            ra[k] = (a_half, y)
            rb[k] = (-a_half, y)
            d0[k] = (lh, 0.0)
        else:
            x = a_half if even else -a_half
            ra[k] = (x, -a_half)
            rb[k] = (x, a_half)
            d0[k] = (0.0, -lh)
    return topo.joint_pairs[:, 0], topo.joint_pairs[:, 1], ra, rb, d0


def flat_positions_mm(scene):
    ij = scene.topology.node_ij().astype(float)
    p = scene.cell_size_mm
    return np.column_stack([ij[:, 1] * p, -ij[:, 0] * p, np.zeros(len(ij))])


def _rot(phi, v):
    c, s = np.cos(phi), np.sin(phi)
    return np.column_stack([c * v[:, 0] - s * v[:, 1], s * v[:, 0] + c * v[:, 1]])


class PlanarKinematics:
    """Factored hinge-closure solver for one scene topology (reuse it across frames)."""

    def __init__(self, scene):
        self.scene = scene
        topo = scene.topology
        self.a, self.b, self.ra, self.rb, self.d0 = _hinge_geometry(scene)
        n = topo.n_nodes
        m = topo.n_joints
        inc = sp.csr_matrix((np.concatenate([-np.ones(m), np.ones(m)]),
                             (np.concatenate([np.arange(m), np.arange(m)]), np.concatenate([self.a, self.b]))),
                            shape=(m, n))
        self.inc = inc
        L = (inc.T @ inc).tocsc()
        self.flat = flat_positions_mm(scene)
        self.n = n
        if n > 1:
            self._lu = spla.splu(L[1:, 1:].tocsc(), permc_spec="MMD_AT_PLUS_A")
        else:
            self._lu = None

    def positions(self, phi):
        """Node centres (n, 3) in mm for in-plane node rotations ``phi`` (radians)."""
        phi = np.asarray(phi, dtype=float)
        a, b = self.a, self.b
        mean = 0.5 * (phi[a] + phi[b])
        e = _rot(mean, self.d0) - _rot(phi[b], self.rb) + _rot(phi[a], self.ra)
        xy = np.zeros((self.n, 2))
        if self._lu is not None:
            rhs = (self.inc.T @ e)[1:]
            xy[1:] = self._lu.solve(np.ascontiguousarray(rhs))
        # keep the centroid where the flat sheet's centroid is
        xy += self.flat[:, :2].mean(axis=0) - xy.mean(axis=0)
        return np.column_stack([xy, np.zeros(self.n)])

    def closure_residual(self, phi, pos):
        """Max hinge-closure error (mm) of positions ``pos`` for rotations ``phi``."""
        a, b = self.a, self.b
        mean = 0.5 * (phi[a] + phi[b])
        e = _rot(mean, self.d0) - _rot(phi[b], self.rb) + _rot(phi[a], self.ra)
        r = pos[b, :2] - pos[a, :2] - e
        return float(np.abs(r).max()) if len(r) else 0.0


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


def node_poses(scene, D, kin=None):
    """``(positions_mm (n,3), rotations (n,3,3), phi (n,))`` for a D field."""
    phi = node_angles(scene, D)
    kin = kin or PlanarKinematics(scene)
    pos = kin.positions(phi)
    return pos, rotation_matrices(phi), phi
