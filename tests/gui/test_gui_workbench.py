"""GUI tests in the real FreeCAD GUI (under Xvfb, via tests/run_gui_pytest.py).

Every command runs on an example through its task panel, driven by the panel's own widgets; the
simulate slider and the animation are compared with the core package called directly; the document
round trip is checked with the view providers. Under plain pytest (no GUI) the module is skipped.
"""
import json
import os
import time
import zipfile

import numpy as np
import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

import FreeCADGui  # noqa: E402
from PySide import QtCore, QtGui  # noqa: E402

import metamaterial_wb  # noqa: E402
from metamaterial_wb.core import design, kinematics  # noqa: E402
from metamaterial_wb.core.motion import scene_values_at  # noqa: E402
from metamaterial_wb.core.scene import Scene  # noqa: E402
from metamaterial_wb.core.solver import solve_scene  # noqa: E402
from metamaterial_wb.gui import commands, panels  # noqa: E402
from metamaterial_wb.objects import structure  # noqa: E402
from guihelpers import dialog_button, doc, run_panel, shown_placements, workbench  # noqa: E402,F401


def process_events():
    QtGui.QApplication.processEvents()


def open_fish(doc):
    p = run_panel("MM_OpenExample")
    p.select("fish")
    assert p.accept() is True
    return structure.find_scene_objects(doc)[-1]


def xyz(arr):
    return np.array([[q.Base.x, q.Base.y, q.Base.z] for q in shown_placements(arr)])


def core_positions(scene, values=None, g=None):
    sc = scene.copy()
    for k, v in (values or {}).items():
        sc.set_value(k, v)
    D, _m, _w, _t = solve_scene(sc, global_deformation=g)
    pos, _R, phi = kinematics.node_poses(sc, D, kin=design.kinematics_for(sc))
    return D, pos, phi


# ----------------------------------------------------------------------------------------------
def test_workbench_registers_every_command_with_an_icon():
    names = [c[0] for c in commands.COMMANDS]
    listed = FreeCADGui.listCommands()
    for n in names:
        assert n in listed, n
        res = FreeCADGui.Command.get(n).getInfo() if hasattr(FreeCADGui.Command, "get") else None
        icon = metamaterial_wb.icon_path(dict(c[:2] for c in [(c[0], c[1]) for c in commands.COMMANDS])[n])
        assert os.path.exists(icon), icon
        assert open(icon).read().lstrip().startswith("<svg")
        if res:
            assert res["menuText"]
    assert os.path.exists(metamaterial_wb.icon_path("Metamaterial_Workbench.svg"))
    wb = FreeCADGui.getWorkbench("MetamaterialWorkbench")
    bars = wb.listToolbars()
    assert "Metamaterial design" in bars and "Metamaterial simulation" in bars


def test_the_preferences_group_has_its_icon():
    """Edit > Preferences looks for the icon ``preferences-`` + the group's name in lower case: it printed "Cannot
    find icon: preferences-metamaterial" three times (audit, session 28)."""
    icon = metamaterial_wb.icon_path("preferences-metamaterial.svg")
    assert os.path.exists(icon), icon
    with open(icon, encoding="utf-8") as f:
        assert f.read().lstrip().startswith("<svg")


def test_preferences_page_loads_with_defaults():
    from metamaterial_wb.gui import preferences
    ui = os.path.join(metamaterial_wb.RESOURCES_DIR, "ui", "preferences.ui")
    w = FreeCADGui.PySideUic.loadUi(ui)
    for name in ("PrinterClearance", "RigidMaterial", "FlexibleMaterial", "ModuleMaterial", "DefaultServo",
                 "SerialPort", "AnimationFps"):
        assert w.findChild(QtCore.QObject, name) is not None, name
    assert preferences.get("PrinterClearance") == pytest.approx(0.2)
    preferences.params().SetString("SerialPort", "loop://")
    try:
        assert preferences.get("SerialPort") == "loop://"
    finally:
        preferences.params().RemString("SerialPort")


