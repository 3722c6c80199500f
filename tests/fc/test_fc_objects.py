"""App-level (no GUI) tests of the scene document objects: mirror, dependencies, errors, round trip, undo.

References are the core package called directly (solve_scene + kinematics.node_poses), which the
objects must reproduce, and FreeCAD's own save / load.
"""
import json
import os

import numpy as np
import pytest

FreeCAD = pytest.importorskip("FreeCAD")

import metamaterial_wb  # noqa: E402
from metamaterial_wb.core import design, kinematics  # noqa: E402
from metamaterial_wb.core.scene import Scene  # noqa: E402
from metamaterial_wb.core.solver import solve_scene  # noqa: E402
from metamaterial_wb.objects import structure  # noqa: E402
from metamaterial_wb.objects.common import execute_count  # noqa: E402


@pytest.fixture
def doc():
    d = FreeCAD.newDocument("MMApp")
    name = d.Name
    yield d
    if name in FreeCAD.listDocuments():
        FreeCAD.closeDocument(name)


def fish():
    return Scene.load(metamaterial_wb.example_path("fish"))


def placements_xyz(arr):
    return np.array([[p.Base.x, p.Base.y, p.Base.z] for p in arr.PlacementList])


def placements_angle_z(arr):
    out = []
    for p in arr.PlacementList:
        ax = p.Rotation.Axis
        out.append(p.Rotation.Angle * (1 if ax.z >= 0 else -1))
    return np.array(out)


def core_reference(scene):
    D, _m, _w, _t = solve_scene(scene)
    pos, R, phi = kinematics.node_poses(scene, D, kin=design.kinematics_for(scene))
    return D, pos, phi


def test_structure_mirrors_the_core_solution(doc):
    sc = structure.make_structure(doc, fish())
    assert sc.isValid(), sc.State
    scene = fish()
    D, pos, phi = core_reference(scene)
    assert sc.NodeCount == scene.topology.n_nodes == 21
    assert sc.JointCount == scene.topology.n_joints
    np.testing.assert_allclose(sc.Deformation, D, atol=1e-12)
    np.testing.assert_allclose(placements_xyz(sc.NodeArray), pos, atol=1e-6)
    np.testing.assert_allclose(placements_angle_z(sc.NodeArray), phi, atol=1e-6)
    assert len(sc.HingeArray.PlacementList) == scene.topology.n_joints
    # two motors, red markers linked in Items, named as in the file
    names = sorted(o.ItemName for o in sc.Items)
    assert names == ["head", "tail"]
    # the composed scene equals the file (items come back from the marker objects)
    assert structure.compose_scene(sc).to_dict() == scene.to_dict()
    for o in doc.Objects:
        assert o.isValid(), (o.Name, o.State)


def test_hinge_ends_meet_the_node_corners(doc):
    """Each hinge centre is the midpoint of the two node corners it joins (exact mechanism: they coincide
    up to the hinge length)."""
    sc = structure.make_structure(doc, fish())
    scene = structure.compose_scene(sc)
    nodes = sc.NodeArray.PlacementList
    hinges = sc.HingeArray.PlacementList
    half = 0.5 * (scene.cell_size_mm - scene.hinge["length_mm"])
    for k, (kind, i, j) in enumerate(scene.topology.joints):
        a, b = scene.topology.joint_pairs[k]
        # the hinge centre lies within half a hinge length of both nodes' nearest corners
        c = hinges[k].Base
        da = min((nodes[a].multVec(FreeCAD.Vector(sx * half, sy * half, 0)) - c).Length
                 for sx in (-1, 1) for sy in (-1, 1))
        db = min((nodes[b].multVec(FreeCAD.Vector(sx * half, sy * half, 0)) - c).Length
                 for sx in (-1, 1) for sy in (-1, 1))
        assert da <= scene.hinge["length_mm"] and db <= scene.hinge["length_mm"], (kind, i, j, da, db)


