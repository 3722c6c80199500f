"""Triangle meshes for surface targets: STL (ASCII / binary) and OBJ readers, exact closest points.

``closest_points(tri, q)`` returns, for every query point, the closest point on the mesh and the
linearisation of the distance vector ``r = q - cp(q)``: ``dr = N dq`` with ``N = n n^T`` on a face,
``I - e e^T`` on an edge and ``I`` at a vertex (exact almost everywhere), which makes the surface
fit an ordinary Gauss-Newton problem (point-to-plane near a face).
"""
import os
import struct

import numpy as np
from scipy.spatial import cKDTree

from metamaterial_wb.core.errors import MetamaterialError


class TargetError(MetamaterialError):
    """A target (file or object) is invalid or cannot be reached."""

    def __init__(self, field, message):
        self.field = field
        self.message = message
        super().__init__(f"target {field}: {message}" if field else f"target: {message}")


def load_mesh(path):
    """Triangles (t, 3, 3) in mm of an STL or OBJ file."""
    ext = os.path.splitext(path)[1].lower()
    if ext == ".stl":
        tri = _read_stl(path)
    elif ext == ".obj":
        tri = _read_obj(path)
    else:
        raise TargetError("surface.file", f"{path!r}: unknown mesh type {ext!r}; allowed: .stl, .obj "
                                          f"(.step/.stp through the CLI when FreeCAD is installed)")
    return check_mesh(tri, path)


COORD_MAX_MM = 10 ** 6          # mesh coordinates within [-1e6, 1e6] mm (as target positions, targets.COORD_MAX_MM)


def check_mesh(tri, where="surface"):
    """``(t, 3, 3)`` triangles (mm): finite, within ``COORD_MAX_MM``, the degenerate ones dropped; a TargetError
    naming ``where`` otherwise."""
    try:
        tri = np.asarray(tri, dtype=float)
    except (TypeError, ValueError):
        raise TargetError("surface", f"{where}: expected triangles of three [x, y, z] points (numbers)") from None
    if tri.size % 9 or (tri.size and (tri.ndim < 2 or tri.shape[-1] not in (3, 9))):
        raise TargetError("surface", f"{where}: expected triangles of three [x, y, z] points, got an array of "
                                     f"shape {tri.shape}")
    tri = tri.reshape(-1, 3, 3)
    if tri.shape[0] == 0:
        raise TargetError("surface", f"{where}: the mesh has no triangles")
    if not np.all(np.isfinite(tri)):
        raise TargetError("surface", f"{where}: the mesh has non-finite coordinates (NaN or inf)")
    big = float(np.abs(tri).max())
    if big > COORD_MAX_MM:
        raise TargetError("surface", f"{where}: a coordinate of magnitude {big:.4g} mm is outside the allowed range "
                                     f"[-{COORD_MAX_MM:g}, {COORD_MAX_MM:g}] mm")
    area = 0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1)
    keep = area > 1e-12 * max(1.0, float(np.abs(tri).max()) ** 2)
    if not np.any(keep):
        raise TargetError("surface", f"{where}: every triangle of the mesh is degenerate (zero area)")
    return tri[keep]


def _read_stl(path):
    with open(path, "rb") as f:
        data = f.read()
    if len(data) >= 84:
        (count,) = struct.unpack("<I", data[80:84])
        if 84 + 50 * count == len(data):
            rec = np.frombuffer(data, dtype=np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")]),
                                count=count, offset=84)
            return rec["v"].astype(float)
    try:
        text = data.decode("ascii")
    except UnicodeDecodeError:
        raise TargetError("surface.file", f"{path!r} is neither a binary STL (size mismatch) nor ASCII STL") from None
    verts = [line.split()[1:4] for line in text.splitlines() if line.strip().startswith("vertex")]
    try:
        v = np.array(verts, dtype=float)
    except ValueError:
        raise TargetError("surface.file", f"{path!r}: malformed vertex line in ASCII STL") from None
    if len(v) % 3:
        raise TargetError("surface.file", f"{path!r}: {len(v)} vertices is not a multiple of 3")
    return v.reshape(-1, 3, 3)


def _read_obj(path):
    verts, faces = [], []
    with open(path, encoding="utf-8", errors="replace") as f:
        for ln, line in enumerate(f, 1):
            p = line.split()
            if not p:
                continue
            try:
                if p[0] == "v":
                    verts.append([float(x) for x in p[1:4]])
                elif p[0] == "f":
                    idx = [int(x.split("/")[0]) for x in p[1:]]
                    idx = [i - 1 if i > 0 else len(verts) + i for i in idx]
                    for k in range(1, len(idx) - 1):      # fan triangulation of polygons
                        faces.append([idx[0], idx[k], idx[k + 1]])
            except ValueError:
                raise TargetError("surface.file", f"{path}:{ln}: cannot read {line.strip()!r}") from None
    v = np.asarray(verts, dtype=float).reshape(-1, 3)
    fa = np.asarray(faces, dtype=np.int64).reshape(-1, 3)
    if fa.size and (fa.min() < 0 or fa.max() >= len(v)):
        raise TargetError("surface.file", f"{path}: a face refers to a vertex that does not exist")
    return v[fa]


