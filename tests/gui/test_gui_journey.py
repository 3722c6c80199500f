"""Issue 15's journey: from an empty document to an exported, saved and reopened fish, by a person's
actions only: typed fields, button clicks, clicks on default 2 mm hinges in the 3D view, slider drags
and the task dialog's OK / Close buttons. With MM_GUI_SCREENSHOTS=1 each step is saved to
docs/img/gui-journey-NN-*.png (used by docs/gui.md)."""
import json
import os

import numpy as np
import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

import FreeCADGui  # noqa: E402

from metamaterial_wb.gui import panels  # noqa: E402
from metamaterial_wb.objects import structure  # noqa: E402
from metamaterial_wb.core.live import joint_node_indices  # noqa: E402
from guihelpers import (hinge_mid, click, click_view, dialog_button, drag_slider, press_ok, process, run_panel,  # noqa: E402
                        screen_point, shown_placements, type_into, view_widget, workbench)  # noqa: F401

IMG = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))), "docs", "img")
SHOTS = os.environ.get("MM_GUI_SCREENSHOTS") == "1"


def shot(n, name):
    """The main window with the 3D view's own render pasted in (grab() does not see the GL image)."""
    if not SHOTS:
        return
    import tempfile

    from PySide import QtCore, QtGui
    process(150)
    mw = FreeCADGui.getMainWindow()
    pix = mw.grab()
    view = FreeCADGui.ActiveDocument.ActiveView
    w = view.graphicsView().viewport()
    tmp = os.path.join(tempfile.mkdtemp(), "view.png")
    view.saveImage(tmp, w.width(), w.height(), "Current")
    painter = QtGui.QPainter(pix)
    painter.drawImage(w.mapTo(mw, QtCore.QPoint(0, 0)), QtGui.QImage(tmp))
    painter.end()
    pix.save(os.path.join(IMG, f"gui-journey-{n:02d}-{name}.png"))


def hinge_point(sc, joint):
    return screen_point(hinge_mid(sc, joint))


def xyz(arr):
    return np.array([[q.Base.x, q.Base.y, q.Base.z] for q in shown_placements(arr)])


