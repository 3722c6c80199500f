"""The sleeve's unit cell and an N-cell ring in CalculiX: 2-D plane strain, 8-node quadrilaterals (CPE8R).

The solid is the printed outline of ``core.sleeve.cell.CellGeometry`` (single layout): bottom bar, central
pillar, the cosine beam (thickness ``t`` measured along its normal, as ``beam_surface`` and the B-rep draw
it), the edge pillar shared with the neighbour and the top bar. It is meshed here, without an external
mesher, as nine mapped blocks per half cell (transfinite interpolation; the beam blocks follow the exact
normal-offset surfaces, mid-side nodes included), mirrored about the cell's centre, so the left and right
cell edges carry identical node heights and the periodic ties are node to node. Refinement ``r`` multiplies
every block's element counts (``r`` elements through the beam's thickness), so ``r = 1, 2, 4`` are nested
meshes with element size ratio 2 (Richardson).

Material: incompressible-limit neo-Hooke with shear modulus 1 (forces come out in ``G L^2`` after division
by ``L^2``; lengths in mm), bulk modulus ``BULK_RATIO`` times the shear modulus; out-of-plane thickness ``T``.

Loading, as in the seed's FE and our beam model (``core.sleeve.model``):

* unit cell: bottom edge clamped; left and right edges periodic (every node of the right edge moves with
  its image on the left edge); the top edge is pulled up by ``d`` (every node), its horizontal shift free
  and common (the kinematic coupling; with periodic edges the top cannot rotate);
* ring of N cells: the cells unrolled side by side, the last one's right edge tied to the first one's left
  edge; the top edge follows a rigid plate that rises by ``d`` and tilts freely,
  ``v = d + R (psi_x sin phi - psi_y cos phi)`` at the angle ``phi = x / R`` (``R = N W / 2 pi``), with a
  common tangential shift (twist): the same linear ring kinematics as the beam model. A flat, unrolled 2-D
  ring has no curvature: compare it with the beam model's ``curvature=False`` ring (the default model adds
  the curvature's radial relief, which the curved 3-D ring of ``sleeve3d`` checks). A tiny bias force on the tilt
  (``bias``, towards the beam model's imperfection direction) picks the branch the model picks.

Displacement control, ``*STATIC`` with ``NLGEOM`` and a fixed number of increments (automatic cut-back);
reaction forces are the sum of the top edge's (cell) or of the clamped bottom edge's (ring: ccx reports none at
a node that only enters equations).
"""
import math

import numpy as np

from metamaterial_wb.fe import ccx, checks
from metamaterial_wb.fe.mesh import Mesh

BULK_RATIO = 500.0      # K / G of the nearly incompressible neo-Hooke solid (nu = 0.499)
R_MAX, CELLS_MAX = 8, 64  # the largest refinement and number of cells a mesh takes (sleeve3d's bounds)
D_MAX = 1.5             # the largest travel d_max of a deck, in L (sleeve3d's)


def _beam_point(g, p, s):
    """Point of the beam at centre-line abscissa ``p`` and normal offset ``s`` in [-1, 1] (t/2 units)."""
    p = np.asarray(p, float)
    sl = g.slope(p)
    nrm = np.hypot(1.0, sl)
    nx, ny = -sl / nrm, 1.0 / nrm
    return np.stack([p + s * 0.5 * g.t * nx, g.centre_line(p) + s * 0.5 * g.t * ny], axis=-1)


def _tfi(bottom, top, left, right):
    """Transfinite interpolation of a block from its four boundary functions of one parameter in [0, 1]
    (bottom/top along u, left/right along v). Returns ``f(u, v)`` for arrays."""
    P00, P10, P01, P11 = bottom(0.0), bottom(1.0), top(0.0), top(1.0)

    def f(u, v):
        u = np.asarray(u, float)[..., None]
        v = np.asarray(v, float)[..., None]
        uu, vv = u[..., 0], v[..., 0]
        return ((1 - v) * bottom(uu) + v * top(uu) + (1 - u) * left(vv) + u * right(vv)
                - ((1 - u) * (1 - v) * P00 + u * (1 - v) * P10 + (1 - u) * v * P01 + u * v * P11))
    return f


