"""The Export panel's folders, driven through its widgets: it writes into a folder on another file system (a
link to another drive), the scripting ``accept()`` is False when the files could not be moved in, Cancel /
an error / closing the panel leave no folder the export created, and a killed FreeCAD's staging folder is
removed by the next export (the command line's ``build`` does all of these)."""
import os
import shutil
import subprocess
import tempfile

import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

from metamaterial_wb.core import fileio  # noqa: E402
from metamaterial_wb.gui import panels  # noqa: E402
from guihelpers import (click, dialog_button, doc, press_ok, process, run_panel, type_into,  # noqa: E402,F401
                        workbench)
from test_gui_panel_details import open_example, unprintable_structure  # noqa: E402


def other_file_system(path):
    """A writable folder on another file system than ``path`` (a tmpfs such as /dev/shm), or None."""
    dev = os.stat(path).st_dev
    for cand in (os.environ.get("MM_OTHER_FS_DIR", ""), "/dev/shm", "/run/shm", "/run/user/%d" % os.getuid()):
        if cand and os.path.isdir(cand) and os.access(cand, os.W_OK | os.X_OK) and os.stat(cand).st_dev != dev:
            return cand
    return None


def dead_pid():
    child = subprocess.Popen(["/bin/sh", "-c", "exit 0"])
    child.wait()
    return child.pid


def staging_names(folder):
    return [n for n in os.listdir(folder) if n.startswith(".mm-export-")] if os.path.isdir(folder) else []


@pytest.fixture
def other_drive(tmp_path):
    """``(link, drive)``: ``tmp_path/on_the_other_drive``, a link to a fresh folder on another file system."""
    other = other_file_system(tmp_path)
    if other is None:
        pytest.skip(f"no writable folder on another file system than {tmp_path} (set MM_OTHER_FS_DIR)")
    drive = tempfile.mkdtemp(prefix="mm-gui-export-", dir=other)
    link = tmp_path / "on_the_other_drive"
    os.symlink(drive, link)
    yield link, drive
    shutil.rmtree(drive, ignore_errors=True)


def test_export_into_a_link_to_another_file_system(doc, tmp_path, other_drive):
    """The files were staged in the link's parent and then moved: '[Errno 18] Invalid cross-device link'."""
    link, drive = other_drive
    open_example("fish")
    p = run_panel("MM_Export")
    type_into(p.path, str(link))
    click(p.export_btn)
    assert p.wait(300), "export did not finish"
    assert p.job.outcome == "done" and p.error.text() == "", p.error.text()
    names = sorted(os.listdir(drive))
    assert "manifest.json" in names and any(n.endswith(".step") for n in names), names
    assert p.jobbox.summary.text().startswith(f"wrote {len(names)} file(s) to {link}"), p.jobbox.summary.text()
    assert sorted(os.listdir(tmp_path)) == ["on_the_other_drive"], "nothing staged beside the link"


def test_accept_is_false_when_the_files_cannot_be_moved_in(doc, tmp_path):
    """The child process succeeded (outcome "done"), the move was refused: accept() said True and closed."""
    open_example("fish")
    out = tmp_path / "OUT"
    (out / "fish_sheet.step").mkdir(parents=True)     # the user's folder where an output file goes
    p = run_panel("MM_Export")
    type_into(p.path, str(out))
    assert p.accept() is False
    assert panels.active() is p, "the panel stays open with the reason"
    err = p.error.text()
    assert err.startswith("not exported:") and "fish_sheet.step" in err and "not replaced" in err, err
    assert p.written == []
    assert sorted(os.listdir(out)) == ["fish_sheet.step"] and os.listdir(out / "fish_sheet.step") == []


def test_cancel_or_closing_the_panel_leaves_no_folder_the_export_made(doc, tmp_path):
    open_example("gripper")
    p = run_panel("MM_Export")
    out = tmp_path / "x" / "a" / "b" / "out"
    type_into(p.path, str(out))
    click(p.export_btn)
    assert p.job.running
    process(3000)                                      # the child is building
    click(p.jobbox.cancel_btn)
    assert p.job.outcome == "cancelled", p.error.text()
    assert os.listdir(tmp_path) == [], "Cancel left the folders the export made"
    # a folder that exists stays (it is the user's), also when the export made folders inside it
    (tmp_path / "x").mkdir()
    type_into(p.path, str(tmp_path / "x" / "a" / "out"))
    click(p.export_btn)
    process(1000)
    click(p.jobbox.cancel_btn)
    assert os.listdir(tmp_path) == ["x"] and os.listdir(tmp_path / "x") == []
    # the panel closed while the export runs
    type_into(p.path, str(out))
    click(p.export_btn)
    assert p.job.running
    click(dialog_button("Close"))
    assert panels.active() is None
    assert os.listdir(tmp_path / "x") == [], "closing the panel left the folders the export made"


