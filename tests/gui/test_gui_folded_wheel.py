"""Folded shape: the mouse wheel on a slider at its end with a fold beyond it (typed beyond the maximum, then "Limit to
printable folds" ticked). A wheel turn pushing toward that end puts the fold on the slider's end (the largest fold it
offers): the red line goes and OK stores that fold. The slider cannot move further, so it emitted no valueChanged and
the fold, its red line and the refused OK stayed (session 32 handled it with the keys and the clicks; no test turned
the wheel). A turn away from the end steps the fold from the slider's end."""
import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

from PySide import QtCore, QtGui  # noqa: E402

from guihelpers import dialog_button, doc, process, workbench  # noqa: E402,F401
from test_gui_folded_keys import K, STEP, _accepted_at_end, _beyond  # noqa: E402


def wheel(s, notches):
    """A real wheel turn over the middle of slider ``s``: ``notches`` clicks of a mouse wheel (15 deg each, 120 in
    Qt's units), positive away from the user (a horizontal slider's value goes up)."""
    process(100)                                                       # the layout settles (the slider's width)
    pos = QtCore.QPointF(s.width() / 2.0, s.height() / 2.0)
    ev = QtGui.QWheelEvent(pos, QtCore.QPointF(s.mapToGlobal(pos.toPoint())), QtCore.QPoint(0, 0),
                           QtCore.QPoint(0, 120 * notches), QtCore.Qt.MouseButton.NoButton,
                           QtCore.Qt.KeyboardModifier.NoModifier, QtCore.Qt.ScrollPhase.NoScrollPhase, False)
    QtGui.QApplication.sendEvent(s, ev)
    process()


@pytest.mark.parametrize("sign", [1, -1])
def test_a_wheel_turn_toward_the_end_puts_a_fold_beyond_it_on_the_slider_end(doc, sign):
    sc, p, s, lab = _beyond(sign)
    wheel(s, sign)
    assert s.value() == (s.maximum() if sign > 0 else s.minimum())      # (the slider could not move)
    _accepted_at_end(sc, p, s, lab, sign)


def test_a_wheel_turn_away_from_the_end_steps_from_the_slider_end(doc):
    _sc, p, s, lab = _beyond(1)
    wheel(s, -1)
    assert s.minimum() < s.value() < s.maximum(), (s.minimum(), s.value(), s.maximum())
    assert p.spins[K].value() == pytest.approx(s.value() * STEP)        # the fold follows the slider, from its end
    assert not lab.isVisible() and dialog_button("Ok").isEnabled()
    p.reject()
