"""Tessellate built parts for the 3MF writer: each unique shape once, copies by transforming vertices."""
import numpy as np

from metamaterial_wb.core.errors import MetamaterialError


def weld(points, triangles, grid_mm=1e-5):
    """Merge coincident vertices (OCC repeats them along face boundaries) and drop degenerate triangles."""
    P = np.asarray(points, dtype=float)
    T = np.asarray(triangles, dtype=np.int64)
    q = np.round(P / grid_mm).astype(np.int64)
    uniq, inv = np.unique(q, axis=0, return_inverse=True)
    inv = inv.reshape(-1)
    P2 = np.zeros((len(uniq), 3))
    P2[inv] = P
    T2 = inv[T]
    ok = (T2[:, 0] != T2[:, 1]) & (T2[:, 1] != T2[:, 2]) & (T2[:, 0] != T2[:, 2])
    return P2, T2[ok]


def signed_volume(P, T):
    a, b, c = P[T[:, 0]], P[T[:, 1]], P[T[:, 2]]
    return float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6.0)


def open_edges(T):
    """Number of directed edges without their opposite (0 for a closed, consistently oriented mesh)."""
    e = np.concatenate([T[:, [0, 1]], T[:, [1, 2]], T[:, [2, 0]]])
    fwd = set(map(tuple, e.tolist()))
    return sum(1 for (u, v) in fwd if (v, u) not in fwd) + (len(e) - len(fwd))


def tessellate(shape, tolerance_mm=0.05, name="shape"):
    """``(vertices, triangles)`` of a closed solid, welded, outward-oriented.

    MeshPart with an explicit angular deflection (0.5 rad) is deterministic; ``Shape.tessellate``
    reuses whatever finer triangulation an earlier call left on the shape.
    """
    import MeshPart

    mesh = MeshPart.meshFromShape(Shape=shape, LinearDeflection=tolerance_mm, AngularDeflection=0.5,
                                  Relative=False)
    pts, tris = mesh.Topology
    P = np.array([(p.x, p.y, p.z) for p in pts], dtype=float)
    T = np.array(tris, dtype=np.int64).reshape(-1, 3)
    P, T = weld(P, T)
    if len(T) == 0:
        raise MetamaterialError(f"{name}: tessellation produced no triangles")
    vol = signed_volume(P, T)
    if vol < 0:
        T = T[:, ::-1].copy()
    return P, T


def transform(P, M):
    """Apply a 4x4 matrix to (n, 3) points."""
    return P @ M[:3, :3].T + M[:3, 3]


def part_meshes(result, parts, tolerance_mm=None):
    """``[(name, V, T, material, extruder)]`` for ``parts`` of a BuildResult (unique shapes tessellated once)."""
    from metamaterial_wb.geometry.fc import matrix4

    tol = tolerance_mm or result.params.tolerance_mm
    cache = {}
    out = []
    for part in parts:
        if part.key not in cache:
            cache[part.key] = tessellate(result.shapes[part.key], tol, part.name)
        P, T = cache[part.key]
        out.append((part.name, transform(P, matrix4(part.placement)), T, part.material, part.extruder))
    return out


def lay_out_for_print(meshes, flip=True, gap_mm=5.0):
    """Separate prints (modules): turn each part upside down (``flip``: 180 deg about x, so that the
    snap pins point up and the flat top lies on the bed), put it on z = 0 and line the parts up along x
    with ``gap_mm`` between them. ``meshes``: ``[(name, V, T, material, extruder)]``; returns a new list."""
    out = []
    x = 0.0
    for name, V, T, mat, ext in meshes:
        W = V.copy()
        if flip:
            W[:, 1] = -W[:, 1]
            W[:, 2] = -W[:, 2]          # rotation by 180 deg about x keeps the orientation of the triangles
        W -= np.array([W[:, 0].min() - x, W[:, 1].min(), W[:, 2].min()])
        x = W[:, 0].max() + gap_mm
        out.append((name, W, T, mat, ext))
    return out
