"""The sleeve's N-cell ring in CalculiX as a curved 3-D solid: 20-node bricks (C3D20R) on the cylinder.

The flat ring of :mod:`.sleeve2d` has no curvature: its cells lie side by side in a plane and are closed on
themselves by ties, so the radial relief of the curved wall (the beams are arcs; their axial force pushes the
pillars outward) is missing. Here the same structured mesh of the printed outline
(``sleeve2d.cell_mesh(g, r, n_cells)``, x along the circumference, y axial) is wrapped onto a cylinder and
extruded radially through the wall thickness ``T``:

* a point at unrolled ``x`` sits at the angle ``phi = x / R`` with ``R = N W / (2 pi)`` on the wall's mid
  surface (``wall="mid"``, the default): the beam model's ring (``core.sleeve.model``: "a point at unrolled x
  sits at the angle phi = x / R on the mid radius R") and the flat ring use the same ``R``, and the mid
  surface keeps the 2-D lengths. The wall spans radii ``R - T/2 .. R + T/2`` (``wall="inner"``: ``R .. R + T``,
  used by the tests for the exact volume factor);
* global axes: ``X = rho cos phi``, ``Y = rho sin phi``, ``Z = y`` (axial). ``n_layers`` bricks through the
  wall; a quad's corners become the brick's corners on both faces of a layer (and its mid-thickness edge
  nodes), its mid-side nodes the brick's mid-edge nodes. The map ``(x, y, s)`` (``s`` radial) is
  right-handed, so the CPE8 order (counter-clockwise) gives CalculiX's C3D20 order with positive Jacobians:
  corners 1-4 on the inner face, 5-8 on the outer face, 9-12 and 13-16 the face mid-edges, 17-20 the radial
  mid-edges;
* the ring is closed by merging: the last cell's right edge nodes are the first cell's left edge nodes.

Loading, as the flat ring and the beam model: the bottom edge (``Z = 0``) clamped in all three directions; the
top edge (``Z = H``) on a rigid plate (``*RIGID BODY`` with a reference node on the axis at the top and a
rotation node) that rises by ``d`` (the reference node's axial displacement), tilts freely about ``X`` and ``Y``
(``psi_x``, ``psi_y``: a point of the plate at ``phi`` rises by ``R (psi_x sin phi - psi_y cos phi)``, the beam
model's convention) and twists freely about the axis (the flat ring's common tangential shift). Its in-plane
translation is fixed: neither the beam model's plate (axial rise, two tilts, twist) nor the flat ring (whose
top nodes share one tangential shift, which is the twist) has one, and the seed's kinematic coupling only says
the top is "free to tilt". A tiny bias moment (``bias`` in ``G L^2`` times ``R``, the work-equivalent of the
flat ring's bias force on ``R psi``) turns the plate towards the beam model's imperfection direction
``bias_angle * pi / N``. Same neo-Hooke solid as the flat ring (``sleeve2d.BULK_RATIO``), no plane-strain
restraint: the wall is free through its thickness.

Displacement control, ``*STATIC`` (as the flat ring) or implicit dynamics (``method="dynamic"``, which carries
the curved ring into the snap where static Newton stalls: docs/sleeves.md, "A curved 3-D FE ring"). The force is
the clamped bottom's axial reaction (sum over its nodes), per converged increment.
"""
import math

import numpy as np

from metamaterial_wb.fe import ccx, checks, sleeve2d
from metamaterial_wb.fe.mesh import Mesh

REF, ROT = 9000001, 9000002
DENSITY = 1e-10          # t/mm^3 with G = 1 MPa and a step of time 1 (a tenth of rubber's at 0.7 L per second)
WALLS = ("mid", "inner")
# natural coordinates of a brick's corners, mid-edges and face and element centres (3 x 3 x 3)
_NODE_POINTS = [(a, b, c) for a in (-1.0, 0.0, 1.0) for b in (-1.0, 0.0, 1.0) for c in (-1.0, 0.0, 1.0)]
PARTS = ("bars", "central", "edge", "pillars", "beams")     # radial="<part>": only that part held at its radius

# natural coordinates of CalculiX's C3D20 nodes (corners, face mid-edges, radial mid-edges)
_XI = np.array([(-1, -1, -1), (1, -1, -1), (1, 1, -1), (-1, 1, -1), (-1, -1, 1), (1, -1, 1), (1, 1, 1), (-1, 1, 1),
                (0, -1, -1), (1, 0, -1), (0, 1, -1), (-1, 0, -1), (0, -1, 1), (1, 0, 1), (0, 1, 1), (-1, 0, 1),
                (-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0)], float)