def test_new_structure_panel_layout_editor(doc):
    p = run_panel("MM_NewStructure")
    p.rows.setValue(3)
    p.cols.setValue(3)
    p.preset_grid()
    p.toggle(1, 1)                      # a hole in the middle: the seed forbids a closed contour
    assert "closed contour" in p.problem_label("grid").text() and p.problem_label("grid").isVisible()
    assert p.accept() is False and "closed contour" in p.error.text()
    assert FreeCADGui.Control.activeDialog()
    p.preset_chain()
    assert len(p.cells()) == 3 and "valid" in p.status.text()
    undo0 = doc.UndoCount
    assert p.accept() is True
    sc = structure.find_scene_objects(doc)[-1]
    assert sorted(structure.compose_scene(sc).cells) == [(0, 0), (0, 1), (0, 2)]
    assert sc.isValid() and sc.NodeCount == 8
    assert doc.UndoCount == undo0 + 1
    doc.undo()
    assert not structure.find_scene_objects(doc)


def test_command_on_an_invalid_structure_reports_and_opens_nothing(doc):
    sc = open_fish(doc)
    sc.Items[0].Joint = "V7,7"
    doc.recompute()
    assert not sc.isValid()
    FreeCADGui.runCommand("MM_Simulate")
    process_events()
    assert not FreeCADGui.Control.activeDialog()
    assert "V7,7" in commands.INSTANCES["MM_Simulate"].last_error


def test_new_structure_from_scene_file(doc):
    p = run_panel("MM_NewStructure")
    assert p.load_file(metamaterial_wb.example_path("worm")) is not None
    assert p.accept() is True
    sc = structure.find_scene_objects(doc)[-1]
    assert structure.compose_scene(sc).to_dict() == Scene.load(metamaterial_wb.example_path("worm")).to_dict()


def test_open_example_fish(doc):
    sc = open_fish(doc)
    assert sc.isValid()
    assert sorted(o.ItemName for o in sc.Items) == ["head", "tail"]
    head = [o for o in sc.Items if o.ItemName == "head"][0]
    assert head.ViewObject.ShapeColor[0] > 0.8 and head.ViewObject.ShapeColor[1] < 0.2   # red marker


def test_rotary_axes_rules_and_picking(doc):
    sc = open_fish(doc)
    p = run_panel("MM_RotaryAxes")
    p.set_axis("vertical", 3)
    p.set_axis("horizontal", 0)
    assert "cross" in p.violations.text()
    assert p.accept() is False
    p.set_axis("horizontal", 0, False)
    assert p.violations.text() == ""
    # a hinge clicked in the 3D view toggles the axis that crosses it: H1,1 -> vertical line 1
    scene = structure.compose_scene(sc)
    k = scene.topology.joint_index["H1,1"]
    FreeCADGui.Selection.clearSelection()
    FreeCADGui.Selection.addSelection(doc.Name, sc.HingeArray.Name, f"{k}.Face1")
    process_events()
    assert p.buttons[("vertical", 1)].isChecked()
    FreeCADGui.Selection.clearSelection()
    # while the panel is open: the flat sheet, with the 8 candidate lines and the 2 chosen axes drawn
    flat = xyz(sc.NodeArray)
    _D, pos0, _phi = core_positions(scene, g=0.0)
    np.testing.assert_allclose(flat, pos0, atol=1e-6)
    assert (p.overlay.n_candidates, p.overlay.n_chosen) == (8, 2)
    graph = FreeCADGui.getDocument(doc.Name).ActiveView.getSceneGraph()
    assert graph.findChild(p.overlay.root) >= 0
    root = p.overlay.root
    undo0 = doc.UndoCount
    assert p.accept() is True
    assert graph.findChild(root) < 0, "the axis overlay must be removed when the panel closes"
    axes = json.loads(sc.SceneJSON)["axes"]
    assert [(a["direction"], a["line"]) for a in axes] == [("vertical", 1), ("vertical", 3)]
    assert doc.UndoCount == undo0 + 1


