"""The Sleeve panel's Predict and Export share one progress box (bar, status, Cancel): one job runs at a time
(audit). Starting the other while one runs is refused with a message; before, both ran, and the end of the
first hid the bar and Cancel of the second while it still ran, and Cancel went to both."""
import os

import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

from guihelpers import click, doc, run_panel, type_into, workbench  # noqa: E402,F401


def no_staging(folder):
    return not [n for n in os.listdir(folder) if n.startswith(".sleeve-export-")]


def test_export_is_refused_while_the_prediction_runs(doc, tmp_path):
    p = run_panel("MM_Sleeve")
    assert p.predict() is True
    assert p.prediction.running
    type_into(p.export_dir, str(tmp_path / "exp"))
    click(p.export_btn)
    assert not p.export_job.running, "an export started beside the running prediction"
    assert "the prediction is still running" in p.error.text(), p.error.text()
    assert no_staging(tmp_path) and not os.path.exists(tmp_path / "exp")
    # the box belongs to the prediction: Cancel stops it, and only it
    assert p.jobbox.progress.isVisible() and p.jobbox.cancel_btn.isVisible()
    click(p.jobbox.cancel_btn)
    assert p.prediction.outcome == "cancelled" and not p.jobbox.cancel_btn.isVisible()
    # once it ended the export starts, with its own bar and Cancel
    click(p.export_btn)
    assert p.export_job.running, p.error.text()
    assert p.jobbox.progress.isVisible() and p.jobbox.cancel_btn.isVisible()
    click(p.jobbox.cancel_btn)
    assert p.export_job.outcome == "cancelled" and not p.export_job.running
    assert no_staging(tmp_path)
    p.reject()


def test_prediction_is_refused_while_the_export_runs(doc, tmp_path):
    p = run_panel("MM_Sleeve")
    type_into(p.export_dir, str(tmp_path / "exp"))
    click(p.export_btn)
    assert p.export_job.running, p.error.text()
    assert p.predict() is False
    assert not p.prediction.running, "a prediction started beside the running export"
    assert "the export is still running" in p.error.text(), p.error.text()
    assert p.predict_btn.isEnabled()
    # the export keeps its progress bar and Cancel, and Cancel stops it
    assert p.jobbox.progress.isVisible() and p.jobbox.cancel_btn.isVisible()
    click(p.jobbox.cancel_btn)
    assert p.export_job.outcome == "cancelled" and not p.export_job.running
    assert no_staging(tmp_path)
    assert p.predict() is True          # free again
    click(p.jobbox.cancel_btn)
    assert p.prediction.outcome == "cancelled"
    p.reject()


def test_a_job_box_runs_one_job_at_a_time():
    import threading

    from metamaterial_wb.gui.panels.jobs import JobBox, ThreadJob

    box = JobBox()
    gate = threading.Event()
    done = []
    a = ThreadJob(box, done.append)
    b = ThreadJob(box, done.append)
    assert a.start(lambda report: gate.wait(30) and "a") is True
    assert b.start(lambda report: "b") is False and not b.running
    assert box.job is a
    gate.set()
    assert a.wait(30) and done == ["a"]
    assert b.start(lambda report: "b") is True and b.wait(30)
    assert done == ["a", "b"] and box.job is b
