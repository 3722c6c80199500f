"""The document objects' errors as a user meets them by editing properties (App level): the object at fault is
the one marked invalid, with a message naming its property; nothing stale is shown as valid."""
import pytest

FreeCAD = pytest.importorskip("FreeCAD")

from metamaterial_wb.objects import structure  # noqa: E402
from test_fc_objects import doc, fish  # noqa: E402,F401 - the App tests' document fixture and example


def test_a_module_that_no_longer_fits_is_marked_invalid_and_recovers(doc):
    """The cell shrank under a servo housing: the housing kept its old solid and stayed valid (only a line in
    the Scene's SolveWarnings said so), while a recompute of the module alone made it invalid."""
    sc = structure.make_structure(doc, fish())
    m = structure.make_module(doc, sc, "servo_housing", "V0,1")
    doc.recompute()
    assert m.isValid() and sc.isValid()
    sc.HingeLength = 2.0
    sc.CellSize = 17.0                                 # the sheet builds, the SG90 housing does not fit
    doc.recompute()
    assert sc.isValid(), sc.State                       # the sheet itself is fine at 16 mm
    assert not m.isValid() and "Invalid" in m.State
    assert any(m.Label in w and "cell" in w for w in sc.SolveWarnings)
    sc.CellSize = 27.0
    sc.HingeLength = 2.0
    doc.recompute()
    assert m.isValid() and sc.isValid(), (m.State, sc.State)
    assert '"cell_size_mm": 27.0' in m.BuiltFor         # rebuilt for the new cell (BuiltFor: the builder's inputs)


def test_an_invalid_module_stays_listed_in_the_scenes_warnings(doc):
    """The Scene listed a module's error only on the recompute that broke it: after moving a motor the module
    was still invalid, and SolveWarnings no longer said so."""
    sc = structure.make_structure(doc, fish())
    m = structure.make_module(doc, sc, "servo_housing", "V0,1")
    doc.recompute()
    sc.HingeLength = 2.0
    sc.CellSize = 17.0                                 # the sheet builds, the SG90 housing does not fit
    doc.recompute()
    assert not m.isValid() and any(m.Label in w for w in sc.SolveWarnings)
    sc.Items[0].Value = 0.7
    doc.recompute()
    assert sc.isValid() and not m.isValid()
    assert [w for w in sc.SolveWarnings if m.Label in w] == [m.getStatusString()], list(sc.SolveWarnings)


def test_a_scene_error_is_the_scenes_not_its_modules(doc):
    """A motor moved onto a joint that does not exist while a module was edited: the module was marked invalid
    with the Scene's error, and the Scene, skipped, reported itself valid with stale results."""
    sc = structure.make_structure(doc, fish())
    m = structure.make_module(doc, sc, "friction_pad", "N2,3")
    doc.recompute()
    sc.Items[0].Joint = "V9,9"
    m.Target = "N1,3"
    doc.recompute()
    assert not sc.isValid() and "V9,9" in sc.getStatusString()
    assert m.isValid(), m.getStatusString()
    sc.Items[0].Joint = "V0,1"
    doc.recompute()
    assert sc.isValid() and m.isValid()
    assert '"N1,3"' in m.BuiltFor                       # the Scene rebuilt it for its new node


def test_an_empty_layout_is_an_error_not_ignored(doc):
    sc = structure.make_structure(doc, fish())
    doc.recompute()
    sc.Layout = []
    doc.recompute()
    assert not sc.isValid() and "Layout" in sc.getStatusString() and "empty" in sc.getStatusString()


