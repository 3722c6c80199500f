"""Print poses of separate prints (modules), checked on the exported triangle mesh (numpy only).

A pose prints without supports when every downward-facing triangle either lies on the bed or is a
printable overhang (at most ``max_overhang_deg`` from the vertical, i.e. its normal at most that far
below the horizontal) or belongs to a bridge: a connected downward, near-horizontal region whose
span between two walls (material below it just beyond both ends, along x or y) is under
``max_bridge_mm``. The check is
conservative about bridges (a region's bounding box, not its true span) and exact about overhangs.
One allowance: a flat downward ledge at most ``MAX_LEDGE_MM`` wide (its width taken as
``2 area / perimeter``: exact for strips and rings, such as a snap pin's barb) prints as overhanging
perimeters and needs no support.

:func:`best_pose` tries the six axis-aligned poses (each principal direction down) and keeps the one
that needs the least support, then the largest area on the bed.
"""
import math

import numpy as np

MAX_OVERHANG_DEG = 45.0
MAX_BRIDGE_MM = 10.0
MAX_LEDGE_MM = 0.8       # a flat downward ledge this narrow (two nozzle widths) prints as overhanging perimeters
BED_TOL_MM = 1e-3


def _normals_areas(V, T):
    a, b, c = V[T[:, 0]], V[T[:, 1]], V[T[:, 2]]
    n = np.cross(b - a, c - a)
    area2 = np.linalg.norm(n, axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        unit = n / np.where(area2 > 0, area2, 1.0)[:, None]
    return unit, 0.5 * area2


def _regions(T, mask):
    """Connected components (sharing a vertex) of the triangles where ``mask`` is true."""
    idx = np.flatnonzero(mask)
    parent = {int(k): int(k) for k in idx}

    def find(x):
        while parent[x] != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x

    by_vertex = {}
    for k in idx:
        for v in T[k]:
            by_vertex.setdefault(int(v), []).append(int(k))
    for tris in by_vertex.values():
        r0 = find(tris[0])
        for t in tris[1:]:
            r = find(t)
            if r != r0:
                parent[r] = r0
    out = {}
    for k in idx:
        out.setdefault(find(int(k)), []).append(int(k))
    return list(out.values())


def _perimeter(V, tris):
    """Length of the boundary of a triangle set (edges used by one of its triangles only)."""
    e = np.sort(np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [2, 0]]]), axis=1)
    uniq, count = np.unique(e, axis=0, return_counts=True)
    b = uniq[count == 1]
    return float(np.linalg.norm(V[b[:, 0]] - V[b[:, 1]], axis=1).sum())


def inside(V, T, points):
    """Point-in-solid test for a closed mesh (ray parity, Moller-Trumbore along a generic direction)."""
    d = np.array([0.5773, 0.5774, 0.5775])
    d /= np.linalg.norm(d)
    a, b, c = V[T[:, 0]], V[T[:, 1]], V[T[:, 2]]
    e1, e2 = b - a, c - a
    h = np.cross(d, e2)
    det = np.einsum("ij,ij->i", e1, h)
    ok = np.abs(det) > 1e-12
    inv = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)
    out = []
    for p in np.atleast_2d(points):
        s_ = p - a
        u = np.einsum("ij,ij->i", s_, h) * inv
        q = np.cross(s_, e1)
        v = (q @ d) * inv
        t = np.einsum("ij,ij->i", e2, q) * inv
        hit = ok & (u >= 0) & (v >= 0) & (u + v <= 1) & (t > 1e-9)
        out.append(int(hit.sum()) % 2 == 1)
    return np.array(out)


def _bridge_span(V, T, verts, max_bridge_mm):
    """Span (mm) of a flat downward region bridged between two walls (material below it just beyond
    both ends along x or along y, checked at three points per end), or None when it is not a bridge."""
    P = V[verts]
    z = P[:, 2].mean() - 0.3
    lo, hi = P[:, :2].min(axis=0), P[:, :2].max(axis=0)
    best = None
    for ax in (0, 1):
        span = float(hi[ax] - lo[ax])
        if span >= max_bridge_mm:
            continue
        other = 1 - ax
        pts = []
        for end, off in ((lo[ax], -0.3), (hi[ax], 0.3)):
            for f in (0.25, 0.5, 0.75):
                q = np.zeros(3)
                q[ax] = end + off
                q[other] = lo[other] + f * (hi[other] - lo[other])
                q[2] = z
                pts.append(q)
        if np.all(inside(V, T, np.array(pts))):
            best = span if best is None else min(best, span)
    return best


