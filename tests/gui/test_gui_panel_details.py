"""Issue 15 items 5 and 7 through real widgets: conflicting modules refused in the panel; export
failures shown in the panel; Cancel leaves a saved document unmodified; stale messages cleared; New
structure beyond 16 x 16 with [row, col] labels; motor sliders disabled under Global deformation and
motor values in servo degrees."""
import os

import numpy as np
import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

import FreeCADGui  # noqa: E402

from metamaterial_wb.gui import panels  # noqa: E402
from metamaterial_wb.objects import structure  # noqa: E402
from guihelpers import (click, dialog_button, doc, drag_slider, press_cancel, press_ok, process, run_panel,  # noqa: E402,F401,E501
                        type_into, workbench)


def open_example(name):
    p = run_panel("MM_OpenExample")
    p.select(name)
    assert press_ok()
    return structure.find_scene_objects(FreeCAD.ActiveDocument)[-1]


def test_a_second_module_on_a_joint_or_node_is_refused_in_the_panel(doc):
    sc = open_example("fish_modules")
    n0 = len(sc.Modules)
    p = run_panel("MM_AddModule")
    p.set_type("constraint_clip")
    p.target.setCurrentText("H0,3")              # the joint of the stable hub fin_mount_top
    lab = p.problem_label("target")
    assert lab.isVisible() and "fin_mount_top" in lab.text() and "one module per joint" in lab.text(), lab.text()
    assert not dialog_button("Ok").isEnabled()
    assert not press_ok()
    p.target.setCurrentText("H0,2")
    assert not lab.isVisible()
    # a clip holds the constraint on its joint: H0,2 has none, a red line says so before OK, nothing is kept
    clip = p.problem_label("constraint")
    assert clip.isVisible() and "H0,2" in clip.text() and "Angular constraint" in clip.text(), clip.text()
    assert not dialog_button("Ok").isEnabled()
    assert not press_ok()
    assert len(sc.Modules) == n0 and sc.isValid()
    p.set_type("stable_hub")
    p.target.setCurrentText("H0,2")
    assert press_ok(), p.error.text()
    assert len(sc.Modules) == n0 + 1
    # two pads on one node
    for k, expect in ((0, True), (1, False)):
        p = run_panel("MM_AddModule")
        p.set_type("friction_pad")
        p.target.setCurrentText("N0,0")
        assert press_ok() is expect
    assert "N0,0" in p.problem_label("target").text() and "one module per node socket" in \
        p.problem_label("target").text()
    assert press_cancel()


def unprintable_structure(doc):
    """A new structure with a 10 deg fold on its 2 mm hinges: kinematically fine (31.9 deg), not printable (3.96
    deg): the export's checks refuse it."""
    run_panel("MM_NewStructure")
    assert press_ok()
    sc = structure.find_scene_objects(doc)[-1]
    structure.set_scene_fields(sc, axes=[{"direction": "vertical", "line": 3, "fold_deg": 10.0}])
    doc.recompute()
    return sc


def test_export_failure_is_shown_in_the_panel(doc, tmp_path):
    sc = unprintable_structure(doc)
    assert sc.isValid()
    p = run_panel("MM_Export")
    blocker = tmp_path / "a_file"
    blocker.write_text("not a folder")
    type_into(p.path, str(blocker))
    assert p.problem_label("path").isVisible() and "not a folder" in p.problem_label("path").text()
    assert not p.export_btn.isEnabled()
    type_into(p.path, str(tmp_path / "out"))
    assert not p.problem_label("path").isVisible()
    click(p.export_btn)
    assert p.wait(300)
    assert p.job.outcome == "error" and p.error.text().startswith("not exported:"), p.error.text()
    assert "tilt" in p.error.text(), p.error.text()
    assert not os.path.exists(tmp_path / "out") or not os.listdir(tmp_path / "out")
    assert FreeCAD.ActiveDocument is not None