def _shape20(a, b, c):
    """The 20 serendipity shape functions at natural coordinates ``(a, b, c)``."""
    x, y, z = _XI.T
    N = np.empty(20)
    k = slice(0, 8)
    N[k] = 0.125 * (1 + x[k] * a) * (1 + y[k] * b) * (1 + z[k] * c) * (x[k] * a + y[k] * b + z[k] * c - 2)
    for i in range(8, 20):
        f = [1 + x[i] * a, 1 + y[i] * b, 1 + z[i] * c]
        j = [x[i], y[i], z[i]].index(0.0)
        f[j] = 1 - (a, b, c)[j] ** 2
        N[i] = 0.25 * f[0] * f[1] * f[2]
    return N


def _dshape20(a, b, c, h=1e-4):
    """(3, 20) derivatives of the shape functions (central differences: exact to round-off for polynomials
    of degree 3 up to h^2 times the third derivative's constant, ~1e-9 here)."""
    p = np.array([a, b, c], float)
    out = np.empty((3, 20))
    for k in range(3):
        e = np.zeros(3)
        e[k] = h
        out[k] = (_shape20(*(p + e)) - _shape20(*(p - e))) / (2 * h)
    return out


class RingMesh(Mesh):
    """``nodes`` (N, 3) mm, ``elements`` (E, 20) 0-based C3D20 connectivity; ``radius`` (mm, where ``phi =
    x / radius``), ``wall`` and the 2-D mesh it was wrapped from (``quad``, seam already merged in
    ``quad_elements``)."""

    def __init__(self, nodes, elements, geom, cells, radius, wall, n_layers, quad, quad_elements):
        self.nodes, self.elements, self.geom, self.cells = nodes, elements, geom, cells
        self.radius, self.wall, self.n_layers, self.quad, self.quad_elements = radius, wall, n_layers, quad, quad_elements
        self.geoms, self.height = quad.geoms, quad.height          # every cell's geometry (a mixed ring), the top


    def parts(self):
        """Boolean node masks of the outline's parts, from each node's place in its cell: ``bars`` (the bottom and
        top bars, ``c/2`` high), ``central`` (the central pillar, within ``c/2`` of a cell's middle), ``edge`` (the
        edge pillars, within ``c/2`` of a cell's side), ``pillars`` (both) and ``beams`` (the rest). Cell 0's
        middle is at ``phi = 0``."""
        g = self.geom
        X = self.nodes
        x = (np.arctan2(X[:, 1], X[:, 0]) * self.radius) % g.width
        xc = np.minimum(x, g.width - x)                        # distance from the cell's middle along the arc
        tol = 1e-6 * g.L
        bars = (X[:, 2] < 0.5 * g.c + tol) | (X[:, 2] > self.height - 0.5 * g.c - tol)
        central = (xc < 0.5 * g.c + tol) & ~bars
        edge = (np.abs(xc - 0.5 * g.width) < 0.5 * g.c + tol) & ~bars
        return {"bars": bars, "central": central, "edge": edge, "pillars": central | edge,
                "beams": ~(bars | central | edge)}

    def _jacobians(self, points):
        X = self.nodes[self.elements]                          # (E, 20, 3)
        for p in points:
            yield p, np.linalg.det(np.einsum("kn,enc->ekc", _dshape20(*p), X))

    def volume(self):
        """Volume by the bricks' quadratic map (3 x 3 x 3 Gauss), mm^3."""
        g = [-math.sqrt(0.6), 0.0, math.sqrt(0.6)]
        w = dict(zip(g, (5 / 9, 8 / 9, 5 / 9)))
        pts = [(a, b, c) for a in g for b in g for c in g]
        return float(sum(w[a] * w[b] * w[c] * np.sum(J) for (a, b, c), J in self._jacobians(pts)))

    def min_jacobian(self):
        """Smallest Jacobian determinant over every element's 27 points (corners, mid-edges, centres of faces
        and of the element): all positive means every brick is positively oriented and not folded."""
        return min(float(np.min(J)) for _, J in self._jacobians(_NODE_POINTS))

    def volume_ratios(self, u):
        """``(E, 27)`` local volume ratios ``det F`` of every brick deformed by the node displacements ``u``
        (``(n_nodes, 3)`` mm) at its corners, mid-edges and face and element centres (the points of
        :meth:`min_jacobian`), and ``(E, 8, 3)`` principal stretches at its 2 x 2 x 2 (reduced) integration points.
        A nearly incompressible solid keeps ``det F`` near 1 at the integration points; a brick whose nodal
        ``det F`` falls far below 1 while its integration points stay at 1 is deforming in a mode those points
        do not see (reduced integration's spurious mode), not in the material."""
        x = self.nodes + np.asarray(u, float)
        X0, X1 = self.nodes[self.elements], x[self.elements]

        def grads(p):
            dN = _dshape20(*p)
            return np.einsum("kn,enc->eck", dN, X1) @ np.linalg.inv(np.einsum("kn,enc->eck", dN, X0))
        J = np.stack([np.linalg.det(grads(p)) for p in _NODE_POINTS], axis=1)
        q = 1 / math.sqrt(3)
        gp = [(a, b, c) for a in (-q, q) for b in (-q, q) for c in (-q, q)]
        S = np.stack([np.linalg.svd(grads(p), compute_uv=False) for p in gp], axis=1)
        return J, S

    def beam_end_elements(self, dist, low=False):
        """0-based ids of the bricks over ``quad.corner_elements(dist, low)`` (the beam's bricks within ``dist`` mm
        of its two re-entrant corners, along the unrolled circumference; with ``low``, the edge pillar's strip at
        the beam's height too) through every layer of the wall."""
        q = self.quad.corner_elements(dist, low)
        return np.concatenate([q + k * self.quad.n_elements for k in range(self.n_layers)])

    def beam_ends(self):
        """The free beams' ends, as the beam model and the frame read a hysteron (``analysis.snap_order``): per
        beam half (cell ``k``'s right half, then its left half, cell by cell) the node ids of its outer end (on
        the edge pillar's face, centre line ``x = +-L/2``) and of its inner end (on the central pillar's face,
        ``x = +-c/2``), through the wall (every level that has a node there), and ``units`` (per half): the edge
        pillar it hangs on, pillar ``k`` between cells ``k`` and ``k + 1``, and ``cells`` (per half): its cell
        (whose own ``h`` a mixed ring's half snaps past). ``{"outer": (halves, m), "inner": (halves, m), "units":
        (halves,), "cells": (halves,)}`` 0-based."""
        g = self.geom
        span = self.cells * g.width
        x = (np.arctan2(self.nodes[:, 1], self.nodes[:, 0]) * self.radius) % span
        key = np.column_stack([x, self.nodes[:, 2]])
        from scipy.spatial import cKDTree
        tree = cKDTree(key)
        out = {"outer": [], "inner": [], "units": [], "cells": []}
        for k, gk in enumerate(self.geoms):
            ends = {p: sleeve2d._beam_point(gk, p, 0.0) for p in (0.5 * g.c, 0.5 * g.L)}
            for side in (1, -1):
                for name, p in (("outer", 0.5 * g.L), ("inner", 0.5 * g.c)):
                    at = ((k * g.width + side * ends[p][0]) % span, ends[p][1])
                    ids = sorted(tree.query_ball_point(at, 1e-6 * g.L))
                    if not ids:
                        raise AssertionError(f"no node at the beam end {at} of cell {k}")
                    out[name].append(ids)
                out["units"].append(k if side > 0 else (k - 1) % self.cells)
                out["cells"].append(k)
        m = min(len(i) for i in out["outer"] + out["inner"])
        return {"outer": np.array([i[:m] for i in out["outer"]]), "inner": np.array([i[:m] for i in out["inner"]]),
                "units": np.array(out["units"]), "cells": np.array(out["cells"])}

    def exact_volume(self):
        """The wrapped solid's volume from the 2-D outline's area ``A``: a wall between radii ``rho_0`` and
        ``rho_1`` wrapped at ``phi = x / R`` has ``dV = (rho / R) dA drho``, so ``V = A T rho_mid / R``."""
        T = self.geom.T
        rho_mid = self.radius + (0.0 if self.wall == "mid" else 0.5 * T)
        return self.quad.area() * T * rho_mid / self.radius


