"""Structured 20-node hexahedral meshes (C3D20R) of unions of axis-aligned boxes.

Plates and hinges of the sheet are boxes, so one tensor grid whose lines pass through every box face meshes
them all conformingly: a grid cell belongs to the box that contains its centre (or to none). Nodes are
numbered on the doubled grid (corner nodes on even indices, edge mid-nodes on one odd index), so shared
faces share nodes by construction. No external mesher is needed for these shapes; :func:`graded` spaces the
grid lines finely where stresses vary (the hinge) and coarsely away from it.
"""
import numpy as np

# C3D20 node order (Abaqus / CalculiX): 8 corners, 4 bottom mid-edges, 4 top mid-edges, 4 vertical ones,
# as offsets on the doubled grid (0 = low corner, 1 = midpoint, 2 = high corner) along x, y, z
_C3D20 = np.array([
    (0, 0, 0), (2, 0, 0), (2, 2, 0), (0, 2, 0), (0, 0, 2), (2, 0, 2), (2, 2, 2), (0, 2, 2),
    (1, 0, 0), (2, 1, 0), (1, 2, 0), (0, 1, 0), (1, 0, 2), (2, 1, 2), (1, 2, 2), (0, 1, 2),
    (0, 0, 1), (2, 0, 1), (2, 2, 1), (0, 2, 1)])


def graded(a, b, h_fine, h_coarse=None, fine_at="both", growth=1.5):
    """Grid lines from ``a`` to ``b``: spacing ``h_fine`` at the fine end(s), growing geometrically by
    ``growth`` up to ``h_coarse`` (default: uniform ``h_fine``)."""
    length = b - a
    if length <= 0:
        raise ValueError(f"empty interval [{a}, {b}]")
    if h_coarse is None or h_coarse <= h_fine:
        n = max(1, int(np.ceil(length / h_fine - 1e-9)))
        return np.linspace(a, b, n + 1)
    if fine_at == "both":
        m = 0.5 * (a + b)
        left = graded(a, m, h_fine, h_coarse, "low", growth)
        right = graded(m, b, h_fine, h_coarse, "high", growth)
        return np.concatenate([left, right[1:]])
    steps = []
    h = h_fine
    while sum(steps) < length - 1e-12:
        steps.append(h)
        h = min(h * growth, h_coarse)
    steps = np.array(steps) * (length / sum(steps))
    x = a + np.concatenate([[0.0], np.cumsum(steps)])
    x[-1] = b
    return x if fine_at == "low" else (a + b) - x[::-1]


class Mesh:
    """What every structured mesh here has: ``nodes`` (N, dim) and ``elements`` (E, k), and their counts."""

    @property
    def n_nodes(self):
        return self.nodes.shape[0]

    @property
    def n_elements(self):
        return self.elements.shape[0]


class HexMesh(Mesh):
    """``nodes`` (N, 3) mm, ``elements`` (E, 20) node indices (0-based), ``part`` (E,) index of the box of
    every element."""

    def __init__(self, nodes, elements, part, lines):
        self.nodes, self.elements, self.part, self.lines = nodes, elements, part, lines


    def nodes_where(self, axis, value, tol=1e-9):
        """Indices of the nodes on the plane ``x[axis] = value``."""
        return np.flatnonzero(np.abs(self.nodes[:, axis] - value) <= tol)

    def nodes_of(self, parts):
        """Indices of the nodes of the elements of the given boxes."""
        sel = np.isin(self.part, list(parts))
        return np.unique(self.elements[sel])

    def volume(self):
        """Total volume of the cells (corner boxes), mm^3."""
        c = self.nodes[self.elements[:, [0, 6]]]
        return float(np.prod(c[:, 1] - c[:, 0], axis=1).sum())


def box_union_mesh(boxes, lines):
    """Mesh the union of ``boxes`` ``[(xmin, xmax, ymin, ymax, zmin, zmax), ...]`` on the tensor grid of the
    grid lines ``lines = (xs, ys, zs)`` (sorted; every box face must lie on a grid line)."""
    xs, ys, zs = (np.asarray(v, float) for v in lines)
    for k, (lo, hi) in enumerate([(0, 1), (2, 3), (4, 5)]):
        g = (xs, ys, zs)[k]
        for b in boxes:
            for v in (b[lo], b[hi]):
                if np.abs(g - v).min() > 1e-9:
                    raise ValueError(f"box face {v} is not on a grid line of axis {'xyz'[k]}")
    cx, cy, cz = 0.5 * (xs[1:] + xs[:-1]), 0.5 * (ys[1:] + ys[:-1]), 0.5 * (zs[1:] + zs[:-1])
    CX, CY, CZ = np.meshgrid(cx, cy, cz, indexing="ij")
    owner = -np.ones(CX.shape, dtype=np.int64)
    for k, (x0, x1, y0, y1, z0, z1) in enumerate(boxes):
        inside = (CX > x0) & (CX < x1) & (CY > y0) & (CY < y1) & (CZ > z0) & (CZ < z1) & (owner < 0)
        owner[inside] = k
    ii, jj, kk = np.nonzero(owner >= 0)
    part = owner[ii, jj, kk]
    # doubled-grid coordinates of every element node
    di = 2 * ii[:, None] + _C3D20[None, :, 0]
    dj = 2 * jj[:, None] + _C3D20[None, :, 1]
    dk = 2 * kk[:, None] + _C3D20[None, :, 2]
    ny2, nz2 = 2 * len(ys) - 1, 2 * len(zs) - 1
    key = (di * ny2 + dj) * nz2 + dk
    uniq, inv = np.unique(key.ravel(), return_inverse=True)
    elements = inv.reshape(key.shape)
    ui, rem = np.divmod(uniq, ny2 * nz2)
    uj, uk = np.divmod(rem, nz2)

    def coord(g, d):
        lo = g[d // 2]
        hi = g[np.minimum(d // 2 + 1, len(g) - 1)]
        return np.where(d % 2 == 0, lo, 0.5 * (lo + hi))

    nodes = np.column_stack([coord(xs, ui), coord(ys, uj), coord(zs, uk)])
    return HexMesh(nodes, elements, part, (xs, ys, zs))
