"""Modules: valid solids, placed where the scene says, clear of the sheet at rest, parametric."""
import math

import pytest

from fabhelpers import make_scene

C, S, T, CLR = 20.0, 18.0, 7.0, 0.2
MODULES = [
    {"type": "servo_housing", "name": "servo", "joint": "V0,1", "servo": "SG90"},
    {"type": "friction_pad", "name": "pad", "node": "N0,0", "mu": 0.9},
    {"type": "connection_hub", "name": "hub", "node": "N2,3"},
    {"type": "stable_hub", "name": "stable", "joint": "H0,2"},
    {"type": "constraint_clip", "name": "clip", "joint": "H2,1", "angle_deg": 6.0},
]


@pytest.fixture(scope="module")
def mod_result(fc):
    from metamaterial_wb.geometry.build import build_scene
    return build_scene(make_scene({"grid": [2, 3]}, modules=MODULES), progress=False)


def _part(r, name):
    return r.placed_shape(r.by_name(name))


def test_every_module_is_one_valid_solid_in_its_own_group(mod_result):
    from metamaterial_wb.geometry import validity
    r = mod_result
    assert validity.check_solids(r) == []
    groups = r.groups()
    assert list(groups) == ["sheet", "servo", "pad", "hub", "stable", "clip"]
    assert [q.name for q in groups["servo"]] == ["servo_housing", "servo_horn_adapter", "servo_housing_rivet_1",
                                                 "servo_housing_rivet_2", "servo_horn_adapter_rivet_1",
                                                 "servo_horn_adapter_rivet_2"]
    assert all(q.material == "ABS" and q.extruder == 1 for g in list(groups)[1:] for q in groups[g])


def test_modules_clear_of_the_sheet_at_rest(mod_result):
    from metamaterial_wb.geometry import validity
    assert validity.check_modules(mod_result) == []


def test_clip_holds_its_angle(mod_result):
    """At rest the clip's second half does not fit node N2,2: it fits N2,2 turned by angle_deg. The two rivets
    for N2,2 wait above their channels on the flat sheet (info lifted_mm); on their seats they would collide
    with the flat node but pass through its sockets turned by the clip angle about the pivot."""
    import FreeCAD
    from metamaterial_wb.geometry.validity import _turn_about
    V = FreeCAD.Vector
    r = mod_result
    rivets = [q for q in r.groups()["clip"] if q.info.get("rivet")]
    lift = T + 3.0 + 1.0 - CLR                  # tips 1 mm above the 3 mm clip's face
    assert [q.info.get("lifted_mm", 0.0) for q in rivets] == pytest.approx([0.0, 0.0, lift, lift])
    seated = [r.placed_shape(q).transformed(FreeCAD.Matrix(1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1,
                                                           -q.info.get("lifted_mm", 0.0)), True) for q in rivets]
    clip = _part(r, "clip_clip").fuse(seated)
    node_b = _part(r, "node_2_2")
    assert clip.common(node_b).Volume > 1.0               # its rivets would collide in the flat state ...
    assert clip.common(_part(r, "node_2_1")).Volume < 1e-3     # ... but fit its first node
    spec = [m for m in r.modules if m.name == "clip"][0]
    x, y, _ = spec.pivot.point_mm
    turned = node_b.transformed(_turn_about(V(x, y, 0.0), V(0, 0, 1), 6.0).toMatrix())
    assert clip.common(turned).Volume < 1e-3                    # ... and its second node turned by the angle
    waiting = _part(r, "clip_clip").fuse([r.placed_shape(q) for q in rivets])
    assert waiting.common(node_b).Volume < 1e-3                 # as assembled (flat), they wait clear of it


