"""Audit D: Simulate and Animate details, driven through real widgets.

1. Ctrl+Z (Std_Undo) of the structure while Animate plays / Simulate previews: the panel notices at once
   (playback stops, the preview goes, it says so), no traceback on every timer tick, no ghost sheet.
2. The Animate timeline follows the keyboard and a click on the groove, not only a drag.
3. A row with a stored steps / keyframes profile shows its fields as they are (steps: wave boxes disabled and
   saying why; keyframes: its table shown).
5. The keyframes period never follows the (not stored) timeline length; a key beyond it is said in the panel.
6. Simulate's global deformation is shown and previewed exactly (0.123, not 0.12).
"""
import json

import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

import FreeCADGui  # noqa: E402
from PySide import QtCore  # noqa: E402

from guihelpers import (click, dialog_button, doc, drag_slider, press_cancel, press_ok, process, qtest, run_panel,  # noqa: E402,F401
                        tracebacks,
                        type_into, workbench)
from test_gui_panel_details import open_example  # noqa: E402


def open_fish(doc):
    return open_example("fish")


def items(sc):
    return {i.ItemName: i for i in sc.Items}


def in_graph(p):
    lp = p.live_preview
    if lp is None:
        return False
    return FreeCADGui.ActiveDocument.ActiveView.getSceneGraph().findChild(lp.root) >= 0


# ---- 1: the structure deleted (Ctrl+Z) while the panel is open -------------------------------------------
def test_undo_while_animating_stops_playback_and_says_so(doc, tracebacks):
    open_fish(doc)
    p = run_panel("MM_Animate")
    click(p.play_btn)
    process(200)
    assert p.timer.isActive() and p.frames > 1
    FreeCADGui.runCommand("Std_Undo")          # undoes "Open example": the structure is gone
    process(100)
    assert not doc.Objects, [o.Name for o in doc.Objects]
    f0 = p.frames
    process(400)
    assert not tracebacks, tracebacks[0]
    assert not p.timer.isActive() and not p._playing and not p.play_btn.isChecked()
    assert p.frames == f0, "frames drawn for a deleted structure"
    assert p.live_preview is None, "the preview (a ghost sheet) stayed in the view"
    assert "deleted" in p.error.text() and "Cancel" in p.error.text(), p.error.text()
    # the timeline and Play do nothing more (no traceback either)
    p.timeline.setValue(700)
    click(p.play_btn)
    process(200)
    assert not tracebacks, tracebacks[0]
    assert p.frames == f0 and not p.timer.isActive()
    assert press_ok() is False and "deleted" in p.error.text()
    assert press_cancel()


def test_undo_while_simulating_says_so_at_the_next_move(doc, tracebacks):
    open_fish(doc)
    p = run_panel("MM_Simulate")
    if p.use_global.isChecked():
        click(p.use_global)
    name = list(p.sliders)[0]
    drag_slider(p.sliders[name], 300)
    assert p.live_preview is not None
    FreeCADGui.runCommand("Std_Undo")
    process(100)
    assert "deleted" in p.error.text(), p.error.text()      # at once, not only at OK
    assert p.live_preview is None
    f0 = p.frames
    drag_slider(p.sliders[name], 600)
    process(100)
    assert not tracebacks, tracebacks[0]
    assert p.frames == f0 and p.live_preview is None
    assert "deleted" in p.error.text() and "Cancel" in p.error.text(), p.error.text()
    assert press_ok() is False
    assert press_cancel()


