"""Screenshots of the main panels for docs/gui.md (a FreeCAD macro, not a test):

    xvfb-run -a -s "-screen 0 1680x1050x24" freecad -u <copy of resources/test_user.cfg> \
        tests/gui/make_screenshots.py -M "$PWD"

Writes docs/img/gui-*.png (whole main window, 3D view plus task panel) and ends FreeCAD.
"""
import os
import sys
import traceback

from PySide import QtCore, QtGui

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
OUT = os.path.join(REPO, "docs", "img")


def settle(n=5):
    import FreeCADGui
    for _ in range(n):
        QtGui.QApplication.processEvents()
    try:
        FreeCADGui.ActiveDocument.ActiveView.redraw()
    except Exception:
        pass
    FreeCADGui.updateGui()
    for _ in range(n):
        QtGui.QApplication.processEvents()


def shot(name):
    import FreeCADGui
    settle()
    mw = FreeCADGui.getMainWindow()
    pix = QtGui.QGuiApplication.primaryScreen().grabWindow(0)   # the whole (virtual) screen
    if pix.isNull():
        pix = mw.grab()
    path = os.path.join(OUT, f"gui-{name}.png")
    pix.save(path)
    print("wrote", path, file=sys.__stdout__)


def view(iso=True):
    import FreeCADGui
    v = FreeCADGui.ActiveDocument.ActiveView
    if iso:
        v.viewIsometric()
    else:
        v.viewTop()
    v.fitAll()


def new_shots(FreeCAD, FreeCADGui, panels, structure):
    """The simulated-trajectory player (Animate) and the Sleeve actuator panel."""
    doc = FreeCAD.newDocument("worm")
    FreeCAD.setActiveDocument(doc.Name)
    structure.load_scene_file(doc, os.path.join(REPO, "examples", "worm_crawl.json"))
    doc.recompute()
    FreeCADGui.runCommand("MM_Animate")
    p = panels.active()
    p.traj_seconds.setValue(3.0)
    p.simulate_trajectory(3.0)
    p.wait_simulation(120.0)
    p.show_time(2.4)
    v = FreeCADGui.ActiveDocument.ActiveView
    v.viewIsometric()
    v.fitAll()
    shot("animate-trajectory")
    p.reject()
    FreeCAD.closeDocument(doc.Name)

    doc = FreeCAD.newDocument("sleeve")
    FreeCAD.setActiveDocument(doc.Name)
    FreeCADGui.runCommand("MM_Sleeve")
    panels.active().accept()
    FreeCADGui.runCommand("MM_Sleeve")
    p = panels.active()
    p.frame_nl.setChecked(True)            # the prediction with the 3-D frame's first peaks and sequence
    p.predict()
    p.wait_prediction(300.0)
    view(True)
    shot("sleeve")
    p.reject()
    FreeCAD.closeDocument(doc.Name)


def run():
    rc = 0
    try:
        sys.path.insert(0, REPO)
        import FreeCAD
        import FreeCADGui
        from metamaterial_wb.gui import panels
        from metamaterial_wb.objects import structure

        mw = FreeCADGui.getMainWindow()
        mw.setGeometry(0, 0, 1680, 1050)
        docks = {d.objectName() or d.windowTitle(): d for d in mw.findChildren(QtGui.QDockWidget)}
        for name, d in docks.items():
            if "Python" in name or "Report" in name:
                d.hide()
        combo = [d for n, d in docks.items() if "Combo" in n or "Tree" in n]
        if combo and hasattr(mw, "resizeDocks"):
            mw.resizeDocks(combo[:1], [460], QtCore.Qt.Horizontal)
        FreeCADGui.activateWorkbench("MetamaterialWorkbench")
        new_shots(FreeCAD, FreeCADGui, panels, structure)
        if os.environ.get("MM_SHOTS_NEW_ONLY"):
            sys.__stdout__.flush()
            os._exit(0)
        doc = FreeCAD.newDocument("fish")
        FreeCAD.setActiveDocument(doc.Name)
        FreeCADGui.runCommand("MM_NewStructure")
        p = panels.active()
        p.name.setText("fish")
        p.rows.setValue(2)
        p.cols.setValue(6)
        p.preset_grid()
        shot("new-structure")
        p.reject()

        FreeCADGui.runCommand("MM_OpenExample")
        p = panels.active()
        p.select("fish_axes" if p.list.findItems("fish_axes", QtCore.Qt.MatchExactly) else "fish")
        p.accept()
        sc = structure.find_scene_objects(doc)[-1]
        view(False)
        FreeCADGui.runCommand("MM_RotaryAxes")
        shot("rotary-axes")
        panels.active().reject()

        view(True)
        FreeCADGui.runCommand("MM_FoldedShape")
        p = panels.active()
        p.global_slider.setValue(100)
        p.preview()
        view(True)
        shot("folded-shape")
        p.reject()

        FreeCADGui.runCommand("MM_Flexibility")
        shot("flexibility")
        panels.active().reject()

        view(False)
        FreeCADGui.runCommand("MM_PlaceMotor")
        p = panels.active()
        p.joint.setCurrentText("H2,3")
        shot("place-motor")
        p.reject()

        view(True)
        FreeCADGui.runCommand("MM_Simulate")
        p = panels.active()
        p.set_value("tail", 0.9)
        p.set_value("head", -0.5)
        view(True)
        shot("simulate")
        p.reject()

        FreeCADGui.runCommand("MM_Animate")
        p = panels.active()
        p.step(20)
        view(True)
        shot("animate")
        p.reject()

        FreeCADGui.runCommand("MM_Export")
        shot("export")
        panels.active().reject()

        # modules on the moving sheet (the fish with servo housings and fin mounts)
        if panels.example_files().count("fish_modules.json"):
            FreeCADGui.runCommand("MM_OpenExample")
            p = panels.active()
            p.select("fish_modules")
            p.accept()
            for o in list(doc.Objects):
                if o.TypeId == "App::Part" and o.Label != "fish_modules" and hasattr(o, "ViewObject"):
                    o.ViewObject.Visibility = False
            FreeCADGui.runCommand("MM_Simulate")
            p = panels.active()
            p.set_value("tail", 0.9)
            p.set_value("head", 0.6)
            view(True)
            shot("modules")
            p.reject()

        ui = os.path.join(REPO, "resources", "ui", "preferences.ui")
        w = FreeCADGui.PySideUic.loadUi(ui)
        w.resize(520, 360)
        w.show()
        settle()
        w.grab().save(os.path.join(OUT, "gui-preferences.png"))
        w.close()
        FreeCAD.closeDocument(doc.Name)
    except Exception:
        traceback.print_exc(file=sys.__stderr__)
        rc = 1
    sys.__stdout__.flush()
    os._exit(rc)


QtCore.QTimer.singleShot(240 * 1000, lambda: os._exit(124))
QtCore.QTimer.singleShot(500, run)