def test_folded_shape_sliders_store_folds(doc):
    sc = open_fish(doc)
    structure.set_scene_fields(sc, axes=[{"direction": "vertical", "line": 3, "fold_deg": 0.0}])
    doc.recompute()
    before = xyz(sc.NodeArray)
    p = run_panel("MM_FoldedShape")
    assert len(p.sliders) == 1
    p.set_fold(0, 20)
    p.global_slider.setValue(50)
    process_events()
    assert p.accept() is True
    assert json.loads(sc.SceneJSON)["axes"][0]["fold_deg"] == 20.0
    assert sc.isValid()
    # after Confirm the document shows the solved state of the (configured) scene, as the core says
    scene = structure.compose_scene(sc)
    _D, pos, _phi = core_positions(scene, {})
    np.testing.assert_allclose(xyz(sc.NodeArray), pos, atol=1e-6)
    assert scene.joint_config, "Confirm must run the joint configuration"
    assert before.shape == pos.shape


def test_flexibility_sets_sizes_and_shows_k(doc):
    from metamaterial_wb.core.calibration import default_calibration
    sc = open_fish(doc)
    p = run_panel("MM_Flexibility")
    p.length.setValue(3.0)
    cal = default_calibration()
    assert f"{cal.k1(3.0):.3f}" in p.k_label.text()
    p.joint.setCurrentText("V1,3")
    p.j_length.setValue(2.5)
    p.set_override()
    assert p.accept() is True
    assert sc.HingeLength.Value == pytest.approx(3.0)
    assert sc.K1 == pytest.approx(cal.k1(3.0))
    joints = json.loads(sc.SceneJSON)["joints"]
    assert joints == [{"joint": "V1,3", "length_mm": 2.5}], "only the size the user edited is the joint's own"
    assert sc.isValid()


def test_flexibility_checks_a_joint_size_when_it_is_set(doc):
    """"Set for this joint" took a 20 mm hinge on a 27 mm cell without a word; only OK refused it."""
    open_fish(doc)
    p = run_panel("MM_Flexibility")
    p.joint.setCurrentText("V0,1")
    p.j_length.setValue(20.0)
    p.set_override()
    lab = p.problem_label("joints")
    assert "V0,1" in lab.text() and "length_mm" in lab.text() and "outside the allowed range" in lab.text()
    assert not dialog_button("Ok").isEnabled()
    p.remove_override()
    assert lab.text() == "" and dialog_button("Ok").isEnabled()


def test_place_motor_by_clicking_a_hinge_is_one_undo_step(doc):
    sc = open_fish(doc)
    p = run_panel("MM_PlaceMotor")
    scene = structure.compose_scene(sc)
    k = scene.topology.joint_index["H2,3"]
    FreeCADGui.Selection.clearSelection()
    FreeCADGui.Selection.addSelection(doc.Name, sc.HingeArray.Name, f"{k}.Face2")
    process_events()
    FreeCADGui.Selection.clearSelection()
    assert p.joint.currentText() == "H2,3"
    p.value.setValue(-0.4)
    n0, undo0 = len(doc.Objects), doc.UndoCount
    assert p.accept() is True
    assert len(doc.Objects) == n0 + 1 and doc.UndoCount == undo0 + 1
    m = sc.Items[-1]
    assert m.Joint == "H2,3" and m.Kind == "actuator" and m.Value == pytest.approx(-0.4)
    assert sc.isValid()
    hp = sc.HingeArray.PlacementList[k].Base
    assert abs(m.Placement.Base.x - hp.x) < 1e-6 and abs(m.Placement.Base.y - hp.y) < 1e-6
    doc.undo()
    assert len(doc.Objects) == n0 and len(sc.Items) == 2


def test_angular_constraint_and_conflict_error(doc):
    sc = open_fish(doc)
    p = run_panel("MM_PlaceConstraint")
    p.joint.setCurrentText("V0,1")       # the head motor's joint with another value: a conflict
    p.value.setValue(-0.5)
    assert p.accept() is False and "head" in p.error.text()
    p.joint.setCurrentText("H0,3")
    assert p.accept() is True
    c = sc.Items[-1]
    assert c.Kind == "constraint" and c.Joint == "H0,3"
    assert c.ViewObject.ShapeColor[2] > 0.8
    # turned into a motor in the property editor: the marker turns red (it kept the clip's blue), and back
    c.Kind = "actuator"
    doc.recompute()
    assert c.ViewObject.ShapeColor[0] > 0.8 and c.ViewObject.ShapeColor[2] < 0.2
    c.Kind = "constraint"
    doc.recompute()
    assert c.ViewObject.ShapeColor[2] > 0.8 and c.ViewObject.ShapeColor[0] < 0.2


