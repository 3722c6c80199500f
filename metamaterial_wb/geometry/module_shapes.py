"""The shapes of the snap-fit modules other than the servo housing (geometry/servo.py): the connection hub, the
friction pad, the stable hub and the constraint clip, each built in its module frame (geometry/modules.py: the node
centre, or the joint midpoint with ``u`` from node A to node B) from sizes :func:`modules.parse_modules` has checked.
:func:`modules.build_module` picks the builder, caches the shapes and places them on the sheet."""
import math

from metamaterial_wb.geometry.rivet import HEAD_HEIGHT_MM, HEAD_RIM_MM
from metamaterial_wb.geometry.solids import (
    _fc, _finish, _lateral_points, box, clip_waiting_rivets, rivet_parts, riveted)

HUB_POST_HALF_MM = 3.0       # half the stable hub's post / foot length along the joint
HUB_HOLE_RADIUS_MM = 1.6     # the stable hub platform's M3 clearance hole (for the attached shape)
DOWEL_DIAMETER_MM = 1.8      # holes for two pieces of 1.75 mm filament that align the hub's halves


def hub_dowel_points(p):
    """Centres (node frame) of the two dowel holes through both halves of a connection hub."""
    q = 0.3 * p.plate_side_mm_global
    return [(q, q), (-q, -q)]


def build_connection_hub(spec, p):
    """Two plain halves split at mid-thickness (each prints flat), aligned by two filament dowels, with
    a channel through both at each socket for a double rivet (geometry/rivet.make_double_rivet): its
    lower end snaps into the sheet below, its upper end into the second sheet that lies upside down on
    the hub's top face; the rivets print lying, their prongs bend along the layers."""
    from metamaterial_wb.geometry.rivet import make_double_rivet

    App, Part = _fc()
    V = App.Vector
    T = p.sheet_thickness_mm
    t = spec.values["thickness_mm"]
    s = p.plate_side_mm_global
    h = 0.5 * s - 0.3
    zm = T + 0.5 * t
    d = 0.5 * s - p.socket_inset_mm
    pts = [(d, 0.0), (0.0, d), (-d, 0.0), (0.0, -d)]
    cut = [Part.makeCylinder(0.5 * DOWEL_DIAMETER_MM, t + 2.0, V(x, y, T - 1.0)) for x, y in hub_dowel_points(p)]
    cut += [Part.makeCylinder(p.socket_radius_mm, t + 2.0, V(u, w, T - 1.0)) for u, w in pts]
    lower = _finish([box(-h, h, -h, h, T, zm)], cut, f"{spec.name} lower half")
    upper = _finish([box(-h, h, -h, h, zm, T + t)], cut, f"{spec.name} upper half")
    pin = make_double_rivet(p, t, spec.snap)
    rivets = []
    for u, w in pts:
        m = App.Matrix()
        m.move(V(u, w, 0.0))
        rivets.append((pin.transformed(m, True), t, (u, w)))     # a copy: STEP keeps one body each
    return [("hub_lower", lower), ("hub_upper", upper)] + rivet_parts("hub", rivets)


def build_friction_pad(spec, p):
    T = p.sheet_thickness_mm
    v = spec.values
    s = p.plate_side_mm_global
    h = 0.5 * s - 0.3
    t = v["thickness_mm"]
    plate = box(-h, h, -h, h, T, T + t)
    ins = h - v["pocket_inset_mm"]
    # the pocket (for the friction insert) faces the bed when the pad prints pins up: ribs of two
    # nozzle widths split it into strips narrower than a printable bridge
    n, rib = pocket_strips(2 * ins, p.min_wall_mm)
    w = (2 * ins - (n - 1) * rib) / n
    z0 = T + t - v["pocket_depth_mm"]
    pockets = [box(-ins + k * (w + rib), -ins + k * (w + rib) + w, -ins, ins, z0, T + t + 1.0) for k in range(n)]
    d = 0.5 * s - p.socket_inset_mm
    pts = [(d, 0.0), (0.0, d), (-d, 0.0), (0.0, -d)]
    # the rivet heads sit recessed in the pocket side, at least a head below the pad's face
    z_head = min(z0, T + t - HEAD_HEIGHT_MM - 0.2)      # parse_modules checked the floor under it
    App, Part = _fc()
    recess = [Part.makeCylinder(p.socket_radius_mm + HEAD_RIM_MM, T + t + 1.0 - z_head,
                                App.Vector(u, w, z_head)) for u, w in pts]
    pad, rivets = riveted(p, _finish([plate], pockets + recess, spec.name), pts, spec.snap, spec.name)
    return [("pad", pad)] + rivet_parts("pad", rivets)


