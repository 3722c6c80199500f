"""Undo / Redo of the document while a task panel is open (audit aud_gui10, session 33).

A panel copies the stored state when it opens. Ctrl+Z in the 3D view under it put the document back, but the
panel kept showing the undone values, and its OK (even an untouched one) wrote them again: a new undo step, the
redo list cleared (Simulate wrote the undone tail value, Folded shape deleted the axis Ctrl+Z had brought back,
Animate wrote the undone amplitude). The panel now says so and refuses OK until the document is back where the
panel opened it (``BasePanel.undo_moved``); its own preview, its own OK (also a failed one) and Undo of objects it
does not edit leave it usable. An untouched OK after Ctrl+Z records no step (it recorded the recompute
Ctrl+Z had left, which emptied the redo list)."""
import json

import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

import FreeCADGui  # noqa: E402
from PySide import QtCore  # noqa: E402

from metamaterial_wb.core.errors import MetamaterialError  # noqa: E402
from metamaterial_wb.gui.panels import base  # noqa: E402
from guihelpers import (click, dialog_button, doc, drag_slider, press_cancel, press_ok, process, qtest,  # noqa: E402,F401
                        run_panel, tracebacks, type_into, view_widget, workbench)
from test_gui_panel_details import open_example  # noqa: E402


def ctrl_z():
    """A real Ctrl+Z in the 3D view (Std_Undo's shortcut)."""
    w = view_widget()
    w.setFocus()
    process()
    qtest().keyClick(w, QtCore.Qt.Key.Key_Z, QtCore.Qt.KeyboardModifier.ControlModifier)
    process(200)


def redo():
    FreeCADGui.runCommand("Std_Redo")        # Ctrl+Shift+Z on Linux with 1.1, Ctrl+Y elsewhere
    process(200)


def item(sc, name):
    return [it for it in sc.Items if it.ItemName == name][0]


def axes(sc):
    return [a["line"] for a in json.loads(sc.SceneJSON)["axes"]]


def assert_stale(p):
    """The panel says why, once, at its top (its error line does not repeat it), and OK is disabled and refused."""
    lab = p.problem_label("stale")
    assert "Undo / Redo" in lab.text() and "Cancel" in lab.text(), (lab.text(), p.problems)
    assert lab.isVisible()
    assert "Undo / Redo" not in p.error.text(), p.error.text()
    assert not dialog_button("Ok").isEnabled(), "OK enabled on a panel older than the document"
    assert press_ok() is False


def assert_usable(p):
    assert "stale" not in p.problems, p.problems
    assert not p.problem_label("stale").isVisible()
    assert "Undo / Redo" not in p.error.text(), p.error.text()
    assert dialog_button("Ok").isEnabled()


# ---- the audit's three cases: Ctrl+Z under the open panel, then OK ------------------------------------------
def test_simulate_refuses_ok_after_ctrl_z_and_cancel_keeps_the_undone_state(doc, tracebacks):
    sc = open_example("fish")
    tail = item(sc, "tail")
    p = run_panel("MM_Simulate")
    p.set_value("tail", -0.5)
    process()
    assert press_ok()
    assert tail.Value == -0.5
    p = run_panel("MM_Simulate")                 # open it again, touch nothing
    assert_usable(p)
    ctrl_z()
    assert tail.Value == 0.8 and "Simulate" in doc.RedoNames, (tail.Value, doc.RedoNames)
    assert p.values()["tail"] == -0.5            # the panel's copy: older than the document
    assert_stale(p)
    assert tail.Value == 0.8, "an untouched OK wrote the value the user had just undone"
    assert "Simulate" in doc.RedoNames and "Simulate" not in doc.UndoNames, (doc.UndoNames, doc.RedoNames)
    assert press_cancel()
    assert tail.Value == 0.8 and "Simulate" in doc.RedoNames
    assert not tracebacks, tracebacks[0]