def test_add_module(doc):
    sc = open_fish(doc)
    p = run_panel("MM_AddModule")
    p.set_type("friction_pad")
    p.target.setCurrentText("N2,6")
    assert p.accept() is True
    m = sc.Modules[-1]
    assert m.ModuleType == "friction_pad" and m.Target == "N2,6" and m.isValid()
    scene = structure.compose_scene(sc)
    k = scene.topology.node_index[(2, 6)]
    node = sc.NodeArray.PlacementList[k].Base
    assert abs(m.Placement.Base.x - node.x) < 1e-6 and abs(m.Placement.Base.y - node.y) < 1e-6
    p = run_panel("MM_AddModule")
    p.set_type("servo_housing")
    p.target.setCurrentText("V0,1")
    assert p.accept() is True
    assert sc.Modules[-1].TargetKind == "joint"


def test_simulate_motor_slider_moves_nodes_as_the_solver_says(doc):
    sc = open_fish(doc)
    scene = structure.compose_scene(sc)
    ns = doc.getObject("NodeShape")
    builds = ns.BuildCount
    before = xyz(sc.NodeArray)
    p = run_panel("MM_Simulate")
    # the panel reuses the factorisation stored by the last recompute
    assert p.solver is structure.solver_for(sc, scene)
    p.set_value("tail", -0.6)
    process_events()
    D, pos, phi = core_positions(scene, {"tail": -0.6})
    np.testing.assert_allclose(xyz(sc.NodeArray), pos, atol=1e-6)
    np.testing.assert_allclose(p.last_frame.D, D, atol=1e-12)
    assert not np.allclose(xyz(sc.NodeArray), before)
    # no recompute while sliding: nothing touched, the shape not rebuilt
    assert "Touched" not in sc.State and "Touched" not in sc.NodeArray.State
    assert ns.BuildCount == builds
    # the global slider: every D = g
    p.global_slider.setValue(700)
    process_events()
    _D, pos_g, _phi = core_positions(scene, g=0.7)
    np.testing.assert_allclose(xyz(sc.NodeArray), pos_g, atol=1e-6)
    # Cancel restores the placements
    p.reject()
    np.testing.assert_allclose(xyz(sc.NodeArray), before, atol=1e-9)


def test_simulate_ok_commits_the_values_in_one_undo_step(doc):
    sc = open_fish(doc)
    scene = structure.compose_scene(sc)
    p = run_panel("MM_Simulate")
    p.set_value("head", 0.1)
    undo0 = doc.UndoCount
    assert p.accept() is True
    assert doc.UndoCount == undo0 + 1
    head = [o for o in sc.Items if o.ItemName == "head"][0]
    assert head.Value == pytest.approx(0.1)
    _D, pos, _phi = core_positions(scene, {"head": 0.1})
    np.testing.assert_allclose(xyz(sc.NodeArray), pos, atol=1e-6)


def test_simulate_shows_solver_warnings(doc):
    """A sheet without motor or constraint is reported (every D = 0 then), not hidden."""
    sc = structure.make_structure(doc, Scene.from_dict({
        "format": "metamaterial-scene", "version": 1, "layout": {"rows": ["###"]}, "actuators": []}))
    p = run_panel("MM_Simulate")
    assert p.sliders == {}
    assert "no motor" in p.warn.text()
    p.global_slider.setValue(300)
    process_events()
    _D, pos, _phi = core_positions(structure.compose_scene(sc), g=0.3)
    np.testing.assert_allclose(xyz(sc.NodeArray), pos, atol=1e-6)
    p.reject()
    assert any("no motor" in w for w in sc.SolveWarnings)
    structure.make_item(doc, sc, "constraint", "c1", "V0,0", 0.5)
    doc.recompute()
    p = run_panel("MM_Simulate")
    assert p.warn.text() == "", p.warn.text()
    p.reject()


