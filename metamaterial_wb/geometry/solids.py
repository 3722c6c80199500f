"""Solid primitives shared by the module builders (modules.py, servo.py): boxes, the designed snap pin, pins
placed at socket points, and the one-fuse-one-cut finish that returns a single valid solid."""
from metamaterial_wb.geometry.snapfit import design_snap_fit

PIN_OVERLAP_MM = 0.5        # pins reach this far into the module body so that the fuse joins them


def _fc():
    from metamaterial_wb.geometry.fc import freecad
    return freecad()


def box(u0, u1, v0, v1, z0, z1):
    App, Part = _fc()
    return Part.makeBox(u1 - u0, v1 - v0, z1 - z0, App.Vector(u0, v0, z0))


def make_pin(p, up=False, snap=None):
    """Split snap pin at the origin (socket axis). Down (default): from the sheet top face into the socket,
    barb latching under the bottom ledge. ``up``: the same pin mirrored to stick up from z = 0. ``snap``:
    the designed prongs (geometry/snapfit.py; default: designed for the module material of ``p``)."""
    if snap is None:
        snap = design_snap_fit(p, p.module_material)
    App, Part = _fc()
    V = App.Vector
    T = p.sheet_thickness_mm
    clr = p.clearance_mm
    lip = p.socket_lip_height_mm
    r = p.socket_radius_mm - clr
    rb = p.counterbore_radius_mm - clr
    z_tip = clr
    z_sh = lip - clr
    shaft = Part.makeCylinder(r, T + PIN_OVERLAP_MM - z_sh, V(0, 0, z_sh))
    barb = Part.makeCone(r, rb, z_sh - z_tip, V(0, 0, z_tip))
    pin = shaft.fuse(barb)
    slot_w = snap.slot_mm
    slot = Part.makeBox(slot_w, 2 * rb + 2, snap.slot_top_mm - (z_tip - 1.0), V(-0.5 * slot_w, -rb - 1, z_tip - 1.0))
    pin = pin.cut(slot).removeSplitter()
    pin = pin.Solids[0] if len(pin.Solids) == 1 else pin
    if up:
        pin = pin.mirror(V(0, 0, 0.5 * T), V(0, 0, 1))       # now from z = -overlap up to T - clearance
    return pin


def _pins_at(p, points, up=False, z_shift=0.0, snap=None):
    App, _ = _fc()
    proto = make_pin(p, up, snap)
    out = []
    for (u, v) in points:
        m = App.Matrix()
        m.move(App.Vector(u, v, z_shift))
        out.append(proto.transformed(m))
    return out


def _lateral_points(p, u_centre):
    d = 0.5 * p.plate_side_mm_global - p.socket_inset_mm
    return [(u_centre, d), (u_centre, -d)]



def adapter_pin_points(spec, p):
    """Module-frame centres of the horn adapter's pins (node B's lateral sockets, one of them swapped
    for the far socket by :func:`_adapter_sockets`)."""
    u_b = 0.5 * p.cell_size_mm
    d = 0.5 * p.plate_side_mm_global - p.socket_inset_mm
    sw = spec.values.get("pin_b_swap_v", 0.0)
    pts = [(u, v) for u, v in _lateral_points(p, u_b) if not (sw and v * sw > 0)]
    return pts + ([(u_b + d, 0.0)] if sw else [])


CLIP_RIVET_WAIT_MM = 1.0    # a clip's rivets for its second node wait this far off the clip's face (assembly)


def clip_waiting_rivets(spec, p):
    """``{part name: lift (mm)}`` of a constraint clip's rivets in node B's sockets (riveted after node A's
    two). The clip is built holding its angle (its second plate and these rivets turned about the joint's
    pivot), so they go in only once the joint is bent to that angle; on the flat sheet (the assembly, the
    document) they wait on their channels' axes, their tips ``CLIP_RIVET_WAIT_MM`` above the clip's face
    (``lift`` above their seats; mirrored with the clip on the bottom face). Empty for a clip that holds
    0 deg: then every rivet seats in the flat sheet."""
    if spec.values["angle_deg"] == 0.0:
        return {}
    lift = p.sheet_thickness_mm + spec.values["thickness_mm"] + CLIP_RIVET_WAIT_MM - p.clearance_mm
    return {f"clip_rivet_{k}": lift for k in (3, 4)}


def _finish(body_parts, cutters, what):
    """One fuse for all bodies, one cut for all cutters; returns a single valid solid."""
    base, rest = body_parts[0], body_parts[1:]
    shape = base.fuse(rest) if rest else base
    if cutters:
        shape = shape.cut(cutters)
    shape = shape.removeSplitter()
    if len(shape.Solids) != 1:
        from metamaterial_wb.core.errors import MetamaterialError
        raise MetamaterialError(f"{what}: the module came out as {len(shape.Solids)} solids")
    return shape.Solids[0]


