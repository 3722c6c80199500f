"""The Sleeve panel's prediction is never shown as current for values it was not computed from (an audit on
FreeCAD 1.0, session 34): after Predict, typing T = 2.5 and Rings = 2 left "sleeve (1 x 4 cells): peaks ..." on
screen as if it were the new sleeve's, and ``summary`` kept; a prediction finishing after an edit showed the old
spec's figures as current.

Now an edit keeps the last prediction greyed under a line saying it is for the earlier values, ``summary`` is None
(typing the values back makes it current again; the name is no input of the prediction); a prediction that ends
after an edit is shown the same way, for the values it ran on. Export writes the spec the fields describe, never
the prediction's."""
import json
import os
import threading

import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

import metamaterial_wb  # noqa: E402
from guihelpers import click, doc, process, run_panel, tracebacks, type_into, workbench  # noqa: E402,F401

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(metamaterial_wb.__file__)))
EARLIER = "prediction for the earlier values"


def coarse_panel(tmp_path):
    p = run_panel("MM_Sleeve")
    with open(os.path.join(ROOT, "examples", "sleeve.json"), encoding="utf-8") as f:
        spec = json.load(f)
    spec["model"] = {"elements_cell": 6, "elements_ring": 6, "steps": 60}      # coarse: keeps the test short
    path = tmp_path / "coarse.json"
    path.write_text(json.dumps(spec), encoding="utf-8")
    assert p.load_spec(str(path)) is True
    return p, spec


def predict_with_button(p):
    click(p.predict_btn)
    assert p.wait_prediction(300.0)
    assert not p.error.text(), p.error.text()


def ring_line(text):
    return [ln for ln in text.splitlines() if ln.startswith("sleeve (")]


def test_an_edit_marks_the_prediction_as_for_the_earlier_values(doc, tmp_path, tracebacks):
    from metamaterial_wb.core.sleeve.pipeline import analyse
    from metamaterial_wb.core.sleeve.spec import SleeveSpec

    p, spec = coarse_panel(tmp_path)
    predict_with_button(p)
    first = p.summary
    assert first is not None and ring_line(p.result.text())[0].startswith("sleeve (1 x 4 cells)")
    shown = p.result.text()
    assert EARLIER not in shown and "gray" not in p.result.styleSheet()
    # the name is no input of the prediction: it stays current
    type_into(p.name, "renamed")
    assert p.summary is first and p.result.text() == shown
    # T and Rings typed: the figures stay, greyed, under a line saying they are for the earlier values
    type_into(p.dims["T_mm"], "2.5")
    type_into(p.rings, "2")
    assert p.spec_dict()["T_mm"] == 2.5 and p.spec_dict()["rings"] == 2
    text = p.result.text()
    assert p.summary is None
    assert text.splitlines()[0].startswith(EARLIER), text
    assert "Predict" in text.splitlines()[0]
    assert ring_line(text) == ring_line(shown)          # the earlier figures, still readable
    assert "gray" in p.result.styleSheet()
    # typed back: the prediction is current again
    type_into(p.dims["T_mm"], f"{spec['T_mm']:g}")
    type_into(p.rings, "1")
    assert p.summary is first and p.result.text() == shown and "gray" not in p.result.styleSheet()
    # a new prediction for the new values replaces it, for them
    type_into(p.dims["T_mm"], "2.5")
    type_into(p.rings, "2")
    predict_with_button(p)
    assert p.summary is not None and EARLIER not in p.result.text()
    assert ring_line(p.result.text())[0].startswith("sleeve (2 x 4 cells)"), p.result.text()
    ref, _ = analyse(SleeveSpec(p.spec_dict()))
    assert p.summary["ring"]["peaks"] == pytest.approx(ref["ring"]["peaks"])
    assert not tracebacks, tracebacks[-1]
    p.reject()


def test_a_prediction_ending_after_an_edit_is_shown_for_its_own_values(doc, tmp_path, tracebacks, monkeypatch):
    from metamaterial_wb.core.sleeve import pipeline

    p, spec = coarse_panel(tmp_path)
    gate, ran_on = threading.Event(), []
    real = pipeline.analyse

    def held(s, **k):               # the prediction waits until the test has edited the fields
        ran_on.append((s.T, s.M))
        assert gate.wait(60.0)
        return real(s, **k)
    monkeypatch.setattr(pipeline, "analyse", held)
    click(p.predict_btn)
    assert p.prediction.running
    type_into(p.dims["T_mm"], "2.5")
    assert p.prediction.running, "the prediction ended before the edit: the test would be empty"
    assert "edited since" in p.result.text(), p.result.text()
    gate.set()
    assert p.wait_prediction(300.0)
    assert not p.error.text(), p.error.text()
    assert ran_on == [(spec["T_mm"], 1)]
    text = p.result.text()
    assert p.summary is None and text.splitlines()[0].startswith(EARLIER), text
    assert p.predicted[1]["ring"]["rings"] == 1
    # typed back to the values it ran on: current
    type_into(p.dims["T_mm"], f"{spec['T_mm']:g}")
    assert p.summary is p.predicted[1] and EARLIER not in p.result.text()
    assert not tracebacks, tracebacks[-1]
    p.reject()


def test_export_writes_the_fields_spec_not_the_predictions(doc, tmp_path, monkeypatch):
    """Export takes the spec the fields describe (a stale prediction plays no part): the job file it writes."""
    p, spec = coarse_panel(tmp_path)
    predict_with_button(p)
    type_into(p.dims["T_mm"], "2.5")
    assert p.summary is None
    jobs = []
    monkeypatch.setattr(p.export_job, "start", lambda module, args, text=None: jobs.append(args) or True)
    type_into(p.export_dir, str(tmp_path / "exp"))
    click(p.export_btn)
    assert jobs, p.error.text()
    with open(jobs[0][0], encoding="utf-8") as f:
        job = json.load(f)
    assert job["spec"]["T_mm"] == 2.5 and job["spec"]["rings"] == 1
    p._drop_staging(created=True)
    p.reject()
