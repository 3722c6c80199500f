"""Folded shape: a slider at its end with a fold beyond it (typed beyond the maximum, or "Limit to printable folds"
ticked after a large fold) answers the keys and the mouse as a person expects. End / Home, the arrows, PageUp /
PageDown pushing toward that end, a click at its end or a drag of its handle to the end put the fold on the slider's
end (the largest fold it offers): the red line goes and OK stores that fold. A key away from the end steps from the
slider's end. A fold nobody acted on keeps its value (ticking the box, focusing the slider, another axis's slider),
and an allowed fold typed past the slider's last 0.1 deg step is never pulled back by a push toward that end."""
import json

import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

from PySide import QtCore, QtGui  # noqa: E402

from metamaterial_wb.gui.panels import folded_shape  # noqa: E402
from guihelpers import (click, dialog_button, doc, process, press_ok, qtest, run_panel,  # noqa: E402,F401
                        type_into, workbench)
from guihelpers import _slider_geometry  # noqa: E402
from test_gui_panel_details import open_example  # noqa: E402

K = 2                         # the axis driven (fish_axes: printable maximum 15.2522 deg, slider end 15.2)
STEP = folded_shape.STEP


def _folds(sc):
    return [a["fold_deg"] for a in json.loads(sc.SceneJSON)["axes"]]


def _beyond(sign):
    """Open Folded shape on fish_axes, type sign * 40 deg on axis K (allowed kinematically), tick "Limit to printable
    folds": the fold is kept and refused in red, its slider sits at its end. Returns (scene, panel, slider, label)."""
    sc = open_example("fish_axes")
    p = run_panel("MM_FoldedShape")
    type_into(p.spins[K], f"{40 * sign}")
    assert f"axis{K}" not in p.problems
    click(p.printable)
    assert p.printable.isChecked()
    s = p.sliders[K][0]
    lab = p.problem_label(f"axis{K}")
    assert p.spins[K].value() == pytest.approx(40.0 * sign)            # ticking the box changed no fold
    assert lab.isVisible() and "printable maximum" in lab.text(), lab.text()
    assert s.value() == (s.maximum() if sign > 0 else s.minimum())
    assert not dialog_button("Ok").isEnabled()
    return sc, p, s, lab


def _end(s, sign):
    return (s.maximum() if sign > 0 else s.minimum()) * STEP


def _key(s, name):
    s.setFocus()
    process()
    qtest().keyClick(s, getattr(QtCore.Qt.Key, name))
    process()


def _accepted_at_end(sc, p, s, lab, sign):
    """The fold is the slider's end, the red line is gone, OK stores that fold and no other."""
    end = _end(s, sign)
    assert p.spins[K].value() == pytest.approx(end, abs=1e-9), (p.spins[K].value(), end)
    assert abs(end) <= p.limit_deg(K) and abs(end) > 15.0
    assert not lab.isVisible(), lab.text()
    assert f"axis{K}" not in p.problems
    assert dialog_button("Ok").isEnabled()
    before = _folds(sc)
    assert press_ok()
    after = _folds(sc)
    assert after[K] == pytest.approx(end, abs=1e-9), (before, after)
    assert after[:K] + after[K + 1:] == before[:K] + before[K + 1:]


@pytest.mark.parametrize("key,sign", [("Key_End", 1), ("Key_Right", 1), ("Key_Up", 1), ("Key_PageUp", 1),
                                      ("Key_Home", -1), ("Key_Left", -1), ("Key_Down", -1), ("Key_PageDown", -1)])
def test_a_key_toward_the_end_puts_a_fold_beyond_it_on_the_slider_end(doc, key, sign):
    sc, p, s, lab = _beyond(sign)
    _key(s, key)
    _accepted_at_end(sc, p, s, lab, sign)


def test_a_key_away_from_the_end_steps_from_the_slider_end(doc):
    _sc, p, s, lab = _beyond(1)
    _key(s, "Key_Left")                                                 # one step below the slider's end
    assert s.value() == s.maximum() - 1
    assert p.spins[K].value() == pytest.approx((s.maximum() - 1) * STEP)
    assert not lab.isVisible() and dialog_button("Ok").isEnabled()
    type_into(p.spins[K], "40")
    assert lab.isVisible()
    _key(s, "Key_Home")                                                 # to the other end
    assert p.spins[K].value() == pytest.approx(s.minimum() * STEP)
    assert not lab.isVisible() and dialog_button("Ok").isEnabled()
    p.reject()


