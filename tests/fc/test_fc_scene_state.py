"""What a Scene keeps across recomputes, saves and copies (App level): the [-1, 1] ranges of the D values, the
design warnings, and its own display arrays (a copy of the Scene alone must never move the original's)."""
import pytest

FreeCAD = pytest.importorskip("FreeCAD")

from metamaterial_wb.core import design  # noqa: E402
from metamaterial_wb.core.scene import Scene  # noqa: E402
from metamaterial_wb.objects import design_adapter, structure  # noqa: E402
from test_fc_objects import doc, fish  # noqa: E402,F401 - the App tests' document fixture and example


FOLD = [{"direction": "vertical", "line": 2, "fold_deg": 30.0}]   # beyond the printable fold of the fish


def reopen(doc, tmp_path, name="state.FCStd"):
    path = str(tmp_path / name)
    doc.saveAs(path)
    FreeCAD.closeDocument(doc.Name)
    return FreeCAD.openDocument(path)


# ---- 1. the [-1, 1] ranges survive save and reopen (FreeCAD does not save a PropertyFloatConstraint's limits) ----
def test_value_ranges_survive_save_and_reopen(doc, tmp_path):
    """p2: after reopening, 5.0 / 3.0 were accepted as typed and the Scene went invalid; a new document clamps."""
    sc = structure.make_structure(doc, fish())
    clip = structure.make_item(doc, sc, "constraint", "clip1", "H1,2", 0.3)
    sc.UseGlobal = True
    sc.GlobalDeformation = -0.4
    doc.recompute()
    names = (sc.Name, clip.Name, sc.Items[0].Name)
    head_value = sc.Items[0].Value
    d2 = reopen(doc, tmp_path)
    try:
        sc2, clip2, head2 = (d2.getObject(n) for n in names)
        # the stored values are kept, and opening touches nothing
        assert clip2.Value == pytest.approx(0.3) and sc2.GlobalDeformation == pytest.approx(-0.4)
        assert head2.Value == pytest.approx(head_value)
        assert not [o.Name for o in d2.Objects if "Touched" in o.State]
        clip2.Value = 5.0
        head2.Value = -7.0
        sc2.GlobalDeformation = 3.0
        assert (clip2.Value, head2.Value, sc2.GlobalDeformation) == (1.0, -1.0, 1.0)
        d2.recompute()
        assert all(o.isValid() for o in d2.Objects), [(o.Name, o.getStatusString()) for o in d2.Objects
                                                      if not o.isValid()]
    finally:
        FreeCAD.closeDocument(d2.Name)


def test_out_of_range_value_in_a_file_is_clamped_with_a_warning(doc, tmp_path, capfd):
    """A file saved by a version that lost the ranges can hold 5.0: opening it clamps it and says so (object,
    value, allowed range), and the recompute then uses the clamped value."""
    sc = structure.make_structure(doc, fish())
    clip = structure.make_item(doc, sc, "constraint", "clip1", "H1,2", 0.3)
    doc.recompute()
    clip.Value = (5.0, -10.0, 10.0, 0.05)     # what a lost range allowed
    name = clip.Name
    d2 = reopen(doc, tmp_path)
    try:
        clip2 = d2.getObject(name)
        assert clip2.Value == 1.0
        err = capfd.readouterr().err
        assert clip2.Label in err and "5" in err and "[-1, 1]" in err, err
        d2.recompute()
        assert all(o.isValid() for o in d2.Objects)
        sc2 = structure.find_scene_objects(d2)[0]
        assert [c.value for c in structure.compose_scene(sc2).constraints] == [1.0]
    finally:
        FreeCAD.closeDocument(d2.Name)


# ---- 4. the design warnings are the design check's, on every recompute ----------------------------------------
def _printable_warning(ws):
    return [w for w in ws if "axis v2" in w and "build will reject it" in w.replace("`", "")]


def test_design_warnings_stay_on_later_recomputes_and_after_reopen(doc, tmp_path):
    """p5: the warning was shown only by the recompute that configured the axes; moving a motor (or reopening)
    emptied SolveWarnings although the design check still finds it."""
    sc = structure.make_structure(doc, fish())
    structure.set_scene_fields(sc, axes=FOLD, joint_config=None)
    doc.recompute()
    assert _printable_warning(sc.SolveWarnings), list(sc.SolveWarnings)
    assert _printable_warning(design.configure(structure.compose_scene(sc).copy())["warnings"])
    head = [o for o in sc.Items if o.ItemName == "head"][0]
    head.Value = 0.1
    doc.recompute()
    assert _printable_warning(sc.SolveWarnings), list(sc.SolveWarnings)
    name = sc.Name
    d2 = reopen(doc, tmp_path)
    try:
        sc2 = d2.getObject(name)
        sc2.touch()
        d2.recompute()
        assert _printable_warning(sc2.SolveWarnings), list(sc2.SolveWarnings)
    finally:
        FreeCAD.closeDocument(d2.Name)


