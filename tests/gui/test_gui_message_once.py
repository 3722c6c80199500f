"""The two document-watch messages of an open task panel are said once (GUI audit, session 34).

An Undo / Redo that moves the panel's structure away from the values it shows (``UndoWatch.check_stale``) and a
motor deleted under Simulate / Animate (``BasePanel.check_items``) were each said twice: in the red line put at the
top of the panel and again, word for word, in the panel's error line at the bottom. The top line stays (a preview
clears the error line, the top one stays visible until its cause is gone); the error line no longer repeats it.
OK stays disabled and refused while the line stands (the OK button, Enter), and the line still says why."""
import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

from PySide import QtCore, QtGui  # noqa: E402

from metamaterial_wb.gui.panels import base  # noqa: E402

from guihelpers import (dialog_button, doc, press_cancel, press_ok, process, qtest, run_panel,  # noqa: E402,F401
                        tracebacks, type_into, workbench)
from test_gui_panel_details import open_example  # noqa: E402
from test_gui_undo_stale import ctrl_z, item, redo  # noqa: E402


def shown(p, text):
    """The panel's visible text widgets (labels, text boxes) that hold ``text``."""
    out = [w for w in p.form.findChildren(QtGui.QLabel) if w.isVisible() and text in w.text()]
    for cls in (QtGui.QTextEdit, QtGui.QPlainTextEdit):
        out += [w for w in p.form.findChildren(cls) if w.isVisible() and text in w.toPlainText()]
    return out


def said_once_at_top(p, key, words):
    """The panel's ``key`` line holds ``words`` and is the one visible widget that says it; it sits above the
    panel's error line; OK is disabled and refused, and the line still says why afterwards."""
    lab = p.problem_label(key)
    text = lab.text()
    assert all(w in text for w in words), text
    labs = shown(p, text)
    assert len(labs) == 1, [w.text() if isinstance(w, QtGui.QLabel) else w.toPlainText() for w in labs]
    assert labs[0] is lab and lab is not p.error
    assert p.layout.indexOf(lab) < p.layout.indexOf(p.error), (p.layout.indexOf(lab), p.layout.indexOf(p.error))
    assert not dialog_button("Ok").isEnabled(), "OK enabled while the panel's line stands"
    assert press_ok() is False
    qtest().keyClick(p.form, QtCore.Qt.Key.Key_Return)       # Enter, the task dialog's OK key: refused too
    process()
    assert base.ACTIVE is p, "Enter applied a panel whose line stands"
    assert lab.isVisible() and lab.text() == text
    assert len(shown(p, text)) == 1, [w.text() for w in shown(p, text)]
    return text


def each_said_once(p):
    """Every problem the panel knows of is said by one visible widget (two lines at once: neither repeated)."""
    for key, text in p.problems.items():
        assert len(shown(p, text)) == 1, (key, [w.text() for w in shown(p, text)])


@pytest.mark.parametrize("cmd", ["MM_Simulate", "MM_Animate"])
def test_the_stale_line_after_ctrl_z_is_said_once(doc, tracebacks, cmd):
    sc = open_example("fish")
    tail = item(sc, "tail")
    p = run_panel("MM_Simulate")
    p.set_value("tail", -0.5)
    process()
    assert press_ok()
    p = run_panel(cmd)
    ctrl_z()                                     # real Ctrl+Z in the 3D view: the panel is older than the document
    assert tail.Value == 0.8
    text = said_once_at_top(p, "stale", ["Undo / Redo", "Cancel"])
    redo()                                       # back where the panel opened it: the line goes, nothing repeats it
    assert tail.Value == -0.5
    assert "stale" not in p.problems, p.problems
    assert not shown(p, text), [w.text() for w in shown(p, text)]
    assert dialog_button("Ok").isEnabled()
    assert not tracebacks, tracebacks[0]
    assert press_cancel()


@pytest.mark.parametrize("cmd", ["MM_Simulate", "MM_Animate"])
def test_a_motor_taken_away_by_ctrl_z_of_place_motor_is_named_once(doc, tracebacks, cmd):
    sc = open_example("fish")
    p = run_panel("MM_PlaceMotor")
    p.joint.setCurrentText("H0,3")                 # a free joint
    type_into(p.name, "once_motor")
    process()
    assert press_ok(), p.error.text()
    p = run_panel(cmd)
    ctrl_z()                                       # the Place motor goes under the open panel
    assert "once_motor" not in {i.ItemName for i in sc.Items}
    assert "stale" in p.problems, p.problems     # Ctrl+Z changed the panel's structure too: two lines at the top
    each_said_once(p)
    text = said_once_at_top(p, "items", ["'once_motor'", "deleted"])
    each_said_once(p)
    redo()                                         # it comes back: the line goes
    assert "items" not in p.problems, p.problems
    assert not shown(p, text), [w.text() for w in shown(p, text)]
    assert not tracebacks, tracebacks[0]
    assert press_ok(), p.error.text()


@pytest.mark.parametrize("cmd", ["MM_Simulate", "MM_Animate"])
def test_a_deleted_motor_is_named_once(doc, tracebacks, cmd):
    sc = open_example("fish")
    p = run_panel(cmd)
    gone = list(p.sliders if cmd == "MM_Simulate" else p.shapes)[1]
    doc.openTransaction("Delete")
    doc.removeObject(item(sc, gone).Name)
    doc.commitTransaction()
    process(100)
    said_once_at_top(p, "items", [repr(gone), "deleted"])
    assert not tracebacks, tracebacks[0]
    assert press_cancel()