def pocket_strips(width_mm, rib_mm, max_bridge_mm=9.0):
    """``(n, rib)``: how many strips a pocket ``width_mm`` wide is split into so that each spans less
    than ``max_bridge_mm`` (a printable bridge, with a margin under the 10 mm rule)."""
    n = max(1, math.ceil((width_mm + rib_mm) / (max_bridge_mm + rib_mm)))
    return n, rib_mm


def build_stable_hub(spec, p):
    App, Part = _fc()
    V = App.Vector
    T = p.sheet_thickness_mm
    v = spec.values
    c, s = p.cell_size_mm, p.plate_side_mm_global
    d = 0.5 * s - p.socket_inset_mm
    fv = d + p.counterbore_radius_mm + 1.0
    foot_t = 2.0
    zp = T + v["height_mm"]
    bw, bh = 0.5 * v["beam_width_mm"], v["beam_height_mm"]
    P = 0.5 * v["platform_mm"]
    parts = []
    pins = []
    pu = v.get("pivot_u_mm", 0.0)          # the platform over the joint's pivot (core/joints.py)
    hp = HUB_POST_HALF_MM
    for uc in (-0.5 * c, 0.5 * c):
        parts.append(box(uc - hp, uc + hp, -fv, fv, T, T + foot_t))
        # posts as wide as the feet: printed upside down (platform on the bed) nothing overhangs
        parts.append(box(uc - hp, uc + hp, -fv, fv, T + foot_t - 0.01, zp + bh))
        u0, u1 = (uc, pu - P + 0.01) if uc < 0 else (pu + P - 0.01, uc)
        parts.append(box(u0, u1, -bw, bw, zp, zp + bh))
        pins += _lateral_points(p, uc)
    parts.append(box(pu - P, pu + P, -P, P, zp, zp + bh))
    hole = Part.makeCylinder(HUB_HOLE_RADIUS_MM, bh + 2.0, V(pu, 0, zp - 1.0))   # M3 clearance (attached shape)
    hub, rivets = riveted(p, _finish(parts, [hole], spec.name), pins, spec.snap, spec.name)
    return [("hub", hub)] + rivet_parts("hub", rivets)


def build_constraint_clip(spec, p, pivot):
    App, Part = _fc()
    V = App.Vector
    T = p.sheet_thickness_mm
    c, s, gap = p.cell_size_mm, p.plate_side_mm_global, p.gap_mm
    t = spec.values["thickness_mm"]
    h = 0.5 * s - 0.3
    ang = spec.values["angle_deg"]
    half_a = box(-0.5 * gap - s + 0.3, 0.0, -h, h, T, T + t)
    half_b = box(0.0, 0.5 * gap + s - 0.3, -h, h, T, T + t)
    pts_a = _lateral_points(p, -0.5 * c)
    pts_b = _lateral_points(p, 0.5 * c)
    rot = App.Placement(V(pivot[0], pivot[1], 0), App.Rotation(V(0, 0, 1), ang)).multiply(
        App.Placement(V(-pivot[0], -pivot[1], 0), App.Rotation()))
    m = rot.toMatrix()
    half_b = half_b.transformed(m)
    pts_b = [(q.x, q.y) for q in (rot.multVec(V(u, w, 0.0)) for u, w in pts_b)]
    r = min(0.5 * s, 8.0)
    bridge = Part.makeCylinder(r, t, V(pivot[0], pivot[1], T))
    # separate rivet pins (geometry/rivet.py) through the plate, heads on its top face: the clip prints
    # flat on its underside, the rivets lying (their prongs bend along the layers)
    clip, rivets = riveted(p, _finish([half_a, half_b, bridge], [], spec.name), pts_a + pts_b, spec.snap, spec.name)
    wait = clip_waiting_rivets(spec, p)         # node B's: in once the joint is bent, above their channels till then
    return [(n, sh.transformed(App.Matrix(1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, wait[n]), True) if n in wait else sh)
            for n, sh in [("clip", clip)] + rivet_parts("clip", rivets)]     # a copy, moved in the geometry (riveted)