def test_design_warnings_of_axes_stored_with_their_configuration(doc):
    """p15: the Folded shape panel stores axes and joint_config together; no recompute reconfigures, and the
    warning that its own design run reported never reached SolveWarnings."""
    sc = structure.make_structure(doc, fish())
    s = Scene.from_dict(dict(structure.compose_scene(sc).to_dict(), axes=FOLD))
    conf, report = design_adapter.configure(s)
    assert _printable_warning(report["warnings"])
    structure.set_scene_fields(sc, axes=[a.to_dict() for a in conf.axes], joint_config=conf.joint_config)
    doc.recompute()
    assert sc.isValid(), sc.getStatusString()
    assert _printable_warning(sc.SolveWarnings), list(sc.SolveWarnings)


def test_no_design_warning_without_axes_or_for_a_printable_fold(doc):
    sc = structure.make_structure(doc, fish())
    doc.recompute()
    assert list(sc.SolveWarnings) == []
    structure.set_scene_fields(sc, axes=[{"direction": "vertical", "line": 2, "fold_deg": 6.0}], joint_config=None)
    doc.recompute()
    head = [o for o in sc.Items if o.ItemName == "head"][0]
    head.Value = 0.2
    doc.recompute()
    assert list(sc.SolveWarnings) == []


# ---- 5. a copy of the Scene alone never drives the original's arrays -------------------------------------------
def _nodes(sc):
    return [tuple(round(x, 9) for x in p.Base) for p in sc.NodeArray.PlacementList]


def test_copy_of_the_scene_alone_never_moves_the_original(doc):
    """p9: doc.copyObject(scene, True) copies the markers and modules but not the hidden-linked arrays: the copy
    wrote its solution into the original's Nodes / Hinges."""
    sc = structure.make_structure(doc, fish())
    structure.make_module(doc, sc, "friction_pad", "N0,0")
    doc.recompute()
    before, hinges = _nodes(sc), list(sc.HingeArray.PlacementList)
    cp = doc.copyObject(sc, True)
    doc.recompute()
    cp.Items[0].Value = 0.9
    doc.recompute()
    assert _nodes(sc) == before and list(sc.HingeArray.PlacementList) == hinges
    assert not cp.isValid()
    msg = cp.getStatusString()
    assert cp.Label in msg and sc.NodeArray.Label in msg and sc.Label in msg and "Metamaterial part" in msg, msg
    # what the task panels call while dragging does not write into the original either
    from metamaterial_wb.objects.display import apply_frame, apply_hinge_scales
    from metamaterial_wb.objects.scene import solver_for
    scene = structure.compose_scene(cp)
    solver = solver_for(cp, scene)
    apply_frame(cp, solver, solver.frame(global_deformation=0.7))
    apply_hinge_scales(cp, Scene.from_dict(dict(scene.to_dict(), joints=[{"joint": "V0,1", "length_mm": 6.0}])))
    assert _nodes(sc) == before and list(sc.HingeArray.PlacementList) == hinges
    assert all(tuple(v) == (1.0, 1.0, 1.0) for v in sc.HingeArray.ScaleList)
    # the original still recomputes valid, its own way
    sc.touch()
    doc.recompute()
    assert sc.isValid() and _nodes(sc) == before


def test_copy_of_the_whole_part_has_its_own_arrays(doc):
    """p6: copying the Metamaterial part copies the arrays too; both structures stay valid and independent."""
    sc = structure.make_structure(doc, fish())
    doc.recompute()
    before = _nodes(sc)
    doc.copyObject(structure.container_of(sc), True)
    doc.recompute()
    cp = [s for s in structure.find_scene_objects(doc) if s.Name != sc.Name][0]
    assert cp.NodeArray is not None and cp.NodeArray.Name != sc.NodeArray.Name
    cp.Items[0].Value = 0.9
    doc.recompute()
    assert cp.isValid() and sc.isValid(), (cp.getStatusString(), sc.getStatusString())
    assert _nodes(sc) == before and _nodes(cp) != before


def test_an_edit_that_changes_nothing_leaves_no_undo_step_and_a_real_one_does(doc):
    """The task panels write through ``common.assign`` and ``set_scene_fields``, which skip equal values: FreeCAD
    records every set, an equal one too (an undo step, the document marked modified), and drops a transaction
    that recorded nothing. A real change is one undo step that Undo takes back."""
    from metamaterial_wb.objects.common import assign
    doc.UndoMode = 1
    sc = structure.make_structure(doc, fish())
    doc.recompute()
    stored = structure.compose_scene(sc).to_dict()
    n0 = doc.UndoCount
    doc.openTransaction("same")
    assert not assign(sc, "HingeLength", stored["hinge"]["length_mm"])
    structure.set_scene_fields(sc, axes=stored.get("axes"), joint_config=stored.get("joint_config"))
    doc.commitTransaction()
    assert doc.UndoCount == n0
    doc.openTransaction("changed")
    assert assign(sc, "HingeLength", stored["hinge"]["length_mm"] + 0.5)
    doc.commitTransaction()
    assert doc.UndoCount == n0 + 1
    doc.undo()
    assert sc.HingeLength.Value == stored["hinge"]["length_mm"]
