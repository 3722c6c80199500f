"""The servo housing module: presets from real dimensions, the cavity, tab seats with screw pilot
holes, and the horn adapter whose arm holds the whole horn over the shaft, the shaft on the joint's
pivot (core/joints.py). Parsed and placed by geometry/modules.py (scene format: docs/scene-format.md,
"Modules"; geometry: docs/fabrication.md)."""
import math

from metamaterial_wb.core.errors import SceneError, check_number, in_range, range_message
from metamaterial_wb.core.numbers import inward_g

# Servo presets (mm) from public datasheet drawings, bodies at the upper end of what the parts measure
# (SG90s measure 22.2-23.0 x 11.8-12.5 mm): the cavity adds the fit clearance on every side. ``tab_z_mm``:
# tab underside above the body bottom; ``screw_inset_mm``: screw hole centre to the tab's end;
# ``screw_diameter_mm``: the self-tapping screw (the seat gets a pilot hole 0.3 mm smaller).
# ``horn_*``: the single-arm horn in the box (hub diameter, thickness, shaft axis to arm tip, arm
# width at the hub). Measure yours and override any of them with "dims".
SERVO_PRESETS = {
    "SG90": {"body_length_mm": 23.0, "body_width_mm": 12.5, "body_height_mm": 22.7, "tab_length_mm": 32.2,
             "tab_thickness_mm": 2.5, "tab_z_mm": 15.9, "shaft_offset_mm": 5.9, "shaft_top_mm": 27.0,
             "screw_inset_mm": 2.3, "screw_diameter_mm": 2.0,
             "horn_hub_diameter_mm": 7.0, "horn_thickness_mm": 1.5, "horn_arm_length_mm": 14.0,
             "horn_arm_width_mm": 4.0},
    "MG90S": {"body_length_mm": 23.0, "body_width_mm": 12.5, "body_height_mm": 22.5, "tab_length_mm": 32.5,
              "tab_thickness_mm": 2.5, "tab_z_mm": 16.0, "shaft_offset_mm": 6.1, "shaft_top_mm": 28.4,
              "screw_inset_mm": 2.3, "screw_diameter_mm": 2.0,
              "horn_hub_diameter_mm": 7.0, "horn_thickness_mm": 1.8, "horn_arm_length_mm": 14.0,
              "horn_arm_width_mm": 4.5},
    "MG996R": {"body_length_mm": 40.7, "body_width_mm": 19.7, "body_height_mm": 37.0, "tab_length_mm": 54.0,
               "tab_thickness_mm": 2.5, "tab_z_mm": 26.7, "shaft_offset_mm": 10.2, "shaft_top_mm": 42.9,
               "screw_inset_mm": 3.4, "screw_diameter_mm": 3.0,
               "horn_hub_diameter_mm": 9.0, "horn_thickness_mm": 2.5, "horn_arm_length_mm": 19.0,
               "horn_arm_width_mm": 6.0},
}
SERVO_KEYS = tuple(SERVO_PRESETS["SG90"])
SERVO_OPTIONAL = ("screw_inset_mm", "screw_diameter_mm")   # a custom servo may leave these out
CABLE_SLOT_MM = 5.0         # height of the cable's way out at the housing's far end (above the floor)
# The housing prints upside down (tub top on the bed): the cavity's floor is then a ceiling. A flat
# ceiling as wide as the cavity (12.9 mm for an SG90) is too long a bridge, so the cavity runs on
# below the servo's bottom as a trough whose walls slope at GROOVE_SLOPE_DEG from the horizontal
# (steeper than the 45 deg overhang rule) down to a flat GROOVE_BRIDGE_MM wide (a printable bridge with
# a margin under 10 mm). The servo hangs on its tabs (screwed into the seats), not on the floor.
GROOVE_BRIDGE_MM = 8.0
GROOVE_SLOPE_DEG = 55.0
PILOT_UNDERSIZE_MM = 0.3    # a tab screw's pilot hole is this much narrower than the screw
FIT_MARGIN_MM = 0.3         # the horn adapter's column ends at least this far inside node B's far edge


def cable_height_mm(tab_z_mm, wall_mm):
    """Height of the cable's way out under the tab seat (CABLE_SLOT_MM where the seat is tall enough)."""
    return min(CABLE_SLOT_MM, max(tab_z_mm - 2 * wall_mm - 4.0, 1.0))