def ring_mesh(g, n_cells=4, r=1, n_layers=1, wall="mid", top=None):
    """The N-cell ring as a closed cylinder of C3D20 bricks (see the module docstring); ``g`` one ``CellGeometry``
    or one per cell in ring order (a mixed ring: ``sleeve2d.cell_mesh``, a flat top at the tallest cell's height, or
    at ``top`` mm)."""
    n_cells, r, n_layers = _checked(n_cells, r, n_layers)
    if wall not in WALLS:
        raise ValueError(f"wall: {wall!r}; allowed: {', '.join(map(repr, WALLS))}")
    quad = sleeve2d.cell_mesh(g, r, n_cells, top)
    g = quad.geom
    _bottom, _top, pairs = sleeve2d._edges(quad)
    rep = np.arange(quad.n_nodes)
    for i, j in pairs:                                         # the seam: right edge -> first cell's left edge
        rep[i] = j
    E2 = rep[quad.elements]
    R = n_cells * g.width / (2 * math.pi)
    n_lev = 2 * n_layers + 1
    s = np.linspace(0.0, g.T, n_lev) - (0.5 * g.T if wall == "mid" else 0.0)
    # candidate node (2-D node a, level k): every level for quad corners, the corner levels for mid-sides
    ids = -np.ones((quad.n_nodes, n_lev), dtype=np.int64)
    corner = np.zeros(quad.n_nodes, bool)
    corner[np.unique(E2[:, :4])] = True
    used2 = np.unique(E2)
    want = np.zeros_like(ids, dtype=bool)
    want[np.ix_(used2, np.arange(0, n_lev, 2))] = True
    want[np.ix_(np.flatnonzero(corner), np.arange(n_lev))] = True
    a_idx, k_idx = np.nonzero(want)
    ids[a_idx, k_idx] = np.arange(a_idx.size)
    phi = quad.nodes[a_idx, 0] / R
    rho = R + s[k_idx]
    nodes = np.column_stack([rho * np.cos(phi), rho * np.sin(phi), quad.nodes[a_idx, 1]])
    els = []
    for lay in range(n_layers):
        k0, km, k1 = 2 * lay, 2 * lay + 1, 2 * lay + 2
        els.append(np.hstack([ids[E2[:, :4], k0], ids[E2[:, :4], k1], ids[E2[:, 4:], k0], ids[E2[:, 4:], k1],
                              ids[E2[:, :4], km]]))
    elements = np.vstack(els)
    assert elements.min() >= 0
    return RingMesh(nodes, elements, quad.geom, n_cells, R, wall, n_layers, quad, E2)


