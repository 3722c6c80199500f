"""Force-displacement models of one unit cell, one ring of cells and a sleeve of rings.

Mechanics (see ``docs/sleeves.md``):

* single layout (default): per cell one cosine beam whose two free halves are chains of
  corotational beam elements (``beam.py``); the central pillar (standing on the bottom bar) and the
  edge pillars (hanging from the top bar, each shared by two neighbouring cells) are beam chains of
  width ``c``; the bars are rigid with their ring interface. Double layout (the former reading):
  two parallel beams, rigid pillars, central pillar rigid with the top bar;
* units: lengths / L, forces / (G L^2): the material enters only through ``E = 4 G`` (incompressible
  neo-Hookean, small-strain plane-strain modulus, out-of-plane motion restricted as in the seed) or
  ``E = 3 G`` (``plane="stress"``); section ``A = t T``, ``I = T t^3 / 12``;
* unit cell: the top bar's vertical displacement ``d`` is prescribed, its horizontal shift free;
  the periodic left/right edges share the edge pillar (elements joined to its periodic image), so
  the top bar cannot rotate (single layout; the double layout's central pillar may rotate);
* ring of N cells (the cells unrolled side by side, closing on themselves; a point at unrolled x
  sits at the angle ``phi = x / R`` on the mid radius ``R``) and M rings in series: every ring
  interface is a rigid plate with axial displacement ``w``, tilt ``(psi_x, psi_y)`` and twist; a
  node fixed to it at ``phi`` moves by ``v = w + R (psi_x sin phi - psi_y cos phi)``, rotates in
  the cell's plane by ``psi_x cos phi + psi_y sin phi`` and shifts tangentially by ``R * twist``;
  the top plate's ``w = d`` is prescribed, all tilts are free;
* ring curvature (single layout, ``radial_end_stiffness``): the beams are arcs on the cylinder;
  their axial force presses the pillars outward, which lengthens the arcs (tangential springs at the
  beam ends), and a tilted bar swings its pillars' tips radially (tilt-dependent shifts of the beam
  ends). A flat unit cell has neither;
* path following: displacement control with a secant predictor; at every step the total energy is
  *minimised* (Newton with Cholesky; a negative-curvature direction from the smallest eigenvector
  when the tangent is indefinite), so the traced path is the stable one a slow, quasi-static
  displacement-controlled test follows: through negative stiffness continuously, and with a jump
  (recorded as an event) where the stable branch ends (snap-back).
"""
import time
from dataclasses import dataclass

import numpy as np

from metamaterial_wb.core.errors import MetamaterialError, SceneError, check_number
from metamaterial_wb.core.sleeve.beam import BeamMesh
from metamaterial_wb.core.sleeve.tangent import TangentSolver

LINK_FACTOR = 1.0e3     # stiffness of the rigid-body links relative to the beam's axial stiffness
# A traced path's force resolution (``Path.noise``), in units of the equilibrium tolerance ``trace`` converges to (the
# residual force's norm, 1e-9 of the stiffest element's axial stiffness / LINK_FACTOR, so it scales with the model's
# forces): below it a force is round-off, not mechanics. Measured on strokes of 1e-10 L, where the force is nothing
# else (docs/sleeves.md, "Force resolution"): a unit cell's reaction is at most 1.03 tolerances, a ring's at d = 0
# without its bias moment at most 5.2 (2-32 cells, L 6-200 mm); the slenderest cell's valley (t 0.4 on L 200 mm) is
# 57 times the resolution, the seed's peak 4e5 times. The bias moment's own push at rest is no round-off: counted
# apart (pipeline.force_resolution).
FORCE_NOISE_FACTOR = 100.0
# The smallest eigenvalue of an indefinite tangent that is its round-off, not a saddle, relative to its largest
# diagonal entry (~4500 machine epsilons; the path's physical eigenvalues are >= 1e-9 of it): a perfect ring's lean
# direction on its leaning branch (``model.imperfection`` 0) measured -1.1e-14.
NEUTRAL_CURVATURE = 1e-12
# Its residual's round-off floor, in tolerances: measured 1.16-1.27 (numpy of FreeCAD 1.1 and 0.20) on that branch,
# where no energy is released along the mode; well inside the path's force resolution (FORCE_NOISE_FACTOR).
NEUTRAL_RESIDUAL = 10.0
# A shallow saddle's shortened step (``SleeveModel._shallow_saddle_step``) is tried while the energy it should release
# (the tangent's prediction) exceeds this fraction of the energy: the energy's round-off measured ~5e-16 of it (a
# two-cell perfect ring at d/L 0.93).
SADDLE_ENERGY_FLOOR = 1e-14
# A ring-curvature end spring (the soft axial link of ``add_row_single``) shorter than this fraction of its length: past
# the linear springs' range; its link degenerates as its length nears zero (a mixed two-cell ring at d/L 0.94: 1.7%).
SPRING_COLLAPSE = 0.1