def pilot_depth_mm(tab_z_mm, wall_mm):
    """Depth of the tab screws' pilot holes: down from the seat top to two nozzle widths above the cable slot."""
    return tab_z_mm - cable_height_mm(tab_z_mm, wall_mm) - wall_mm


def _min_tab_z_mm(depth_mm, wall_mm):
    """Lowest ``tab_z_mm`` whose pilot holes are ``depth_mm`` deep (:func:`pilot_depth_mm` grows with tab_z: by
    1 while the cable slot is 1 mm high, not at all while the slot grows, by 1 again once it is CABLE_SLOT_MM)."""
    if depth_mm <= wall_mm + 4.0:
        return depth_mm + 1.0 + wall_mm
    return depth_mm + CABLE_SLOT_MM + wall_mm


def _dims_range(field, value, low, high, why):
    if not in_range(value, low, high):
        raise SceneError(field, f"{range_message(value, low, high, 'mm')}: {why}")


def _servo_dims(item, f, nm, p=None):
    servo = item.get("servo", "SG90")
    if not isinstance(servo, str) or servo.upper() not in list(SERVO_PRESETS) + ["CUSTOM"]:
        raise SceneError(f"{f}.servo ({nm})", f"{servo!r} is not a known servo; allowed: {sorted(SERVO_PRESETS)} or "
                                       f"\"custom\" with \"dims\"")
    servo = servo.upper()
    dims = item.get("dims", {})
    if not isinstance(dims, dict):
        raise SceneError(f"{f}.dims ({nm})", f"expected an object of servo dimensions in mm, got {dims!r}")
    for k in dims:
        if k not in SERVO_KEYS:
            raise SceneError(f"{f}.dims.{k} ({nm})", f"unknown servo dimension; allowed: {list(SERVO_KEYS)}")
    if servo == "CUSTOM":
        missing = [k for k in SERVO_KEYS if k not in dims and k not in SERVO_OPTIONAL]
        if missing:
            raise SceneError(f"{f}.dims ({nm})", f"a custom servo needs every dimension; missing: {missing}")
        d = {}
        ext = 0.5 * (float(dims.get("tab_length_mm", 0)) - float(dims.get("body_length_mm", 0)))
        d.update({"screw_inset_mm": max(0.5 * ext, 1e-3), "screw_diameter_mm": 2.0})
    else:
        d = dict(SERVO_PRESETS[servo])
    for k, v in dims.items():
        d[k] = check_number(f"{f}.dims.{k} ({nm})", v, 0.0, 500.0, "mm", low_open=True)
    if d["tab_length_mm"] < d["body_length_mm"]:
        raise SceneError(f"{f}.dims.tab_length_mm ({nm})", f"{d['tab_length_mm']} mm is shorter than the body "
                                                    f"({d['body_length_mm']} mm); it is the length over both tabs")
    if not 0 < d["shaft_offset_mm"] < d["body_length_mm"]:
        raise SceneError(f"{f}.dims.shaft_offset_mm ({nm})", f"{d['shaft_offset_mm']} mm is outside the body; allowed "
                                                      f"range (0, {d['body_length_mm']}) mm")
    nozzle = p.nozzle_mm if p is not None else 0.4
    W = 2.0 * nozzle
    ext = 0.5 * (d["tab_length_mm"] - d["body_length_mm"])
    # the tab screws' pilot holes (build_servo_housing): radius (screw - 0.3) / 2, at screw_inset_mm from the seat's
    # end, pilot_depth_mm deep. At least a nozzle width wide (a narrower hole does not print), two nozzle widths
    # of seat around it, as deep as the screw is wide (its thread needs that much to hold)
    tab = inward_g(ext)         # rounded down: the bound typed back is accepted, a refused inset lies beyond it
    if not 0 < d["screw_inset_mm"] < ext:
        raise SceneError(f"{f}.dims.screw_inset_mm ({nm})", f"{d['screw_inset_mm']} mm puts the tab's screw outside "
                                                           f"the {tab} mm tab; allowed range (0, {tab}) mm")
    _dims_range(f"{f}.dims.screw_inset_mm ({nm})", d["screw_inset_mm"], 0.5 * nozzle + W, ext,
                f"the narrowest pilot hole (a nozzle width, {nozzle:g} mm) needs two nozzle widths ({W:.3g} mm) of "
                f"tab seat between it and the seat's end, and the screw must stay on the {tab} mm tab")
    _dims_range(f"{f}.dims.screw_diameter_mm ({nm})", d["screw_diameter_mm"], PILOT_UNDERSIZE_MM + nozzle,
                2 * (d["screw_inset_mm"] - W) + PILOT_UNDERSIZE_MM,
                f"the tab seat's pilot hole ({PILOT_UNDERSIZE_MM} mm narrower than the screw) must be at least "
                f"a nozzle width ({nozzle:g} mm) wide and leave two nozzle widths ({W:.3g} mm) of seat before "
                f"the seat's end, {d['screw_inset_mm']} mm (screw_inset_mm) from the screw's centre")
    _dims_range(f"{f}.dims.tab_z_mm ({nm})", d["tab_z_mm"], _min_tab_z_mm(d["screw_diameter_mm"], W),
                d["body_height_mm"] - d["tab_thickness_mm"],
                f"the tabs ({d['tab_thickness_mm']} mm thick) must stay on the {d['body_height_mm']} mm body, and "
                f"the tab seat under them must hold pilot holes as deep as the {d['screw_diameter_mm']} mm screw "
                f"is wide above the cable slot and two nozzle widths ({W:.3g} mm) of floor")
    if d["shaft_top_mm"] - d["horn_thickness_mm"] <= d["body_height_mm"]:
        raise SceneError(f"{f}.dims.shaft_top_mm ({nm})", f"the horn ({d['horn_thickness_mm']} mm) under the shaft top at "
                                                   f"{d['shaft_top_mm']} mm would touch the body top "
                                                   f"({d['body_height_mm']} mm)")
    d["servo"] = servo
    return d