def _line(a, b):
    a, b = np.asarray(a, float), np.asarray(b, float)
    return lambda s: a + np.asarray(s, float)[..., None] * (b - a)


def _quad(p00, p10, p11, p01):
    """The bilinear block with corners ``p00`` (u = v = 0), ``p10``, ``p11``, ``p01`` (counter-clockwise)."""
    return _tfi(_line(p00, p10), _line(p01, p11), _line(p00, p01), _line(p10, p11))


MATCH = ("L", "c", "delta", "T", "layout")     # what a mixed solid ring's cell types share


def ring_cells(g, cells):
    """The cell geometry of each of the ring's ``cells`` cells: ``g`` one ``CellGeometry`` (a uniform ring) or a
    list of ``cells`` of them in ring order (a mixed ring: the types may differ in ``h`` and ``t``; ``MATCH``
    they share, or the cells' sides and bars would not meet)."""
    geoms = list(g) if isinstance(g, (list, tuple)) else [g] * int(cells)
    if len(geoms) != cells:
        raise ValueError(f"cell geometries: {len(geoms)} for a ring of {cells} cells; allowed: one, or one per cell")
    for name in MATCH:
        vals = sorted({getattr(x, name) for x in geoms}, key=str)
        if len(vals) > 1:
            raise ValueError(f"cell geometries: {name} takes the values {', '.join(map(str, vals))} around the ring; "
                             f"allowed: one {name} (a solid ring's cell types may differ in h and t only)")
    return geoms


def _blocks(g, r, height=None, side_t=None):
    """The nine blocks of the right half cell (x >= 0): ``(name, mapping f(u, v), nu, nv)``. A mixed ring's cell
    (``ring_cells``): ``height`` the ring's top (its tallest cell's; the cell's own by default), ``side_t`` the beam
    thickness whose end heights the edge half-pillar carries on the cell's side ``x = W/2``, where it meets the
    neighbour's (the thickest in the ring; the cell's own ``t`` by default): its two pillar blocks are then
    quadrilaterals from the cell's own beam end on the pillar's face to those heights, so every cell's side
    carries the same nodes."""
    L, t, c, d = g.L, g.t, g.c, g.delta
    H, W = (g.height if height is None else height), g.width
    yb, yt = c / 2, H - c / 2
    ye0, ye1 = yb + d, yb + d + t                       # beam end on the edge pillar (flat there)
    ys1 = yb + d + (t if side_t is None else side_t)    # the same on the cell's side
    n_t = r
    n_a = 2 * r                                         # beam over the central pillar, pillar width
    n_b = 7 * r                                         # free beam half
    n_cv = 3 * r                                        # central pillar's height
    n_bar = r
    n_e = 3 * r                                         # bottom bar beyond the pillar
    n_p = 2 * r                                         # edge half-pillar's width
    n_g = 3 * r                                         # edge pillar above the beam end
    n_h = 3 * r                                         # top bar over the void
    beam = lambda p0, p1: (lambda u, v: _beam_point(g, p0 + np.asarray(u) * (p1 - p0), 2 * np.asarray(v) - 1))  # noqa: E731
    low = lambda s: _beam_point(g, np.asarray(s, float) * c / 2, -1.0)           # noqa: E731
    A = beam(0.0, c / 2)
    B = beam(c / 2, L / 2)
    C = _tfi(_line((0, yb), (c / 2, yb)), low, _line((0, yb), low(0.0)), _line((c / 2, yb), low(1.0)))
    rect = lambda x0, x1, y0, y1: (lambda u, v: np.stack(  # noqa: E731
        np.broadcast_arrays(x0 + np.asarray(u, float) * (x1 - x0), y0 + np.asarray(v, float) * (y1 - y0)), axis=-1))
    return [("beam_pillar", A, n_a, n_t), ("beam_free", B, n_b, n_t), ("central_pillar", C, n_a, n_cv),
            ("bar_under_pillar", rect(0, c / 2, 0, yb), n_a, n_bar), ("bar_bottom", rect(c / 2, W / 2, 0, yb), n_e, n_bar),
            ("edge_pillar_low", _quad((L / 2, ye0), (W / 2, ye0), (W / 2, ys1), (L / 2, ye1)), n_p, n_t),
            ("edge_pillar", _quad((L / 2, ye1), (W / 2, ys1), (W / 2, yt), (L / 2, yt)), n_p, n_g),
            ("bar_top_pillar", rect(L / 2, W / 2, yt, H), n_p, n_bar), ("bar_top", rect(0, L / 2, yt, H), n_h, n_bar)]