def modulus(plane="strain"):
    """Young's modulus in units of G for an incompressible neo-Hookean material."""
    if plane == "strain":
        return 4.0
    if plane == "stress":
        return 3.0
    raise MetamaterialError(f"plane: {plane!r}; allowed: 'strain', 'stress'")


class _MeshBuilder:
    """Accumulates nodes and elements (units of L) of a sleeve, and the nodes rigidly attached to a
    ring interface ("plate"): ``ties`` = (node, plate, angle)."""

    def __init__(self):
        self.X, self.conn, self.EA, self.EI, self.shift = [], [], [], [], []
        self.ties = []
        self.slaves = []     # (node, master node, plate, x, coef): node = master shifted by coef * tilt
        self.states = []     # (outer node, inner node or None, cell number): one per snapping beam part
        self.units = []      # per state: the hysteron (rigid body) it belongs to
        self.springs = []    # (element, cell number, pillar): the ring-curvature end springs

    def node(self, x, y):
        self.X.append(np.array([x, y], dtype=float))
        return len(self.X) - 1

    def element(self, i, j, EA, EI, shift=(0.0, 0.0)):
        self.conn.append((i, j)); self.EA.append(EA); self.EI.append(EI)
        self.shift.append(np.asarray(shift, dtype=float))

    def link(self, i, j, EA_b, shift=(0.0, 0.0), k_axial=None):
        """Rigid link (stiff beam element) between nodes i and j; ``k_axial``: an elastic axial
        stiffness (force per length) instead of a rigid one (bending stays rigid)."""
        ell = float(np.hypot(*(self.X[j] - self.X[i] + np.asarray(shift))))
        EA = LINK_FACTOR * EA_b if k_axial is None else k_axial * ell
        self.element(i, j, EA, LINK_FACTOR * EA_b * ell ** 2 / 12.0, shift)

    def chain(self, xs, ys, EA, EI):
        idx = [self.node(x, y) for x, y in zip(xs, ys)]
        for i, j in zip(idx[:-1], idx[1:]):
            self.element(i, j, EA, EI)
        return idx


def _segment_nodes(geom, n_el, side, which=0, root_extension=0.0):
    """Cosine-graded nodes (units of L) of one free beam segment, from the central pillar outward.
    ``root_extension``: how far (in units of the beam's thickness t) the flexible beam continues into each
    pillar past its face (root flexibility, see :data:`ROOT_EXTENSION_FE`); 0 clamps it at the faces."""
    L, c = geom.L, geom.c / geom.L
    e = root_extension * geom.t / L
    s = 0.5 * (1 - np.cos(np.linspace(0, np.pi, n_el + 1)))
    xs = side * (c / 2 - e + (0.5 - c / 2 + 2 * e) * s)
    return xs, geom.centre_line(xs * L, which) / L


def _sections(geom, E, t_scale=1.0):
    t, T = geom.t * t_scale / geom.L, geom.T / geom.L
    return E * t * T, E * T * t ** 3 / 12.0


PILLAR_ELEMENTS = 3
# Root flexibility (issue 18): a beam built into a support of its own soft material is not clamped at the
# support's face; the support's material near the root deforms too, so the beam behaves as if clamped a
# fraction of its thickness inside (the classical root-rotation correction of cantilevers built into elastic
# walls). Fitted on the CalculiX unit cell's converged peak (bench/fe_sleeve_calibration.py, docs/sleeves.md
# "Calibrating the beam model on CalculiX") and checked on the four-cell ring it was not fitted on. Not the
# default: ``root_extension=0`` keeps the beam model as documented, every table of docs/sleeves.md included.
ROOT_EXTENSION_FE = 0.63
BIAS_ANGLE = 0.5   # the imperfection's direction, in units of pi / N from cell 0's centre
E_RADIAL = 3.0     # modulus / G for bending through the wall thickness T (narrow sections: plane stress)
PILLAR_TIP = {"free": 3.0, "guided": 12.0}   # cantilever k_r = coef E I / a^3 by the tip's rotation