def pose_report(V, T, max_overhang_deg=MAX_OVERHANG_DEG, max_bridge_mm=MAX_BRIDGE_MM):
    """What a mesh standing on ``z = min z`` needs: bed area, unsupported overhang area, the widest
    bridge, ``supports_free``."""
    V = np.asarray(V, dtype=float)
    z0 = V[:, 2].min()
    n, area = _normals_areas(V, T)
    zmax = V[T][:, :, 2].max(axis=1) - z0
    down = n[:, 2] < 0
    on_bed = down & (zmax <= BED_TOL_MM) & (n[:, 2] < -0.999)
    # overhang: normal more than max_overhang_deg below the horizontal -> needs support unless bridged
    steep = down & ~on_bed & (n[:, 2] < -math.sin(math.radians(90.0 - max_overhang_deg)) - 1e-9)
    unsupported = 0.0
    widest = 0.0
    for reg in _regions(T, steep):
        verts = np.unique(T[reg].reshape(-1))
        flat = bool(np.all(n[reg, 2] < -0.999))
        a = float(area[reg].sum())
        span = _bridge_span(V, T, verts, max_bridge_mm) if flat else None
        if span is not None:
            widest = max(widest, span)
            continue
        if flat and 2.0 * a / max(_perimeter(V, T[reg]), 1e-12) <= MAX_LEDGE_MM:
            continue
        unsupported += a

    return {"bed_area_mm2": round(float(area[on_bed].sum()), 3),
            "unsupported_area_mm2": round(unsupported, 3),
            "widest_bridge_mm": round(widest, 3),
            "height_mm": round(float(np.ptp(V[:, 2])), 3),
            "supports_free": unsupported <= 1e-6 and bool(on_bed.any()),
            "max_overhang_deg": max_overhang_deg, "max_bridge_mm": max_bridge_mm}


_ROTATIONS = [np.eye(3), np.diag([1.0, -1.0, -1.0]),
              np.array([[0.0, 0.0, -1.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]]),
              np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]]),
              np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]]),
              np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]])]


def _pose_name(R):
    d = R.T @ np.array([0.0, 0.0, -1.0])          # the module direction that points down
    k = int(np.argmax(np.abs(d)))
    return f"{'+' if d[k] > 0 else '-'}{'xyz'[k]} down"


# name ("+z down": the module's +z, its top, on the bed) -> rotation module frame -> print frame (det +1)
POSES = {_pose_name(R): R for R in _ROTATIONS}


def best_pose(V, T, prefer=None):
    """``(pose name, rotated V, report)`` of the axis-aligned pose that needs the least support, then
    has the most bed area; ``prefer`` (a pose name) wins ties."""
    best = None
    for name, R in POSES.items():
        W = np.asarray(V, dtype=float) @ R.T
        rep = pose_report(W, T)
        score = (rep["unsupported_area_mm2"], -rep["bed_area_mm2"], 0 if name == prefer else 1)
        if best is None or score < best[0]:
            best = (score, name, W, rep)
    return best[1], best[2], best[3]


def forced_poses(parts):
    """``{part name: pose}`` of the parts whose info names the pose they must print in (a rivet pin lies
    on its flat so that its prongs bend along the layers: geometry/rivet.py)."""
    return {q.name: q.info["print_pose"] for q in parts if q.info.get("print_pose")}


def lay_out_best_poses(meshes, gap_mm=5.0, forced=None):
    """Separate prints: each part in its :func:`best_pose` (pins-up, ``+z down``, wins ties) or the pose
    ``forced`` names for it (:func:`forced_poses`), on ``z = 0``, side by side along x. Returns
    ``(meshes, {part name: report + pose})``."""
    out, reports = [], {}
    x = 0.0
    forced = forced or {}
    for name, V, T, mat, ext in meshes:
        if name in forced:
            pose = forced[name]
            W = np.asarray(V, dtype=float) @ POSES[pose].T
            W = W - np.array([0.0, 0.0, W[:, 2].min()])
            rep = pose_report(W, T)
        else:
            pose, W, rep = best_pose(V, T, prefer="+z down")
        W = W - np.array([W[:, 0].min() - x, W[:, 1].min(), W[:, 2].min()])
        x = W[:, 0].max() + gap_mm
        out.append((name, W, T, mat, ext))
        reports[name] = dict(rep, pose=pose)
    return out, reports