def servo_layout(spec, p):
    """Key u / z coordinates (mm) of the servo housing and the horn adapter, relative to the shaft
    axis (``u`` along the joint from the housing node towards the other node). The shaft itself sits
    on the joint's pivot (core/joints.py) at ``(shaft_u_mm, shaft_v_mm)`` of the module frame."""
    v = spec.values
    T = p.sheet_thickness_mm
    clr = p.clearance_mm
    a = v["shaft_offset_mm"]
    L = v["body_length_mm"]
    standoff = v["pad_mm"] + clr
    wall = v["wall_mm"]
    w = v["body_width_mm"] + 2 * clr
    groove = max(0.0, 0.5 * (w - GROOVE_BRIDGE_MM)) * math.tan(math.radians(GROOVE_SLOPE_DEG))
    lay = {
        "a": a, "L": L, "clr": clr,
        "hu0": a - L - clr - wall, "hu1": a + clr + wall,
        "hv": 0.5 * v["body_width_mm"] + clr + wall,
        "z_floor": T + standoff, "zb": T + standoff + v["floor_mm"] + groove, "groove_mm": groove,
        # the column turns against the housing about the shaft: it stands 1 mm outside the circle through
        # the housing's far corners (tab seats), and beyond the whole horn arm (which turns with it: the
        # horn pocket ends at the column)
        "col_u0": max(_housing_radius_mm(v, clr, wall), v["horn_arm_length_mm"] + clr),
        "col_t": 3.0, "arm_t": max(2.5, v["horn_thickness_mm"] + clr + 1.0),
    }
    lay["z_arm"] = lay["zb"] + v["shaft_top_mm"] - v["horn_thickness_mm"]
    return lay


def _housing_radius_mm(v, clr, wall):
    """Radius about the shaft of the circle the housing's far corners (tub and tab seats) sweep, plus 1 mm: where
    the horn adapter's column may start (servo_layout ``col_u0`` but for the horn arm)."""
    a = v["shaft_offset_mm"]
    tab_end = a + 0.5 * (v["tab_length_mm"] - v["body_length_mm"])
    return math.hypot(max(a + clr + wall, tab_end), 0.5 * v["body_width_mm"] + clr + wall) + 1.0