def _press_move_release(s, points):
    t = qtest()
    left, none = QtCore.Qt.MouseButton.LeftButton, QtCore.Qt.KeyboardModifier.NoModifier
    t.mousePress(s, left, none, points[0])
    process()
    for pt in points[1:]:
        ev = QtGui.QMouseEvent(QtCore.QEvent.Type.MouseMove, QtCore.QPointF(pt), QtCore.QPointF(s.mapToGlobal(pt)),
                               left, left, none)
        QtGui.QApplication.sendEvent(s, ev)
        process()
    t.mouseRelease(s, left, none, points[-1])
    process()


@pytest.mark.parametrize("sign", [1, -1])
def test_dragging_the_handle_to_the_end_puts_the_fold_there(doc, sign):
    sc, p, s, lab = _beyond(sign)
    process(100)                                                        # the layout settles (the slider's width)
    handle, _groove = _slider_geometry(s)
    c = handle.center()
    out = s.width() + 30 if sign > 0 else -30                           # pulled on past the slider's end
    _press_move_release(s, [c] + [QtCore.QPoint(c.x() + (out - c.x()) * i // 4, c.y()) for i in range(1, 5)])
    _accepted_at_end(sc, p, s, lab, sign)


@pytest.mark.parametrize("sign", [1, -1])
def test_a_click_at_the_slider_end_puts_the_fold_there(doc, sign):
    sc, p, s, lab = _beyond(sign)
    process(100)
    handle, groove = _slider_geometry(s)
    x = groove.right() - 1 if sign > 0 else groove.left() + 1
    qtest().mouseClick(s, QtCore.Qt.MouseButton.LeftButton, QtCore.Qt.KeyboardModifier.NoModifier,
                       QtCore.QPoint(x, handle.center().y()))
    process()
    _accepted_at_end(sc, p, s, lab, sign)


def test_a_fold_nobody_acted_on_keeps_its_value(doc):
    sc, p, s, lab = _beyond(1)
    # Tab from the fold box into its slider (focus only), keys on another axis's slider, the box toggled twice
    p.spins[K].setFocus()
    process()
    qtest().keyClick(p.spins[K], QtCore.Qt.Key.Key_Tab)
    process()
    other = p.sliders[K + 1][0]
    _key(other, "Key_End")
    _key(other, "Key_Home")
    assert p.spins[K + 1].value() == pytest.approx(other.minimum() * STEP)
    click(p.printable)
    click(p.printable)
    assert p.printable.isChecked()
    assert p.spins[K].value() == pytest.approx(40.0)
    assert s.value() == s.maximum() and lab.isVisible()
    assert not dialog_button("Ok").isEnabled()
    p.reject()


def test_a_fold_short_of_the_end_goes_to_it_and_an_allowed_fold_past_it_is_kept(doc):
    open_example("fish_axes")
    p = run_panel("MM_FoldedShape")
    click(p.printable)
    s = p.sliders[K][0]
    lab = p.problem_label(f"axis{K}")
    end = s.maximum() * STEP                                            # 15.2; the printable maximum is 15.2522
    assert p.limit_deg(K) - end > 0.04
    for key in ("Key_End", "Key_Right", "Key_PageUp"):
        type_into(p.spins[K], f"{end - 0.04:.3f}")                     # the slider shows it at its end
        assert s.value() == s.maximum()
        _key(s, key)
        assert p.spins[K].value() == pytest.approx(end), key            # End goes to the end, not short of it
    for key in ("Key_End", "Key_Right", "Key_PageUp"):
        type_into(p.spins[K], f"{end + 0.04:.3f}")                     # allowed, past the slider's last step
        assert not lab.isVisible() and s.value() == s.maximum()
        _key(s, key)
        assert p.spins[K].value() == pytest.approx(end + 0.04), key     # never pulled back by a push forward
        assert not lab.isVisible() and dialog_button("Ok").isEnabled()
    p.reject()
