"""Issue 14: the 3D view draws stand-in boxes, and says so where the user looks (the tree's Description column
and the property editor), and the claim is true: the printable B-rep of the same scene is another solid."""
import pytest

FreeCAD = pytest.importorskip("FreeCAD")

import metamaterial_wb  # noqa: E402
from metamaterial_wb.core.scene import Scene  # noqa: E402
from metamaterial_wb.objects import make  # noqa: E402
from metamaterial_wb.objects.shapes import SIMPLIFIED_NOTE  # noqa: E402


@pytest.fixture
def doc():
    d = FreeCAD.newDocument("MMSimplified")
    yield d
    FreeCAD.closeDocument(d.Name)


def test_view_says_it_is_simplified_and_it_is(doc):
    scene = Scene.load(metamaterial_wb.example_path("fish"))
    sc = make.make_structure(doc, scene)
    ns, hs = sc.NodeArray.LinkedObject, sc.HingeArray.LinkedObject
    for o in (ns, hs, sc.NodeArray, sc.HingeArray):
        assert "Simplified view" in o.Label2 and "printable" in o.Label2, o.Name
    for o, what in ((ns, "node"), (hs, "hinge")):
        assert o.Simplified is True
        tip = o.getDocumentationOfProperty("Simplified")
        assert f"every {what}" in tip and "not the printable B-rep" in tip
        assert len(o.Shape.Faces) == 6 and len(o.Shape.Vertexes) == 8    # a box: what the note says
    # the printable node is not that box: the note is needed (drop it when the view shows the B-rep)
    from metamaterial_wb.geometry.build import build_scene
    res = build_scene(scene, modules=False, progress=False)
    node = next(p for p in res.parts if p.role == "node")
    printable = res.shapes[node.key]
    assert len(printable.Faces) > 6
    assert abs(printable.Volume - ns.Shape.Volume) > 1e-3 * ns.Shape.Volume


def test_note_reaches_documents_saved_before_it(tmp_path):
    """The fixture saved before the split has neither the note nor the Simplified property."""
    import os
    import shutil
    path = str(tmp_path / "old.FCStd")
    shutil.copy(os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "fixtures",
                             "legacy_structure.FCStd"), path)
    back = FreeCAD.openDocument(path)
    try:
        for name in ("NodeShape", "HingeShape", "Nodes", "Hinges"):
            assert back.getObject(name).Label2 == SIMPLIFIED_NOTE, name
        assert back.getObject("NodeShape").Simplified is True
    finally:
        FreeCAD.closeDocument(back.Name)
