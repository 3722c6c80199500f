"""The printed sheet: rigid node plates (PLA) with snap-fit sockets and flexible hinges (TPU).

Local frame of a hinge (docs/fabrication.md): ``u`` crosses the gap from the joint's first node
``N(i,j)`` (u < 0) to its second node (u > 0); ``v = z x u``; ``v = 0`` is the plate edge line the
hinge is flush with; the plate lies on the side ``side * v > 0`` (``side = -1`` when i + j is even,
the corner rule of core/kinematics.py). A hinge is an 8-corner polygon extruded along the
(possibly tilted) hinge axis:

* neck: ``|u| <= gap/2 + anchor_neck``, ``0 <= side*v <= neck width``;
* two anchor heads: ``gap/2 + anchor_neck <= |u| <= gap/2 + anchor_neck + anchor_depth``,
  ``0 <= side*v <= neck width + anchor_margin`` -- wider than the neck, so the node material
  between the plate edge and the head (the lip) hooks it (seed 5.1);
* tilt: the extrusion leans by ``tilt_deg`` about ``u`` (right-hand rule), so a positive tilt moves the
  top face towards ``-v``; the hinge's true blade width stays ``width_mm``.

Each node plate is a box with the hinge solids (necks + heads) and the socket holes cut away in one
boolean call; node variants are cached by their features, hinges by their spec.
"""
import math

from metamaterial_wb.core.joints import joint_frame as _joint_frame
from metamaterial_wb.geometry.fc import freecad
from metamaterial_wb.core.fabrication import anchor_width_mm, neck_width_mm


def joint_frame(kind, i, j, p):
    """``(x, y, angle_deg, side)`` of a joint's local frame: origin at the gap centre on the edge line
    (core/joints.py owns the convention)."""
    return _joint_frame(kind, i, j, p.cell_size_mm, p.plate_side_mm_global)


def node_centre(i, j, p):
    return (j * p.cell_size_mm, -i * p.cell_size_mm)


def _lean(p, h):
    """``(k, o)``: dv'/dz of the lean (v' = side*v, the inward coordinate) and the v' offset at z = T/2."""
    t = math.tan(math.radians(h.tilt_deg))
    return t, 0.5 * p.sheet_thickness_mm * abs(t)


def _prism(uv_prime, side, k, o, z0, height, T):
    """Extrude a polygon given in (u, v') from z0 to z0 + height along the lean; returns a solid."""
    App, Part = freecad()
    V = App.Vector
    kk = -side * k                      # dv'/dz: the top moves towards -v for a positive tilt
    vshift = o + kk * (z0 - 0.5 * T)
    pts = [V(u, side * (vp + vshift), z0) for (u, vp) in uv_prime]
    wire = Part.makePolygon(pts + [pts[0]])
    face = Part.Face(wire)
    return face.extrude(V(0.0, side * kk * height, height))


def hinge_outline(p, h):
    """The 8 (u, v') corners of the hinge outline (v' inward from the edge line)."""
    wn = neck_width_mm(h)
    wa = anchor_width_mm(p, h)
    u1 = 0.5 * p.gap_mm + p.anchor_neck_mm
    u2 = u1 + p.anchor_depth_mm
    return [(-u2, 0.0), (u2, 0.0), (u2, wa), (u1, wa), (u1, wn), (-u1, wn), (-u1, wa), (-u2, wa)]


def hinge_volume_mm3(p, h):
    """Closed form: outline area times hinge thickness (a sheared prism keeps base area x height)."""
    wn = neck_width_mm(h)
    wa = anchor_width_mm(p, h)
    u1 = 0.5 * p.gap_mm + p.anchor_neck_mm
    return (2 * u1 * wn + 2 * p.anchor_depth_mm * wa) * h.thickness_mm


def make_hinge(p, h, side):
    """Hinge solid in its local frame."""
    k, o = _lean(p, h)
    T = p.sheet_thickness_mm
    z0 = 0.5 * (T - h.thickness_mm)
    return _prism(hinge_outline(p, h), side, k, o, z0, h.thickness_mm, T)