def _checked(n_cells, r, n_layers):
    return [checks.integer(name, v, lo, hi) for name, v, lo, hi in
            (("n_cells", n_cells, 3, sleeve2d.CELLS_MAX), ("r", r, 1, sleeve2d.R_MAX), ("n_layers", n_layers, 1, 8))]


def ring_deck3d(g, n_cells=4, r=1, n_layers=1, d_max=None, increments=70, bias=1e-5, bias_angle=0.5,
                radial="free", method="static", element="C3D20R", patient=False, stability=0, shapes=False,
                imperfection=None, full_near=0.0, print_all=False, full_low=False, watch=None, unload=False,
                top=None):
    """``(deck, meta)``: the curved ring under a rising, tilting rigid top plate (module docstring); ``d_max`` in
    mm (default 0.25 L), ``bias`` in ``G L^2`` (a moment ``bias L^2 R`` towards ``bias_angle * pi / N``).
    ``radial="fixed"`` holds every node between the bars at its radius (a cylindrical ``*TRANSFORM``): the wall
    can then neither bulge nor thin, the curved counterpart of the flat ring's plane strain (a check).
    ``radial="<part>"`` (one of ``PARTS``: ``RingMesh.parts``) holds only that part's nodes (the clamped and the
    plate's edges excluded) at its radius: which part's radial freedom softens the ring.
    ``method="dynamic"``: implicit dynamics (``*DYNAMIC``, HHT ``ALPHA=-0.3``) with the load ramped over a step
    of time 1 and a small density (``DENSITY``, with G = 1 MPa: the ring's lowest period a few thousandths of
    the step; rubber's would excite oscillations at the start and slow the run). The inertia regularises the
    near-singular tilt mode and carries the ring into a snap, where static Newton (displacement control, no arc
    length in ccx) stalls; between snaps it is the static path (the seed's FE used the dynamic implicit method,
    loading slowly, too). ``patient=True`` lets Newton run longer before ccx cuts an increment back
    (``*CONTROLS``: divergence checked from iteration 8 instead of 4, at most 30 iterations).
    ``element="C3D20"``: full integration (a check of the reduced one's hourglass freedom; locks somewhat).
    ``stability=n``: after the loading step, a ``*FREQUENCY`` perturbation step for the ``n`` eigenvalues of the
    tangent stiffness (with the mass of ``DENSITY``) nearest zero at the state reached: all positive means the
    state is stable under displacement control; a negative one means the path traced there is unstable (a branch
    the static solver follows that the ring would leave). ``shapes=True`` prints every node's mode displacement too.
    ``imperfection``: an ``(n_nodes, 3)`` array in mm added to the mesh's nodes (a geometric imperfection, e.g. a
    scaled unstable mode, to follow the branch the ring takes instead of the symmetric one).
    ``full_near`` (mm): the beam's bricks within that distance of its two re-entrant corners
    (``RingMesh.beam_end_elements``) fully integrated (C3D20, element set ``SOLIDF``), the rest ``element``: on
    r = 2 the reduced bricks at the beam's underside next to the central pillar fold in reduced integration's
    spurious mode (nodal ``det F`` 0.73 while the integration points stay at 1.000) and stop static Newton at d/L
    0.468 (docs/sleeves.md, "One or two stages"). ``full_low=True``: with the bricks of the beam's continuation
    into the edge pillar (``edge_pillar_low``) within ``full_near`` of the pillar's side too: on r = 3 those
    reduced bricks fold the same way (nodal ``det F`` 0.77) and stop Newton at d/L 0.157. ``print_all=True`` prints every node's displacement at every
    increment (set ``ALLN``; ``solve_ring3d`` returns the last converged one). ``watch``: 0-based node ids whose
    displacements are printed at every increment (set ``WATCH``; ``solve_ring3d`` returns them all: the beams'
    ends, ``RingMesh.beam_ends``, for ``hysterons``). ``g``: one ``CellGeometry``, or one per cell (a mixed ring,
    ``ring_mesh``). ``unload=True``: the step runs on for a second unit of time along an amplitude
    that lowers the plate back to its start (0 -> 1 -> 0; the bias moment, ramped up over the first, held), as
    the frame's cycle (``core/sleeve/frame3d_sequence.py``): a second ``*STEP`` from the deformed ring does not
    converge (its first increment diverged at every size down to 5e-5 of the step, measured at d/L 0.2); with
    ``method="dynamic"`` the same amplitude replaces the loading ramp. ``top``:
    ``ring_mesh``'s."""
    mesh = ring_mesh(g, n_cells, r, n_layers, top=top)
    g = mesh.geom
    check_procedure(element, method)
    if radial not in ("free", "fixed") + PARTS:
        raise ValueError(f"radial: {radial!r}; allowed: 'free', 'fixed' or a part: {', '.join(map(repr, PARTS))}")
    if isinstance(stability, bool) or int(stability) != stability or not 0 <= stability <= 20:
        raise ValueError(f"stability: {stability!r}; allowed: an integer from 0 (none) to 20 eigenvalues")
    if not 0 <= full_near <= 0.5 * g.L:
        raise ValueError(f"full_near: {full_near!r} mm; allowed: 0 (none) to L/2 = {0.5 * g.L:g} mm")
    increments = checks.integer("increments", increments, 1)
    sleeve2d.check_bias(bias, bias_angle, "a moment bias L^2 R")
    d_max = 0.25 * g.L if d_max is None else float(d_max)
    if not 0 < d_max <= 1.5 * g.L:
        raise ValueError(f"d_max: {d_max!r} mm; allowed: 0 < d_max <= 1.5 L = {1.5 * g.L:g} mm")
    if watch is not None:
        watch = checked_watch(watch, mesh.n_nodes)
    X = mesh.nodes
    full = mesh.beam_end_elements(full_near, low=full_low)
    tol = 1e-7 * g.L
    if imperfection is not None:
        imp = np.asarray(imperfection, float)
        t_min = min(x.t for x in mesh.geoms)
        if imp.shape != X.shape or not np.all(np.isfinite(imp)) or np.abs(imp).max() > 0.1 * t_min:
            raise ValueError(f"imperfection: shape {imp.shape}, largest {np.abs(imp).max() if imp.size else 0:g} mm; "
                             f"allowed: finite offsets of shape {X.shape}, at most 0.1 t = {0.1 * t_min:g} mm")
    bottom = np.flatnonzero(np.abs(X[:, 2]) < tol)
    top = np.flatnonzero(np.abs(X[:, 2] - mesh.height) < tol)
    if imperfection is not None:                   # the clamped and the plate's edges stay where they are
        imp = imp.copy()
        imp[np.concatenate([bottom, top])] = 0.0
        X = X + imp
    out = [f"*HEADING\nmetamaterial_wb: sleeve ring, curved 3-D solid ({element}), rigid tilting top plate\n",
           "*NODE\n", ccx.fmt_nodes(X), f"{REF},0,0,{mesh.height:.9g}\n{ROT},0,0,{mesh.height:.9g}\n",
           _element_text(mesh, element, full),
           "*NSET, NSET=BOTTOM\n", ccx.fmt_set(bottom + 1), "*NSET, NSET=TOP\n", ccx.fmt_set(top + 1),
           f"*NSET, NSET=NREF\n{REF}\n*NSET, NSET=NROT\n{ROT}\n",
           ("*NSET, NSET=SHAPE\n" + ccx.fmt_set(np.arange(1, mesh.n_nodes + 1)) if shapes else ""),
           ("*NSET, NSET=ALLN\n" + ccx.fmt_set(np.arange(1, mesh.n_nodes + 1)) if print_all else ""),
           ("*NSET, NSET=WATCH\n" + ccx.fmt_set(watch + 1) if watch is not None else ""),
           material_text(method == "dynamic" or stability),
           ("*SOLID SECTION, ELSET=SOLIDF, MATERIAL=RUBBER\n" if full.size else ""),
           f"*RIGID BODY, NSET=TOP, REF NODE={REF}, ROT NODE={ROT}\n"]
    if radial != "free":
        held = np.ones(mesh.n_nodes, bool) if radial == "fixed" else mesh.parts()[radial].copy()
        held[np.concatenate([bottom, top])] = False
        inner = np.flatnonzero(held)
        out += ["*NSET, NSET=WALL\n", ccx.fmt_set(inner + 1), "*TRANSFORM, NSET=WALL, TYPE=C\n0,0,0,0,0,1\n"]
    amp, amp_text = amplitudes(method, unload)
    out.append(amp_text)
    bc = f"*BOUNDARY{amp}\nBOTTOM,1,3,0\n{REF},1,2,0\n{REF},3,3,{d_max:.12g}\n"
    if radial != "free":
        bc += "WALL,1,1,0\n"
    bc += bias_text(bias * g.L ** 2 * mesh.radius, bias_angle * math.pi / n_cells, amp, unload)
    prints = ("*NODE PRINT, NSET=BOTTOM\nRF\n*NODE PRINT, NSET=NROT\nU\n"
              + ("*NODE PRINT, NSET=ALLN\nU\n" if print_all else "")
              + ("*NODE PRINT, NSET=WATCH\nU\n" if watch is not None else ""))
    out.append(step_text(method, unload, increments, patient, bc + prints))
    if stability:
        out.append(f"*STEP, PERTURBATION\n*FREQUENCY\n{int(stability)}\n*NODE PRINT, NSET=NROT\nU\n"
                   + ("*NODE PRINT, NSET=SHAPE\nU\n" if shapes else "") + "*END STEP\n")
    meta = {"mesh": mesh, "bottom": bottom, "radius_mm": mesh.radius, "d_max_mm": d_max, "r": int(r),
            "n_layers": int(n_layers),
            "dofs": 3 * mesh.n_nodes, "elements": mesh.n_elements, "increments": int(increments),
            "n_cells": int(n_cells), "bias": bias, "bias_angle": bias_angle, "radial": radial,
            "method": method, "element": element, "patient": patient, "stability": int(stability),
            "full_near": float(full_near), "full_low": bool(full_low), "full_elements": int(full.size),
            "unload": bool(unload), "top_mm": mesh.height}
    return "".join(out), meta