def _closest_on_triangles(q, A, B, C):
    """Closest points of q (k, 3) on triangles (k, 3) each (Ericson, Real-Time Collision Detection 5.1.5).

    Returns points (k, 3) and a feature code: 0 face, 1 edge, 2 vertex; and the edge direction."""
    ab, ac, ap = B - A, C - A, q - A
    d1, d2 = np.einsum("ij,ij->i", ab, ap), np.einsum("ij,ij->i", ac, ap)
    bp = q - B
    d3, d4 = np.einsum("ij,ij->i", ab, bp), np.einsum("ij,ij->i", ac, bp)
    cp_ = q - C
    d5, d6 = np.einsum("ij,ij->i", ab, cp_), np.einsum("ij,ij->i", ac, cp_)
    va = d3 * d6 - d5 * d4
    vb = d5 * d2 - d1 * d6
    vc = d1 * d4 - d3 * d2
    k = len(q)
    out = np.empty((k, 3))
    feat = np.zeros(k, dtype=np.int8)
    edge = np.zeros((k, 3))
    done = np.zeros(k, dtype=bool)

    def put(mask, pts, f, e=None):
        mask = mask & ~done
        out[mask] = pts[mask]
        feat[mask] = f
        if e is not None:
            edge[mask] = e[mask]
        done[mask] = True

    put((d1 <= 0) & (d2 <= 0), A, 2)
    put((d3 >= 0) & (d4 <= d3), B, 2)
    put((d6 >= 0) & (d5 <= d6), C, 2)
    with np.errstate(divide="ignore", invalid="ignore"):
        v = d1 / (d1 - d3)
        put((vc <= 0) & (d1 >= 0) & (d3 <= 0), A + v[:, None] * ab, 1, ab)
        w = d2 / (d2 - d6)
        put((vb <= 0) & (d2 >= 0) & (d6 <= 0), A + w[:, None] * ac, 1, ac)
        w2 = (d4 - d3) / ((d4 - d3) + (d5 - d6))
        put((va <= 0) & ((d4 - d3) >= 0) & ((d5 - d6) >= 0), B + w2[:, None] * (C - B), 1, C - B)
        den = 1.0 / (va + vb + vc)
        vv, ww = vb * den, vc * den
    put(np.ones(k, dtype=bool), A + vv[:, None] * ab + ww[:, None] * ac, 0)
    return out, feat, edge


class Surface:
    """A triangle mesh with a closest-point query."""

    def __init__(self, tri):
        self.tri = check_mesh(tri)
        self.centroids = self.tri.mean(axis=1)
        self.normals = np.cross(self.tri[:, 1] - self.tri[:, 0], self.tri[:, 2] - self.tri[:, 0])
        self.normals /= np.linalg.norm(self.normals, axis=1)[:, None]
        self._tree = cKDTree(self.centroids)
        # a triangle's points lie within its circumradius-like bound of its centroid
        self._reach = float(np.max(np.linalg.norm(self.tri - self.centroids[:, None], axis=2)))
        self.bbox = (self.tri.reshape(-1, 3).min(axis=0), self.tri.reshape(-1, 3).max(axis=0))

    def closest(self, q):
        """``(cp (k,3), N (k,3,3))`` exact closest points and the distance-vector linearisation."""
        q = np.asarray(q, dtype=float).reshape(-1, 3)
        t = len(self.tri)
        # candidate triangles: all whose centroid is within (nearest centroid distance + 2 reach)
        d0, _ = self._tree.query(q)
        best = np.full(len(q), np.inf)
        cp = np.zeros_like(q)
        feat = np.zeros(len(q), dtype=np.int8)
        edge = np.zeros_like(q)
        tri_of = np.zeros(len(q), dtype=np.int64)
        cand = self._tree.query_ball_point(q, d0 + 2.0 * self._reach) if t > 64 else [range(t)] * len(q)
        rows = np.repeat(np.arange(len(q)), [len(c) for c in cand])
        cols = np.concatenate([np.asarray(list(c), dtype=np.int64) for c in cand])
        T = self.tri[cols]
        pts, ft, ed = _closest_on_triangles(q[rows], T[:, 0], T[:, 1], T[:, 2])
        dist = np.linalg.norm(q[rows] - pts, axis=1)
        order = np.lexsort((dist, rows))
        first = np.ones(len(order), dtype=bool)
        first[1:] = rows[order][1:] != rows[order][:-1]
        sel = order[first]
        r = rows[sel]
        best[r], cp[r], feat[r], edge[r], tri_of[r] = dist[sel], pts[sel], ft[sel], ed[sel], cols[sel]
        N = np.zeros((len(q), 3, 3))
        nf = self.normals[tri_of]
        face = feat == 0
        N[face] = np.einsum("ki,kj->kij", nf[face], nf[face])
        e = edge / np.maximum(np.linalg.norm(edge, axis=1), 1e-300)[:, None]
        ed_ = feat == 1
        N[ed_] = np.eye(3) - np.einsum("ki,kj->kij", e[ed_], e[ed_])
        N[feat == 2] = np.eye(3)
        return cp, N