# CPE8 node order on the doubled block grid (i along u, j along v): 4 corners counter-clockwise, 4 mid-sides
_Q8 = [(0, 0), (2, 0), (2, 2), (0, 2), (1, 0), (2, 1), (1, 2), (0, 1)]


class QuadMesh(Mesh):
    """``nodes`` (N, 2) mm, ``elements`` (E, 8) 0-based CPE8 connectivity (counter-clockwise), ``block`` (E,)
    block names, and the geometry it was made for (``geom``; a mixed ring's first cell's, ``geoms`` every cell's,
    ``height`` its top)."""

    def __init__(self, nodes, elements, block, geom, cells, geoms=None, height=None):
        self.nodes, self.elements, self.block, self.geom, self.cells = nodes, elements, block, geom, cells
        self.geoms = list(geoms) if geoms is not None else [geom] * cells
        self.height = geom.height if height is None else float(height)


    def area(self):
        """Area by the element's quadratic map (3 x 3 Gauss), mm^2."""
        g = np.array([-math.sqrt(0.6), 0.0, math.sqrt(0.6)])
        w = np.array([5 / 9, 8 / 9, 5 / 9])
        X = self.nodes[self.elements]                     # (E, 8, 2)
        tot = 0.0
        for a, wa in zip(g, w):
            for b, wb in zip(g, w):
                dN = _dshape(a, b)                        # (2, 8)
                J = np.einsum("kn,enc->ekc", dN, X)
                tot += wa * wb * np.sum(J[:, 0, 0] * J[:, 1, 1] - J[:, 0, 1] * J[:, 1, 0])
        return float(tot)

    def corner_elements(self, dist, low=False):
        """0-based ids of the beam's elements (blocks ``beam_pillar``, ``beam_free``) whose centre lies within
        ``dist`` mm (along x, inclusive: an element centred exactly that far is in, in every cell alike) of the
        central pillar's side or of the edge pillar: the two re-entrant corners where the beam bends most.
        ``low=True`` adds the elements of the beam's continuation into the edge pillar (block ``edge_pillar_low``:
        the pillar's strip at the beam's height, free below) within ``dist`` of the pillar's side."""
        if dist <= 0:
            return np.zeros(0, dtype=np.int64)
        g = self.geom
        x = self.nodes[self.elements[:, :4], 0].mean(axis=1)
        x = np.abs(x - np.round(x / g.width) * g.width)       # distance from the cell's middle
        lim = dist + 1e-6 * g.L
        sel = (np.isin(self.block, ("beam_pillar", "beam_free"))
               & ((np.abs(x - g.c / 2) < lim) | (np.abs(g.L / 2 - x) < lim)))
        if low:
            sel |= (self.block == "edge_pillar_low") & (np.abs(x - g.L / 2) < lim)
        return np.flatnonzero(sel)

    def min_jacobian(self):
        X = self.nodes[self.elements]
        out = np.inf
        for a in (-1.0, 0.0, 1.0):
            for b in (-1.0, 0.0, 1.0):
                J = np.einsum("kn,enc->ekc", _dshape(a, b), X)
                out = min(out, float(np.min(J[:, 0, 0] * J[:, 1, 1] - J[:, 0, 1] * J[:, 1, 0])))
        return out


