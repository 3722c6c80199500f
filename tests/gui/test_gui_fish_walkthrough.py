"""The seed's walkthrough (section 4) done the FreeCAD way: from an empty document to an animated,
exportable fish using only the workbench's commands and panels (no scripting of the model)."""
import json
import os

import numpy as np
import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

import FreeCADGui  # noqa: E402
from PySide import QtGui  # noqa: E402

from metamaterial_wb.core import design, kinematics  # noqa: E402
from metamaterial_wb.core.motion import scene_values_at  # noqa: E402
from metamaterial_wb.core.solver import solve_scene  # noqa: E402
from metamaterial_wb.gui import panels  # noqa: E402
from metamaterial_wb.objects import structure  # noqa: E402
from guihelpers import shown_placements  # noqa: E402


def panel(cmd):
    FreeCADGui.runCommand(cmd)
    QtGui.QApplication.processEvents()
    assert panels.active() is not None, cmd
    return panels.active()


def xyz(arr):
    return np.array([[q.Base.x, q.Base.y, q.Base.z] for q in shown_placements(arr)])


def core_pos(scene, values):
    sc = scene.copy()
    for k, v in values.items():
        sc.set_value(k, v)
    D, _m, _w, _t = solve_scene(sc)
    return kinematics.node_poses(sc, D, kin=design.kinematics_for(sc))[0]


def test_fish_from_an_empty_document(tmp_path):
    FreeCADGui.activateWorkbench("MetamaterialWorkbench")
    doc = FreeCAD.newDocument("FishWalkthrough")
    FreeCAD.setActiveDocument(doc.Name)
    try:
        undo0 = doc.UndoCount
        # (1) lay out the 2 x 6 grid
        p = panel("MM_NewStructure")
        p.name.setText("fish")
        p.rows.setValue(2)
        p.cols.setValue(6)
        p.preset_grid()
        assert p.accept() is True
        sc = structure.find_scene_objects(doc)[0]
        assert sc.NodeCount == 21
        # (2) rotary axes: the fish's skeleton, columns 2..5
        p = panel("MM_RotaryAxes")
        for line in (2, 3, 4, 5):
            p.set_axis("vertical", line)
        assert p.violations.text() == ""
        assert p.accept() is True
        # (3) flexibility: 3 mm hinges (k shown live); longer hinges need less tilt for a fold, which keeps
        # the bending hinges printable beside the snap-fit sockets
        p = panel("MM_Flexibility")
        p.length.setValue(3.0)
        assert "k1 =" in p.k_label.text()
        assert p.accept() is True, p.error.text()
        # (4) folded shape: one slider per axis, Confirm runs the joint configuration
        p = panel("MM_FoldedShape")
        assert len(p.sliders) == 4
        for k, deg in enumerate((2, 3, 4, 5)):
            p.set_fold(k, deg)
        assert p.accept() is True, p.error.text()
        data = json.loads(sc.SceneJSON)
        assert [a["fold_deg"] for a in data["axes"]] == [2.0, 3.0, 4.0, 5.0]
        assert data.get("joint_config"), "the joint configuration was not stored"
        # (5) motors: head and tail with their sine profiles
        for name, joint, amp, freq, phase in (("head", "V0,1", 0.3, 0.5, 0.0), ("tail", "V1,5", 0.9, 1.0, 90.0)):
            p = panel("MM_PlaceMotor")
            p.name.setText(name)
            p.joint.setCurrentText(joint)
            p.amp.setValue(amp)
            p.freq.setValue(freq)
            p.phase.setValue(phase)
            assert p.accept() is True, p.error.text()
        # (6) a servo housing on the head motor's joint
        p = panel("MM_AddModule")
        p.set_type("servo_housing")
        p.target.setCurrentText("V0,1")
        assert p.accept() is True
        assert doc.UndoCount == undo0 + 7, "every step is one undo transaction"
        scene = structure.compose_scene(sc)
        assert [a.name for a in scene.actuators] == ["head", "tail"]
        # (7) simulate: the tail slider bends the sheet as the core solver says
        p = panel("MM_Simulate")
        p.set_value("tail", 0.8)
        QtGui.QApplication.processEvents()
        np.testing.assert_allclose(xyz(sc.NodeArray), core_pos(scene, {"tail": 0.8}), atol=1e-6)
        p.reject()
        # (8) animate: frames follow the profiles
        p = panel("MM_Animate")
        p.step(15)
        np.testing.assert_allclose(xyz(sc.NodeArray), core_pos(scene, scene_values_at(scene, p.t)), atol=1e-6)
        p.reject()
        # (9) export
        p = panel("MM_Export")
        out = str(tmp_path / "fish_out")
        p.path.setText(out)
        if not p.accept():
            # strongly tilted bending hinges may not fit beside the snap-fit sockets: the panel says so,
            # writes nothing, and the user exports without sockets
            assert "socket" in p.error.text(), p.error.text()
            assert not os.path.exists(out) or not [n for n in os.listdir(out) if not n.startswith(".")]
            p.sockets.setChecked(False)
            assert p.accept() is True, p.error.text()
        names = sorted(os.listdir(out))
        assert any(n.endswith(".step") for n in names) and any(n.endswith(".3mf") for n in names), names
        # (10) save and reopen: the configured, animated design comes back
        path = str(tmp_path / "fish.FCStd")
        text = sc.SceneJSON
        doc.saveAs(path)
        FreeCAD.closeDocument(doc.Name)
        doc = FreeCAD.openDocument(path)
        sc2 = structure.find_scene_objects(doc)[0]
        assert sc2.SceneJSON == text
    finally:
        if FreeCADGui.Control.activeDialog() and panels.active() is not None:
            panels.active().reject()
        FreeCAD.closeDocument(doc.Name)