def _check_servo_fit(spec, p, f):
    """The horn adapter's column (servo_layout: outside the housing's circle and beyond the horn arm) must end
    FIT_MARGIN_MM inside node B. The advice names what sets the column's place, with numbers that work: the cell
    size rounded up, a shorter horn arm only when the horn sets it, a thinner wall_mm only when the housing does
    (both rounded down to 0.1 mm)."""
    lay = servo_layout(spec, p)
    v = spec.values
    c = p.cell_size_mm
    clr = p.clearance_mm
    far_b = 0.5 * p.gap_mm + p.plate_side_mm_global - v.get("shaft_u_mm", 0.0)
    need = lay["col_u0"] + lay["col_t"] + FIT_MARGIN_MM
    if need <= far_b:
        return
    room = far_b - lay["col_t"] - FIT_MARGIN_MM             # the largest col_u0 that fits
    housing = _housing_radius_mm(v, clr, v["wall_mm"])
    horn = v["horn_arm_length_mm"] + clr
    cell = math.ceil((c + need - far_b) * 10.0 - 1e-6) / 10.0
    tips = [f"cells of at least {cell:g} mm (cell_size_mm is {c:g})"]
    by = (f"the circle the housing's corners sweep (wall_mm {v['wall_mm']:g} mm)" if housing >= horn else
          f"the {v['horn_arm_length_mm']:g} mm horn arm")
    if horn > housing and housing <= room:
        arm = math.floor((room - clr) * 10.0 + 1e-6) / 10.0
        if arm > 0:
            tips.append(f"a shorter horn (dims.horn_arm_length_mm at most {arm:g} mm)")
    if housing >= horn and horn <= room and _housing_radius_mm(v, clr, p.min_wall_mm) <= room:
        lo, hi = p.min_wall_mm, v["wall_mm"]
        for _ in range(60):                                  # the radius grows with the wall
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if _housing_radius_mm(v, clr, mid) <= room else (lo, mid)
        wall = math.floor(lo * 10.0 + 1e-6) / 10.0
        if wall >= p.min_wall_mm - 1e-9:
            tips.append(f"a thinner housing wall (wall_mm at most {wall:g} mm; at least two nozzle widths, "
                        f"{inward_g(p.min_wall_mm, up=True)} mm)")
    raise SceneError(f"{f}.servo ({spec.name})",
                     f"the horn adapter's column, outside {by}, needs {math.ceil(need * 100) / 100:.2f} mm from the "
                     f"shaft (its {lay['col_t']:g} mm width and a {FIT_MARGIN_MM} mm margin included) but node "
                     f"N{spec.b[0]},{spec.b[1]} ends {math.floor(far_b * 100) / 100:.2f} mm from it; allowed: "
                     + " or ".join(tips))


def adapter_block_fits(spec, p):
    """Whether the horn adapter's pad can be the foot of a block outside the circle the housing sweeps
    (radius ``col_u0`` about the shaft): every pin centre on node B lies outside it."""
    from metamaterial_wb.geometry.solids import adapter_pin_points

    lay = servo_layout(spec, p)
    su, sv = spec.values.get("shaft_u_mm", 0.0), spec.values.get("shaft_v_mm", 0.0)
    return all(math.hypot(u - su, v - sv) >= lay["col_u0"] for u, v in adapter_pin_points(spec, p))


def blind_rivet_problem(spec, p):
    """Why the housing and its horn adapter cannot be held by blind rivets (geometry/rivet.make_blind_rivet:
    pushed in from the sheet's underside, printed lying, prongs bending along the layers), or None. A
    blind socket needs a ledge and an undercut of ``socket_lip_height_mm`` each and two nozzle widths
    of roof above the sheet, and two nozzle widths of wall around the undercut: under the servo that is
    the housing's feet and floor; on node B the adapter's block outside the circle the housing sweeps."""
    from metamaterial_wb.geometry.solids import adapter_pin_points

    v = spec.values
    W, lip, cbr = p.min_wall_mm, p.socket_lip_height_mm, p.counterbore_radius_mm
    need, have = 2 * lip + W, v["pad_mm"] + p.clearance_mm + v["floor_mm"]
    if have < need - 1e-9:
        need_t = inward_g(need, up=True, slack=1e-9)        # rounded up: feet and floor that thick are enough
        return (f"the housing's feet and floor under the servo (pad_mm + clearance + floor_mm = {have:.3g} mm) are "
                f"thinner than a blind rivet socket ({need_t} mm: ledge and undercut of socket_lip_height_mm "
                f"each and two nozzle widths of roof)")
    if p.socket_inset_mm - 0.3 < cbr + W - 1e-9:
        return (f"sockets {p.socket_inset_mm} mm inside the plate edge leave less than two nozzle widths of wall "
                f"around a blind rivet socket (socket_inset_mm at least {inward_g(cbr + W + 0.3, up=True)} mm)")
    lay = servo_layout(spec, p)
    su, sv = v.get("shaft_u_mm", 0.0), v.get("shaft_v_mm", 0.0)
    for u, w in adapter_pin_points(spec, p):
        out = math.hypot(u - su, w - sv) - lay["col_u0"]
        if out < cbr + W - 1e-9:
            return (f"node B's socket at ({u:.3g}, {w:.3g}) mm (module frame) lies {out:.3g} mm outside the circle "
                    f"the housing sweeps about the shaft; the adapter's blind rivet socket needs {cbr + W:.3g} mm")
    return None


