"""A linear 3-D frame of a sleeve ring wrapped on its cylinder (issue 18): why the curved ring is softer.

The beam model (``model.py``) bends its beams and pillars in the cell's plane only; its ring curvature is a
pair of springs at the beam ends (``radial_end_stiffness``). The curved CalculiX solid (``fe/sleeve3d.py``)
shows the wall bending *out of* the cylinder, and is 2-4 times softer (docs/sleeves.md, "Curvature by ring
size"). This module takes the beam model's own mesh of a uniform ring (its nodes, elements and sections,
``add_row_single`` without the curvature springs), wraps it onto the cylinder of radius ``R = N W / 2 pi``
(a point at unrolled ``x`` sits at the angle ``x / R``; the mid surface keeps the 2-D lengths) and solves it
as a linear 3-D frame: every element a straight Euler-Bernoulli beam between its wrapped end nodes, with its
in-plane bending (``EI`` of the model, about the radial axis), bending through the wall (``E_r b T^3 / 12``,
``b`` the section's in-plane width, ``T`` the wall), torsion (``G J`` of the ``b x T`` rectangle) and
stretching. The bars are rigid with their plates as in the model: the bottom plate clamped, the top plate
raised by ``d`` without tilt or twist (by the ring's symmetry a linear axial load excites neither).

Flat (``curved=False``) the same frame lies in a plane, where out-of-plane motion decouples: it is the beam
model's linear flat ring. The ratio curved / flat is the curvature's knock-down of the initial stiffness,
measured against the solid's in ``bench/fe_frame3d.py``. Linear only: no peak, no snap. Units as the model's:
lengths / L, forces / (G L^2).
"""
import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from metamaterial_wb.core.sleeve.model import (E_RADIAL, LINK_FACTOR, _MeshBuilder, add_row_single, modulus)


def torsion_constant(a, b):
    """Saint-Venant torsion constant of an ``a x b`` rectangle (Roark's series, within 4 %)."""
    a, b = np.maximum(a, b), np.minimum(a, b)
    return a * b ** 3 * (1.0 / 3.0 - 0.21 * (b / a) * (1.0 - b ** 4 / (12.0 * a ** 4)))


def element_stiffness(l, EA, EI2, EI3, GJ):
    """12 x 12 local stiffness of a straight 3-D Euler-Bernoulli beam of length ``l``: DOFs per node
    ``(u1, u2, u3, r1, r2, r3)`` along and about the local axes (1 along the beam); ``EI3`` bends it in the
    1-2 plane (displacement u2, rotation r3), ``EI2`` in the 1-3 plane (u3, r2), ``GJ`` twists it."""
    k = np.zeros((12, 12))
    for i, j, v in ((0, 0, 1), (0, 6, -1), (6, 6, 1)):
        k[i, j] = k[j, i] = v * EA / l
    for i, j, v in ((3, 3, 1), (3, 9, -1), (9, 9, 1)):
        k[i, j] = k[j, i] = v * GJ / l
    for (u, r, EI, s) in ((1, 5, EI3, 1.0), (2, 4, EI2, -1.0)):
        c = EI / l ** 3
        idx = (u, r, u + 6, r + 6)
        m = c * np.array([[12, 6 * l * s, -12, 6 * l * s],
                          [6 * l * s, 4 * l * l, -6 * l * s, 2 * l * l],
                          [-12, -6 * l * s, 12, -6 * l * s],
                          [6 * l * s, 2 * l * l, -6 * l * s, 4 * l * l]])
        for a_, ia in enumerate(idx):
            for b_, ib in enumerate(idx):
                k[ia, ib] += m[a_, b_]
    return k