def test_servo_shaft_on_the_joint_pivot(mod_result):
    """The horn pocket's hub cylinder is centred on the hinge pivot of V0,1 (N0,1 odd: left corners,
    edge line x = 20 - 9 = 11, blade centre 0.4 mm inside, shifted by the pivot offset), y = -10."""
    r = mod_result
    spec = [m for m in r.modules if m.name == "servo"][0]
    C_PIVOT = 11.0 + 0.4 + spec.pivot.offset_mm
    adapter = _part(r, "servo_horn_adapter")
    hub_r = 0.5 * 7.0 + CLR
    cyl = [f for f in adapter.Faces if f.Surface.__class__.__name__ == "Cylinder"
           and abs(f.Surface.Radius - hub_r) < 1e-9]
    assert cyl, "no horn hub pocket"
    for f in cyl:
        # u runs from N0,1 down to N1,1 (-y): the shaft sits along the blade towards A by -along_mm
        assert (f.Surface.Center.x, f.Surface.Center.y) == pytest.approx((C_PIVOT, -C / 2 - spec.pivot.along_mm),
                                                                         abs=2e-6)
        assert abs(f.Surface.Axis.z) == pytest.approx(1.0)
    # the housing sits on the first node N0,1, the adapter on the second N1,1 (below it, y < -10)
    hb, ab = _part(r, "servo_housing").BoundBox, adapter.BoundBox
    assert hb.YMax > -C / 2 > hb.YMin                       # housing spans the joint (shaft inside it)
    assert ab.YMax == pytest.approx(-C / 2 - spec.pivot.along_mm + 3.5 + 2.0)   # the arm ends 2 mm beyond the horn hub


def test_pins_reach_into_the_sockets(mod_result):
    r = mod_result
    # riveted modules: the part stays on its face, its separate rivet pins reach through the sheet (the
    # servo's blind rivets from the underside: heads in the bottom counterbores, just above the bed)
    for name in ("servo_housing", "servo_horn_adapter"):
        assert _part(r, name).BoundBox.ZMin == pytest.approx(T), name
        rivets = [q for q in r.groups()["servo"] if q.name.startswith(f"{name}_rivet_")]
        assert len(rivets) == 2 and all(r.placed_shape(q).BoundBox.ZMin == pytest.approx(CLR) for q in rivets)
    for group, part in (("stable", "stable_hub"), ("clip", "clip_clip")):
        assert _part(r, part).BoundBox.ZMin == pytest.approx(T), part
        rivets = [q for q in r.groups()[group] if q.info.get("rivet")]
        # (the clip's two rivets for its second node wait above their seats until the joint is bent: lifted_mm)
        assert len(rivets) == 4 and all(r.placed_shape(q).BoundBox.ZMin
                                        == pytest.approx(CLR + q.info.get("lifted_mm", 0.0)) for q in rivets)
    pad = _part(r, "pad_pad").BoundBox                          # bottom side: mirrored
    assert (pad.ZMin, pad.ZMax) == pytest.approx((-3.0, 0.0))
    rivets = [q for q in r.groups()["pad"] if q.info.get("rivet")]
    assert len(rivets) == 4 and all(r.placed_shape(q).BoundBox.ZMax == pytest.approx(T - CLR) for q in rivets)
    lo, up = _part(r, "hub_hub_lower").BoundBox, _part(r, "hub_hub_upper").BoundBox
    assert (lo.ZMin, up.ZMax) == pytest.approx((T, T + 3.0))       # the halves stay between the sheets ...
    rivets = [r.placed_shape(q).BoundBox for q in r.groups()["hub"] if q.info.get("rivet")]
    assert len(rivets) == 4                                        # ... double rivets reach into both sheets
    assert all((b.ZMin, b.ZMax) == pytest.approx((CLR, T + 3.0 + T - CLR)) for b in rivets)


