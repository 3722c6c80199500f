"""FreeCAD GUI macro (run under xvfb by test_export.py): import a STEP with the GUI importer (OCCT
XCAF, reads colours) and dump every body's colour; optionally save a picture. Environment: STEP,
OUT (json), PNG (optional). Ends FreeCAD with os._exit (rc 0 = ok)."""
import json
import os
import sys
import traceback

from PySide import QtCore


def run():
    rc = 1
    try:
        import FreeCAD
        import FreeCADGui
        import ImportGui
        doc = FreeCAD.newDocument("colours")
        ImportGui.insert(os.environ["STEP"], doc.Name, merge=False, useLinkGroup=False)
        out = {}
        for o in doc.Objects:
            if o.TypeId == "Part::Feature":
                vo = o.ViewObject
                cols = [list(c)[:3] for c in vo.DiffuseColor] or [list(vo.ShapeColor)[:3]]
                out[o.Label] = cols[0]
        with open(os.environ["OUT"], "w") as f:
            json.dump(out, f)
        if os.environ.get("PNG"):
            view = FreeCADGui.getDocument(doc.Name).ActiveView
            view.viewIsometric()
            view.fitAll()
            for _ in range(int(os.environ.get("ZOOM_IN", "0"))):
                view.zoomIn()
            view.saveImage(os.environ["PNG"], int(os.environ.get("PNG_W", 1000)), int(os.environ.get("PNG_H", 650)),
                           "White")
        rc = 0
    except Exception:
        traceback.print_exc()
    finally:
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(rc)


QtCore.QTimer.singleShot(240000, lambda: os._exit(124))
QtCore.QTimer.singleShot(0, run)
