"""The "Fit to target" panel in the real FreeCAD GUI: background run, preview, one undoable apply, Cancel."""
import json

import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

import FreeCADGui  # noqa: E402

from metamaterial_wb.cli.solve import result_dict  # noqa: E402
from metamaterial_wb.core.models import run_model  # noqa: E402
from metamaterial_wb.core.scene import Scene  # noqa: E402
from metamaterial_wb.objects import structure  # noqa: E402
from guihelpers import doc, run_panel, workbench  # noqa: E402,F401


def _structure(doc, n=4):
    s = Scene.grid(n, n, actuators=[{"name": "old", "joint": "H0,0", "value": 0.2}])
    return structure.make_structure(doc, s)


def _planted_target(tmp_path):
    s = Scene.grid(4, 4, actuators=[{"name": "a", "joint": "H1,1", "value": 0.6},
                                    {"name": "b", "joint": "V2,3", "value": 0.5}])
    path = tmp_path / "target.json"
    path.write_text(json.dumps(result_dict(s, run_model("quadratic", s))))
    return str(path)


def _motors(sc):
    return sorted((it.Joint, round(it.Value, 6)) for it in sc.Items if it.Kind == "actuator")


def test_fit_to_target_runs_in_background_previews_and_applies_in_one_undo_step(doc, tmp_path):
    sc = _structure(doc)
    doc.recompute()
    p = run_panel("MM_FitTarget")
    p.path.setText(_planted_target(tmp_path))
    p.servos.setValue(2)
    assert p.run() is True
    assert not p.run_btn.isEnabled() and p.cancel_btn.isEnabled()     # running in the background
    assert p.wait(300)
    assert p.error.text() == "", p.error.text()
    assert set(p.result["joints"]) == {"H1,1", "V2,3"}
    assert p.result["errors"]["max_mm"] < 1e-6
    assert p.preview is not None and len(p.preview.Shape.Solids) == 25
    assert len(p.preview.ViewObject.DiffuseColor) == 25                  # one colour per node (distance)
    before = _motors(sc)
    n_undo = doc.UndoCount
    assert p.accept() is True
    assert _motors(sc) == [("H1,1", 0.6), ("V2,3", 0.5)]
    assert doc.getObject(p.__class__.__name__) is None and not [o for o in doc.Objects
                                                                if o.Label.startswith("FitTargetPreview")]
    assert doc.UndoCount == n_undo + 1
    assert sc.isValid()
    doc.undo()
    assert _motors(sc) == before == [("H0,0", 0.2)]


def test_fit_to_target_cancel_and_bad_target(doc, tmp_path):
    _structure(doc, 8)
    doc.recompute()
    p = run_panel("MM_FitTarget")
    bad = tmp_path / "bad.json"
    bad.write_text('{"nodes": [{"name": "N99,0", "position_mm": [0, 0, 0]}]}')
    p.path.setText(str(bad))
    assert p.run() is False and "N99,0" in p.error.text()
    far = tmp_path / "t.json"
    s = Scene.grid(8, 8, actuators=[{"name": "a", "joint": "H1,1", "value": 0.6},
                                    {"name": "b", "joint": "V5,3", "value": -0.5}])
    far.write_text(json.dumps(result_dict(s, run_model("quadratic", s))))
    p.path.setText(str(far))
    p.servos.setValue(3)
    assert p.run() is True
    p.cancel()
    assert p.wait(300)
    assert "cancelled" in p.error.text() and p.result is None
    assert p.accept() is False and "run the fit first" in p.error.text()
    p.reject()
    assert FreeCADGui.Control.activeDialog() is False or not FreeCADGui.Control.activeDialog()