# ---- 2: the timeline follows keys and clicks --------------------------------------------------------------
def test_timeline_follows_keys_and_a_click_on_the_groove(doc):
    open_fish(doc)
    p = run_panel("MM_Animate")
    process(50)
    dur = p.duration.value()
    f0 = p.frames
    p.timeline.setFocus()
    qtest().keyClick(p.timeline, QtCore.Qt.Key.Key_PageUp)
    process()
    v = p.timeline.value()
    assert v > 0
    assert p.t == pytest.approx(v / 1000.0 * dur), (v, p.t)
    assert p.time_label.text() == "t = %.2f s" % p.t and p.frames > f0
    t = p.t
    p.step(1)                                   # the next frame carries on from there (no snap back)
    assert p.t > t
    qtest().keyClick(p.timeline, QtCore.Qt.Key.Key_Right)
    process()
    assert p.t == pytest.approx(p.timeline.value() / 1000.0 * dur) and p.timeline.value() > v
    w = p.timeline
    v = w.value()
    qtest().mouseClick(w, QtCore.Qt.MouseButton.LeftButton, QtCore.Qt.KeyboardModifier.NoModifier,
                       QtCore.QPoint(w.width() - 5, w.height() // 2))
    process()          # a page step or a jump there, depending on the style (offscreen: maybe nothing)
    assert p.t == pytest.approx(p.timeline.value() / 1000.0 * dur), (v, p.timeline.value(), p.t)
    qtest().keyClick(p.timeline, QtCore.Qt.Key.Key_End)
    process()
    assert p.timeline.value() == 1000 and p.t == pytest.approx(dur)
    qtest().keyClick(p.timeline, QtCore.Qt.Key.Key_PageDown)
    process()
    assert p.timeline.value() < 1000 and p.t == pytest.approx(p.timeline.value() / 1000.0 * dur)
    assert press_cancel()


# ---- 3: stored steps / keyframes rows ---------------------------------------------------------------------
def test_stored_rows_show_what_they_are(doc):
    sc = open_fish(doc)
    p = run_panel("MM_Animate")
    head, tail = list(p.shapes)[:2]
    p.set_shape(tail, "keyframes")
    process()
    assert press_ok(), p.error.text()
    # steps that are no square the panel writes (a square it wrote reopens as a square: test_gui_animate_stored_square)
    doc.openTransaction("steps")
    items(sc)[head].ProfileShape = "steps"
    items(sc)[head].ProfileData = json.dumps({"times_s": [0.0, 0.5, 1.0], "values": [0.5, -0.5, 0.25],
                                              "period_s": 2.0})
    doc.commitTransaction()
    doc.recompute()
    stored = items(sc)[head].ProfileData, items(sc)[tail].ProfileData
    assert items(sc)[head].ProfileShape == "steps" and items(sc)[tail].ProfileShape == "keyframes"
    p = run_panel("MM_Animate")
    process(50)
    assert p.shapes[head].currentText() == "stored steps"
    assert not any(w.isEnabled() for w in p.spins[head]), "the stored steps row looks editable"
    tip = p.spins[head][0].toolTip()
    assert "stored" in tip and "another shape" in tip, tip
    assert p.shapes[tail].currentText() == "keyframes"
    assert p.keyframes.isVisible() and p.key_motor == tail
    assert p.keyframes.points() == [tuple(k) for k in zip(*[json.loads(stored[1])[f] for f in ("times_s", "values")])]
    assert not any(w.isEnabled() for w in p.spins[tail])
    # untouched: OK writes nothing
    n = doc.UndoCount
    assert press_ok(), p.error.text()
    assert doc.UndoCount == n and (items(sc)[head].ProfileData, items(sc)[tail].ProfileData) == stored
    # choosing a wave shape again makes the boxes editable and replaces the stored steps
    p = run_panel("MM_Animate")
    p.set_shape(head, "square")
    process()
    assert all(w.isEnabled() for w in p.spins[head])
    type_into(p.spins[head][0], "0.2")
    assert p.profiles()[head]["shape"] == "steps" and max(p.profiles()[head]["values"]) == pytest.approx(0.2)
    assert press_ok(), p.error.text()
    assert max(json.loads(items(sc)[head].ProfileData)["values"]) == pytest.approx(0.2)


# ---- 5: the keyframes period ------------------------------------------------------------------------------
def test_keyframes_period_never_follows_the_timeline_length(doc):
    sc = open_fish(doc)
    p = run_panel("MM_Animate")
    tail = list(p.shapes)[1]
    p.set_shape(tail, "keyframes")
    process()
    period = p.profiles()[tail]["period_s"]
    type_into(p.duration, "7")
    assert p.profiles()[tail]["period_s"] == period, "the not-stored length changed the stored period"
    assert press_ok(), p.error.text()
    assert json.loads(items(sc)[tail].ProfileData)["period_s"] == period
    p = run_panel("MM_Animate")
    type_into(p.duration, "7")
    assert p.profiles()[tail]["period_s"] == period
    tbl = p.keyframes.table
    type_into(tbl.cellWidget(1, 0), "9")           # a key beyond the period: it is extended, and said
    assert p.profiles()[tail]["period_s"] == pytest.approx(9.1)
    assert "beyond the period" in p.period_note.text() and "9.100" in p.period_note.text(), p.period_note.text()
    type_into(tbl.cellWidget(1, 0), "0.5")
    assert p.profiles()[tail]["period_s"] == period and "beyond" not in p.period_note.text()
    assert press_cancel()


# ---- 6: the global deformation exactly --------------------------------------------------------------------
def test_global_deformation_shown_and_previewed_exactly(doc):
    sc = open_fish(doc)
    sc.GlobalDeformation = 0.123
    sc.UseGlobal = True
    doc.recompute()
    p = run_panel("MM_Simulate")
    process(50)
    assert p.global_label.text() == "+0.123", p.global_label.text()
    assert p.global_value() == 0.123
    assert abs(p.last_frame.D).max() == pytest.approx(0.123, abs=1e-12)
    p.global_slider.setFocus()
    qtest().keyClick(p.global_slider, QtCore.Qt.Key.Key_Right)
    process()
    assert p.global_label.text() == "+0.124" and abs(p.last_frame.D).max() == pytest.approx(0.124, abs=1e-12)
    qtest().keyClick(p.global_slider, QtCore.Qt.Key.Key_Left)      # back on the stored value: kept exactly
    process()
    assert p.global_value() == 0.123
    n = doc.UndoCount
    assert press_ok(), p.error.text()
    assert sc.GlobalDeformation == 0.123 and doc.UndoCount == n
    p = run_panel("MM_Simulate")
    drag_slider(p.global_slider, 456)
    g = p.global_slider.value() / 1000.0
    assert p.global_label.text() == "%+.3f" % g and abs(p.last_frame.D).max() == pytest.approx(abs(g), abs=1e-12)
    assert press_ok(), p.error.text()
    assert sc.GlobalDeformation == pytest.approx(g, abs=1e-15)


def test_a_target_choice_after_the_structure_went_keeps_ok_refused(doc, tracebacks):
    """The deleted-structure problem shared the key "target" with Add module's own target check: choosing another
    target after Ctrl+Z cleared it and enabled OK again (review, session 28)."""
    open_fish(doc)
    p = run_panel("MM_AddModule")
    FreeCADGui.runCommand("Std_Undo")
    process(100)
    assert "deleted" in p.error.text(), p.error.text()
    p.target.setCurrentIndex(min(3, p.target.count() - 1))
    process()
    assert not tracebacks, tracebacks[0]
    assert not dialog_button("Ok").isEnabled(), "OK enabled again for a deleted structure"
    assert press_ok() is False
    assert press_cancel()


def test_a_stored_keyframes_row_shows_its_table_inside_the_form(doc, monkeypatch):
    """The row's table was shown while the panel was being built, before it was put in the form: without a parent
    Qt shows a widget as a window of its own, a flash of a separate "Keyframes" window (review, session 28)."""
    from metamaterial_wb.gui.panels import animate
    shown_as_window = []

    class Watched(animate.KeyframeTable):
        def setVisible(self, visible):
            if visible:
                shown_as_window.append(self.isWindow())
            super().setVisible(visible)
    sc = open_fish(doc)
    p = run_panel("MM_Animate")
    tail = list(p.shapes)[1]
    p.set_shape(tail, "keyframes")
    process()
    assert press_ok(), p.error.text()
    assert items(sc)[tail].ProfileShape == "keyframes"
    monkeypatch.setattr(animate, "KeyframeTable", Watched)
    shown_as_window.clear()
    p = run_panel("MM_Animate")
    assert shown_as_window and not any(shown_as_window), shown_as_window
    assert press_cancel()


def test_stored_keyframes_without_a_period_stay_played_once(doc):
    # the scene format's keyframes without period_s play once and hold the last value; editing a key wrote the
    # row's default wave period (2 s), so the motion repeated
    sc = open_fish(doc)
    p = run_panel("MM_Animate")
    tail = list(p.shapes)[1]
    assert press_cancel()
    doc.openTransaction("one-shot keyframes")
    items(sc)[tail].ProfileShape = "keyframes"
    items(sc)[tail].ProfileData = json.dumps({"times_s": [0.0, 1.0, 3.0], "values": [0.0, 0.6, -0.2]})
    doc.commitTransaction()
    doc.recompute()
    p = run_panel("MM_Animate")
    assert p.shapes[tail].currentText() == "keyframes"
    p.set_shape(tail, "keyframes")
    process()
    assert "play once" in p.period_note.text(), p.period_note.text()
    type_into(p.keyframes.table.cellWidget(1, 1), "0.7")
    prof = p.profiles()[tail]
    assert prof["values"] == [0.0, 0.7, -0.2] and "period_s" not in prof, prof
    assert press_ok(), p.error.text()
    stored = json.loads(items(sc)[tail].ProfileData)
    assert "period_s" not in stored and stored["values"] == [0.0, 0.7, -0.2], stored


@pytest.mark.parametrize("cmd", ["MM_Simulate", "MM_Animate"])
def test_a_motor_deleted_under_the_panel_is_named_and_ok_refused(doc, tracebacks, cmd):
    # Delete (or Ctrl+Z of Place motor) of a motor while the panel shows its slider / row: the panel kept it and
    # OK applied values to the motors left, as if nothing had happened
    sc = open_fish(doc)
    p = run_panel(cmd)
    gone = list(p.sliders if cmd == "MM_Simulate" else p.shapes)[1]
    doc.removeObject(items(sc)[gone].Name)
    process(100)
    text = p.problem_label("items").text()
    assert repr(gone) in text and "deleted" in text, text
    assert p.problem_label("items").isVisible()
    assert press_ok() is False
    assert not tracebacks, tracebacks[0]
    assert press_cancel()


@pytest.mark.parametrize("cmd", ["MM_Simulate", "MM_Animate"])
def test_a_deleted_motor_brought_back_by_undo_clears_the_line(doc, tracebacks, cmd):
    # the red line and the refused OK stayed until the panel was reopened, though Ctrl+Z of the Delete had
    # brought the motor back (review, session 29)
    sc = open_fish(doc)
    p = run_panel(cmd)
    gone = list(p.sliders if cmd == "MM_Simulate" else p.shapes)[1]
    doc.openTransaction("Delete")
    doc.removeObject(items(sc)[gone].Name)
    doc.commitTransaction()
    process(100)
    assert "items" in p.problems, p.problems
    doc.undo()
    process(100)
    assert gone in items(sc), sorted(items(sc))
    assert "items" not in p.problems, p.problems
    assert not p.problem_label("items").isVisible()
    assert "deleted" not in p.error.text(), p.error.text()
    assert not tracebacks, tracebacks[0]
    assert press_ok(), p.error.text()


@pytest.mark.parametrize("cmd", ["MM_Flexibility", "MM_FoldedShape"])
def test_panels_without_motor_rows_do_not_name_a_deleted_motor(doc, tracebacks, cmd):
    # Flexibility and Folded shape show no motor: the "deleted from the structure" line and a refused OK there
    # were wrong (review, session 29)
    sc = open_fish(doc)
    gone = sorted(n for n, it in items(sc).items() if getattr(it, "Kind", "") == "actuator")[0]
    p = run_panel(cmd)
    doc.removeObject(items(sc)[gone].Name)
    process(100)
    assert "items" not in p.problems, p.problems
    assert "deleted" not in p.error.text(), p.error.text()
    assert not tracebacks, tracebacks[0]
    assert press_cancel()