def test_connection_hub_prints_as_two_one_way_halves(mod_result):
    """The two-way hub is two plain halves split at mid-thickness (each prints flat; double rivets run
    through both): they touch without overlap, and the dowel holes run through both in line."""
    from metamaterial_wb.geometry.modules import DOWEL_DIAMETER_MM
    r = mod_result
    lo, up = _part(r, "hub_hub_lower"), _part(r, "hub_hub_upper")
    zm = T + 1.5
    assert lo.BoundBox.ZMax == pytest.approx(zm) and up.BoundBox.ZMin == pytest.approx(zm)
    assert lo.common(up).Volume < 1e-6
    for half in (lo, up):
        holes = [f for f in half.Faces if f.Surface.__class__.__name__ == "Cylinder"
                 and abs(f.Surface.Radius - 0.5 * DOWEL_DIAMETER_MM) < 1e-9]
        assert len(holes) == 2
    assert {round(f.Surface.Center.x, 6) for f in lo.Faces if f.Surface.__class__.__name__ == "Cylinder"
            and abs(f.Surface.Radius - 0.5 * DOWEL_DIAMETER_MM) < 1e-9} == \
        {round(f.Surface.Center.x, 6) for f in up.Faces if f.Surface.__class__.__name__ == "Cylinder"
         and abs(f.Surface.Radius - 0.5 * DOWEL_DIAMETER_MM) < 1e-9}


def test_friction_pad_mu_reaches_the_scene_and_the_parts(mod_result):
    r = mod_result
    assert r.by_name("pad_pad").info["mu"] == 0.9
    assert [m.get("mu") for m in r.scene.modules if m["type"] == "friction_pad"] == [0.9]


def test_friction_pad_pocket_volume(mod_result):
    """Pad = plate - pocket - rivet channels and head recesses (the heads sit on the pocket floor);
    the pocket volume follows the parameters."""
    import FreeCAD as App
    import Part
    from metamaterial_wb.geometry.build import build_scene
    r = mod_result
    sc = make_scene({"grid": [2, 3]}, modules=[dict(MODULES[1], pocket_depth_mm=1.7)])
    r2 = build_scene(sc, progress=False)
    v1 = r.placed_shape(r.by_name("pad_pad")).Volume
    v2 = r2.placed_shape(r2.by_name("pad_pad")).Volume
    side = S - 0.6 - 2 * 1.5
    # 14.4 mm pocket: two strips with one 0.8 mm rib between them (each spans < 10 mm: bridged); the
    # head recesses (socket radius + 1 mm, down to the pocket floor) also cut the rib by the extra depth;
    # the rivet channels go through in both
    p = r.params
    d = 0.5 * S - p.socket_inset_mm
    w = 0.5 * (side - 0.8)
    strips = [Part.makeBox(w, side, 1.0, App.Vector(-0.5 * side + k * (w + 0.8), -0.5 * side, 0)) for k in (0, 1)]
    discs = [Part.makeCylinder(p.socket_radius_mm + 1.0, 1.0, App.Vector(u, v, 0))
             for u, v in [(d, 0), (0, d), (-d, 0), (0, -d)]]
    channels = [Part.makeCylinder(p.socket_radius_mm, 1.0, App.Vector(u, v, 0))      # through in both
                for u, v in [(d, 0), (0, d), (-d, 0), (0, -d)]]
    area = strips[0].fuse(strips[1:] + discs).cut(channels).Volume
    assert v1 - v2 == pytest.approx(area * (1.7 - 1.5), rel=1e-6)


