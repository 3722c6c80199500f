"""B-rep of a metamaterial sleeve (seed 002): N x M cells on a cylinder, PLA end rings and caps.

The sleeve is a tube of wall thickness T (radii ``R -+ T/2`` around the mid radius R, whose
circumference holds N cell widths) with the voids of every cell cut out. A void is a polygon in the
unrolled (arc length, height) plane (``CellGeometry.holes``); it is wrapped exactly onto the
cylinder (arc length s -> angle s / R) as a polyhedral cutter that reaches through the wall, so the
sleeve's inner and outer faces stay exact cylinders and the void walls are radial ruled facets
(one facet per outline sample).

End pieces (after the seed's supplementary S1): a PLA ring glued inside each end of the sleeve
(outer radius = sleeve inner radius, height = bar height c/2 + ``ring_extra_mm``), and a PLA cap
(disc of the actuator's cap diameter, ``actuator.core_diameter_mm``) closing each ring's opening, which is
the cap's diameter; the bottom cap has a hole for the supply tube.
"""
import math

import numpy as np

from metamaterial_wb.core.errors import MetamaterialError
from metamaterial_wb.core.materials import MATERIALS
from metamaterial_wb.core.sleeve.cell import triangulate_polygon
from metamaterial_wb.core.sleeve.spec import MIN_FEATURE_MM, TUBE_HOLE_MM
from metamaterial_wb.geometry.fc import freecad, set_shape_colour

TPU = MATERIALS["TPU"]
PLA = MATERIALS["PLA"]


def _cutter(Part, App, poly, r1, r2, rm, s0, z0):
    """Closed polyhedral solid: the polygon (s, z) wrapped on radii r1 < r2 (angle = (s + s0) / rm)."""
    poly = _refine(np.asarray(poly, float), 0.8)
    n = len(poly)
    # flat facets between wrapped vertices sag by r (1 - cos(span / 2)): push the outer skin out
    # so that every facet still lies outside the wall
    span = (poly[:, 0].max() - poly[:, 0].min()) / rm
    r2 = max(r2, (r2 + 0.5) / math.cos(min(span, 2.9) / 2))
    ang = (poly[:, 0] + s0) / rm
    z = poly[:, 1] + z0
    inner = [App.Vector(r1 * math.cos(a), r1 * math.sin(a), zz) for a, zz in zip(ang, z)]
    outer = [App.Vector(r2 * math.cos(a), r2 * math.sin(a), zz) for a, zz in zip(ang, z)]
    faces = []

    def tri(a, b, c):
        faces.append(Part.Face(Part.makePolygon([a, b, c, a])))

    for (i, j, k) in triangulate_polygon(poly):
        tri(inner[i], inner[k], inner[j])
        tri(outer[i], outer[j], outer[k])
    for i in range(n):
        j = (i + 1) % n
        tri(inner[i], inner[j], outer[j])
        tri(inner[i], outer[j], outer[i])
    shell = Part.Shell(faces)
    shell.sewShape()
    solid = Part.Solid(shell)
    if solid.Volume < 0:
        solid.reverse()
    return solid


def _refine(poly, max_len):
    """Split polygon edges longer than ``max_len`` (except horizontal ones, which stay planar)."""
    out = []
    n = len(poly)
    for i in range(n):
        a, b = poly[i], poly[(i + 1) % n]
        out.append(a)
        ln = float(np.hypot(*(b - a)))
        if ln > max_len and abs(b[1] - a[1]) > 1e-12:
            k = int(math.ceil(ln / max_len))
            for j in range(1, k):
                out.append(a + (b - a) * j / k)
    return np.array(out)


def sleeve_layout(spec):
    """Dimensions of the sleeve: radii, ring height, total height (mm)."""
    Rm = spec.radius_mm
    T = spec.T
    Hr = max(g.height for g in spec.cells)
    return {"mid_radius": Rm, "inner_radius": Rm - T / 2, "outer_radius": Rm + T / 2,
            "ring_height": Hr, "height": spec.M * Hr, "cell_width": spec.L + spec.c}