def stub_outline(p, h, sign):
    """Rigid stub (u, v') outline on one side (sign -1: first node, +1: second) when the hinge is shorter
    than the gap; None when it bridges the whole gap."""
    free = h.length_mm
    gap = p.gap_mm
    if gap - free <= 1e-9:
        return None
    w = anchor_width_mm(p, h) + p.min_wall_mm
    a, b = 0.5 * free, 0.5 * gap       # the stub spans from the free length to the plate edge
    if sign < 0:
        a, b = -b, -a
    return [(a, 0.0), (b, 0.0), (b, w), (a, w)]


def make_stub(p, h, side, sign):
    outline = stub_outline(p, h, sign)
    if outline is None:
        return None
    k, o = _lean(p, h)
    T = p.sheet_thickness_mm
    # overlap the plate by a hair so that the fuse merges the stub with the plate
    outline = [(u + 0.01 * sign if abs(abs(u) - 0.5 * p.gap_mm) < 1e-9 else u, v) for (u, v) in outline]
    return _prism(outline, side, k, o, 0.0, T, T)


def socket_positions(p):
    """Socket centres in the node frame: middle of each side, ``socket_inset_mm`` inside the edge."""
    d = 0.5 * p.plate_side_mm_global - p.socket_inset_mm
    return [("E", d, 0.0), ("N", 0.0, d), ("W", -d, 0.0), ("S", 0.0, -d)]


def socket_tools(p):
    App, Part = freecad()
    V = App.Vector
    T = p.sheet_thickness_mm
    lip = p.socket_lip_height_mm
    tools = []
    for _, x, y in socket_positions(p):
        tools.append(Part.makeCylinder(p.socket_radius_mm, T + 2.0, V(x, y, -1.0)))
        tools.append(Part.makeCylinder(p.counterbore_radius_mm, lip + 1.0, V(x, y, -1.0)))
        tools.append(Part.makeCylinder(p.counterbore_radius_mm, lip + 1.0, V(x, y, T - lip)))
    return tools


def socket_volume_mm3(p):
    """Material removed by one socket (hole + two counterbores), closed form."""
    T = p.sheet_thickness_mm
    lip = p.socket_lip_height_mm
    return math.pi * (p.socket_radius_mm ** 2 * (T - 2 * lip) + 2 * p.counterbore_radius_mm ** 2 * lip)


def node_features(topo, ij, p):
    """The hinges attached to node ``ij`` as hashable features in the node frame:
    ``(spec_key, side, angle_deg, dx, dy, sign)`` where sign -1 means the node is the joint's first node."""
    i, j = ij
    cx, cy = node_centre(i, j, p)
    feats = []
    for kind, (a, b) in (("H", ((i, j), (i, j - 1))), ("V", ((i, j), (i - 1, j)))):
        for (ji, jj), sign in ((a, -1), (b, 1)):
            name = f"{kind}{ji},{jj}"
            if name not in topo.joint_index:
                continue
            h = p.hinges[name]
            x, y, ang, side = joint_frame(kind, ji, jj, p)
            feats.append((h.key(), side, ang, round(x - cx, 6), round(y - cy, 6), sign, name))
    return feats


def make_node(p, feats, spec_of):
    """Node plate with pockets for the anchors of its hinges, sockets and (if any) rigid stubs.

    ``feats``: from :func:`node_features` (without the joint names); ``spec_of(key)`` -> HingeSpec.
    One fuse (stubs) and one cut (all pockets and sockets) per variant.
    """
    App, Part = freecad()
    V = App.Vector
    s = p.plate_side_mm_global
    T = p.sheet_thickness_mm
    plate = Part.makeBox(s, s, T, V(-0.5 * s, -0.5 * s, 0.0))
    cutters = []
    stubs = []
    for key, side, ang, dx, dy, sign in feats:
        h = spec_of(key)
        pl = App.Placement(V(dx, dy, 0.0), App.Rotation(V(0, 0, 1), ang))
        cutters.append(make_hinge(p, h, side).transformed(pl.toMatrix()))
        st = make_stub(p, h, side, sign)
        if st is not None:
            stubs.append(st.transformed(pl.toMatrix()))
    if stubs:
        plate = plate.fuse(stubs).removeSplitter()
    if p.sockets:
        cutters += socket_tools(p)
    if cutters:
        plate = plate.cut(cutters)
    solids = plate.Solids
    if len(solids) != 1:
        from metamaterial_wb.core.errors import MetamaterialError
        raise MetamaterialError(f"node variant {feats!r} came out as {len(solids)} solids; check the anchor and "
                                f"socket parameters")
    return solids[0]