def test_servo_presets_and_custom_dims(fc):
    from metamaterial_wb.geometry.build import build_scene

    def housing_width(**kw):
        m = dict({"type": "servo_housing", "name": "s", "joint": "H0,0"}, **kw)
        r = build_scene(make_scene({"grid": [1, 2]}, modules=[m]), progress=False)
        import Part
        h = r.shapes[r.by_name("s_housing").key]             # module frame: u along the joint, v across
        # the tub over node B's side of the joint (u > 0), clear of the feet and their skirt (on node A)
        slab = Part.makeBox(2.0, 200, 5, fc.Vector(0.0, -100, T + 8))
        bb = h.common(slab).BoundBox
        return bb.YMax - bb.YMin, r

    w_sg, _ = housing_width(servo="SG90")
    w_mg, _ = housing_width(servo="MG90S")
    # the tub is the body + clearance + wall on each side
    assert w_sg == pytest.approx(12.5 + 2 * (CLR + 1.6))
    assert w_mg - w_sg == pytest.approx(0.0, abs=1e-9)          # both presets: 12.5 mm bodies
    dims = {"body_length_mm": 23.0, "body_width_mm": 16.0, "body_height_mm": 20.0, "tab_length_mm": 30.0,
            "tab_thickness_mm": 2.0, "tab_z_mm": 14.0, "shaft_offset_mm": 6.0, "shaft_top_mm": 25.0,
            "horn_hub_diameter_mm": 6.0, "horn_thickness_mm": 1.5, "horn_arm_length_mm": 10.0,
            "horn_arm_width_mm": 4.0}
    w_c, r = housing_width(servo="custom", dims=dims)
    assert w_c == pytest.approx(16.0 + 2 * (CLR + 1.6))
    # the housing's cavity fits the custom body with the clearance: its inner length along the joint
    inner = [f for f in r.placed_shape(r.by_name("s_housing")).Faces
             if f.Surface.__class__.__name__ == "Plane" and abs(abs(f.normalAt(0, 0).x) - 1) < 1e-9]
    xs = sorted({round(f.CenterOfMass.x, 6) for f in inner})
    assert any(abs((b - a) - (23.0 + 2 * CLR)) < 1e-6 for a in xs for b in xs)


def test_clip_angle_from_the_scene_constraint(fc):
    """Without angle_deg the clip takes the relative rotation of the constrained joint's nodes."""
    from metamaterial_wb.core.kinematics import rotation_limits
    from metamaterial_wb.geometry.modules import parse_modules
    from metamaterial_wb.core.design import effective_tilts_deg
    from metamaterial_wb.core.fabrication import fabrication_params
    sc = make_scene({"chain": 3}, constraints=[{"name": "c1", "joint": "H0,1", "value": 0.5}],
                    modules=[{"type": "constraint_clip", "joint": "H0,1"}])
    spec = parse_modules(sc, fabrication_params(sc, effective_tilts_deg(sc)))[0]
    closing, _ = rotation_limits(sc)
    # N0,1 (odd) turns by -0.5 * closing, N0,2 (even) by +0.5 * closing: B relative to A = +closing
    assert spec.values["angle_deg"] == pytest.approx(math.degrees(closing), rel=1e-9)


def test_gui_forms_are_accepted(fc):
    """The workbench's Add-module command writes {"type": "clip", "joint": ...} and stable hubs on a node."""
    from metamaterial_wb.geometry.modules import parse_modules
    from metamaterial_wb.core.design import effective_tilts_deg
    from metamaterial_wb.core.fabrication import fabrication_params
    sc = make_scene({"grid": [1, 2]}, modules=[{"type": "clip", "joint": "V0,1", "angle_deg": 5},
                                               {"type": "stable_hub", "node": "N1,0"}])
    specs = parse_modules(sc, fabrication_params(sc, effective_tilts_deg(sc)))
    assert [(m.type, m.joint) for m in specs] == [("constraint_clip", "V0,1"), ("stable_hub", "H1,0")]


def test_modules_laid_out_for_printing(mod_result):
    """Module 3MF files: each part turned pins-up, on the bed, side by side; triangles stay outward."""
    from metamaterial_wb.export.mesh import lay_out_for_print, open_edges, part_meshes, signed_volume
    r = mod_result
    parts = r.groups()["servo"]
    meshes = part_meshes(r, parts)
    laid = lay_out_for_print(meshes)
    xs = []
    for (n, V, T, m, e), (_, V0, T0, _, _) in zip(laid, meshes):
        assert V[:, 2].min() == pytest.approx(0.0) and open_edges(T) == 0
        assert signed_volume(V, T) == pytest.approx(signed_volume(V0, T0), rel=1e-9) and signed_volume(V, T) > 0
        # pins up: the highest points of the turned part are the pin tips that were the lowest (z = clearance)
        assert V[:, 2].max() == pytest.approx(V0[:, 2].max() - V0[:, 2].min(), abs=1e-4)
        xs.append((V[:, 0].min(), V[:, 0].max()))
    assert xs[0][1] + 5.0 == pytest.approx(xs[1][0])