def _dshape(a, b):
    """Derivatives (d/dxi, d/deta) of the 8 serendipity shape functions at (a, b)."""
    xi = np.array([-1, 1, 1, -1, 0, 1, 0, -1], float)
    et = np.array([-1, -1, 1, 1, -1, 0, 1, 0], float)
    dx, de = np.zeros(8), np.zeros(8)
    for k in range(4):
        dx[k] = 0.25 * xi[k] * (1 + et[k] * b) * (2 * xi[k] * a + et[k] * b)
        de[k] = 0.25 * et[k] * (1 + xi[k] * a) * (xi[k] * a + 2 * et[k] * b)
    for k in (4, 6):
        dx[k] = -a * (1 + et[k] * b)
        de[k] = 0.5 * et[k] * (1 - a * a)
    for k in (5, 7):
        dx[k] = 0.5 * xi[k] * (1 - b * b)
        de[k] = -b * (1 + xi[k] * a)
    return np.vstack([dx, de])


def cell_mesh(g, r=1, cells=1, top=None):
    """Structured CPE8 mesh of ``cells`` unit cells side by side (cell k centred at ``x = k W``), refinement
    ``r`` (``r`` elements through the beam's thickness). ``g``: one ``CellGeometry``, or one per cell (a mixed
    ring, ``ring_cells``: the top at the tallest cell's height, every cell's sides at the thickest beam's end
    heights, so neighbours share their nodes). ``top`` (mm): the top's height, if higher than the tallest cell's
    (the edge pillars lengthened by the difference: a uniform ring of a mixed ring's shorter type as it stands
    there)."""
    from scipy.spatial import cKDTree

    r = checks.integer("r", r, 1, R_MAX)
    cells = checks.integer("cells", cells, 1, CELLS_MAX)
    geoms = ring_cells(g, cells)
    g = geoms[0]
    if g.layout != "single":
        raise ValueError("the FE sleeve cell is the single layout (one beam per cell)")
    height, side_t = max(x.height for x in geoms), max(x.t for x in geoms)
    if top is not None:
        if not height - 1e-9 * g.L <= top <= height + g.L:
            raise ValueError(f"top: {top!r} mm; allowed: from the tallest cell's height {height:g} mm to L higher, "
                             f"{height + g.L:g} mm")
        height = max(height, float(top))
    pts, quads, names = [], [], []
    base = 0
    blocks = {}                       # per distinct cell type (the same numbering as a uniform ring's)
    for gk in geoms:
        blocks.setdefault(id(gk), _blocks(gk, r, height, side_t))
    for b, (name, _f, nu, nv) in enumerate(blocks[id(g)]):
        U, V = np.meshgrid(np.linspace(0, 1, 2 * nu + 1), np.linspace(0, 1, 2 * nv + 1), indexing="ij")
        idx = np.arange(U.size).reshape(2 * nu + 1, 2 * nv + 1)
        el = np.array([[idx[2 * i + di, 2 * j + dj] for di, dj in _Q8] for i in range(nu) for j in range(nv)])
        P = {key: bl[b][1](U, V).reshape(-1, 2) for key, bl in blocks.items()}
        for mirror in (False, True):
            e = el[:, [0, 3, 2, 1, 7, 6, 5, 4]] if mirror else el       # keep counter-clockwise
            for k, gk in enumerate(geoms):
                Q = P[id(gk)] * ([-1.0, 1.0] if mirror else [1.0, 1.0])
                pts.append(Q + [k * g.width, 0.0])
                quads.append(e + base)
                names += [name] * len(e)
                base += Q.shape[0]
    X = np.vstack(pts)
    E = np.vstack(quads)
    # merge coincident nodes (shared block edges, the mirror line, neighbouring cells)
    tree = cKDTree(X)
    pairs = tree.query_pairs(1e-7 * g.L, output_type="ndarray")
    rep = np.arange(X.shape[0])
    for a, b in sorted(map(tuple, np.sort(pairs, axis=1)), key=lambda p: p[1]):
        ra = rep[a]
        while rep[ra] != ra:
            ra = rep[ra]
        rep[b] = ra
    for i in range(len(rep)):
        j = rep[i]
        while rep[j] != j:
            j = rep[j]
        rep[i] = j
    used, inv = np.unique(rep[E], return_inverse=True)
    return QuadMesh(X[used], inv.reshape(E.shape), np.array(names), g, cells, geoms, height)