def check_procedure(element, method):
    """Refuse a brick type or a procedure the solid decks do not write."""
    if element not in ("C3D20R", "C3D20"):
        raise ValueError(f"element: {element!r}; allowed: 'C3D20R' (reduced integration), 'C3D20' (full)")
    if method not in ("static", "dynamic"):
        raise ValueError(f"method: {method!r}; allowed: 'static', 'dynamic'")


def checked_watch(watch, n_nodes):
    """The node ids ``watch`` (0-based) sorted and unique, or an error naming them unless 1 or more of 0 to
    ``n_nodes - 1``."""
    watch = np.unique(np.asarray(watch, dtype=np.int64).ravel())
    if not watch.size or watch[0] < 0 or watch[-1] >= n_nodes:
        raise ValueError(f"watch: {watch.size} node ids from {watch.min() if watch.size else '-'} to "
                         f"{watch.max() if watch.size else '-'}; allowed: 1 or more of 0 to {n_nodes - 1}")
    return watch


def material_text(dense, damping=0.0):
    """The neo-Hooke rubber (``sleeve2d.BULK_RATIO``) of element set ``SOLID``, with the small density ``DENSITY``
    when ``dense`` (implicit dynamics, or a ``*FREQUENCY`` step) and mass-proportional Rayleigh damping ``damping``
    (``ALPHA`` in 1/s: a damping ratio ``damping / (2 omega)`` at the angular frequency ``omega``; none for 0).
    Stiffness-proportional damping (``BETA``) would damp the nearly incompressible rubber's volumetric modes too:
    with ``BETA`` 1e-3 s the stacked ring's first increments fell to 1e-5 of the step and ccx stopped at d/L
    0.0014 (measured)."""
    return ("*MATERIAL, NAME=RUBBER\n*HYPERELASTIC, NEO HOOKE\n0.5,%.9g\n" % (2.0 / sleeve2d.BULK_RATIO)
            + ("*DENSITY\n%.3g\n" % DENSITY if dense else "")
            + ("*DAMPING, ALPHA=%.6g, BETA=0.\n" % damping if damping else "")
            + "*SOLID SECTION, ELSET=SOLID, MATERIAL=RUBBER\n")