def pillar_tip_coefficient(pillar_tip):
    """``"guided"`` (12: tip rotation held, the default), ``"free"`` (3) or a number in [3, 12]."""
    if isinstance(pillar_tip, str):
        if pillar_tip not in PILLAR_TIP:
            raise SceneError("model.pillar_tip", f"{pillar_tip!r}; allowed: 'guided', 'free' or a number in [3, 12]")
        return PILLAR_TIP[pillar_tip]
    return check_number("model.pillar_tip", pillar_tip, 3, 12, "")


def radial_end_stiffness(g, radius, pillar_tip="guided"):
    """Tangential stiffness (units G L) that the ring's curvature leaves at the two ends of a free
    beam half (central-pillar end, edge-pillar end), or (None, None) for a flat cell.

    On a cylinder of radius R the beams are arcs: an axial force P in a half of length l presses
    the arc outward with P / R per length, P l / (2 R) on each end pillar; every pillar carries two
    halves, so it is pushed out by F = P l / R. A pillar is a cantilever from its bar (length a,
    bent through the wall thickness: k_r = 3 E I / a^3, I = c T^3 / 12), so it moves out by
    u = F / k_r, and the arc between two pillars lengthens by l (u_c + u_e) / (2 R): the half
    behaves as if its ends sat on tangential springs k = 2 R^2 k_r / l^2 (one per end). The pillar
    tip's rotation is restrained by the two beam halves it carries: between a free tip (k_r =
    3 E I / a^3) and a guided one (12 E I / a^3, ``pillar_tip="guided"``, the default; see
    docs/sleeves.md for why and for the sensitivity). This is the
    seed's observation (SI S3.1) that the beams' end points move outward, away from the structure,
    which limits the negative stiffness; a flat periodic cell (the seed's unit cell, out-of-plane
    motion restricted) has none of it.
    """
    if radius is None or not np.isfinite(radius):
        return None, None
    L = g.L
    c, T = g.c / L, g.T / L
    l = 0.5 * (g.L - g.c) / L
    I = c * T ** 3 / 12.0
    a_c = (g.centre_line(0.0) - 0.5 * g.c) / L                       # central pillar, on the bottom bar
    a_e = (g.height - 0.5 * g.c - g.y_lower) / L                      # edge pillar, from the top bar
    coef = pillar_tip_coefficient(pillar_tip)
    k_c = coef * E_RADIAL * I / a_c ** 3
    k_e = coef * E_RADIAL * I / a_e ** 3
    return 2 * radius ** 2 * k_c / l ** 2, 2 * radius ** 2 * k_e / l ** 2


def add_row_double(mb, row, cells, n_el, E, plate_lo, plate_hi, x_of, cell_no):
    """Double layout (the former reading): two parallel beams per cell, edge pillars rigid with the
    lower bar (beam outer ends clamped there), central pillar rigid with the upper bar (one reference
    node, rigid links to the four inner beam ends)."""
    for k, typ in enumerate(row):
        g = cells[typ]
        EA_b, EI_b = _sections(g, E)
        x0 = x_of(k)
        ref = mb.node(x0, (g.y_lower + 0.5 * g.spacing) / g.L)
        mb.ties.append((ref, plate_hi, x0))
        for which in (0, 1):
            for side in (-1, 1):
                xs, ys = _segment_nodes(g, n_el, side, which)
                idx = mb.chain(x0 + xs, ys, EA_b, EI_b)
                mb.ties.append((idx[-1], plate_lo, x0 + xs[-1]))
                mb.link(ref, idx[0], EA_b)
        mb.states.append((ref, None, cell_no + k))
        mb.units.append(("cell", cell_no + k))


