"""Servo housings from real dimensions: cavity clearance, tab seats with the screws in material, the
horn pocket holding the whole horn, presets SG90 / MG90S / MG996R."""
import pytest

from fabhelpers import make_scene

SCENE = dict(cell_size_mm=20, hinge={"length_mm": 2, "width_mm": 0.8, "thickness_mm": 7})


@pytest.fixture(scope="module")
def sg90(fc):
    from metamaterial_wb.geometry.build import build_scene
    return build_scene(make_scene({"chain": 3}, modules=[{"type": "servo_housing", "name": "s", "joint": "V0,1"}],
                                  **SCENE), progress=False)


def _frame(r, spec):
    """Module placement and the shaft point (module frame) of a servo spec."""
    from metamaterial_wb.geometry.modules import module_placement, servo_layout
    return module_placement(spec, r.params), servo_layout(spec, r.params)


def test_whole_horn_fits_its_pocket(sg90, fc):
    """The SG90's horn (7 mm hub, 14 mm arm, 1.5 mm thick) placed on the built shaft shares no volume
    with the adapter (today: 16.5 mm^3 of the arm inside the column)."""
    import Part
    r = sg90
    spec = r.modules[0]
    pl, lay = _frame(r, spec)
    v = spec.values
    su, sv = v["shaft_u_mm"], v["shaft_v_mm"]
    V = fc.Vector
    hub = Part.makeCylinder(0.5 * v["horn_hub_diameter_mm"], v["horn_thickness_mm"], V(su, sv, lay["z_arm"]))
    arm = Part.makeBox(v["horn_arm_length_mm"], v["horn_arm_width_mm"], v["horn_thickness_mm"],
                       V(su, sv - 0.5 * v["horn_arm_width_mm"], lay["z_arm"]))
    horn = hub.fuse(arm).transformed(pl.toMatrix())
    adapter = r.placed_shape(r.by_name("s_horn_adapter"))
    assert horn.common(adapter).Volume < 1e-6
    # and the pocket is no sloppier than the clearance: a horn 0.3 mm longer than the pocket allows hits
    longer = Part.makeBox(v["horn_arm_length_mm"] + r.params.clearance_mm + 0.3, v["horn_arm_width_mm"],
                          v["horn_thickness_mm"], V(su, sv - 0.5 * v["horn_arm_width_mm"], lay["z_arm"]))
    assert longer.transformed(pl.toMatrix()).common(adapter).Volume > 0.1


def test_cavity_clears_the_widest_sg90(sg90):
    """Real SG90s measure 11.8-12.5 mm wide: the cavity is 12.5 mm + the fit clearance on each side."""
    r = sg90
    spec = r.modules[0]
    assert spec.values["body_width_mm"] == 12.5 and spec.values["body_length_mm"] == 23.0
    h = r.shapes[r.by_name("s_housing").key]           # module frame: u along the joint, v across
    import Part
    import FreeCAD as App
    pl, lay = _frame(r, spec)
    sv = spec.values["shaft_v_mm"]
    z = lay["zb"] + 5.0
    slab = Part.makeBox(1.0, 40.0, 0.01, App.Vector(spec.values["shaft_offset_mm"] - 10.0, sv - 20.0, z))
    cut = h.common(slab)
    ys = sorted({round(vx.Y, 6) for vx in cut.Vertexes})
    inner = [b - a for a, b in zip(ys, ys[1:])]
    assert max(inner) == pytest.approx(12.5 + 2 * r.params.clearance_mm, abs=1e-6)


def test_tab_screws_go_into_material(sg90, fc):
    """Each tab's screw has a pilot hole (screw - 0.3 mm) in a seat: a ring of material two nozzle
    widths thick around it, from the tab down 3 mm, lies wholly inside the housing."""
    import Part
    r = sg90
    spec = r.modules[0]
    v = spec.values
    pl, lay = _frame(r, spec)
    h = r.shapes[r.by_name("s_housing").key]
    top = lay["zb"] + v["tab_z_mm"]
    a, L = v["shaft_offset_mm"], v["body_length_mm"]
    ext = 0.5 * (v["tab_length_mm"] - L)
    rp = 0.5 * (v["screw_diameter_mm"] - 0.3)
    W = r.params.min_wall_mm
    for u in (a - L - ext + v["screw_inset_mm"], a + ext - v["screw_inset_mm"]):
        c = fc.Vector(u + v["shaft_u_mm"], v["shaft_v_mm"], top - 3.0)
        ring = Part.makeCylinder(rp + W, 3.0, c).cut(Part.makeCylinder(rp, 3.0, c))
        assert h.common(ring).Volume == pytest.approx(ring.Volume, rel=1e-6)
        assert h.common(Part.makeCylinder(rp * 0.9, 3.0, c)).Volume < 1e-6      # the pilot hole is open


@pytest.mark.parametrize("servo,cell", [("MG90S", 20), ("MG996R", 26.1)])
def test_presets_build_and_clear_their_rotation(fc, servo, cell):
    from metamaterial_wb.geometry import validity
    from metamaterial_wb.geometry.build import build_scene
    r = build_scene(make_scene({"chain": 3}, cell_size_mm=cell,
                               hinge={"length_mm": 2, "width_mm": 0.8, "thickness_mm": 7},
                               modules=[{"type": "servo_housing", "name": "s", "joint": "V0,1", "servo": servo}]),
                    progress=False)
    assert validity.check_solids(r) == [] and validity.check_modules(r) == []
    # held by blind rivets (two per part), every part printable without supports in its chosen pose
    from metamaterial_wb.export.mesh import part_meshes
    from metamaterial_wb.export.printpose import forced_poses, lay_out_best_poses
    from metamaterial_wb.geometry.modules import is_riveted
    spec = r.modules[0]
    assert is_riveted(spec) and spec.note is None, spec.note
    parts = r.groups()["s"]
    assert sum(1 for q in parts if q.info.get("rivet")) == 4
    _, reps = lay_out_best_poses(part_meshes(r, parts), forced=forced_poses(parts))
    assert all(rep["supports_free"] for rep in reps.values()), reps


def test_mg996r_refused_in_small_cells(fc):
    from metamaterial_wb.core.errors import SceneError
    from metamaterial_wb.geometry.modules import parse_modules
    from metamaterial_wb.core.design import effective_tilts_deg
    from metamaterial_wb.core.fabrication import fabrication_params
    sc = make_scene({"chain": 3}, modules=[{"type": "servo_housing", "name": "s", "joint": "V0,1",
                                            "servo": "MG996R"}], **SCENE)
    with pytest.raises(SceneError, match="cells of at least"):
        parse_modules(sc, fabrication_params(sc, effective_tilts_deg(sc)))