def _material(out, T, full=False):
    K = BULK_RATIO
    out.append("*MATERIAL, NAME=RUBBER\n*HYPERELASTIC, NEO HOOKE\n0.5,%.9g\n" % (2.0 / K))
    out.append(f"*SOLID SECTION, ELSET=SOLID, MATERIAL=RUBBER\n{T:.9g}\n")
    if full:
        out.append(f"*SOLID SECTION, ELSET=SOLIDF, MATERIAL=RUBBER\n{T:.9g}\n")


def _mesh_text(mesh, full_ids=()):
    """Nodes and ``*ELEMENT`` cards: CPE8R in set ``SOLID``, but the elements ``full_ids`` (0-based) CPE8 (full
    integration) in set ``SOLIDF``."""
    X = np.column_stack([mesh.nodes, np.zeros(mesh.n_nodes)])
    full = np.zeros(mesh.n_elements, bool)
    full[np.asarray(full_ids, dtype=np.int64)] = True
    card = lambda i, conn: f"{i + 1}," + ",".join(str(int(v) + 1) for v in conn) + "\n"      # noqa: E731
    lines = ["*NODE\n", ccx.fmt_nodes(X), "*ELEMENT, TYPE=CPE8R, ELSET=SOLID\n"]
    lines += [card(i, conn) for i, conn in enumerate(mesh.elements) if not full[i]]
    if full.any():
        lines.append("*ELEMENT, TYPE=CPE8, ELSET=SOLIDF\n")
        lines += [card(i, conn) for i, conn in enumerate(mesh.elements) if full[i]]
    return "".join(lines)


def _edges(mesh):
    g = mesh.geom
    X = mesh.nodes
    tol = 1e-7 * g.L
    x_lo, x_hi = -g.width / 2, (mesh.cells - 0.5) * g.width
    bottom = np.flatnonzero(np.abs(X[:, 1]) < tol)
    top = np.flatnonzero(np.abs(X[:, 1] - mesh.height) < tol)
    left = np.flatnonzero(np.abs(X[:, 0] - x_lo) < tol)
    right = np.flatnonzero(np.abs(X[:, 0] - x_hi) < tol)
    # pair every right-edge node with the left-edge node at the same height
    lo = {round(float(X[i, 1]) / tol): i for i in left}
    pairs = []
    for i in right:
        j = lo.get(round(float(X[i, 1]) / tol))
        if j is None:
            raise ValueError("periodic edges do not match")
        pairs.append((i, j))
    return bottom, top, pairs


def _step(d_total, increments, prints):
    inc = 1.0 / increments
    return (f"*STEP, NLGEOM, INC=100000\n*STATIC\n{inc:.6g},1.0,{inc / 1024:.6g},{inc:.6g}\n{{bc}}{prints}"
            "*END STEP\n")


def check_travel(g, d_max, increments, default):
    """``(d_max, increments)`` of a deck, checked: ``d_max`` (mm; ``default`` times L when None) from 0 (excluded)
    to ``D_MAX`` L, ``increments`` an integer >= 1 (the step's largest increment is ``1 / increments``)."""
    d_max = default * g.L if d_max is None else checks.number("d_max", d_max, 0.0, D_MAX * g.L, "mm", low_open=True,
                                                                note=f"{D_MAX:g} L")
    return d_max, checks.integer("increments", increments, 1)


