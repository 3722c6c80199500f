"""Print poses of separate prints (modules), checked on the exported triangle mesh (numpy only).

A pose prints without supports when every downward-facing triangle either lies on the bed or is a
printable overhang (at most ``max_overhang_deg`` from the vertical, i.e. its normal at most that far
below the horizontal) or belongs to a bridge: a connected downward, near-horizontal region whose
shorter side is under ``max_bridge_mm`` (the printer spans it between two walls). The check is
conservative about bridges (a region's bounding box, not its true span) and exact about overhangs.

:func:`best_pose` tries the six axis-aligned poses (each principal direction down) and keeps the one
that needs the least support, then the largest area on the bed.
"""
import math

import numpy as np

MAX_OVERHANG_DEG = 45.0
MAX_BRIDGE_MM = 10.0
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


def _anchored_both_ends(V, T, reg, verts, axis, tri_zmin, tris_of):
    """A flat downward region is a bridge when, at both ends of its short span, its edge joins a wall
    that goes down (material below the region on both sides), not a cantilever."""
    z = V[verts, 2].mean()
    regset = set(reg)
    a = V[verts, axis]
    for end in (a.min(), a.max()):
        ok = False
        for v in verts[np.abs(a - end) < 1e-3]:
            if any(k not in regset and tri_zmin[k] < z - 0.05 for k in tris_of[int(v)]):
                ok = True
                break
        if not ok:
            return False
    return True


def pose_report(V, T, max_overhang_deg=MAX_OVERHANG_DEG, max_bridge_mm=MAX_BRIDGE_MM):
    """What a mesh standing on ``z = min z`` needs: bed area, unsupported overhang area, the widest
    bridge, ``supports_free``."""
    V = np.asarray(V, dtype=float)
    z0 = V[:, 2].min()
    n, area = _normals_areas(V, T)
    zc = V[T].mean(axis=1)[:, 2] - z0
    zmax = V[T][:, :, 2].max(axis=1) - z0
    down = n[:, 2] < 0
    on_bed = down & (zmax <= BED_TOL_MM) & (n[:, 2] < -0.999)
    # overhang: normal more than max_overhang_deg below the horizontal -> needs support unless bridged
    steep = down & ~on_bed & (n[:, 2] < -math.sin(math.radians(90.0 - max_overhang_deg)) - 1e-9)
    unsupported = 0.0
    widest = 0.0
    worst_region = None
    tri_zmin = V[T][:, :, 2].min(axis=1)
    tris_of = {}
    for k, tri in enumerate(T):
        for v in tri:
            tris_of.setdefault(int(v), []).append(k)
    for reg in _regions(T, steep):
        verts = np.unique(T[reg].reshape(-1))
        pts = V[verts]
        spans = np.ptp(pts[:, :2], axis=0)
        axis = int(np.argmin(spans))
        span = float(spans[axis])
        flat = bool(np.all(n[reg, 2] < -0.999))
        a = float(area[reg].sum())
        if flat and span < max_bridge_mm and _anchored_both_ends(V, T, reg, verts, axis, tri_zmin, tris_of):
            widest = max(widest, span)
            continue
        unsupported += a
        if worst_region is None or a > worst_region[0]:
            worst_region = (a, float(zc[reg].min()), float(span))
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


def lay_out_best_poses(meshes, gap_mm=5.0):
    """Separate prints: each part in its :func:`best_pose` (pins-up, ``+z down``, wins ties), on
    ``z = 0``, side by side along x. Returns ``(meshes, {part name: report + pose})``."""
    out, reports = [], {}
    x = 0.0
    for name, V, T, mat, ext in meshes:
        pose, W, rep = best_pose(V, T, prefer="+z down")
        W = W - np.array([W[:, 0].min() - x, W[:, 1].min(), W[:, 2].min()])
        x = W[:, 0].max() + gap_mm
        out.append((name, W, T, mat, ext))
        reports[name] = dict(rep, pose=pose)
    return out, reports