@pytest.mark.parametrize("cmd", ["MM_Simulate", "MM_Animate", "MM_RotaryAxes", "MM_FoldedShape"])
def test_cancel_leaves_a_saved_document_unmodified(doc, tmp_path, cmd):
    """The preview is a Coin overlay: a drag or playback writes no property, so Cancel leaves the saved
    document unmodified (FreeCAD 0.20's ``Gui.Document.Modified`` cannot be cleared by a panel)."""
    sc = open_example("fish_axes")
    path = str(tmp_path / "saved.FCStd")
    doc.saveAs(path)                       # names the file; Std_Save then saves as the user does
    FreeCADGui.runCommand("Std_Save")
    process(50)
    gd = FreeCADGui.getDocument(doc.Name)
    assert not gd.Modified
    before = [FreeCAD.Placement(q) for q in sc.NodeArray.PlacementList]
    undo0 = doc.UndoCount
    p = run_panel(cmd)
    if cmd == "MM_Simulate":
        drag_slider(p.sliders["tail"], 500)
    elif cmd == "MM_Animate":
        p.step(5)
    elif cmd == "MM_RotaryAxes":
        click(next(iter(p.buttons.values())))
    else:
        drag_slider(p.global_slider, 60)
        process(300)                       # the folded-shape preview runs on a short timer
    process(50)
    prev = p.live_preview
    assert prev is not None and prev.active and prev.frames >= 1, f"{cmd} drew no preview"
    graph = gd.ActiveView.getSceneGraph()
    assert graph.findChild(prev.root) >= 0
    assert not gd.Modified, f"the preview of {cmd} marked the saved document modified"
    assert press_cancel()
    process(50)
    assert not gd.Modified, f"Cancel on {cmd} marked the saved document modified"
    assert graph.findChild(prev.root) < 0 and not prev.active, "the preview is removed on Cancel"
    assert sc.NodeArray.ViewObject.SwitchNode.whichChild.getValue() >= 0, "the nodes are shown again"
    assert doc.UndoCount == undo0
    assert all((a.Base - b.Base).Length < 1e-12 for a, b in zip(sc.NodeArray.PlacementList, before))


def _nearest(a, b):
    """Largest distance from a corner of box k in ``a`` (n, 8, 3) to the nearest corner of box k in ``b``."""
    d = np.linalg.norm(a[:, :, None, :] - b[:, None, :, :], axis=3)
    return float(max(d.min(axis=2).max(), d.min(axis=1).max()))


def _element_vertices(arr):
    """(n, 8, 3) vertices of every element box of a link array as the document defines it (in the array's
    frame): the shape source's vertices, scaled per element by ``ScaleList``, placed by ``PlacementList``
    (FreeCAD's own Placement arithmetic, independent of the preview's numpy)."""
    src = [FreeCAD.Vector(v.Point) for v in arr.LinkedObject.Shape.Vertexes]
    scales = list(arr.ScaleList) if len(arr.ScaleList) == arr.ElementCount else \
        [FreeCAD.Vector(1, 1, 1)] * arr.ElementCount
    return np.array([[tuple(pl.multVec(FreeCAD.Vector(v.x * s.x, v.y * s.y, v.z * s.z))) for v in src]
                     for pl, s in zip(arr.PlacementList, scales)])


def _shape_vertices(arr):
    """(n, 8, 3) vertices of the link array's elements from its App-level shape (``Part.getShape``). OCC
    transforms scale uniformly only, so this reference holds for unscaled elements (the node plates)."""
    import Part
    shape = Part.getShape(arr, "", needSubElement=False, transform=False)
    return np.array([[(v.X, v.Y, v.Z) for v in s.Vertexes] for s in shape.Solids])