def amplitudes(method, unload):
    """``(suffix, cards)``: the amplitude the plate's rise follows (``", AMPLITUDE=..."`` or none) and the
    ``*AMPLITUDE`` cards it needs. ``unload``: up over the step's first unit of time, back down over its second
    (``UPDOWN``), the bias held (``HOLD``); else static ramps by default and dynamics along ``RAMP``."""
    if unload:
        return ", AMPLITUDE=UPDOWN", "*AMPLITUDE, NAME=UPDOWN\n0,0,1,1,2,0\n*AMPLITUDE, NAME=HOLD\n0,0,1,1,2,1\n"
    if method == "dynamic":
        return ", AMPLITUDE=RAMP", "*AMPLITUDE, NAME=RAMP\n0,0,1,1\n"
    return "", ""


def bias_text(moment, phi, amp, unload):
    """The tilt bias: a moment ``moment`` (N mm) on the top plate's rotation node ``ROT`` about the axis at the angle
    ``phi`` + 90 deg (it raises the plate's side at ``phi``), along the rise's amplitude ``amp`` (``amplitudes``) or
    held after the loading (``unload``); none for a zero moment."""
    if not moment:
        return ""
    return (f"*CLOAD{', AMPLITUDE=HOLD' if unload else amp}\n{ROT},1,{moment * math.sin(phi):.12g}\n"
            f"{ROT},2,{-moment * math.cos(phi):.12g}\n")