def test_motor_joint_change_recomputes_scene_not_shapes(doc):
    sc = structure.make_structure(doc, fish())
    ns = doc.getObject("NodeShape")
    builds = ns.BuildCount
    n_exec = execute_count(sc)
    head = [o for o in sc.Items if o.ItemName == "head"][0]
    head.Joint = "V1,2"
    doc.recompute()
    assert sc.isValid(), sc.State
    assert execute_count(sc) == n_exec + 1
    assert ns.BuildCount == builds, "the node shape must not be rebuilt when only a motor moves"
    scene = fish()
    scene.actuators[0].joint = "V1,2"
    scene = Scene.from_dict(scene.to_dict())
    D, pos, _phi = core_reference(scene)
    np.testing.assert_allclose(sc.Deformation, D, atol=1e-12)
    np.testing.assert_allclose(placements_xyz(sc.NodeArray), pos, atol=1e-6)
    # the marker sits over its new joint: hinge V1,2's centre (x, y)
    k = scene.topology.joint_index["V1,2"]
    h = sc.HingeArray.PlacementList[k].Base
    assert abs(head.Placement.Base.x - h.x) < 1e-6 and abs(head.Placement.Base.y - h.y) < 1e-6
    assert head.Placement.Base.z > h.z


def test_global_deformation_property_changes_only_the_scene(doc):
    sc = structure.make_structure(doc, fish())
    head = sc.Items[0]
    n_item = execute_count(head)
    sc.UseGlobal = True
    sc.GlobalDeformation = 0.5
    doc.recompute()
    assert execute_count(head) == n_item
    assert np.allclose(sc.Deformation, 0.5)
    scene = fish()
    pos, _R, _phi = kinematics.node_poses(scene, np.full(scene.topology.n_nodes, 0.5), kin=design.kinematics_for(scene))
    np.testing.assert_allclose(placements_xyz(sc.NodeArray), pos, atol=1e-6)


def test_cell_size_rebuilds_the_node_shape(doc):
    sc = structure.make_structure(doc, fish())
    ns = doc.getObject("NodeShape")
    b0 = ns.BuildCount
    sc.CellSize = 30.0
    doc.recompute()
    assert sc.isValid() and ns.isValid()
    assert ns.BuildCount == b0 + 1
    side = 30.0 - sc.HingeLength.Value
    assert abs(ns.Shape.BoundBox.XLength - side) < 1e-6
    # node pitch follows: flat neighbours 30 mm apart when D = 0
    sc.UseGlobal = True
    sc.GlobalDeformation = 0.0
    doc.recompute()
    xyz = placements_xyz(sc.NodeArray)
    assert abs(np.linalg.norm(xyz[1] - xyz[0]) - 30.0) < 1e-6


def test_hinge_length_rebuilds_shapes_but_not_the_markers(doc):
    sc = structure.make_structure(doc, fish())
    ns, hs = doc.getObject("NodeShape"), doc.getObject("HingeShape")
    b_node, b_hinge = ns.BuildCount, hs.BuildCount
    marker_execs = [execute_count(o) for o in sc.Items]
    sc.HingeLength = 3.0
    doc.recompute()
    assert sc.isValid()
    assert (ns.BuildCount, hs.BuildCount) == (b_node + 1, b_hinge + 1)
    assert [execute_count(o) for o in sc.Items] == marker_execs, "markers do not depend on the hinge size"
    assert abs(ns.Shape.BoundBox.XLength - (sc.CellSize.Value - 3.0)) < 1e-6
    from metamaterial_wb.core.calibration import default_calibration
    assert sc.K1 == pytest.approx(default_calibration().k1(3.0))
    scene = fish()
    scene.hinge["length_mm"] = 3.0
    scene = Scene.from_dict(scene.to_dict())
    _D, pos, _phi = core_reference(scene)
    np.testing.assert_allclose(placements_xyz(sc.NodeArray), pos, atol=1e-6)


def test_axes_are_configured_and_kept_fresh(doc):
    from metamaterial_wb.core import design
    sc = structure.make_structure(doc, fish())
    structure.set_scene_fields(sc, axes=[{"direction": "vertical", "line": 4, "fold_deg": 3.0}])
    doc.recompute()
    assert sc.isValid(), sc.State
    cfg = json.loads(sc.SceneJSON)["joint_config"]
    ref = fish()
    ref = Scene.from_dict(dict(ref.to_dict(), axes=[{"direction": "vertical", "line": 4, "fold_deg": 3.0}]))
    design.configure(ref)
    assert set(cfg) == set(ref.joint_config)
    for k in cfg:
        assert cfg[k]["tilt_deg"] == pytest.approx(ref.joint_config[k]["tilt_deg"])
    # a longer hinge needs another tilt for the same fold: the stored configuration follows
    sc.HingeLength = 3.0
    doc.recompute()
    cfg2 = json.loads(sc.SceneJSON)["joint_config"]
    assert any(abs(cfg2[k]["tilt_deg"] - cfg[k]["tilt_deg"]) > 1e-6 for k in cfg)
    assert any("stale" in w for w in sc.SolveWarnings)