def test_connection_hub_too_thin_for_two_halves_is_refused():
    """Each half is at least two nozzle widths thick (the double rivets run through both): 1.6 mm at the
    0.4 mm nozzle; thinner is an error naming the field and the range, before any geometry."""
    from metamaterial_wb.core.design import effective_tilts_deg
    from metamaterial_wb.core.errors import SceneError
    from metamaterial_wb.core.fabrication import fabrication_params
    from metamaterial_wb.geometry.modules import parse_modules
    for t, ok in ((1.6, True), (1.5, False)):
        sc = make_scene({"chain": 3}, modules=[{"type": "connection_hub", "name": "h", "node": "N0,1",
                                                "thickness_mm": t}])
        p = fabrication_params(sc, effective_tilts_deg(sc))
        if ok:
            assert parse_modules(sc, p)[0].values["thickness_mm"] == t
        else:
            with pytest.raises(SceneError) as e:
                parse_modules(sc, p)
            assert "thickness_mm" in e.value.field and "[1.6, 200]" in str(e.value)


def test_friction_pad_too_thin_for_recessed_rivet_heads_is_refused():
    """The rivet heads sit recessed in the pad (at least 1.4 mm): a 2 mm pad leaves 0.6 mm under them."""
    from metamaterial_wb.core.errors import SceneError
    from metamaterial_wb.core.design import effective_tilts_deg
    from metamaterial_wb.core.fabrication import fabrication_params
    from metamaterial_wb.geometry.modules import parse_modules
    sc = make_scene({"grid": [2, 3]}, modules=[dict(MODULES[1], thickness_mm=2.0, pocket_depth_mm=0.5)])
    with pytest.raises(SceneError, match=r"thickness_mm \(pad\).*rivet heads recessed 1.4 mm.*allowed range \[2.2, 200\]"):
        parse_modules(sc, fabrication_params(sc, effective_tilts_deg(sc)))


def test_a_module_name_ending_in_a_newline_is_refused():
    """``$`` also matches before a final newline: "h\\n" passed the module naming rule (and named its files)."""
    from metamaterial_wb.core.design import effective_tilts_deg
    from metamaterial_wb.core.errors import SceneError
    from metamaterial_wb.core.fabrication import fabrication_params
    from metamaterial_wb.geometry.modules import parse_modules
    with pytest.raises(SceneError, match="not a valid module name"):     # refused when the scene loads now
        sc = make_scene({"chain": 3}, modules=[{"type": "connection_hub", "name": "h\n", "node": "N0,1"}])
        parse_modules(sc, fabrication_params(sc, effective_tilts_deg(sc)))


def test_check_modules_seats_the_waiting_rivets(mod_result):
    """check_modules checks the two rivets that wait above node B's sockets also seated, against node B turned
    by the clip angle: a clip whose rivets would not go into node B held at its angle is a collision (here the
    angle the check turns node B by is changed under the built clip, so the seated rivets miss the sockets)."""
    from metamaterial_wb.geometry import validity
    spec = [m for m in mod_result.modules if m.name == "clip"][0]
    held = spec.values["angle_deg"]
    try:
        spec.values["angle_deg"] = held + 30.0
        problems = validity.check_modules(mod_result)
    finally:
        spec.values["angle_deg"] = held
    seated = [p for p in problems if "seated" in p and "node_2_2" in p]
    assert seated and all("clip_rivet_3" in p or "clip_rivet_4" in p for p in seated), problems
    assert validity.check_modules(mod_result) == []
