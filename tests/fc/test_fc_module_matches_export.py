"""The document's module solid is the one Export builds (geometry.build.build_scene), or the module is invalid with
Export's own refusal: it follows everything the builder reads (the motor range on its joint, per-joint hinge sizes,
hinge tilts), not a hand-picked subset of the scene."""
import pytest

FreeCAD = pytest.importorskip("FreeCAD")

import metamaterial_wb  # noqa: E402
from metamaterial_wb.core import design  # noqa: E402
from metamaterial_wb.core.scene import Scene  # noqa: E402
from metamaterial_wb.objects import structure  # noqa: E402
from test_fc_objects import doc, fish  # noqa: E402,F401 - the App tests' document fixture and example



def export_volume(sc, mtype):
    """Volume of the document's last module as Export builds it from the composed scene."""
    from metamaterial_wb.geometry.build import build_scene
    scene = structure.compose_scene(sc)
    res = build_scene(scene, modules=True, progress=False)
    name = f"{mtype}_{len(scene.modules)}"    # the fabrication package's default name of the last module
    parts = [p for p in res.parts if p.role == "module" and p.group == name]
    assert parts, sorted({p.group for p in res.parts})
    return sum(res.placed_shape(p).Volume for p in parts)


def assert_same_volume(m, want):
    assert abs(m.Shape.Volume - want) < 1e-6 * max(1.0, want), (m.Label, m.Shape.Volume, want)


def test_servo_follows_the_motor_range_on_its_joint(doc):
    """p4: the servo's shaft sits on the joint's pivot, which depends on the motors' D range on that joint; a
    smaller sine amplitude left the old solid (18613.42 mm3) while Export built 18615.83 mm3."""
    sc = structure.make_structure(doc, fish())
    head = [o for o in sc.Items if o.ItemName == "head"][0]
    m = structure.make_module(doc, sc, "servo_housing", head.Joint)
    doc.recompute()
    v0 = m.Shape.Volume
    assert_same_volume(m, export_volume(sc, "servo_housing"))
    head.Amplitude = 0.2
    doc.recompute()
    assert m.isValid() and sc.isValid(), (m.getStatusString(), sc.getStatusString())
    want = export_volume(sc, "servo_housing")
    assert abs(want - v0) > 1e-3, "the case must change the servo (else it proves nothing)"
    assert_same_volume(m, want)


def test_a_motor_on_another_joint_does_not_rebuild_the_module(doc):
    """What the module does not read does not rebuild it (the key is the builder's inputs, not the whole scene)."""
    sc = structure.make_structure(doc, fish())
    m = structure.make_module(doc, sc, "servo_housing", "V0,1")
    doc.recompute()
    key = m.BuiltFor
    tail = [o for o in sc.Items if o.ItemName == "tail"][0]
    assert tail.Joint != "V0,1"
    tail.Value = 0.4
    tail.Amplitude = 0.1
    doc.recompute()
    assert m.isValid() and m.BuiltFor == key


def test_module_uses_the_per_joint_hinge_sizes(doc):
    """p16: a per-joint override on the servo's joint (6 mm x 1 mm): the document showed the scene-wide hinge's
    servo (18613.42 mm3), Export built 18185.97 mm3."""
    d = dict(fish().to_dict(), joints=[{"joint": "V0,1", "length_mm": 6.0, "width_mm": 1.0}])
    sc = structure.make_structure(doc, Scene.from_dict(d))
    m = structure.make_module(doc, sc, "servo_housing", "V0,1")
    doc.recompute()
    assert m.isValid() and sc.isValid(), (m.getStatusString(), sc.getStatusString())
    assert_same_volume(m, export_volume(sc, "servo_housing"))
    # and it follows a change of the override (SceneJSON's joints) on the next recompute
    structure.set_scene_fields(sc, joints=[{"joint": "V0,1", "length_mm": 5.0, "width_mm": 1.0}])
    doc.recompute()
    assert m.isValid(), m.getStatusString()
    assert_same_volume(m, export_volume(sc, "servo_housing"))


def _tilted_fish():
    fa = Scene.load(metamaterial_wb.example_path("fish_axes")).to_dict()
    s = Scene.from_dict(dict(fish().to_dict(), axes=fa["axes"]))
    design.configure(s)
    assert abs(float(s.joint_config["H0,3"]["tilt_deg"])) > 1.0
    return s


def test_servo_on_a_tilted_joint_is_invalid_with_exports_message(doc):
    """p17: Export refuses a servo on a tilted joint; the document showed it as a valid solid."""
    sc = structure.make_structure(doc, _tilted_fish())
    m = structure.make_module(doc, sc, "servo_housing", "H0,3")
    doc.recompute()
    assert not m.isValid(), "a servo on a tilted joint must not be a valid solid"
    msg = m.getStatusString()
    assert m.Label in msg and "H0,3" in msg and "tilted hinge" in msg and "cannot be coaxial" in msg, msg
    assert sc.isValid() and "Touched" not in sc.State, sc.State    # the module's fault; the Scene still solves
    assert [w for w in sc.SolveWarnings if m.Label in w] == [msg], list(sc.SolveWarnings)
    # the same servo on an untilted joint of the same sheet is valid and is Export's solid
    m.Target = "V0,1"
    doc.recompute()
    assert m.isValid(), m.getStatusString()
    assert_same_volume(m, export_volume(sc, "servo_housing"))


def test_stable_hub_on_a_tilted_joint_is_exports_solid(doc):
    """A stable hub may sit on a tilted joint: its platform follows the tilted joint's pivot as Export's does."""
    sc = structure.make_structure(doc, _tilted_fish())
    m = structure.make_module(doc, sc, "stable_hub", "H1,3")
    doc.recompute()
    assert m.isValid(), m.getStatusString()
    assert_same_volume(m, export_volume(sc, "stable_hub"))


def test_module_on_a_sheet_export_refuses_shows_its_stand_in(doc):
    """A fold whose hinge tilts do not fit their node plates: Export builds nothing (the sheet's error, which the
    Scene's design check reports as a warning), so no module can be Export's solid: it shows its stand-in and says
    so, and stays valid (a design that is not printable yet is a warning, not an error: panels keep working)."""
    from metamaterial_wb.core.design import effective_tilts_deg
    from metamaterial_wb.core.errors import SceneError
    from metamaterial_wb.core.fabrication import fabrication_params
    sc = structure.make_structure(doc, fish())
    m = structure.make_module(doc, sc, "friction_pad", "N0,0")
    doc.recompute()
    assert m.isValid()
    structure.set_scene_fields(sc, axes=[{"direction": "vertical", "line": 2, "fold_deg": 30.0}], joint_config=None)
    doc.recompute()
    scene = structure.compose_scene(sc)
    with pytest.raises(SceneError) as exc:
        fabrication_params(scene, effective_tilts_deg(scene))
    assert exc.value is not None
    assert m.isValid() and m.GeometrySource.startswith("stand-in (the sheet cannot be built"), m.GeometrySource
    assert sc.isValid() and any("build will reject it" in w.replace("`", "") for w in sc.SolveWarnings)
    structure.set_scene_fields(sc, axes=[{"direction": "vertical", "line": 2, "fold_deg": 12.0}], joint_config=None)
    doc.recompute()
    assert m.isValid() and m.GeometrySource == "geometry.modules", m.getStatusString()
    assert_same_volume(m, export_volume(sc, "friction_pad"))