def build_servo_housing(spec, p):
    """Housing (tub with the servo cavity, on the housing node) and horn adapter (on the other node),
    the shaft on the joint's pivot: the servo turns node B about the hinge, as simulated."""
    from metamaterial_wb.geometry.solids import (_fc, _finish, _lateral_points, _pins_at, adapter_pin_points,
                                                 blind_riveted, box, rivet_parts)

    App, Part = _fc()
    V = App.Vector
    v = spec.values
    lay = servo_layout(spec, p)
    T = p.sheet_thickness_mm
    c, s, gap = p.cell_size_mm, p.plate_side_mm_global, p.gap_mm
    clr = p.clearance_mm
    a, L = lay["a"], lay["L"]
    hv = lay["hv"]
    su, sv = v.get("shaft_u_mm", 0.0), v.get("shaft_v_mm", 0.0)
    shift = App.Matrix()
    shift.move(V(su, sv, 0.0))

    def at_shaft(shape):
        return shape.transformed(shift)

    top = lay["zb"] + v["tab_z_mm"]
    ext = 0.5 * (v["tab_length_mm"] - L)
    outer = box(lay["hu0"], lay["hu1"], -hv, hv, lay["z_floor"], top)
    # tab seats: the tub runs on under both tabs, so that the tab screws go into material
    seats = [box(a - L - ext, lay["hu0"] + 0.01, -hv, hv, lay["z_floor"], top),
             box(lay["hu1"] - 0.01, a + ext, -hv, hv, lay["z_floor"], top)]
    inner = box(a - L - clr, a + clr, -(0.5 * v["body_width_mm"] + clr), 0.5 * v["body_width_mm"] + clr,
                lay["zb"], top + 1.0)
    troughs = []
    if lay["groove_mm"] > 0:
        w0 = 0.5 * v["body_width_mm"] + clr
        w1 = 0.5 * min(GROOVE_BRIDGE_MM, 2 * w0)
        zt, zbot = lay["zb"] + 0.01, lay["zb"] - lay["groove_mm"]
        prof = Part.makePolygon([V(a - L - clr, -w0, zt), V(a - L - clr, w0, zt), V(a - L - clr, w0, lay["zb"]),
                                 V(a - L - clr, w1, zbot), V(a - L - clr, -w1, zbot), V(a - L - clr, -w0, lay["zb"]),
                                 V(a - L - clr, -w0, zt)])
        troughs.append(Part.Face(prof).extrude(V(L + 2 * clr, 0, 0)))
    cable_h = cable_height_mm(v["tab_z_mm"], p.min_wall_mm)
    cable = box(a - L - ext - 1.0, a - L, -2.0, 2.0, lay["zb"], lay["zb"] + cable_h)
    pilot_r = 0.5 * (v["screw_diameter_mm"] - PILOT_UNDERSIZE_MM)      # _servo_dims checked the pilot's ranges
    pilot_depth = pilot_depth_mm(v["tab_z_mm"], p.min_wall_mm)
    pilots = [Part.makeCylinder(pilot_r, pilot_depth + 1.0, V(u, 0.0, top - pilot_depth))
              for u in (a - L - ext + v["screw_inset_mm"], a + ext - v["screw_inset_mm"])]
    d = 0.5 * s - p.socket_inset_mm
    fv = max(d + p.counterbore_radius_mm + max(1.0, p.min_wall_mm), 2.0)
    u_a = -0.5 * c
    fu0 = max(-0.5 * gap - s + 0.3, min(lay["hu0"] + su, u_a - p.counterbore_radius_mm - 1.0))
    fu1 = -0.5 * gap - 0.3
    feet = box(fu0, fu1, -fv, fv, T, lay["z_floor"] + 0.01)
    # the feet's footprint runs on up to the tub's top: printed upside down, the feet stand on it
    skirt = box(fu0, fu1, -fv, fv, lay["z_floor"], top)
    # a floor patch joining the feet to the tub (both ranges in v: the tub sits over the hinge pivot)
    v0, v1 = min(-fv, sv - hv), max(fv, sv + hv)
    bridge = box(max(fu0, lay["hu0"] + su), fu1, max(v0, sv - hv), min(v1, sv + hv), T, lay["zb"])
    # held by blind rivets pushed in from the sheet's underside (the cavity lies over node A's sockets);
    # fused upright pins only where they do not fit (blind_rivet_problem, said in the manifest)
    blind = bool(v.get("blind_rivets"))
    pins = [] if blind else _pins_at(p, _lateral_points(p, u_a), snap=spec.snap)
    housing = _finish([at_shaft(outer)] + [at_shaft(q) for q in seats] + [feet, skirt, bridge] + pins,
                      [at_shaft(q) for q in [inner, cable] + troughs + pilots], f"{spec.name} housing")
    rivets_h = []
    if blind:
        housing, rivets_h = blind_riveted(p, housing, _lateral_points(p, u_a), spec.snap, f"{spec.name} housing")
    # horn adapter on node B: pad with pins, column beyond the horn, arm with the horn pocket over the shaft
    u_b = 0.5 * c
    far_b = 0.5 * gap + s - 0.3
    pu0 = min(lay["col_u0"] + su, u_b - p.counterbore_radius_mm - 1.0)
    pu0 = max(pu0, 0.5 * gap + 0.3)          # the housing sits above the pad (z >= z_floor): no overlap
    cw = max(4.0, 0.5 * v["horn_arm_width_mm"] + 2.0)
    col = box(lay["col_u0"], lay["col_u0"] + lay["col_t"], -cw, cw, T,
              lay["z_arm"] + lay["arm_t"])
    hub_r = 0.5 * v["horn_hub_diameter_mm"]
    arm = box(-hub_r - 2.0, lay["col_u0"] + lay["col_t"], -cw, cw, lay["z_arm"], lay["z_arm"] + lay["arm_t"])
    depth = v["horn_thickness_mm"] + clr
    hub = Part.makeCylinder(hub_r + clr, depth + 1.0, V(0, 0, lay["z_arm"] - 1.0))
    horn = box(0.0, v["horn_arm_length_mm"] + clr, -(0.5 * v["horn_arm_width_mm"] + clr),
               0.5 * v["horn_arm_width_mm"] + clr, lay["z_arm"] - 1.0, lay["z_arm"] + depth)
    shaft_hole = Part.makeCylinder(1.2, lay["arm_t"] + 2.0, V(0, 0, lay["z_arm"] - 1.0))  # horn screw
    # The adapter prints upside down (arm top on the bed): the pad then hangs at the top of the print, so
    # it is the foot of a block that stands on the bed under all of it (the arm's top plane), outside the
    # circle the housing sweeps (radius col_u0 about the shaft) so that the servo still turns it freely.
    # When node B's sockets lie inside that circle (small cells) the pins need the pad there: the pad
    # stays whole and the pose check reports what then needs support.
    ztop = lay["z_arm"] + lay["arm_t"]
    bv0 = max(min(-fv, sv - cw), -0.5 * s + 0.3)
    bv1 = min(max(fv, sv + cw), 0.5 * s - 0.3)
    pads = [box(pu0, far_b, bv0, bv1, T, T + v["pad_mm"])]
    if adapter_block_fits(spec, p):
        pads = [pads[0].cut(Part.makeCylinder(lay["col_u0"], v["pad_mm"] + 2.0, V(su, sv, T - 1.0))),
                box(pu0, far_b, bv0, bv1, T, ztop).cut(Part.makeCylinder(lay["col_u0"], ztop - T + 2.0,
                                                                         V(su, sv, T - 1.0)))]
    pins_b = [] if blind else _pins_at(p, adapter_pin_points(spec, p), snap=spec.snap)
    adapter = _finish(pads + [at_shaft(col), at_shaft(arm)] + pins_b,
                      [at_shaft(hub), at_shaft(horn), at_shaft(shaft_hole)], f"{spec.name} horn adapter")
    rivets_a = []
    if blind:
        adapter, rivets_a = blind_riveted(p, adapter, adapter_pin_points(spec, p), spec.snap,
                                          f"{spec.name} horn adapter")
    return ([("housing", housing), ("horn_adapter", adapter)] + rivet_parts("housing", rivets_h) +
            rivet_parts("horn_adapter", rivets_a))