def test_bad_joint_makes_the_scene_invalid_with_its_name(doc):
    sc = structure.make_structure(doc, fish())
    head = sc.Items[0]
    head.Joint = "V9,9"
    doc.recompute()
    assert not sc.isValid()
    with pytest.raises(Exception, match="V9,9"):
        structure.compose_scene(sc)
    head.Joint = "V0,1"
    doc.recompute()
    assert sc.isValid()


def test_layout_property_changes_topology(doc):
    sc = structure.make_structure(doc, Scene.grid(2, 3))
    sc.Layout = ["###", "#.."]
    doc.recompute()
    assert sc.isValid(), sc.State
    s = structure.compose_scene(sc)
    assert sorted(s.cells) == [(0, 0), (0, 1), (0, 2), (1, 0)]
    assert sc.NodeArray.ElementCount == s.topology.n_nodes == len(sc.NodeArray.PlacementList)


def test_save_close_reopen_restores_everything(doc, tmp_path):
    sc = structure.make_structure(doc, fish())
    structure.make_module(doc, sc, "friction_pad", "N0,0")
    # a printable fold: beyond it Export refuses the sheet and the module is invalid with that message
    # (test_fc_module_matches_export.py)
    structure.set_scene_fields(sc, axes=[{"direction": "vertical", "line": 2, "fold_deg": 12.0}])
    sc.Items[1].PhaseDeg = 45.0
    doc.recompute()
    for o in doc.Objects:   # a dependency cycle would leave objects touched
        assert o.isValid() and "Touched" not in o.State, (o.Name, o.State)
    before_json = sc.SceneJSON
    before_pl = placements_xyz(sc.NodeArray)
    names = sorted(o.Name for o in doc.Objects)
    sc_name = sc.Name
    path = str(tmp_path / "fish.FCStd")
    doc.saveAs(path)
    FreeCAD.closeDocument(doc.Name)
    d2 = FreeCAD.openDocument(path)
    try:
        assert sorted(o.Name for o in d2.Objects) == names
        sc2 = d2.getObject(sc_name)
        assert sc2.Proxy.Type == "MetamaterialScene"
        assert sc2.SceneJSON == before_json
        assert json.loads(sc2.SceneJSON)["axes"][0]["fold_deg"] == 12.0
        assert sc2.NodeArray is not None and sc2.NodeArray.Name == "Nodes"
        np.testing.assert_allclose(placements_xyz(sc2.NodeArray), before_pl, atol=1e-9)
        tail = [o for o in sc2.Items if o.ItemName == "tail"][0]
        assert tail.Proxy.Type == "MetamaterialItem" and tail.PhaseDeg == 45.0
        assert sc2.Modules[0].Proxy.Type == "MetamaterialModule"
        # the reopened objects still compute
        d2.recompute()
        for o in d2.Objects:
            assert o.isValid(), (o.Name, o.State)
        assert structure.compose_scene(sc2).to_json() == before_json
    finally:
        FreeCAD.closeDocument(d2.Name)


def test_one_undo_step_removes_a_motor(doc):
    doc.UndoMode = 1
    sc = structure.make_structure(doc, fish())
    n = len(doc.Objects)
    doc.openTransaction("Place motor")
    structure.make_item(doc, sc, "actuator", "m3", "H2,3", 0.2)
    doc.recompute()
    doc.commitTransaction()
    assert len(doc.Objects) == n + 1 and len(sc.Items) == 3
    doc.undo()
    doc.recompute()
    assert len(doc.Objects) == n and len(sc.Items) == 2
    assert sc.isValid()


@pytest.mark.parametrize("mtype,target", [("servo_housing", "V0,1"), ("friction_pad", "N2,3"),
                                          ("connection_hub", "N0,6"), ("stable_hub", "H1,2")])