def step_text(method, unload, increments, patient, body):
    """One nonlinear ``*STEP`` (static or implicit dynamics, HHT ``ALPHA=-0.3``) of time 1, or 2 with ``unload``,
    in ``increments`` per unit of time at most (down to 1e-4 of one), ``patient`` Newton (``ring_deck3d``), with
    ``body`` (boundary conditions, loads, prints)."""
    inc = 1.0 / checks.integer("increments", increments, 1)
    proc = "*DYNAMIC, ALPHA=-0.3" if method == "dynamic" else "*STATIC"
    return (f"*STEP, NLGEOM, INC=100000\n{proc}\n{inc:.6g},{2.0 if unload else 1.0},{inc / 1e4:.6g},{inc:.6g}\n"
            + ("*CONTROLS, PARAMETERS=TIME INCREMENTATION\n8,12,13,30,10,4,0,5\n" if patient else "")
            + body + "*END STEP\n")


def _element_text(mesh, element, full_ids):
    """``*ELEMENT`` cards: every brick ``element`` in set ``SOLID``, but the bricks ``full_ids`` (0-based: the
    beam's bricks near its re-entrant corners) C3D20 in set ``SOLIDF``."""
    ids = np.arange(1, mesh.n_elements + 1)
    full = np.zeros(mesh.n_elements, bool)
    full[full_ids] = True
    out = f"*ELEMENT, TYPE={element}, ELSET=SOLID\n" + ccx.fmt_elements(mesh.elements[~full], ids[~full])
    if full.any():
        out += "*ELEMENT, TYPE=C3D20, ELSET=SOLIDF\n" + ccx.fmt_elements(mesh.elements[full], ids[full])
    return out


def solve_ring3d(g, n_cells=4, r=1, n_layers=1, d_max=None, increments=70, bias=1e-5, timeout_s=3600.0,
                 partial=True, radial="free", method="static", element="C3D20R", patient=False, stability=0,
                 shapes=False, imperfection=None, bias_angle=0.5, full_near=0.0, print_all=False, full_low=False,
                 watch=None, unload=False, top=None):
    """Force-displacement curve of the curved ring and its tilt: ``{"d": d / L, "F": F / (G L^2), "tilt_rad"
    (k, 2): (psi_x, psi_y)}`` per converged increment (with the unloaded start), and the run info. With
    ``partial=True`` a run that stops before ``d_max`` returns what converged (``info["stopped"]`` says why,
    ``info["d_reached"]`` how far, in ``d / L``). ``stability=n`` (a run that reached ``d_max``): ``info["stability"]``
    holds the ``n`` eigenvalues at the end (``ring_deck3d``), each with its mode's plate rotation (about X, Y, Z:
    the tilt pair and the twist are told apart by it; its size, as ccx normalises the modes to unit mass: a mode
    that leaves the plate still has none), and ``stable`` (all positive); with ``shapes=True`` the curve holds
    ``"modes"``, ``(n, n_nodes, 3)``; with ``print_all=True`` ``"u"``, the last converged increment's node
    displacements ``(n_nodes, 3)`` (``RingMesh.volume_ratios`` reads them); with ``watch`` (node ids) ``"u_watch"``,
    ``(k, len(watch), 3)``, those nodes' displacements at every point of the curve (zero at the start), in the
    order given. ``full_near``, ``full_low``, ``top``, ``g`` (a mixed ring: one geometry per cell): ``ring_deck3d``. With
    ``unload=True`` the curve goes on back down to the start (``ring_deck3d``): ``"unloading"`` (k,) marks its
    points (d falls along them; ccx's time past 1), ``info["d_reached"]`` is then the last point's rise."""
    deck, meta = ring_deck3d(g, n_cells, r, n_layers, d_max, increments, bias, bias_angle, radial=radial, method=method,
                             element=element, patient=patient, stability=stability, shapes=shapes,
                             imperfection=imperfection, full_near=full_near, print_all=print_all,
                             full_low=full_low, watch=watch, unload=unload, top=top)
    g = meta["mesh"].geom
    tables, info = ccx.run(deck, "sleeve_ring3d", timeout_s, partial=partial)
    rows = ccx.table(tables, ("forces", "BOTTOM"), "sleeve_ring3d", meta["bottom"] + 1, info)
    t = np.array([r_[0] for r_ in rows])
    F = -np.array([sum(v[2] for v in r_[1].values()) for r_ in rows])
    rot = ccx.table(tables, ("displacements", "NROT"), "sleeve_ring3d", [ROT], info)
    tilt = np.array([r_[1][ROT][:2] for r_ in rot])[:len(t)]
    down = t > 1.0 + 1e-9                                  # ccx's time: unloading from 1 to 2
    d = np.where(down, 2.0 - t, t) * meta["d_max_mm"] / g.L
    info.update({k: meta[k] for k in ("r", "n_layers", "dofs", "elements", "d_max_mm", "n_cells", "radius_mm",
                                      "bias", "bias_angle", "radial", "method",
                                      "element", "patient", "full_near", "full_low", "full_elements")})
    eig = info.pop("eigenvalues", [])
    if stability and eig and "stopped" not in info:
        modes = [np.asarray(r_[1][ROT][:3], float) for r_ in rot[len(t):]]
        info["stability"] = {"d": float(d[-1]), "eigenvalues": eig[0],
                             "plate_rotation": [(m / (np.linalg.norm(m) or 1.0)).tolist() for m in modes],
                             "plate_rotation_size": [float(np.linalg.norm(m)) for m in modes],
                             "stable": bool(min(eig[0]) > 0)}
    info["increments"] = len(t)
    info["d_reached"] = float(d[-1])
    out = {"d": np.concatenate([[0.0], d]), "F": np.concatenate([[0.0], F / g.L ** 2]),
           "tilt_rad": np.vstack([[0.0, 0.0], tilt.reshape(-1, 2)])}
    if unload:
        out["unloading"] = np.concatenate([[False], down])
    last = tables.get(("displacements", "ALLN"), [])[:len(t)]
    if print_all and last:
        out["u"] = np.array([last[-1][1][i + 1][:3] for i in range(meta["mesh"].n_nodes)])
    if watch is not None:
        ids = np.asarray(watch, dtype=np.int64).ravel() + 1
        rows_w = tables.get(("displacements", "WATCH"), [])[:len(t)]
        out["u_watch"] = np.array([np.zeros((ids.size, 3))] + [[r_[1][i][:3] for i in ids] for r_ in rows_w])
    allu = tables.get(("displacements", "SHAPE"), [])
    if shapes and allu:
        n = meta["mesh"].n_nodes
        out["modes"] = np.array([[r_[1].get(i + 1, np.zeros(3))[:3] for i in range(n)] for r_ in allu])
    return out, info


