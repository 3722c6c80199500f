"""Issue 14: the 3D view draws each hinge with its own sizes (``Scene.hinge_sizes(joint)``, what the solver and
the B-rep use), not the scene-wide hinge length / width for every joint. The hinge link array scales each
element (``ScaleList``) in its local frame; the element shapes in the document have the per-joint size."""
import pytest

FreeCAD = pytest.importorskip("FreeCAD")

from metamaterial_wb.core.scene import Scene  # noqa: E402
from metamaterial_wb.objects import make  # noqa: E402
from metamaterial_wb.objects.scene import set_scene_fields  # noqa: E402

CELL, L, W, T = 20.0, 2.0, 3.0, 1.0
OVR = {"joint": "H0,1", "length_mm": 3.5, "width_mm": 1.5}


@pytest.fixture
def doc():
    d = FreeCAD.newDocument("MMHingeSizes")
    yield d
    FreeCAD.closeDocument(d.Name)


def _scene(joints=None):
    data = {"format": "metamaterial-scene", "version": 1, "layout": {"grid": [2, 3]}, "cell_size_mm": CELL,
            "hinge": {"length_mm": L, "width_mm": W, "thickness_mm": T}}
    if joints:
        data["joints"] = joints
    return Scene.from_dict(data)


def _local_extents(arr, i):
    """The element shape's size in the element's own frame (placement undone), and the world box."""
    shape = arr.getSubObject(f"{i}.")
    local = shape.copy()
    local.transformShape(arr.PlacementList[i].inverse().toMatrix())
    bb = local.BoundBox
    return (bb.XLength, bb.YLength, bb.ZLength)


def _expected(length, width, thick):
    return (length + 2 * width, width, thick)    # HingeShapeProxy.build: a little longer than the gap


def test_each_hinge_element_has_its_joint_size(doc):
    sc = make.make_structure(doc, _scene([OVR]))
    assert sc.isValid(), sc.getStatusString()
    arr = sc.HingeArray
    names = _scene().topology.joint_names
    k = names.index(OVR["joint"])
    assert arr.ElementCount == len(names) > 2
    for i, name in enumerate(names):
        want = _expected(OVR["length_mm"], OVR["width_mm"], T) if i == k else _expected(L, W, T)
        got = _local_extents(arr, i)
        assert got == pytest.approx(want, abs=1e-6), (name, got, want)
    # the scale agrees with what the solver / B-rep read for that joint
    sizes = _scene([OVR]).hinge_sizes(OVR["joint"])
    assert (sizes["length_mm"], sizes["width_mm"]) == (OVR["length_mm"], OVR["width_mm"])


def test_override_added_later_reaches_the_view_on_recompute(doc):
    sc = make.make_structure(doc, _scene())
    arr = sc.HingeArray
    k = _scene().topology.joint_names.index(OVR["joint"])
    assert _local_extents(arr, k) == pytest.approx(_expected(L, W, T), abs=1e-6)
    set_scene_fields(sc, joints=[OVR])
    doc.recompute()
    assert sc.isValid(), sc.getStatusString()
    assert _local_extents(arr, k) == pytest.approx(_expected(OVR["length_mm"], OVR["width_mm"], T), abs=1e-6)
    # removing it goes back to the global size
    set_scene_fields(sc, joints=None)
    doc.recompute()
    assert _local_extents(arr, k) == pytest.approx(_expected(L, W, T), abs=1e-6)


def test_live_frames_do_not_rewrite_the_scales(doc):
    """Only recompute writes ScaleList; a live frame writes placements and keeps the per-joint scales."""
    from metamaterial_wb.objects.display import apply_frame
    from metamaterial_wb.objects.scene import compose_scene, solver_for
    sc = make.make_structure(doc, _scene([OVR]))
    arr = sc.HingeArray
    before = [tuple(v) for v in arr.ScaleList]
    assert any(v != (1.0, 1.0, 1.0) for v in before)
    solver = solver_for(sc, compose_scene(sc))
    apply_frame(sc, solver, solver.frame(global_deformation=0.3), purge=True)
    assert [tuple(v) for v in arr.ScaleList] == before