def test_empty_document_to_a_reopened_fish(tmp_path):
    FreeCADGui.activateWorkbench("MetamaterialWorkbench")
    doc = FreeCAD.newDocument("Journey")
    FreeCAD.setActiveDocument(doc.Name)
    FreeCADGui.getMainWindow().resize(1600, 1000)
    path = str(tmp_path / "fish.FCStd")
    try:
        # 1 New structure: name, 2 x 6, Grid, OK (default 2 mm hinges)
        p = run_panel("MM_NewStructure")
        type_into(p.name, "fish")
        type_into(p.rows, "2")
        type_into(p.cols, "6")
        click(p.grid_btn)
        assert "12 cells: a valid layout" in p.status.text()
        shot(1, "new-structure")
        assert press_ok()
        sc = structure.find_scene_objects(doc)[0]
        assert sc.HingeLength.Value == pytest.approx(2.0)
        FreeCADGui.SendMsgToActiveView("ViewFit")
        process(100)
        # 2 Rotary axes: click the 2 mm hinges H0,2 .. H0,5 in the 3D view
        p = run_panel("MM_RotaryAxes")
        for col in (2, 3, 4, 5):
            pt = hinge_point(sc, f"H0,{col}")
            click_view(pt)
            assert p.pick_label.text() == f"picked hinge H0,{col}", (      # the reads, should it fail
                p.pick_label.text(), (pt.x(), pt.y()), view_widget().size(), FreeCADGui.ActiveDocument.ActiveView.getSize(),
                [(q.x(), q.y()) for q in (hinge_point(sc, f"H0,{c}") for c in (col, col + 1))])
        assert [k for k, b in sorted(p.buttons.items()) if b.isChecked()] == [("vertical", c) for c in (2, 3, 4, 5)]
        shot(2, "rotary-axes")
        assert press_ok(), p.error.text()
        # 3 Folded shape: limit to printable, drag the first slider, type the others
        p = run_panel("MM_FoldedShape")
        click(p.printable)
        flat = xyz(sc.NodeArray)
        drag_slider(p.sliders[0][0], 20)
        assert np.abs(xyz(sc.NodeArray) - flat).max() > 0.05, "the view follows the slider"
        for k, deg in ((1, "2.5"), (2, "3"), (3, "3.5")):
            type_into(p.spins[k], deg)
        folds = p.folds()
        assert not p.problems, p.problems
        shot(3, "folded-shape")
        assert press_ok(), p.error.text()
        assert [a["fold_deg"] for a in json.loads(sc.SceneJSON)["axes"]] == folds
        # 4 motors: click the hinge, type the name and the profile
        for name, joint, amp, freq in (("head", "V0,1", "0.3", "0.5"), ("tail", "V1,5", "0.9", "1")):
            p = run_panel("MM_PlaceMotor")
            click_view(hinge_point(sc, joint))
            assert p.joint.currentText() == joint, p.pick_label.text()
            type_into(p.name, name)
            type_into(p.amp, amp)
            type_into(p.freq, freq)
            shot(4 if name == "head" else 5, f"place-motor-{name}")
            assert press_ok(), p.error.text()
        # 5 a servo housing on the head joint, clicked; a second one there is refused
        p = run_panel("MM_AddModule")
        p.set_type("servo_housing")
        click_view(hinge_point(sc, "V0,1"))
        assert p.target.currentText() == "V0,1"
        assert press_ok(), p.error.text()
        p = run_panel("MM_AddModule")
        p.set_type("stable_hub")
        click_view(hinge_point(sc, "V0,1"))
        assert not dialog_button("Ok").isEnabled() and "already carries" in p.problem_label("target").text()
        shot(6, "add-module-refused")
        click(dialog_button("Cancel"))
        # 6 Simulate: drag the tail slider, OK stores it
        p = run_panel("MM_Simulate")
        drag_slider(p.sliders["tail"], 600)
        assert p.values()["tail"] > 0.3 and "deg" in p.labels["tail"].text()
        shot(7, "simulate")
        assert press_ok()
        # 7 Animate: Play one second (wall clock), Pause, OK
        p = run_panel("MM_Animate")
        click(p.play_btn)
        process(1000)
        click(p.play_btn)
        assert 0.6 < p.t < 1.6 and "real-time factor" in p.rate_label.text()
        shot(8, "animate")
        assert press_ok()
        # 8 Export in the background, summary in the panel, document still active
        p = run_panel("MM_Export")
        out = str(tmp_path / "fish_export")
        type_into(p.path, out)
        click(p.export_btn)
        assert p.wait(300)
        if p.job.outcome != "done":
            assert "socket" in p.error.text() or "tilt" in p.error.text(), p.error.text()
            click(p.sockets)
            click(p.export_btn)
            assert p.wait(300)
        assert p.job.outcome == "done", p.error.text()
        assert p.jobbox.summary.text().startswith("wrote "), p.jobbox.summary.text()
        shot(9, "export")
        click(dialog_button("Close"))
        assert panels.active() is None and FreeCAD.ActiveDocument.Name == doc.Name
        names = os.listdir(out)
        assert any(n.endswith(".step") for n in names) and any(n.endswith(".3mf") for n in names)
        # 9 save, close, reopen: the same design comes back, valid
        text = structure.scene_json(sc)
        doc.saveAs(path)
        FreeCADGui.runCommand("Std_Save")
        FreeCAD.closeDocument(doc.Name)
        doc = FreeCAD.openDocument(path)
        sc2 = structure.find_scene_objects(doc)[0]
        assert sc2.isValid() and structure.scene_json(sc2) == text
        scene = structure.compose_scene(sc2)
        assert [a.name for a in scene.actuators] == ["head", "tail"] and len(scene.modules) == 1
        assert [a.fold_deg for a in scene.axes] == folds
        shot(10, "reopened")
    finally:
        if FreeCADGui.Control.activeDialog() and panels.active() is not None:
            panels.active().reject()
        for name in list(FreeCAD.listDocuments()):
            FreeCAD.closeDocument(name)