def cell_deck(g, r=1, d_max=None, increments=100, full_near=0.0, full_low=False):
    """``(deck, meta)``: the periodic unit cell pulled to ``d_max`` (mm; default 0.7 L, past the valley; at most
    ``D_MAX`` L) in at most ``increments`` steps (an integer >= 1; ``r``: ``cell_mesh``).
    ``full_near`` (mm), ``full_low``: the elements of ``QuadMesh.corner_elements(full_near, full_low)`` fully
    integrated (CPE8), the rest CPE8R (as ``sleeve3d.ring_deck3d``'s corner bricks)."""
    d_max, increments = check_travel(g, d_max, increments, 0.7)
    mesh = cell_mesh(g, r, 1)
    if not 0 <= full_near <= 0.5 * g.L:
        raise ValueError(f"full_near: {full_near!r} mm; allowed: 0 (none) to L/2 = {0.5 * g.L:g} mm")
    if full_low and not full_near:
        raise ValueError("full_low: the edge pillar's strip joins the corner elements of full_near, which is 0; "
                         "allowed: full_near > 0 with it")
    full = mesh.corner_elements(full_near, full_low)
    bottom, top, pairs = _edges(mesh)
    out = ["*HEADING\nmetamaterial_wb: sleeve unit cell, plane strain, periodic edges\n", _mesh_text(mesh, full)]
    out += ["*NSET, NSET=BOTTOM\n", ccx.fmt_set(bottom + 1), "*NSET, NSET=TOP\n", ccx.fmt_set(top + 1)]
    _material(out, g.T, full.size > 0)
    topset, bot = set(top.tolist()), set(bottom.tolist())
    master = int(top[np.argmin(np.abs(mesh.nodes[top, 0]))])
    eqs = []
    for n in top:
        if n != master:
            eqs.append(f"*EQUATION\n2\n{n + 1},1,1.0,{master + 1},1,-1.0\n")
    for i, j in pairs:
        if i in bot:
            continue
        if i not in topset:
            eqs.append(f"*EQUATION\n2\n{i + 1},2,1.0,{j + 1},2,-1.0\n")
            eqs.append(f"*EQUATION\n2\n{i + 1},1,1.0,{j + 1},1,-1.0\n")
    out += eqs
    bc = f"*BOUNDARY\nBOTTOM,1,2,0\nTOP,2,2,{d_max:.12g}\n"
    prints = "*NODE PRINT, NSET=TOP\nU,RF\n"
    out.append(_step(d_max, increments, prints).replace("{bc}", bc))
    meta = {"mesh": mesh, "top": top, "d_max_mm": d_max, "r": int(r), "dofs": 2 * mesh.n_nodes,
            "elements": mesh.n_elements, "increments": increments, "full_near": float(full_near),
            "full_low": bool(full_low), "full_elements": int(full.size)}
    return "".join(out), meta


DRV, TILT = 9000001, 9000002


BIAS_MAX = 1e-3      # G L^2: the largest tilt bias a ring deck takes, about the ring's first peak force


def check_bias(bias, bias_angle, what="a force bias L^2"):
    """Refuse a tilt bias that is not an imperfection: ``bias`` (G L^2; ``what`` it is in the deck) outside 0 to
    ``BIAS_MAX`` or not a number, or a non-finite ``bias_angle`` (in pi / n_cells)."""
    if not 0.0 <= bias <= BIAS_MAX:          # False for NaN too
        raise ValueError(f"bias: {bias!r}; allowed: 0 to {BIAS_MAX:g} (G L^2; {what}, an imperfection: {BIAS_MAX:g} "
                         "is about the ring's first peak; reverse it by bias_angle)")
    if not math.isfinite(bias_angle):
        raise ValueError(f"bias_angle: {bias_angle!r}; allowed: a finite number (in pi / n_cells)")