def test_preview_matches_the_document_after_ok(doc):
    """The fast path must not drift: the preview's boxes (nodes, hinges with per-joint sizes, markers) after
    a drag equal the document's shapes after OK, to 1e-6 mm (the Coin copy to float32 resolution)."""
    sc = open_example("fish")
    structure.set_scene_fields(sc, joints=[{"joint": "H0,3", "width_mm": 1.6, "length_mm": 6.0}])
    doc.recompute()
    assert sc.isValid()
    p = run_panel("MM_Simulate")
    if p.use_global.isChecked():
        click(p.use_global)
    drag_slider(p.sliders["tail"], 600)
    drag_slider(p.sliders["head"], -300)
    prev = p.live_preview
    corners = {k: np.array(prev.corners(k)) for k in ("nodes", "hinges")}
    coin_pts = {k: prev.coin_points(k) for k in ("nodes", "hinges")}
    marker = {o.Name: _vp_matrix(o) for o in sc.Items}
    assert press_ok(), p.error.text()
    for kind, arr in (("nodes", sc.NodeArray), ("hinges", sc.HingeArray)):
        ref = _element_vertices(arr)
        assert ref.shape == corners[kind].shape, kind
        assert _nearest(ref, corners[kind]) < 1e-6, kind
        assert _nearest(ref, coin_pts[kind]) < 2e-4 * max(1.0, float(np.abs(ref).max())), kind
    assert _nearest(_shape_vertices(sc.NodeArray), corners["nodes"]) < 1e-6
    # the per-joint hinge size is in the comparison (its element is scaled in the document)
    k = list(structure.compose_scene(sc).topology.joint_names).index("H0,3")
    assert abs(sc.HingeArray.ScaleList[k].y - 2.0) < 1e-9
    # the markers were drawn where OK placed them (Coin holds float32)
    for o in sc.Items:
        err = max(abs(a - b) for a, b in zip(marker[o.Name].A, o.Placement.toMatrix().A))
        assert err < 1e-4, (o.Name, err)


def _vp_matrix(o):
    """The Coin transform of an object's view provider (what the 3D view applies to it)."""
    from pivy import coin
    root = o.ViewObject.RootNode
    for i in range(root.getNumChildren()):
        node = root.getChild(i)
        if node.isOfType(coin.SoTransform.getClassTypeId()):
            t = node.translation.getValue()
            q = node.rotation.getValue().getValue()
            return FreeCAD.Placement(FreeCAD.Vector(t[0], t[1], t[2]), FreeCAD.Rotation(*q)).toMatrix()
    raise AssertionError(f"no SoTransform in the view provider of {o.Name}")


def test_stale_messages_go_and_grid_beyond_16(doc):
    p = run_panel("MM_NewStructure")
    p.rows.setValue(3)
    p.cols.setValue(3)
    click(p.grid_btn)
    click(p.buttons[(1, 1)])                      # a hole: closed contour
    lab = p.problem_label("grid")
    assert lab.isVisible() and "closed contour" in lab.text()
    assert p.buttons[(1, 1)].toolTip() == "cell [1, 1]"
    click(p.buttons[(1, 1)])                      # fixed: the red message goes
    assert not lab.isVisible() and lab.text() == ""
    type_into(p.rows, "20")
    type_into(p.cols, "24")
    assert p.rows.value() == 20 and p.cols.value() == 24 and len(p.buttons) == 20 * 24
    click(p.grid_btn)
    assert press_ok(), p.error.text()
    sc = structure.find_scene_objects(doc)[-1]
    assert sc.NodeCount == 21 * 25 and sc.isValid()


def test_motor_sliders_disabled_under_global_and_servo_degrees(doc):
    open_example("fish")
    p = run_panel("MM_Simulate")
    if p.use_global.isChecked():
        click(p.use_global)
    s = p.sliders["tail"]
    assert s.isEnabled()
    p.set_value("tail", 0.5)
    # the angle stream sends (the tail's joint closes by 12.2 deg at +0.5, negative on its servo), not 0.5 x 90
    assert p.labels["tail"].text() == "-12.2 deg (+0.500)"
    click(p.use_global)
    assert p.use_global.isChecked() and not s.isEnabled() and "overridden" in s.toolTip()
    click(p.use_global)
    assert s.isEnabled()
    assert press_cancel()
    assert panels.active() is None
