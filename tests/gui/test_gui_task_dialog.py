"""The task dialog as a user meets it on every lane (FreeCAD 1.1 shows the task view in a dock that may
sit in an overlay): the panel's form is on screen once its command ran, and ``task_buttons()`` returns the
shown dialog's own OK / Cancel box, never another visible or stale button box of the main window."""
import time

import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

import FreeCADGui  # noqa: E402
from PySide import QtCore, QtGui  # noqa: E402

from metamaterial_wb.gui import panels  # noqa: E402
from metamaterial_wb.gui.panels.base import task_buttons  # noqa: E402
from guihelpers import click, doc, press_cancel, press_ok, process, run_panel, workbench  # noqa: E402,F401

SB = QtGui.QDialogButtonBox.StandardButton


def shiboken():
    try:
        import shiboken6 as shb
    except ImportError:
        import shiboken2 as shb
    return shb


def decoys(form):
    """Visible OK / Cancel boxes elsewhere in the main window: in every other dock and on the window."""
    mw = FreeCADGui.getMainWindow()
    out = []
    docks = [d.widget() for d in mw.findChildren(QtGui.QDockWidget) if d.widget() is not None]
    for host in [w for w in docks if not w.isAncestorOf(form)] + [mw]:
        box = QtGui.QDialogButtonBox(SB.Ok | SB.Cancel, host)
        box.show()
        out.append(box)
    return out


def count_work(monkeypatch):
    """Count, until ``monkeypatch.undo()``, every ``findChildren`` walk (of any widget), every event processing
    and every ``time.sleep``: the cost of a call, independent of the machine's speed."""
    work = {"findChildren": 0, "processEvents": 0, "sleep": 0}

    def counted(key, fn):
        def wrapper(*a, **k):
            work[key] += 1
            return fn(*a, **k)
        return wrapper

    monkeypatch.setattr(QtCore.QObject, "findChildren", counted("findChildren", QtCore.QObject.findChildren))
    monkeypatch.setattr(QtCore.QCoreApplication, "processEvents",
                        staticmethod(counted("processEvents", QtCore.QCoreApplication.processEvents)))
    monkeypatch.setattr(time, "sleep", counted("sleep", time.sleep))
    return work


def test_the_panel_is_on_screen_and_its_own_buttons_are_found(doc):
    p = run_panel("MM_NewStructure")
    process(50)
    assert p.form.isVisible(), "the task panel's form is not on screen"
    box = task_buttons()
    assert box is not None and not box.isHidden() and box.button(SB.Ok).isVisible()
    fakes = decoys(p.form)
    try:
        process()
        assert task_buttons() is box, "a button box outside the task dialog was returned"
        assert task_buttons(p) is box
        assert press_ok(), p.error.text()          # press_ok clicks task_buttons()'s OK: it is the panel's
    finally:
        for f in fakes:
            f.setParent(None)
            f.deleteLater()
    assert task_buttons() is None, "no panel is shown: no box"


def test_after_a_closed_dialog_the_new_dialogs_box_is_returned(doc, monkeypatch):
    first = run_panel("MM_NewStructure")
    old = task_buttons()
    assert press_cancel()
    second = run_panel("MM_NewStructure")
    assert second is not first
    box = task_buttons()
    assert box is not None and not box.isHidden()
    assert second.form.isVisible()
    # the box belongs to the task view that holds the second panel's form
    views = [w for w in FreeCADGui.getMainWindow().findChildren(QtGui.QWidget)
             if w.metaObject().className() == "Gui::TaskView::TaskView" and w.isAncestorOf(second.form)]
    assert views and views[-1].isAncestorOf(box), "the returned box is not in the second dialog's task view"
    # task_buttons() runs on every field change (update_ok): it stays a constant number of walks of the main
    # window (no walk per widget), without event processing or sleeping - counted, not timed
    work = count_work(monkeypatch)
    assert all(task_buttons() is box for _ in range(10))
    monkeypatch.undo()
    assert 10 <= work["findChildren"] <= 2 * 10, f"task_buttons() is called on every field change: {work}"
    assert work["processEvents"] == 0 and work["sleep"] == 0, f"task_buttons() is called on every field change: {work}"
    assert old is box or not shiboken().isValid(old) or old.isHidden(), "a stale box is still shown"
    click(box.button(SB.Cancel))
    assert panels.active() is None and not FreeCADGui.Control.activeDialog()


def test_button_row_puts_the_buttons_side_by_side():
    from metamaterial_wb.gui.panels.base import button_row
    row, buttons = button_row("Add key", "Remove last")
    assert [b.text() for b in buttons] == ["Add key", "Remove last"]
    assert isinstance(row, QtGui.QHBoxLayout) and row.count() == 2
    assert [row.itemAt(k).widget() for k in range(2)] == buttons