def test_simulate_other_model_selector(doc):
    sc = open_fish(doc)
    p = run_panel("MM_Simulate")
    models = [p.model.itemText(i) for i in range(p.model.count())]
    assert "quadratic" in models
    others = [m for m in models if m != "quadratic"]
    if not others:
        pytest.skip("only the quadratic model is installed")
    p.model.setCurrentText(others[0])
    process_events()
    assert p.error.text() == "", p.error.text()
    assert p.solver.model_name == others[0]
    p.set_value("tail", 0.5)
    process_events()
    assert np.all(np.isfinite(xyz(sc.NodeArray)))


def test_simulate_shows_the_other_models_warnings_for_the_state_shown(doc):
    """A lattice model warns per state (the gripper's nonlinear solve at -1 turns hinges past the scene's limits);
    the panel showed only the warnings from when the model was chosen, so the slider drove the sheet through its
    limits without a word. The warning comes with the state and goes with it."""
    p = run_panel("MM_OpenExample")
    p.select("gripper")
    assert p.accept() is True
    p = run_panel("MM_Simulate")
    p.model.setCurrentText("nonlinear")
    process_events()
    assert p.error.text() == "", p.error.text()
    assert "past the scene's rotation limits" not in p.warn.text()
    for name in p.sliders:
        p.set_value(name, -1.0)
    process_events()
    assert "hinge(s) turn past the scene's rotation limits" in p.warn.text(), p.warn.text()
    assert p.last_frame.converged
    for name in p.sliders:
        p.set_value(name, 0.2)
    process_events()
    assert "past the scene's rotation limits" not in p.warn.text(), p.warn.text()
    p.reject()


def test_animation_plays_frames_and_restores(doc):
    sc = open_fish(doc)
    scene = structure.compose_scene(sc)
    before = xyz(sc.NodeArray)
    ns = doc.getObject("NodeShape")
    builds = ns.BuildCount
    p = run_panel("MM_Animate")
    p.speed.setValue(1.0)
    n = 12
    f0 = p.frames
    p.step(n)
    assert p.frames - f0 == n
    t = p.t
    assert t == pytest.approx(n * p.dt)
    vals = scene_values_at(scene, t)
    _D, pos, _phi = core_positions(scene, vals)
    np.testing.assert_allclose(xyz(sc.NodeArray), pos, atol=1e-6)
    # profile edit (phase offset of the tail) changes the motion shown
    p.set_profile("tail", phase_deg=0.0)
    p.show_time(t)
    sc2 = scene.copy()
    sc2.actuators[1].profile["phase_deg"] = 0.0
    _D, pos2, _phi = core_positions(scene, scene_values_at(sc2, t))
    np.testing.assert_allclose(xyz(sc.NodeArray), pos2, atol=1e-6)
    # real playback through the timer
    f1 = p.frames
    p.play()
    deadline = time.perf_counter() + 10.0            # a loaded machine draws fewer frames per second: wait for 4
    while p.frames <= f1 + 3 and time.perf_counter() < deadline:
        loop = QtCore.QEventLoop()
        QtCore.QTimer.singleShot(100, loop.quit)
        (loop.exec if hasattr(loop, "exec") else loop.exec_)()   # PySide6 deprecates exec_
    p.pause()
    assert p.frames > f1 + 3, "the timer did not advance the animation"
    # loop wraps the time
    p.loop.setChecked(True)
    p.show_time(p.duration.value() - 0.5 * p.dt)
    p.step(1)
    assert p.t < p.duration.value()
    assert ns.BuildCount == builds
    p.reject()
    np.testing.assert_allclose(xyz(sc.NodeArray), before, atol=1e-9)
    assert "Touched" not in sc.State and "Touched" not in sc.NodeArray.State


def test_animate_ok_stores_profiles(doc):
    sc = open_fish(doc)
    p = run_panel("MM_Animate")
    p.set_profile("head", amplitude=0.25, frequency_hz=2.0, phase_deg=30.0)
    assert p.accept() is True
    head = [o for o in sc.Items if o.ItemName == "head"][0]
    assert (head.Amplitude, head.FrequencyHz, head.PhaseDeg) == (0.25, 2.0, 30.0)
    prof = structure.compose_scene(sc).actuators[0].profile
    assert prof["amplitude"] == 0.25 and prof["phase_deg"] == 30.0