class RingFrame:
    """The beam model's uniform ring of ``n_cells`` cells of ``geom`` as a 3-D frame (module docstring); with
    ``row`` (cell type indices around the ring) and ``geom`` a list of cell types, a mixed ring; with ``pattern``
    (a list of such rows, ring 0 at the bottom) a sleeve of rings stacked on the axis, each ring's upper bar the
    next one's lower bar (ties to plate ``r`` of ring ``r``'s lower bar and ring ``r - 1``'s upper bar, at the
    mean height of the upper one; ``rings``).
    ``plane``: the model's in-plane modulus (``"strain"``, E = 4 G, as its flat ring; ``"stress"``, 3 G);
    ``E_r``: the modulus for bending through the wall (``E_RADIAL``, 3 G, as the model's curvature springs);
    ``G``: the shear modulus of the torsion (1: units of G); ``n_el``, ``root_extension``: the model's.
    ``bar_root``: how far into its bar (a fraction of the bar's height, half the pillar's width) each pillar
    bends through the wall before it is clamped; the bar stays rigid in the wall's plane and along the axis, as
    in the model. 1 (default): the pillar's own material runs on through the bar to the clamped face or the
    plate's, as in the printed sleeve and the curved solid, whose first peak rises by 15 % when its bars are held
    at their radius (docs/sleeves.md, "Where the frame's excess was"); 0: clamped at the bar's face (the frame
    before; flat, the beam model's ring exactly). ``flat_top``: every edge pillar of a mixed ring hangs from its
    tallest cell's top (``model.add_row_single``; the curved solid's mixed ring) instead of the taller neighbour's."""

    def __init__(self, geom, n_cells=4, curved=True, plane="strain", E_r=E_RADIAL, G=1.0, n_el=24,
                 root_extension=0.0, row=None, pattern=None, bar_root=1.0, flat_top=False):
        E = modulus(plane)
        mb = _MeshBuilder()
        cells = list(geom) if isinstance(geom, (list, tuple)) else [geom]
        if pattern is None:
            pattern = [[0] * n_cells if row is None else [int(t) for t in row]]
        pattern = [[int(t) for t in r] for r in pattern]
        n_cells = len(pattern[0])
        if any(len(r) != n_cells for r in pattern):
            raise ValueError(f"pattern {pattern}: every ring needs the same number of cells")
        flat = [t for r in pattern for t in r]
        geom = cells[flat[0]]
        if len({round(cells[t].width, 12) for t in flat}) > 1:
            raise ValueError(f"pattern {pattern}: the cell types' widths differ; a ring needs one width")
        W = geom.width / geom.L
        if not 0.0 <= bar_root <= 1.0:
            raise ValueError(f"bar_root: {bar_root!r}; allowed: 0 (pillars clamped at the bar's face) to 1 (through "
                             "the bar's whole height c / 2)")
        roots = []                                        # the elements of the pillars' roots in the bars
        top = 0.0                                         # the last ring's upper bar: its ties' mean height
        for r, row in enumerate(pattern):
            first, first_tie = len(mb.X), len(mb.ties)
            add_row_single(mb, row, cells, n_el, E, r, r + 1, lambda k: k * W, r * n_cells, n_cells * W,
                           None, "guided", root_extension, flat_top)
            if bar_root:
                # the pillars bend through the wall on into their bar (its material under or over them), down
                # or up to the plate's face; rigid in the wall's plane and along, as the bars are
                for t_ in range(first_tie, len(mb.ties)):
                    i, p, x = mb.ties[t_]
                    e = next(e for e, ij in enumerate(mb.conn) if i in ij)      # the pillar's end element
                    width = np.sqrt(12.0 * mb.EI[e] / mb.EA[e])                 # c / L; the bar is c / 2 high
                    j = mb.node(mb.X[i][0], mb.X[i][1] + bar_root * 0.5 * width * (-1.0 if p == r else 1.0))
                    mb.element(i, j, mb.EA[e], mb.EI[e])
                    roots.append(len(mb.conn) - 1)
                    mb.ties[t_] = (j, p, x)

            def tie_height(p):
                return float(np.mean([mb.X[i][1] for i, q, _ in mb.ties if i >= first and q == p]))
            if r:
                dz = top - tie_height(r)
                for i in range(first, len(mb.X)):
                    mb.X[i] = mb.X[i] + (0.0, dz)
            top = tie_height(r + 1)
        self.rings = len(pattern)
        self.bar_root = float(bar_root)
        X = np.vstack(mb.X)
        self.radius = n_cells * W / (2 * np.pi)
        self.curved = curved
        self.n_cells = n_cells
        phi = X[:, 0] / self.radius
        if curved:
            self.P = np.column_stack([self.radius * np.cos(phi), self.radius * np.sin(phi), X[:, 1]])
        else:
            self.P = np.column_stack([X[:, 0], np.zeros(len(X)), X[:, 1]])
        conn = np.array(mb.conn)
        shift = np.vstack(mb.shift)
        EA, EI = np.array(mb.EA), np.array(mb.EI)
        b = np.sqrt(12.0 * EI / EA)                       # the section's in-plane width (a link's: its length)
        T = EA / (E * b)                                  # its depth through the wall (geom.T for the real ones)
        t_min = min(cells[t].t for t in flat)
        link = EA > 0.5 * LINK_FACTOR * E * (t_min / geom.L) * (geom.T / geom.L)
        EI_r = E_r * b * T ** 3 / 12.0
        GJ = G * torsion_constant(b, T)
        GJ[link] = LINK_FACTOR * np.max(GJ[~link])
        EI_r[link] = LINK_FACTOR * np.max(EI_r[~link])
        if roots:                                         # the roots: the pillar's through the wall, rigid else
            EA[roots] *= LINK_FACTOR
            EI[roots] *= LINK_FACTOR
        n = len(X)
        rows, cols, vals = [], [], []
        self.conn = conn
        self.shift3 = (np.zeros((len(conn), 3)) if curved else
                       np.column_stack([shift[:, 0], np.zeros(len(conn)), shift[:, 1]]))
        self.EA, self.EI2, self.EI3, self.GJ = EA, EI_r, EI, GJ
        self.frames0 = np.zeros((len(conn), 3, 3))       # rows: the element's axes 1, 2, 3 unloaded
        self.l0 = np.zeros(len(conn))
        for e, (i, j) in enumerate(conn):
            pi_, pj = self.P[i], self.P[j] + self.shift3[e]
            d = pj - pi_
            l = float(np.linalg.norm(d))
            e1 = d / l
            m = 0.5 * (pi_ + pj)
            rad = np.array([m[0], m[1], 0.0]) / np.hypot(m[0], m[1]) if curved else np.array([0.0, 1.0, 0.0])
            e3 = rad - (rad @ e1) * e1
            e3 /= np.linalg.norm(e3)
            e2 = np.cross(e3, e1)
            R = np.vstack([e1, e2, e3])
            self.frames0[e], self.l0[e] = R, l
            Tm = np.kron(np.eye(4), R)
            k = Tm.T @ element_stiffness(l, EA[e], EI_r[e], EI[e], GJ[e]) @ Tm
            dofs = np.concatenate([6 * i + np.arange(6), 6 * j + np.arange(6)])
            rows.append(np.repeat(dofs, 12)); cols.append(np.tile(dofs, 12)); vals.append(k.ravel())
        self.K = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                               shape=(6 * n, 6 * n))
        self.ties = [(i, p) for i, p, _ in mb.ties]
        self.n_nodes = n
        # the model's snapping parts: each beam half's outer and inner end, its edge pillar (``units``) and its
        # snap height h / L (snapped when the outer end has risen over the inner one by more, as in the model)
        self.states = [(a, b) for a, b, _ in mb.states]
        self.units = list(mb.units)
        self.cells = cells
        self.state_types = [flat[c] for _, _, c in mb.states]
        self.snap_height = np.array([cells[t].h / cells[t].L for t in self.state_types])

    def axial_stiffness(self, return_displacements=False):
        """The ring's axial stiffness: the top plate's force per rise, F / (G L^2) per d / L (tied nodes: all six
        DOFs held, the top ones raised by one along the axis); one ring only."""
        if self.rings > 1:
            raise ValueError(f"axial_stiffness: {self.rings} stacked rings; the linear frame's is for one ring")
        n6 = 6 * self.n_nodes
        fixed = np.zeros(n6, bool)
        u = np.zeros(n6)
        top = []
        for i, p in self.ties:
            fixed[6 * i:6 * i + 6] = True
            if p == 1:
                u[6 * i + 2] = 1.0
                top.append(6 * i + 2)
        f = ~fixed
        Kff = self.K[f][:, f].tocsc()
        u[f] = spla.spsolve(Kff, -(self.K[f][:, fixed] @ u[fixed]))
        F = float((self.K[top] @ u).sum())
        return (F, u) if return_displacements else F


def curvature_check(geom, n_cells, plane="strain", root_extension=0.0, pillar_tip="guided", n_el=24):
    """The beam model's curved ring against the linear 3-D frame of the same ring, for any cell: the initial
    axial stiffness of both (the model's: its force over a rise of 1e-6 L, curvature springs on, in its own
    ``plane``; the frame's: plane stress, E = 3 G throughout, the variant whose curvature knock-down matched the
    curved solid's, docs/sleeves.md) and their ratio, with the time both took."""
    import time
    from metamaterial_wb.core.sleeve.model import SleeveModel
    t0 = time.perf_counter()
    p = SleeveModel([geom], [[0] * n_cells], n_el, plane, curvature=True, pillar_tip=pillar_tip,
                    root_extension=root_extension).trace(np.array([0.0, 1e-6]))
    k_model = float(p.F[1] / p.d[1])
    k_frame = RingFrame(geom, n_cells, plane="stress", root_extension=root_extension, n_el=n_el).axial_stiffness()
    return {"beam_model": k_model, "frame3d": float(k_frame), "ratio": k_model / float(k_frame),
            "seconds": time.perf_counter() - t0}