def add_row_single(mb, row, cells, n_el, E, plate_lo, plate_hi, x_of, cell_no, periodic_width,
                   radius=None, pillar_tip="guided", root_extension=0.0, flat_top=False):
    """Single layout (default): one cosine beam per cell, highest at its centre. The central pillar
    stands on the lower bar and carries the beam's centre; the edge pillars hang from the upper bar
    and carry the beam ends; each edge pillar is shared by two neighbouring cells. Pillars are beam
    chains of width c (same material: they bend and stretch), clamped into their bar; the bars are
    rigid with their ring interface. ``periodic_width``: x distance after which the row closes on
    itself (N W for a ring, W for a periodic unit cell). An edge pillar hangs from the taller of its two cells'
    top bars; ``flat_top``: from the row's tallest (every pillar as long: the curved solid's mixed ring,
    ``fe/sleeve2d.cell_mesh``)."""
    n = len(row)
    tallest = max(cells[t].height for t in row)
    pillar_bottom = []
    # edge pillars at x_of(k) + W/2, between cell k and k + 1
    for k in range(n):
        g, gn = cells[row[k]], cells[row[(k + 1) % n]]
        c = max(g.c, gn.c) / g.L
        EA_p, EI_p = E * (g.T / g.L) * c, E * (g.T / g.L) * c ** 3 / 12.0
        xe = x_of(k) + 0.5 * g.width / g.L
        ytop = ((tallest if flat_top else max(g.height, gn.height)) - 0.5 * g.c) / g.L
        ybot = min(g.y_lower, gn.y_lower) / g.L
        ys = np.linspace(ytop, ybot, PILLAR_ELEMENTS + 1)
        idx = mb.chain([xe] * len(ys), ys, EA_p, EI_p)
        mb.ties.append((idx[0], plate_hi, xe))
        pillar_bottom.append((idx[-1], xe))
    for k, typ in enumerate(row):
        g = cells[typ]
        EA_b, EI_b = _sections(g, E)
        c = g.c / g.L
        EA_p, EI_p = E * (g.T / g.L) * c, E * (g.T / g.L) * c ** 3 / 12.0
        x0 = x_of(k)
        ys = np.linspace(0.5 * g.c / g.L, g.centre_line(0.0) / g.L, PILLAR_ELEMENTS + 1)
        cp = mb.chain([x0] * len(ys), ys, EA_p, EI_p)
        mb.ties.append((cp[0], plate_lo, x0))
        k_c, k_e = radial_end_stiffness(g, radius, pillar_tip)
        for side in (-1, 1):
            xs, ys = _segment_nodes(g, n_el, side, root_extension=root_extension)
            idx = mb.chain(x0 + xs, ys, EA_b, EI_b)
            pb, xe = pillar_bottom[k if side > 0 else (k - 1) % n]
            ca, ea = cp[-1], pb
            if radius is not None:
                # a tilted bar swings its pillars' tips radially (hanging: outward where the bar
                # rises; standing: inward), which lengthens the arcs between them: the halves' ends
                # follow the tips shifted tangentially by (l / 2R) * (radial tip displacement)
                l = 0.5 * (g.L - g.c) / g.L
                a_c = (g.centre_line(0.0) - 0.5 * g.c) / g.L
                a_e = (g.height - 0.5 * g.c - g.y_lower) / g.L
                ca = mb.node(*mb.X[cp[-1]])
                mb.slaves.append((ca, cp[-1], plate_lo, x0, side * l * a_c / (2 * radius)))
                ea = mb.node(*mb.X[pb])
                mb.slaves.append((ea, pb, plate_hi, xe, side * l * a_e / (2 * radius)))
            mb.link(ca, idx[0], EA_b, k_axial=k_c)
            # the left end of cell 0 joins the last edge pillar's periodic image
            shift = (0.0, 0.0) if side > 0 or k > 0 else (periodic_width, 0.0)
            mb.link(ea, idx[-1], EA_b, shift, k_axial=k_e)
            if radius is not None:
                n_el_all = len(mb.conn)
                mb.springs += [(n_el_all - 2, cell_no + k, "central"), (n_el_all - 1, cell_no + k, "edge")]
            mb.states.append((idx[-1], idx[0], cell_no + k))
            mb.units.append(("pillar", plate_hi, k if side > 0 else (k - 1) % n))


@dataclass
class Path:
    """A traced FD path. ``d`` and ``F`` normalised (d / L, F / (G L^2))."""
    d: np.ndarray
    F: np.ndarray
    states: np.ndarray            # (n, ncells) top-body displacement of every cell, / L
    tilt: np.ndarray              # (n, 2) tilt (psi_x, psi_y) of the top plate, rad (zeros for a cell)
    theta: np.ndarray             # (n, ncells) in-plane rotation of every cell's top bar, rad
    jumps: list                   # indices i where the state jumped between i-1 and i
    iterations: int = 0
    seconds: float = 0.0
    noise: float = 0.0            # force resolution (F / (G L^2)): a force within it is round-off (FORCE_NOISE_FACTOR)