def build_sleeve(spec, samples=16, progress=None):
    """The sleeve (TPU) as one solid."""
    App, Part = freecad()
    lay = sleeve_layout(spec)
    Rm, Ri, Ro, Hr = lay["mid_radius"], lay["inner_radius"], lay["outer_radius"], lay["ring_height"]
    if Ri <= 0:
        raise MetamaterialError(f"sleeve: wall thickness T = {spec.T} mm exceeds the diameter of a "
                                f"{spec.N}-cell ring (mid radius {Rm:.2f} mm)")
    H = lay["height"]
    tube = Part.makeCylinder(Ro, H).cut(Part.makeCylinder(Ri, H))
    W = lay["cell_width"]
    cutters = []
    total = spec.M * spec.N
    for r, row in enumerate(spec.pattern):
        for k, typ in enumerate(row):
            g = spec.cells[typ]
            left = spec.cells[row[(k - 1) % spec.N]]
            polys = g.holes(samples, top=Hr - g.c / 2, left=left)
            for name, poly in polys.items():
                cutters.append(_cutter(Part, App, poly, Ri - 0.5, Ro + 0.5, Rm, k * W, r * Hr))
            if progress:
                progress(len(cutters) // len(polys), total)
    tool = cutters[0].multiFuse(cutters[1:]) if len(cutters) > 1 else cutters[0]
    sleeve = tube.cut(tool)
    sleeve = sleeve.removeSplitter()
    solids = sleeve.Solids
    if len(solids) != 1:
        raise MetamaterialError(f"sleeve: geometry fell apart into {len(solids)} pieces (check c, delta, t)")
    return solids[0]


def build_end_pieces(spec, ring_extra_mm=4.0, cap_mm=2.0, tube_hole_mm=TUBE_HOLE_MM):
    """PLA end rings (inside the sleeve's end bars) and caps: ``{name: solid}``.

    The cap is the prediction's (``spec.core_diameter``, ``actuator.core_diameter_mm`` or its automatic default):
    as in the seed's actuator (SI S1.1) it closes the inflatable core, whose membrane pushes on it with the pressure
    times its area (``pv.cap_area_mm2``), and it sits in the ring's opening, flush with the ring's outer end. So the
    ring's opening is the cap's diameter and its wall the rest of the sleeve's inside, at least ``MIN_FEATURE_MM``.
    The spec's ``check_end_pieces`` (the default tube hole) is checked first: the CLI checks it before the analysis."""
    if tube_hole_mm == TUBE_HOLE_MM:
        spec.check_end_pieces()
    App, Part = freecad()
    lay = sleeve_layout(spec)
    Ri, H = lay["inner_radius"], lay["height"]
    rc = spec.core_diameter / 2
    hr = spec.c / 2 + ring_extra_mm
    if Ri - rc < MIN_FEATURE_MM - 1e-9:
        raise MetamaterialError(f"end pieces: actuator.core_diameter_mm {2 * rc:.6g} mm leaves the end ring a wall of "
                                f"{Ri - rc:.4g} mm inside the sleeve's inner diameter {2 * Ri:.6g} mm; allowed: a cap of "
                                f"at most {2 * (Ri - MIN_FEATURE_MM):.6g} mm (a {MIN_FEATURE_MM:g} mm ring wall)")
    if tube_hole_mm / 2 + MIN_FEATURE_MM > rc + 1e-9:
        raise MetamaterialError(f"end pieces: a {tube_hole_mm:g} mm tube hole needs a cap of at least "
                                f"{tube_hole_mm + 2 * MIN_FEATURE_MM:g} mm (actuator.core_diameter_mm); "
                                f"the cap is {2 * rc:.6g} mm")
    out = {}
    for name, z in (("ring_bottom", -ring_extra_mm), ("ring_top", H - spec.c / 2)):
        out[name] = Part.makeCylinder(Ri, hr, App.Vector(0, 0, z)).cut(
            Part.makeCylinder(rc, hr, App.Vector(0, 0, z)))
    cap_b = Part.makeCylinder(rc, cap_mm, App.Vector(0, 0, -ring_extra_mm))
    cap_b = cap_b.cut(Part.makeCylinder(tube_hole_mm / 2, cap_mm, App.Vector(0, 0, -ring_extra_mm)))
    cap_t = Part.makeCylinder(rc, cap_mm, App.Vector(0, 0, H + ring_extra_mm - cap_mm))
    out["cap_bottom"] = cap_b
    out["cap_top"] = cap_t
    return out


def build_all(spec, progress=None):
    """``[(name, solid, colour, material)]`` of every printed part."""
    parts = [("sleeve", build_sleeve(spec, progress=progress), TPU, "TPU")]
    for name, s in build_end_pieces(spec).items():
        parts.append((name, s, PLA, "PLA"))
    return parts


def check_parts(parts):
    """Validity: every part one valid closed solid with positive volume. Raises MetamaterialError."""
    for name, s, _, _ in parts:
        if not s.isValid():
            raise MetamaterialError(f"{name}: invalid B-rep")
        if s.ShapeType not in ("Solid",) and len(s.Solids) != 1:
            raise MetamaterialError(f"{name}: expected one solid, got {len(s.Solids)}")
        if not (s.Volume > 0):
            raise MetamaterialError(f"{name}: volume {s.Volume} mm^3 is not positive")
        if not all(sh.isClosed() for sh in s.Shells):
            raise MetamaterialError(f"{name}: open shell")


def build_unit_cell(geom, samples=24):
    """The flat unit cell (seed figure 2A) as a solid: the W x H plate minus its voids, T thick
    (x across, y up, z through the thickness; centred on x = 0)."""
    App, Part = freecad()
    W, H = geom.width, geom.height
    plate = Part.makeBox(W, H, geom.T, App.Vector(-W / 2, 0, 0))
    cut = []
    for name, poly in geom.holes(samples).items():
        pts = [App.Vector(x, y, -1.0) for x, y in poly]
        wire = Part.makePolygon(pts + [pts[0]])
        cut.append(Part.Face(wire).extrude(App.Vector(0, 0, geom.T + 2.0)))
        if min(x for x, _ in poly) < -W / 2:     # the part beyond x = -W/2 belongs to the next cell
            cut.append(cut[-1].translated(App.Vector(W, 0, 0)))
    cell = plate.cut(cut[0].multiFuse(cut[1:])).removeSplitter()
    return cell


def add_to_document(spec, doc=None, progress=None):
    """Build the sleeve's parts and add them to a FreeCAD document as Part::Feature objects
    (coloured when the GUI is up). Returns the created objects."""
    App, Part = freecad()
    doc = doc or App.ActiveDocument or App.newDocument("Sleeve")
    objs = []
    for name, shape, colour, material in build_all(spec, progress=progress):
        o = doc.addObject("Part::Feature", name)
        o.Shape = shape
        o.Label = f"{name} ({material})"
        vo = getattr(o, "ViewObject", None)
        if vo is not None:
            set_shape_colour(vo, colour)
        objs.append(o)
    doc.recompute()
    return objs