def test_folded_shape_after_ctrl_z_of_rotary_axes_never_drops_the_axis_again(doc, tracebacks):
    sc = open_example("fish_axes")
    p = run_panel("MM_RotaryAxes")
    p.set_axis("vertical", 5, on=False)
    assert press_ok()
    assert axes(sc) == [2, 3, 4]
    p = run_panel("MM_FoldedShape")
    assert len(p.spins) == 3
    ctrl_z()                                     # the axis on line 5 comes back
    assert axes(sc) == [2, 3, 4, 5]
    assert_stale(p)
    type_into(p.spins[0], "4")                   # a fold edit does not make OK usable again
    assert_stale(p)
    assert axes(sc) == [2, 3, 4, 5], "OK removed the axis the user had just brought back with Ctrl+Z"
    assert press_cancel()
    assert not tracebacks, tracebacks[0]


def test_animate_refuses_an_untouched_ok_after_ctrl_z(doc, tracebacks):
    sc = open_example("fish")
    head = item(sc, "head")
    p = run_panel("MM_Animate")
    type_into(p.spins["head"][0], "0.5")
    assert press_ok()
    assert head.Amplitude == 0.5
    p = run_panel("MM_Animate")
    ctrl_z()
    assert head.Amplitude == 0.3
    assert_stale(p)
    assert head.Amplitude == 0.3, "an untouched OK wrote the amplitude the user had just undone"
    assert press_cancel()
    assert not tracebacks, tracebacks[0]


# ---- Redo: newer than the panel; back where the panel opened: usable again --------------------------------
def test_redo_under_the_panel_makes_it_stale_and_undo_back_clears_it(doc, tracebacks):
    sc = open_example("fish")
    tail = item(sc, "tail")
    p = run_panel("MM_Simulate")
    p.set_value("tail", -0.5)
    assert press_ok()
    ctrl_z()
    assert tail.Value == 0.8
    p = run_panel("MM_Simulate")                 # opened on the undone state
    redo()
    assert tail.Value == -0.5
    assert_stale(p)
    assert tail.Value == -0.5 and "Simulate" in doc.UndoNames
    ctrl_z()                                     # the document is back where the panel opened it
    assert tail.Value == 0.8
    assert_usable(p)
    n = doc.UndoCount
    assert press_ok()                            # untouched: writes nothing, the redo list stays
    assert tail.Value == 0.8 and doc.UndoCount == n and "Simulate" in doc.RedoNames
    assert not tracebacks, tracebacks[0]


def test_ctrl_z_then_redo_back_leaves_the_panel_usable(doc, tracebacks):
    sc = open_example("fish")
    head = item(sc, "head")
    p = run_panel("MM_Animate")
    type_into(p.spins["head"][0], "0.5")
    assert press_ok()
    p = run_panel("MM_Animate")
    ctrl_z()
    assert_stale(p)
    redo()
    assert head.Amplitude == 0.5
    assert_usable(p)
    type_into(p.spins["head"][0], "0.25")
    assert press_ok(), p.error.text()
    assert head.Amplitude == 0.25
    assert not tracebacks, tracebacks[0]


def test_a_new_step_after_ctrl_z_keeps_the_panel_stale(doc, tracebacks):
    # after Ctrl+Z, another tool's new undo step drops the redo list: the panel's state cannot come back
    sc = open_example("fish")
    tail = item(sc, "tail")
    p = run_panel("MM_Simulate")
    p.set_value("tail", -0.5)
    assert press_ok()
    p = run_panel("MM_Simulate")
    ctrl_z()
    assert_stale(p)
    doc.openTransaction("Box")
    doc.addObject("Part::Box", "Box")
    doc.commitTransaction()
    process(100)
    assert not doc.RedoNames
    ctrl_z()                                     # undoes the box: the document is still not the panel's
    assert tail.Value == 0.8
    assert_stale(p)
    assert press_cancel()
    assert not tracebacks, tracebacks[0]