def test_a_failed_export_leaves_no_folder_it_made(doc, tmp_path):
    unprintable_structure(doc)
    p = run_panel("MM_Export")
    type_into(p.path, str(tmp_path / "x" / "a" / "out"))
    click(p.export_btn)
    assert p.wait(300)
    assert p.job.outcome == "error" and "tilt" in p.error.text(), p.error.text()
    assert os.listdir(tmp_path) == [], "the failed export left the folders it made"


def test_a_killed_exports_staging_folder_is_removed_by_the_next_export(doc, tmp_path):
    """The staging folder had no process id, so nothing could tell a killed FreeCAD's one from a running one."""
    open_example("fish")
    out = tmp_path / "out"
    out.mkdir()
    (out / "mine.txt").write_text("the user's")
    pid = dead_pid()
    left = out / f".mm-export-{pid}-k9x2"               # what a FreeCAD killed during an export leaves
    (left / f".build-{pid + 1}-q").mkdir(parents=True)  # ... with its export child's folder
    (left / f".build-{pid + 1}-q" / "fish_sheet.step").write_text("partial")
    (left / ".job.json").write_text("{}")
    p = run_panel("MM_Export")
    type_into(p.path, str(out))
    click(p.export_btn)
    assert p.job.running
    staging = os.path.basename(p.staging.path)
    m = fileio._STALE_RE.match(staging)
    assert m and int(m.group(1)) == os.getpid(), f"{staging}: the sweep cannot tell whose staging folder it is"
    assert not left.exists(), "the killed export's staging folder was not removed"
    click(p.jobbox.cancel_btn)
    assert sorted(os.listdir(out)) == ["mine.txt"]


def test_sleeve_export_into_a_link_to_another_file_system_leaves_nothing_beside_it(doc, tmp_path, other_drive):
    """The Sleeve panel staged beside the folder (in its parent, with no process id) and moved the files across:
    the same cross-device failure, and a cancelled export left the folders it made. It shares the Export panel's
    staging now (``exporting.Staging``)."""
    link, drive = other_drive
    p = run_panel("MM_Sleeve")
    assert p.export(str(link)), p.error.text()
    assert p.wait_export(300), "export did not finish"
    assert sorted(os.listdir(drive)) == ["sleeve.3mf", "sleeve.step"], (os.listdir(drive), p.error.text())
    assert sorted(os.listdir(tmp_path)) == ["on_the_other_drive"], "nothing staged beside the link"
    deep = tmp_path / "x" / "a" / "b"
    assert p.export(str(deep))
    click(p.jobbox.cancel_btn)
    assert p.export_job.outcome == "cancelled"
    assert not (tmp_path / "x").exists(), "a cancelled export leaves no folder it made"
    p.reject()


def test_sleeve_export_removes_the_earlier_exports_plates_it_does_not_write(doc, tmp_path):
    """A one-plate export into a folder holding an earlier three-plate export left ``sleeve_plate1..3.3mf`` beside
    the new ``sleeve.3mf``: two sleeves' prints in one folder (the command line removes its earlier files). The
    panel removes an earlier export's plates now, and nothing else: a user's file, a link, a folder stay."""
    out = tmp_path / "exp"
    out.mkdir()
    for n in ("sleeve_plate1.3mf", "sleeve_plate2.3mf", "sleeve_plate3.3mf", "mine.txt", "sleeve_plate.3mf"):
        (out / n).write_text("earlier")
    (out / "sleeve_plate9.3mf").mkdir()
    os.symlink(str(out / "mine.txt"), str(out / "sleeve_plate4.3mf"))
    p = run_panel("MM_Sleeve")
    type_into(p.export_dir, str(out))
    click(p.export_btn)
    assert p.wait_export(300), "export did not finish"
    assert sorted(os.listdir(out)) == ["mine.txt", "sleeve.3mf", "sleeve.step", "sleeve_plate.3mf",
                                       "sleeve_plate4.3mf", "sleeve_plate9.3mf"], (os.listdir(out), p.error.text())
    assert (out / "sleeve.3mf").read_bytes()[:2] == b"PK"
    assert "removed the earlier export's sleeve_plate1.3mf, sleeve_plate2.3mf, sleeve_plate3.3mf" in p.result.text()
    p.reject()
