"""A child process that cannot start (no interpreter there) ends its job with an error naming it. Before: FreeCAD
0.20 crashed (segfault): ``ProcessJob._failed`` dropped the last reference to the QProcess while the process was
still emitting ``errorOccurred``, which deleted it under its own signal."""
import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

from guihelpers import process  # noqa: E402


def test_a_child_that_cannot_start_ends_its_job_with_an_error(monkeypatch, tmp_path):
    import gc
    import time

    from metamaterial_wb.gui.panels import jobs

    missing = str(tmp_path / "no-python-here")
    monkeypatch.setattr(jobs, "child_python", lambda: missing)
    box = jobs.JobBox()
    done, errors = [], []
    for attempt in range(3):             # again and again: nothing kept from the failed start breaks the next
        job = jobs.ProcessJob(box, done.append, errors.append)
        assert job.start("metamaterial_wb", ["--help"]) is True
        t0 = time.monotonic()
        while job.running and time.monotonic() - t0 < 30:
            process(50)
        gc.collect()
        process(50)
        assert not job.running and job.outcome == "error", (attempt, job.outcome)
        assert len(errors) == attempt + 1 and missing in errors[-1] and "cannot start" in errors[-1], errors
        assert job.proc is None and done == []
    assert not box.busy_for(jobs.ProcessJob(box, done.append))