@pytest.mark.parametrize("cmd", ["MM_Simulate", "MM_Animate"])
def test_an_untouched_ok_opened_after_ctrl_z_records_nothing_and_keeps_the_redo_list(doc, tracebacks, cmd):
    # Ctrl+Z leaves the structure's objects to recompute: the OK's recompute was recorded as a new undo step
    # (nothing the user changed), which also emptied the redo list
    sc = open_example("fish")
    tail = item(sc, "tail")
    p = run_panel("MM_Simulate")
    p.set_value("tail", -0.5)
    assert press_ok()
    ctrl_z()
    assert tail.Value == 0.8 and list(doc.RedoNames) == ["Simulate"]
    p = run_panel(cmd)                           # opened on the undone state: usable
    assert_usable(p)
    undo = list(doc.UndoNames)
    assert press_ok(), p.error.text()
    assert list(doc.UndoNames) == undo and list(doc.RedoNames) == ["Simulate"], (doc.UndoNames, doc.RedoNames)
    assert tail.Value == 0.8 and sc.isValid()
    redo()                                       # the redo list still works
    assert tail.Value == -0.5
    assert not tracebacks, tracebacks[0]


# ---- no false alarm ---------------------------------------------------------------------------------------
def test_own_preview_and_ok_and_undo_of_other_objects_keep_the_panel_usable(doc, tracebacks):
    sc = open_example("fish")
    tail = item(sc, "tail")
    doc.openTransaction("Box")
    doc.addObject("Part::Box", "Box")            # an object the panel does not edit
    doc.commitTransaction()
    doc.recompute()
    p = run_panel("MM_Simulate")
    if p.use_global.isChecked():
        click(p.use_global)
    drag_slider(p.sliders["tail"], -400)         # the panel's own preview
    process(100)
    assert p.live_preview is not None
    assert_usable(p)
    ctrl_z()                                     # Undo of the box: not the panel's structure
    assert doc.getObject("Box") is None and tail.Value == 0.8
    assert_usable(p)
    assert press_ok(), p.error.text()
    assert tail.Value == pytest.approx(-0.4, abs=0.02)
    # an untouched OK, no Undo: nothing written, no undo step
    p = run_panel("MM_Simulate")
    n, v = doc.UndoCount, tail.Value
    assert_usable(p)
    assert press_ok()
    assert doc.UndoCount == n and tail.Value == v
    assert not tracebacks, tracebacks[0]


def test_a_failed_ok_rolled_back_by_the_panel_keeps_it_usable(doc, tracebacks, monkeypatch):
    # the panel's own OK aborts its transaction when the recompute leaves an object invalid: the rollback is
    # the panel's own, no Undo under it
    sc = open_example("fish")
    head = item(sc, "head")
    p = run_panel("MM_Animate")
    type_into(p.spins["head"][0], "0.5")
    real = base.recompute_checked
    calls = []

    def failing(d):
        calls.append(d.Name)
        raise MetamaterialError("Scene: invalid (test)")
    monkeypatch.setattr(base, "recompute_checked", failing)
    n = doc.UndoCount
    assert press_ok() is False
    assert calls and "invalid (test)" in p.error.text(), p.error.text()
    assert head.Amplitude == 0.3 and doc.UndoCount == n          # rolled back
    monkeypatch.setattr(base, "recompute_checked", real)
    assert "stale" not in p.problems, p.problems
    assert dialog_button("Ok").isEnabled()
    assert press_ok(), p.error.text()
    assert head.Amplitude == 0.5 and doc.UndoCount == n + 1
    assert not tracebacks, tracebacks[0]


def test_export_reads_the_structure_when_it_runs_and_stays_usable(doc, tracebacks):
    sc = open_example("fish")
    p = run_panel("MM_Simulate")
    p.set_value("tail", -0.5)
    assert press_ok()
    p = run_panel("MM_Export")
    ctrl_z()
    assert item(sc, "tail").Value == 0.8
    assert "stale" not in p.problems, p.problems
    assert p.export_btn.isEnabled()
    assert not tracebacks, tracebacks[0]