def riveted(p, shape, points, snap, what):
    """Channels for separate rivet pins (geometry/rivet.py) through a module part at the module-frame
    socket ``points``: a hole of ``socket radius`` (shank + clearance) from the sheet's top face up
    through all the material above the socket, so that a rivet pushed in from above traps the part with
    its head on the part's top face there. Returns ``(part with channels, [(rivet, foot_mm, (u, v))])``.
    Refuses a channel that would run through air (material above the socket not one solid column)."""
    import math

    from metamaterial_wb.core.errors import MetamaterialError
    from metamaterial_wb.geometry.rivet import make_rivet

    App, Part = _fc()
    V = App.Vector
    T = p.sheet_thickness_mm
    rh = p.socket_radius_mm
    top = shape.BoundBox.ZMax + 1.0
    channels, rivets = [], []
    for (u, v) in points:
        com = shape.common(Part.makeCylinder(rh, top - T, V(u, v, T)))
        if com.Volume < 1e-6:
            raise MetamaterialError(f"{what}: no foot above the socket at ({u:.3g}, {v:.3g}) mm for a rivet pin")
        z_top = com.BoundBox.ZMax
        full = math.pi * rh * rh * (z_top - T)
        if com.Volume < 0.97 * full:
            raise MetamaterialError(f"{what}: the rivet channel above the socket at ({u:.3g}, {v:.3g}) mm would run "
                                    f"through air up to z = {z_top:.3g} mm ({com.Volume:.4g} of {full:.4g} mm3 solid)")
        channels.append(Part.makeCylinder(rh, z_top - T + 2.0, V(u, v, T - 1.0)))
        m = App.Matrix()
        m.move(V(u, v, 0.0))
        rivets.append((make_rivet(p, z_top - T, snap).transformed(m, True), z_top - T, (u, v)))   # a copy: the move in the geometry, not a location (FreeCAD 1.0 composed that location twice)
    out = shape.cut(channels).removeSplitter()
    if len(out.Solids) != 1:
        raise MetamaterialError(f"{what}: the rivet channels split it into {len(out.Solids)} solids")
    return out.Solids[0], rivets


def blind_riveted(p, shape, points, snap, what):
    """Blind sockets for rivets pushed in from the sheet's underside (geometry/rivet.make_blind_rivet)
    in a module part at the module-frame socket ``points``: a hole of socket radius through a ledge as
    thick as the sheet's own (``socket_lip_height_mm``) above the sheet's top face, then an undercut
    (counterbore radius, as deep) that the rivet's barb snaps into, closed above. Nothing opens on the
    part's far side (the servo's cavity lies over the housing's sockets). Refuses a socket without two
    nozzle widths of material around the undercut and above it. Returns ``(part with the sockets,
    [(rivet, ledge_mm, (u, v))])``."""
    import math

    from metamaterial_wb.core.errors import MetamaterialError
    from metamaterial_wb.geometry.rivet import make_blind_rivet

    App, Part = _fc()
    V = App.Vector
    T, lip, W = p.sheet_thickness_mm, p.socket_lip_height_mm, p.min_wall_mm
    ledge = lip
    need_h = ledge + lip + W
    rr = p.counterbore_radius_mm + W
    proto = make_blind_rivet(p, ledge, snap)
    cutters, rivets = [], []
    for (u, v) in points:
        com = shape.common(Part.makeCylinder(rr, need_h, V(u, v, T))).Volume
        full = math.pi * rr * rr * need_h
        if com < 0.999 * full:
            raise MetamaterialError(f"{what}: the blind rivet socket at ({u:.3g}, {v:.3g}) mm needs solid material "
                                    f"{need_h:.3g} mm up from the sheet and {rr:.3g} mm around its axis (ledge, "
                                    f"undercut and two nozzle widths of wall); {100 * com / full:.3g} % of it is there")
        cutters += [Part.makeCylinder(p.socket_radius_mm, ledge + 1.5, V(u, v, T - 1.0)),
                    Part.makeCylinder(p.counterbore_radius_mm, lip, V(u, v, T + ledge))]
        m = App.Matrix()
        m.move(V(u, v, 0.0))
        rivets.append((proto.transformed(m, True), ledge, (u, v)))    # a copy (FreeCAD 1.0: see riveted)
    out = shape.cut(cutters).removeSplitter()
    if len(out.Solids) != 1:
        raise MetamaterialError(f"{what}: the blind rivet sockets split it into {len(out.Solids)} solids")
    return out.Solids[0], rivets


def rivet_parts(part, rivets):
    """``[(name, shape)]`` of a part's rivet pins (:func:`riveted`, :func:`blind_riveted`), named
    ``<part>_rivet_<k>``."""
    return [(f"{part}_rivet_{k + 1}", sh) for k, (sh, _foot, _uv) in enumerate(rivets)]