def hysterons(mesh, ends, u_watch, watch):
    """The hysterons' states along a run, by the beam model's rule (``analysis.snap_order``; the frame's
    ``trace_ring``): each beam half's rise, its outer end's axial displacement over its inner end's (each the
    mean through the wall) in units of L, ``(k, halves)``, and per edge pillar (``ends["units"]``) whether it has
    snapped: the mean of its two halves' rises beyond their cells' ``h / L``, ``(k, n_cells)``. ``ends``:
    ``RingMesh.beam_ends``; ``u_watch`` (k, m, 3): the displacements of the nodes ``watch`` (``solve_ring3d``)."""
    pos = {int(n): i for i, n in enumerate(np.asarray(watch).ravel())}
    uz = np.asarray(u_watch, float)[:, :, 2]

    def mean_z(ids):
        return np.stack([uz[:, [pos[int(n)] for n in row]].mean(axis=1) for row in ids], axis=1)
    from metamaterial_wb.core.sleeve.analysis import units_snapped
    rise = (mean_z(ends["outer"]) - mean_z(ends["inner"])) / mesh.geom.L
    h = np.array([mesh.geoms[k].h for k in ends["cells"]]) / mesh.geom.L     # each half's own cell's h / L
    return rise, units_snapped(rise, h, ends["units"])


def all_extrema(d, F, rel_prominence=0.02):
    """Every alternating peak and valley of a force curve, as the sleeve analysis counts them
    (``core.sleeve.analysis.extrema``: a wiggle smaller than ``rel_prominence`` of the curve's range is none),
    each refined by a parabola through its three points: a list of ``("peak"|"valley", d, F)``."""
    from metamaterial_wb.core.sleeve.analysis import extrema
    d, F = np.asarray(d, float), np.asarray(F, float)
    p, v = extrema(F, rel_prominence)
    out = []
    for i in sorted(p + v):
        kind = "peak" if i in p else "valley"
        x, y = float(d[i]), float(F[i])
        if 0 < i < len(F) - 1:
            A = np.polyfit(d[i - 1:i + 2], F[i - 1:i + 2], 2)
            if A[0] != 0 and d[i - 1] <= -A[1] / (2 * A[0]) <= d[i + 1]:
                x = float(-A[1] / (2 * A[0]))
                y = float(np.polyval(A, x))
        out.append((kind, x, y))
    return out


peak_valley = sleeve2d.peak_valley

__all__ = ["ring_mesh", "ring_deck3d", "solve_ring3d", "hysterons", "all_extrema", "peak_valley", "RingMesh"]