def ring_deck(g, n_cells=4, r=1, d_max=None, increments=60, bias=1e-5, bias_angle=0.5):
    """``(deck, meta)``: ``n_cells`` cells unrolled into a closed ring under a tilting top plate (see the
    module docstring); ``bias``: the tilt bias force in ``G L^2`` (towards ``bias_angle * pi / N``;
    ``check_bias``)."""
    check_bias(bias, bias_angle)
    n_cells = checks.integer("n_cells", n_cells, 2, CELLS_MAX, "cells around the ring")
    d_max, increments = check_travel(g, d_max, increments, 0.25)
    mesh = cell_mesh(g, r, n_cells)
    R = n_cells * g.width / (2 * math.pi)
    bottom, top, pairs = _edges(mesh)
    out = ["*HEADING\nmetamaterial_wb: sleeve ring (unrolled), plane strain, tilting top plate\n", _mesh_text(mesh)]
    out.append(f"*NODE\n{DRV},0,{g.height:.9g},0\n{TILT},0,{g.height:.9g},0\n")
    out += ["*NSET, NSET=BOTTOM\n", ccx.fmt_set(bottom + 1), f"*NSET, NSET=NDRV\n{DRV}\n*NSET, NSET=NTILT\n{TILT}\n"]
    _material(out, g.T)
    topset, bot = set(top.tolist()), set(bottom.tolist())
    master = int(top[np.argmin(np.abs(mesh.nodes[top, 0]))])
    for n in top:
        phi = mesh.nodes[n, 0] / R
        s, c = math.sin(phi), math.cos(phi)
        # v_n = d + (R psi_x) sin(phi) - (R psi_y) cos(phi); TILT's DOFs 1, 2 carry R psi_x, R psi_y
        out.append(f"*EQUATION\n4\n{n + 1},2,1.0,{DRV},2,-1.0,{TILT},1,{-s:.12g},{TILT},2,{c:.12g}\n")
        if n != master:
            out.append(f"*EQUATION\n2\n{n + 1},1,1.0,{master + 1},1,-1.0\n")
    for i, j in pairs:
        if i in bot or i in topset:
            continue
        out.append(f"*EQUATION\n2\n{i + 1},2,1.0,{j + 1},2,-1.0\n*EQUATION\n2\n{i + 1},1,1.0,{j + 1},1,-1.0\n")
    bc = f"*BOUNDARY\nBOTTOM,1,2,0\n{DRV},1,1,0\n{DRV},2,2,{d_max:.12g}\n{TILT},3,3,0\n"
    phi_b = bias_angle * math.pi / n_cells
    f = bias * g.L ** 2
    if f:
        bc += f"*CLOAD\n{TILT},1,{f * math.sin(phi_b):.12g}\n{TILT},2,{-f * math.cos(phi_b):.12g}\n"
    # ccx reports no reaction at a driver node that only enters equations: the force is the clamped bottom
    # edge's reaction (the bias is a pure tilt load, its net vertical force is zero to round-off)
    prints = "*NODE PRINT, NSET=BOTTOM\nRF\n*NODE PRINT, NSET=NTILT\nU\n"
    out.append(_step(d_max, increments, prints).replace("{bc}", bc))
    meta = {"mesh": mesh, "bottom": bottom, "radius_mm": R, "d_max_mm": d_max, "r": int(r), "dofs": 2 * mesh.n_nodes,
            "elements": mesh.n_elements, "increments": increments, "n_cells": n_cells}
    return "".join(out), meta


def _curve(times, d_max, forces, L):
    d = np.asarray(times) * d_max / L
    return d, np.asarray(forces) / L ** 2