def test_export_step_and_3mf(doc, tmp_path):
    sc = open_fish(doc)
    p = run_panel("MM_Export")
    p.path.setText(str(tmp_path / "out"))
    assert p.accept() is True, p.error.text()
    files = p.written
    steps = [f for f in files if f.endswith(".step")]
    mfs = [f for f in files if f.endswith(".3mf")]
    assert steps and mfs
    for f in steps:
        with open(f, encoding="latin-1") as fh:
            head = fh.read(200)
        assert head.startswith("ISO-10303-21")
    for f in mfs:
        with zipfile.ZipFile(f) as z:
            assert "3D/3dmodel.model" in z.namelist()
    # the STEP re-imports with a solid per node and hinge (at least)
    import Part
    shape = Part.read(steps[0])
    n = structure.compose_scene(sc).topology
    assert len(shape.Solids) >= n.n_nodes


def test_document_round_trip_in_gui(doc, tmp_path):
    sc = open_fish(doc)
    p = run_panel("MM_PlaceMotor")
    p.joint.setCurrentText("H2,2")
    assert p.accept() is True, p.error.text()
    path = str(tmp_path / "fish_gui.FCStd")
    scene_json = sc.SceneJSON
    pl = xyz(sc.NodeArray)
    sc_name = sc.Name
    doc.saveAs(path)
    FreeCAD.closeDocument(doc.Name)
    d2 = FreeCAD.openDocument(path)
    try:
        sc2 = d2.getObject(sc_name)
        assert sc2.SceneJSON == scene_json
        np.testing.assert_allclose(xyz(sc2.NodeArray), pl, atol=1e-9)
        assert type(sc2.ViewObject.Proxy).__name__ == "ViewProviderScene"
        motor = sc2.Items[-1]
        assert type(motor.ViewObject.Proxy).__name__ == "ViewProviderItem"
        assert motor.Joint == "H2,2"
        d2.recompute()
        assert all(o.isValid() for o in d2.Objects)
        # commands work on the reopened document
        FreeCAD.setActiveDocument(d2.Name)
        p = run_panel("MM_Simulate")
        p.set_value("tail", 0.2)
        p.reject()
    finally:
        FreeCAD.closeDocument(d2.Name)


def test_double_click_scene_opens_simulate(doc):
    sc = open_fish(doc)
    sc.ViewObject.Proxy.doubleClicked(sc.ViewObject)
    process_events()
    assert isinstance(panels.active(), panels.SimulatePanel)
    panels.active().reject()


def test_animate_connect_streams_what_is_shown(doc):
    """The Connect button streams the values shown to the firmware link (dry run over loop://)."""
    from metamaterial_wb.gui.panels import hardware_available
    if not hardware_available():
        pytest.skip("metamaterial_wb.hardware is not in this checkout")
    pytest.importorskip("serial")
    import time as _time
    from metamaterial_wb.hardware import channel_map
    sc = open_fish(doc)
    p = run_panel("MM_Animate")
    assert p.connect("loop://") is True, p.error.text()
    sent = []
    p.streamer.on_frame = lambda t, angles: sent.append(dict(angles))
    p.show_time(0.3)
    shown = dict(p.shown_values)
    deadline = _time.time() + 2.0
    while len(sent) < 5 and _time.time() < deadline:
        process_events()
        _time.sleep(0.02)
    assert len(sent) >= 5, "no frames streamed"
    chans = {c.name: c for c in channel_map(structure.compose_scene(sc))}
    for name, v in shown.items():
        # the angle sent, in the whole centidegrees on the wire
        assert sent[-1][name] == pytest.approx(round(chans[name].angle_deg(v) * 100) / 100, abs=1e-9)
    stats = p.disconnect()
    assert stats.frames >= 5 and not stats.error and stats.acked == stats.frames
    assert p.connect_btn.text() == "Connect"
    p.reject()