@pytest.mark.parametrize("target, prop, text, words", [
    ("item", "ProfileData", "{bad", "not valid JSON"),
    ("item", "ProfileData", "[1, 2]", "holds list JSON; expected an object with the steps profile's fields"),
    ("item", "ExtraJSON", "[1, 2]", "holds list JSON"),
    ("module", "ModuleData", "{bad", "not valid JSON"),
    ("scene", "SceneJSON", "not json", "not valid JSON"),
])
def test_bad_json_in_a_text_property_names_the_object_and_property(doc, target, prop, text, words):
    sc = structure.make_structure(doc, fish())
    m = structure.make_module(doc, sc, "friction_pad", "N2,3")
    doc.recompute()
    obj = {"item": sc.Items[0], "module": m, "scene": sc}[target]
    if target == "item":
        obj.ProfileShape = "steps"
    setattr(obj, prop, text)
    doc.recompute()
    bad = [o for o in doc.Objects if not o.isValid()]
    msgs = " | ".join(o.getStatusString() for o in bad)
    assert f"{obj.Label}.{prop}: " in msgs and words in msgs, msgs


def test_a_module_error_names_the_field(doc):
    """A friction pad turned into a servo housing keeps its node target: the error said 'unknown field' without
    naming it."""
    sc = structure.make_structure(doc, fish())
    m = structure.make_module(doc, sc, "friction_pad", "N2,3")
    doc.recompute()
    m.ModuleType = "servo_housing"
    doc.recompute()
    assert not m.isValid()
    assert f"module {m.Label}: node: unknown field" in m.getStatusString(), m.getStatusString()


def test_a_module_that_fails_at_its_own_run_does_not_stop_the_scene(doc):
    """FreeCAD skips an object whose input failed in the same recompute: a module that could not be built when it
    ran itself (made or edited where it does not fit, or on a sheet Export refuses) kept its Scene from solving,
    on every recompute until the module was fixed (the Scene stayed Touched, moving a motor moved nothing)."""
    sc = structure.make_structure(doc, fish())
    doc.recompute()
    m = structure.make_module(doc, sc, "servo_housing", "V0,1", {"wall_mm": 0.1})   # under two nozzle widths
    doc.recompute()
    assert not m.isValid() and "wall_mm" in m.getStatusString() and m.Label in m.getStatusString()
    assert sc.isValid() and "Touched" not in sc.State, sc.State
    assert [w for w in sc.SolveWarnings if m.Label in w] == [m.getStatusString()], list(sc.SolveWarnings)
    d0 = list(sc.Deformation)
    sc.Items[0].Value = 0.7
    doc.recompute()
    assert "Touched" not in sc.State and list(sc.Deformation) != d0
    assert not m.isValid()
    m.ModuleData = ""                                   # fixed: it builds again
    doc.recompute()
    assert m.isValid() and sc.isValid() and not m.Shape.isNull(), m.getStatusString()
    assert not any(m.Label in w for w in sc.SolveWarnings)
    m.ModuleData = '{"wall_mm": 0.1}'                 # only the module changes, and breaks again
    doc.recompute()
    assert not m.isValid() and "wall_mm" in m.getStatusString()
    assert sc.isValid() and "Touched" not in sc.State, sc.State
    assert [w for w in sc.SolveWarnings if m.Label in w] == [m.getStatusString()], list(sc.SolveWarnings)


def test_modules_on_a_sheet_export_refuses_show_stand_ins_and_the_scene_says_why(doc):
    """At 12 mm cells the sheet's own sockets do not fit: Export builds nothing, so a module cannot be Export's
    solid. It shows its stand-in and stays valid (panels keep working on the design); the Scene says why, once."""
    sc = structure.make_structure(doc, fish())
    m = structure.make_module(doc, sc, "servo_housing", "V0,1")
    doc.recompute()
    sc.HingeLength = 2.0
    sc.CellSize = 12.0
    doc.recompute()
    assert sc.isValid() and m.isValid(), (sc.State, m.getStatusString())
    assert m.GeometrySource.startswith("stand-in (the sheet cannot be built")
    said = [w for w in sc.SolveWarnings if m.Label in w]
    assert len(said) == 1 and "Export refuses the sheet itself" in said[0] and "hinge.length_mm" in said[0], said
    sc.CellSize = 27.0
    doc.recompute()
    assert m.isValid() and m.GeometrySource == "geometry.modules"
    assert not [w for w in sc.SolveWarnings if m.Label in w]