def solve_cell(g, r=1, d_max=None, increments=100, timeout_s=1800.0, full_near=0.0, full_low=False):
    """Force-displacement curve of the periodic unit cell: ``{"d": d / L, "F": F / (G L^2)}`` per converged
    increment, and the run info (``full_near``, ``full_low``: ``cell_deck``)."""
    deck, meta = cell_deck(g, r, d_max, increments, full_near, full_low)
    tables, info = ccx.run(deck, "sleeve_cell", timeout_s)
    top = meta["top"] + 1
    rows = ccx.table(tables, ("forces", "TOP"), "sleeve_cell", top, info)
    t = np.array([r_[0] for r_ in rows])
    F = np.array([sum(r_[1][int(n)][1] for n in top) for r_ in rows])
    d, Fn = _curve(t, meta["d_max_mm"], F, g.L)
    info.update({k: meta[k] for k in ("r", "dofs", "elements", "d_max_mm", "full_near", "full_low", "full_elements")})
    info["increments"] = len(t)
    return {"d": np.concatenate([[0.0], d]), "F": np.concatenate([[0.0], Fn])}, info


def solve_ring(g, n_cells=4, r=1, d_max=None, increments=60, bias=1e-5, timeout_s=3600.0, partial=False):
    """Force-displacement curve of the unrolled ring and its tilt: ``{"d", "F", "tilt_rad" (k, 2)}``. With
    ``partial=True`` a run that stops before ``d_max`` returns the converged increments (``info["stopped"]``
    says why, ``info["d_reached"]`` how far, in ``d / L``)."""
    deck, meta = ring_deck(g, n_cells, r, d_max, increments, bias)
    tables, info = ccx.run(deck, "sleeve_ring", timeout_s, partial=partial)
    rows = ccx.table(tables, ("forces", "BOTTOM"), "sleeve_ring", meta["bottom"] + 1, info)
    t = np.array([r_[0] for r_ in rows])
    F = -np.array([sum(v[1] for v in r_[1].values()) for r_ in rows])
    tilt = ccx.table(tables, ("displacements", "NTILT"), "sleeve_ring", [TILT], info)
    tilt = np.array([r_[1][TILT][:2] for r_ in tilt]) / meta["radius_mm"]
    d, Fn = _curve(t, meta["d_max_mm"], F, g.L)
    info.update({k: meta[k] for k in ("r", "dofs", "elements", "d_max_mm", "n_cells", "radius_mm")})
    info["increments"] = len(t)
    tilt = tilt[:len(t)]
    info["d_reached"] = float(d[-1])
    return {"d": np.concatenate([[0.0], d]), "F": np.concatenate([[0.0], Fn]),
            "tilt_rad": np.vstack([[0.0, 0.0], tilt])}, info


def peak_valley(d, F):
    """First local maximum of F and the following minimum: ``(d_peak, F_peak, d_valley, F_valley)`` (valley
    NaN when the curve ends before it), refined by a parabola through the three points around each."""
    d, F = np.asarray(d, float), np.asarray(F, float)

    def refine(i):
        if 0 < i < len(F) - 1:
            x, y = d[i - 1:i + 2], F[i - 1:i + 2]
            A = np.polyfit(x, y, 2)
            if A[0] != 0:
                xv = -A[1] / (2 * A[0])
                if x[0] <= xv <= x[2]:
                    return float(xv), float(np.polyval(A, xv))
        return float(d[i]), float(F[i])

    ip = next((i for i in range(1, len(F) - 1) if F[i] >= F[i - 1] and F[i] > F[i + 1]), None)
    if ip is None:
        return (np.nan,) * 4
    iv = next((i for i in range(ip + 1, len(F) - 1) if F[i] <= F[i - 1] and F[i] < F[i + 1]), None)
    dp, Fp = refine(ip)
    dv, Fv = refine(iv) if iv is not None else (np.nan, np.nan)
    return dp, Fp, dv, Fv


__all__ = ["cell_mesh", "cell_deck", "ring_deck", "solve_cell", "solve_ring", "peak_valley", "QuadMesh"]