class SleeveModel(TangentSolver):
    """M rings of N cells (or one bare unit cell when ``ring is None``).

    ``cells``: list of CellGeometry, one per cell type; ``pattern``: list of rings, each a list of
    type indices around the circumference (ring 0 at the bottom). ``radius_L``: mid radius / L
    (default: the circumference is N cell widths).
    """

    def __init__(self, cells, pattern=None, n_el=10, plane="strain", radius_L=None,
                 imperfection=0.0, top_rotation="default", curvature=True, pillar_tip="guided",
                 root_extension=0.0):
        self.cells = list(cells)
        self.root_extension = check_number("model.root_extension", root_extension, 0.0, 2.0, " (units of t)")
        self.curvature = curvature
        pillar_tip_coefficient(pillar_tip)           # validate early
        self.unit = pattern is None
        self.pattern = [[0]] if pattern is None else [list(r) for r in pattern]
        self.M = len(self.pattern)
        self.N = len(self.pattern[0])
        L = self.cells[0].L
        if any(abs(g.L - L) > 1e-12 for g in self.cells):
            raise MetamaterialError("cell_types: every type must have the same L (cells share the ring)")
        W = self.cells[0].width / L
        self.radius = radius_L if radius_L is not None else self.N * W / (2 * np.pi)
        layouts = {g.layout for g in self.cells}
        if len(layouts) > 1:
            raise MetamaterialError("cell_types: every type must have the same layout")
        self.layout = layouts.pop()
        E = modulus(plane)
        mb = _MeshBuilder()
        self.cell_index = []
        for r, row in enumerate(self.pattern):
            x_of = lambda k: k * W            # noqa: E731  unrolled position of cell k's centre
            if self.layout == "double":
                add_row_double(mb, row, self.cells, n_el, E, r, r + 1, x_of, len(self.cell_index))
            else:
                add_row_single(mb, row, self.cells, n_el, E, r, r + 1, x_of, len(self.cell_index),
                               self.N * W, None if (self.unit or not self.curvature) else self.radius,
                               pillar_tip, self.root_extension)
            self.cell_index.extend((r, k, typ) for k, typ in enumerate(row))
        self.mesh = BeamMesh(np.vstack(mb.X), np.array(mb.conn), np.array(mb.EA), np.array(mb.EI),
                             np.vstack(mb.shift))
        # one "state" per snapping beam part: the rise of its outer end over its inner end (double
        # layout: of the central pillar), / L; snapped when it exceeds h / L
        self.state_nodes = [(a_, b_) for a_, b_, _ in mb.states]
        self.springs = list(mb.springs)
        self.state_cells = [ci for _, _, ci in mb.states]
        uids = sorted(set(mb.units), key=mb.units.index)
        self.state_units = [uids.index(u) for u in mb.units]
        self.state_types = [self.cell_index[ci][2] for ci in self.state_cells]
        self.state_geoms = [self.cells[t] for t in self.state_types]
        self.tops = np.array([a_ for a_, _, _ in mb.states])
        nfull = self.mesh.ndof
        tied = {n for n, _, _ in mb.ties} | {n for n, _, _, _, _ in mb.slaves}
        free = [i for i in range(nfull) if i // 3 not in tied]
        self.nfree = len(free)
        if top_rotation not in ("free", "fixed", "default"):
            raise MetamaterialError(f"top_rotation: {top_rotation!r}; allowed: 'free', 'fixed'")
        if top_rotation == "default":
            # a single-layout cell's top bar carries the edge pillars, which the periodic edges tie
            # to each other (seed: periodic left/right edges): no rigid rotation; a double-layout
            # cell's top is its central pillar, free to rotate (seed: kinematic coupling)
            top_rotation = "fixed" if self.layout == "single" else "free"
        self.rot_free = top_rotation == "free"
        if self.unit:
            nplate = 2 if self.rot_free else 1      # the top's horizontal shift (and rotation)
        else:
            nplate = 4 * (self.M - 1) + 3           # interfaces (w, psi_x, psi_y, twist); top: no w
        nred = self.nfree + nplate
        T = np.zeros((nfull, nred))
        P = np.zeros(nfull)
        T[free, np.arange(self.nfree)] = 1.0
        if self.unit:
            for n, p, x in mb.ties:
                if p == 0:
                    continue                                     # on the clamped bottom bar
                P[3 * n + 1] = 1.0
                T[3 * n, self.nfree] = 1.0                       # common horizontal shift
                if self.rot_free:                                # rigid rotation about x = 0
                    T[3 * n + 2, self.nfree + 1] = 1.0
                    T[3 * n + 1, self.nfree + 1] = x
        else:
            def plate(p):
                """Columns (w, psi_x, psi_y, twist) of plate p (0 = fixed bottom, M = top)."""
                if p == 0:
                    return (None, None, None, None)
                if p == self.M:
                    b = self.nfree + 4 * (self.M - 1)
                    return ("d", b, b + 1, b + 2)
                b = self.nfree + 4 * (p - 1)
                return (b, b + 1, b + 2, b + 3)
            for n, p, x in mb.ties:
                phi = x / self.radius
                sn, cs = np.sin(phi), np.cos(phi)
                w, px, py, tw = plate(p)
                if w is None:
                    continue
                T[3 * n, tw] += self.radius
                if w == "d":
                    P[3 * n + 1] += 1.0
                else:
                    T[3 * n + 1, w] += 1.0
                T[3 * n + 1, px] += self.radius * sn
                T[3 * n + 1, py] += -self.radius * cs
                T[3 * n + 2, px] += cs
                T[3 * n + 2, py] += sn
            for n, m, p, x, coef in mb.slaves:
                T[3 * n:3 * n + 3] = T[3 * m:3 * m + 3]
                P[3 * n:3 * n + 3] = P[3 * m:3 * m + 3]
                w, px, py, tw = plate(p)
                if px is None:
                    continue
                phi = x / self.radius
                T[3 * n, px] += coef * np.sin(phi)
                T[3 * n, py] -= coef * np.cos(phi)
        import scipy.sparse as sp
        self.T, self.P = sp.csr_matrix(T), P
        # imperfection: a tiny constant moment on the top plate that makes it rise towards the angle
        # BIAS_ANGLE * pi / N, half-way between a cell's centre (phi = 0) and the next edge pillar
        # (phi = pi / N): on no mirror axis of the ring (the axes pass through cells and pillars),
        # so no symmetric bifurcation is left for the solver (or the mesh) to decide, as the
        # seed's mesh imperfections decide it. ``tilt_reference``: the same direction as a unit
        # tilt in reduced coordinates, the mesh-independent tie-break of ``minimise``.
        self.bias = np.zeros(nred)
        self.tilt_reference = np.zeros(nred)
        if not self.unit:
            b = self.nfree + 4 * (self.M - 1)
            phi_b = BIAS_ANGLE * np.pi / self.N
            # a pillar at phi rises by R (psi_x sin phi - psi_y cos phi): psi ~ (sin phi_b, -cos phi_b)
            self.tilt_reference[b], self.tilt_reference[b + 1] = np.sin(phi_b), -np.cos(phi_b)
            if imperfection:
                mag = imperfection * float(np.max(self.mesh.EA)) / LINK_FACTOR * self.radius
                self.bias = mag * self.tilt_reference
        self.TT = self.T.T.tocsr()
        # sparse LDL^T-like factorisation (SuperLU, symmetric mode, diagonal pivots) for larger systems
        self.sparse = nred > 200
        self.nred = nred
        self.phi = np.array([2 * np.pi * k / self.N for (_, k, _) in self.cell_index])

    # ------------------------------------------------------------------------------------------
    def full(self, q, d):
        return self.T @ q + self.P * d

    def evaluate(self, q, d, need_hessian=True):
        e, g, K = self.mesh.evaluate(self.full(q, d), need_hessian, self.sparse)
        e -= float(self.bias @ q)
        gr = self.TT @ g - self.bias
        if K is None:
            Kr = None
        elif self.sparse:
            Kr = (self.TT @ K @ self.T).tocsc()
        else:
            Kr = np.asarray(self.TT @ np.asarray(self.TT @ K).T)
        return e, gr, Kr, float(self.P @ g)

    def tilt_of(self, q):
        if self.unit:
            return np.zeros(2)
        b = self.nfree + 4 * (self.M - 1)
        return np.array([q[b], q[b + 1]])

    def cell_states(self, q, d):
        """Per snapping beam part: rise of its outer end over its inner end (/ L) and the outer
        end's rotation."""
        qf = self.full(q, d)
        v = np.array([qf[3 * a + 1] - (qf[3 * b + 1] if b is not None else 0.0) for a, b in self.state_nodes])
        return v, qf[3 * self.tops + 2].copy()

    # ------------------------------------------------------------------------------------------
    def minimise(self, q, d, tol, maxit=60):
        """Local energy minimum at prescribed ``d`` starting from ``q``. Returns (q, F, iterations)."""
        it = 0
        kicked = 0
        while it < maxit:
            it += 1
            e, g, K, F = self.evaluate(q, d)
            gn = np.linalg.norm(g)
            solve, pd = self._factor(K)
            if pd and gn < tol:
                return q, F, it
            if pd:
                step = -solve(g)
                # converged to round-off: a tiny step, or a Newton decrement (the energy the step
                # would still release) at the energy's round-off level (soft modes, large forces)
                if np.abs(step).max() < 1e-12 or abs(float(g @ step)) < 1e-16 * max(abs(e), 1e-30):
                    return q + step, F, it
            else:
                v = self._descent_direction(q, d, e, g, K)
                # negative curvature: expanding search along the descent direction v
                best_a, best_e, a = 0.0, e, 1e-3
                while a <= 0.5:
                    ea = self._energy(q + a * v, d)
                    if ea < best_e:
                        best_a, best_e = a, ea
                        a *= 2.0
                    else:
                        break
                if best_a > 0:
                    q = q + best_a * v
                    continue
                # a neutral mode, not a saddle: the negative curvature is the tangent's round-off (a perfect ring's
                # leaning branch, where the lean's direction is free: ``model.imperfection`` 0) and no energy is
                # released along it; a kick would only turn the lean (docs/sleeves.md, "A perfect ring")
                neutral = -self._last_min_eig <= NEUTRAL_CURVATURE * float(np.abs(K.diagonal()).max())
                if neutral and gn < NEUTRAL_RESIDUAL * tol:
                    return q, F, it
                if gn < tol:
                    kicked += 1
                    if kicked > 20:
                        break
                    q = q + 1e-3 * v
                    continue
                shift = -self._last_min_eig * 1.5 + 1e-8 * np.mean(np.abs(K.diagonal()))
                if self.sparse:
                    import scipy.sparse as sp
                    import scipy.sparse.linalg as spla
                    step = -spla.spsolve((K + shift * sp.identity(K.shape[0], format="csc")).tocsc(), g)
                else:
                    step = -np.linalg.solve(K + shift * np.eye(len(K)), g)
                # on a neutral mode the residual cannot fall below its round-off floor: converged when the shifted
                # step's decrement is at the energy's round-off level (the criterion of the definite case)
                if neutral and abs(float(g @ step)) < 1e-16 * max(abs(e), 1e-30):
                    return q + step, F, it
                # a saddle converged to its round-off (the shifted step's decrement too), the first trial along v
                # too long: a shallow saddle next to its bifurcation, to be left by a shorter step
                if not neutral and abs(float(g @ step)) < 1e-16 * max(abs(e), 1e-30):
                    a = self._shallow_saddle_step(q, d, e, v)
                    if a > 0:
                        q = q + a * v
                        continue
            # backtracking on the energy (full step accepted when it does not raise the energy)
            a = 1.0
            smax = np.abs(step).max()
            if smax > 0.05:
                a = 0.05 / smax
            for _ in range(30):
                e2 = self._energy(q + a * step, d)
                if e2 <= e + 1e-14 * max(1.0, abs(e)):
                    break
                a *= 0.5
            q = q + a * step
        raise _NoConvergence()

    def _shallow_saddle_step(self, q, d, e, v):
        """A step along the negative-curvature direction ``v`` shorter than the first trial (1e-3), or 0.

        Just past a symmetry-breaking bifurcation of a perfect ring (``model.imperfection`` 0; a two-cell ring's
        twist near full stretch) the symmetric state is a shallow saddle: the branch it falls to lies closer than
        1e-3, where the quartic terms already raise the energy. Halving the trial until the energy falls by at least
        half the tangent's prediction (``0.5 lambda a^2 |v|^2``; docs/sleeves.md, "A perfect ring"), while that
        prediction stays above the energy's round-off."""
        curv = 0.5 * self._last_min_eig * float(v @ v)
        floor = SADDLE_ENERGY_FLOOR * max(abs(e), 1e-30)
        a = 0.5e-3
        while -curv * a * a > floor:
            if self._energy(q + a * v, d) - e <= 0.5 * curv * a * a:
                return a
            a *= 0.5
        return 0.0

    def _energy(self, q, d):
        return self.mesh.evaluate(self.full(q, d), False)[0] - float(self.bias @ q)

    def trace(self, d_values, q0=None, tol=None, progress=None):
        """Follow the stable equilibrium path through the prescribed displacements ``d_values``."""
        t0 = time.perf_counter()
        if tol is None:
            tol = 1e-9 * float(np.max(self.mesh.EA)) / LINK_FACTOR
        q = np.zeros(self.nred) if q0 is None else q0.copy()
        d_prev = None
        q_prev = None
        ds, Fs, states, tilts, thetas, jumps = [], [], [], [], [], []
        total_it = 0
        dv = list(d_values)
        for i, d in enumerate(dv):
            # secant predictor along the previous step
            if q_prev is not None and d_prev is not None and abs(d - d_prev) > 0 and not (jumps and jumps[-1] == i - 1):
                pass
            guess = q
            if len(ds) >= 2 and (not jumps or jumps[-1] < len(ds) - 1):
                dd0 = ds[-1] - ds[-2]
                if abs(dd0) > 0:
                    guess = q + (q - q_prev) * (d - ds[-1]) / dd0
            qn, F, it = self._solve_step(guess, q, d, ds[-1] if ds else 0.0, tol)
            total_it += it
            if ds:
                v_old = states[-1]
                v_new, _ = self.cell_states(qn, d)
                dl = abs(d - ds[-1])
                if np.max(np.abs(v_new - v_old)) > 5 * dl + 0.02:
                    jumps.append(len(ds))
            q_prev = q
            q = qn
            ds.append(d)
            Fs.append(F)
            v, th = self.cell_states(q, d)
            states.append(v)
            thetas.append(th)
            tilts.append(self.tilt_of(q))
            if progress:
                progress(i + 1, len(dv))
        self.last_q = q
        return Path(np.array(ds), np.array(Fs), np.array(states), np.array(tilts), np.array(thetas),
                    jumps, total_it, time.perf_counter() - t0, FORCE_NOISE_FACTOR * tol)

    def _solve_step(self, guess, q, d, d_old, tol, depth=0):
        try:
            return self.minimise(guess, d, tol)
        except _NoConvergence:
            pass
        try:
            return self.minimise(q, d, tol, maxit=200)
        except _NoConvergence:
            pass
        if depth < 6:
            dm = 0.5 * (d + d_old)
            qm, _, it1 = self._solve_step(q, q, dm, d_old, tol, depth + 1)
            qn, F, it2 = self._solve_step(qm, qm, d, dm, tol, depth + 1)
            return qn, F, it1 + it2
        raise MetamaterialError(f"sleeve model: no equilibrium found at d/L = {d:.4g}" + self._collapsed_spring(q, d_old))

    def _collapsed_spring(self, q, d):
        """Why the path stops, when a ring-curvature end spring has collapsed at the last equilibrium (``q``, ``d``):
        a mixed two-cell ring's beam slides along its pillar's tip past the spring's length (docs/sleeves.md, "A perfect
        ring"); else ''."""
        if not self.springs:
            return ""
        el = np.array([k for k, _, _ in self.springs])
        u = self.full(q, d).reshape(-1, 3)
        i, j = self.mesh.conn[el, 0], self.mesh.conn[el, 1]
        chord = self.mesh.d0[el] + u[j, :2] - u[i, :2]
        ratio = np.hypot(chord[:, 0], chord[:, 1]) / self.mesh.L0[el]
        k = int(np.argmin(ratio))
        if ratio[k] >= SPRING_COLLAPSE:
            return ""
        _, cell, pillar = self.springs[k]
        return (f": the ring-curvature end spring between cell {cell}'s beam and its {pillar} pillar is compressed to "
                f"{ratio[k]:.2g} of its length at d/L = {d:.4g} (the beam's end has slid onto the pillar's tip), past the "
                f"range of the beam model's linear curvature springs (soft on a ring of {self.N} cells, mid radius "
                f"{self.radius:.3g} L): the path ends there in this model; trace a shorter stroke (below d/L {d:.4g}), "
                f"more cells around the ring, or model.ring_curvature false")


class _NoConvergence(Exception):
    pass


def default_stroke(cells):
    """Default maximum displacement / L: past the full inversion of the tallest cell type."""
    h = max(g.h / g.L for g in cells)
    return 2.0 * h + 0.12


def cell_curve(geom, n_el=10, steps=200, d_max=None, plane="strain", unload=True, top_rotation="default",
               root_extension=0.0):
    """Loading (and unloading) FD path of one unit cell. Returns (load, unload_or_None)."""
    m = SleeveModel([geom], None, n_el, plane, top_rotation=top_rotation, root_extension=root_extension)
    d_max = default_stroke([geom]) if d_max is None else d_max
    d = np.linspace(0, d_max, steps + 1)
    up = m.trace(d)
    down = m.trace(d[::-1], q0=m.last_q) if unload else None
    return up, down


def ring_curve(cells, pattern, n_el=8, steps=200, d_max=None, plane="strain", unload=True,
               imperfection=0.0, progress=None):
    m = SleeveModel(cells, pattern, n_el, plane, imperfection=imperfection)
    d_max = default_stroke(cells) * len(pattern) if d_max is None else d_max
    d = np.linspace(0, d_max, steps + 1)
    up = m.trace(d, progress=progress)
    down = m.trace(d[::-1], q0=m.last_q, progress=progress) if unload else None
    return m, up, down