def test_module_solid_and_place_match_the_fabrication_build(doc, mtype, target):
    """In the flat state the document's module is the fabrication package's module at the same place
    (our sheet is centred on z = 0, the fabrication sheet spans z = 0..t)."""
    from metamaterial_wb.geometry.build import build_scene
    sc = structure.make_structure(doc, fish())
    m = structure.make_module(doc, sc, mtype, target)
    sc.UseGlobal = True
    sc.GlobalDeformation = 0.0
    doc.recompute()
    assert m.isValid() and sc.isValid(), (m.State, sc.State)
    assert m.GeometrySource == "geometry.modules"
    scene = structure.compose_scene(sc)
    res = build_scene(scene, modules=True, progress=False)
    name = f"{mtype}_{len(scene.modules)}"    # the fabrication package's default name of our (last) module
    parts = [p for p in res.parts if p.role == "module" and p.group == name]
    assert parts, sorted({p.group for p in res.parts})
    ref = parts[0]
    placed = res.placed_shape(ref)
    mine = m.Shape.copy()   # Part shapes carry the object's placement
    t = scene.hinge["thickness_mm"]
    assert abs(mine.Volume - sum(res.placed_shape(p).Volume for p in parts)) < 1e-6 * max(1.0, mine.Volume)
    bb_ref = placed.BoundBox if len(parts) == 1 else None
    if bb_ref is not None:
        bb = mine.BoundBox
        for a, b in ((bb.XMin, bb_ref.XMin), (bb.XMax, bb_ref.XMax), (bb.YMin, bb_ref.YMin),
                     (bb.YMax, bb_ref.YMax), (bb.ZMin, bb_ref.ZMin - 0.5 * t), (bb.ZMax, bb_ref.ZMax - 0.5 * t)):
            assert abs(a - b) < 1e-6, (mtype, a, b)


def test_module_follows_cell_size_without_a_dependency_cycle(doc):
    sc = structure.make_structure(doc, fish())
    m = structure.make_module(doc, sc, "connection_hub", "N1,1")
    doc.recompute()
    key0 = m.BuiltFor
    sc.CellSize = 24.0
    doc.recompute()
    assert m.BuiltFor != key0, "the Scene refreshes its modules' solids when the sizes change"
    for o in doc.Objects:
        assert o.isValid() and "Touched" not in o.State, (o.Name, o.State)
    node = sc.NodeArray.PlacementList[structure.compose_scene(sc).topology.node_index[(1, 1)]].Base
    assert abs(m.Placement.Base.x - node.x) < 1e-6 and abs(m.Placement.Base.y - node.y) < 1e-6


def _example_scenes():
    import glob
    out = []
    for f in sorted(glob.glob(os.path.join(metamaterial_wb.EXAMPLES_DIR, "*.json"))):
        with open(f, encoding="utf-8") as fh:
            if json.load(fh).get("format") == "metamaterial-scene":
                out.append(os.path.basename(f)[:-5])
    return out


@pytest.mark.parametrize("name", _example_scenes())
def test_every_example_becomes_a_valid_structure_that_round_trips(doc, name):
    scene = Scene.load(metamaterial_wb.example_path(name))
    sc = structure.make_structure(doc, scene)
    for o in doc.Objects:
        assert o.isValid(), (name, o.Name, o.State)
    again = structure.compose_scene(sc).to_dict()
    want = scene.to_dict()
    # the document may add the joint configuration of the axes (design stage); everything else is equal
    if "joint_config" not in want:
        again.pop("joint_config", None)
    assert again == want


def test_preference_clearance_reaches_the_module_solid(doc):
    prm = FreeCAD.ParamGet(structure.PREFS_PATH)
    sc = structure.make_structure(doc, fish())
    m = structure.make_module(doc, sc, "connection_hub", "N1,2")
    doc.recompute()
    v0 = m.Shape.Volume
    try:
        prm.SetFloat("PrinterClearance", 0.4)
        m.touch()
        doc.recompute()
        assert m.isValid()
        assert m.Shape.Volume < v0, "a larger clearance makes the snap pins thinner"
    finally:
        prm.RemFloat("PrinterClearance")
