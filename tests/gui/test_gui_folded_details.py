"""Folded shape through real widgets on the fish_axes example: a slider's ends are allowed folds (with and
without "Limit to printable folds"), a stated maximum never contains a value it refuses, and Return in a fold
box (which also presses OK) stores the fold once and leaves no late signal to fail after the panel closed."""
import json
import re
import sys

import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

from PySide import QtCore  # noqa: E402

from metamaterial_wb.gui import panels  # noqa: E402
from metamaterial_wb.gui.panels import folded_shape  # noqa: E402
from guihelpers import (click, dialog_button, doc, process, qtest, run_panel,  # noqa: E402,F401
                        type_into, workbench)
from test_gui_panel_details import open_example  # noqa: E402


def folds(sc):
    return [a["fold_deg"] for a in json.loads(sc.SceneJSON)["axes"]]


def test_slider_ends_and_ranges_on_exact_multiples():
    assert folded_shape.slider_span(15.252198682394653) == 152           # 15.3 would be beyond it
    assert folded_shape.slider_span(97.6281496685807) == 976
    assert folded_shape.slider_span(15.3) == 153                         # an exact multiple keeps its step
    assert folded_shape.slider_span(0.3) == 3 and folded_shape.slider_span(0.7) == 7
    assert folded_shape.toward_zero(97.6281496685807) == pytest.approx(97.628)
    assert folded_shape.toward_zero(15.2529) == pytest.approx(15.252)
    assert folded_shape.toward_zero(0.3) == pytest.approx(0.3) and folded_shape.toward_zero(12.5) == 12.5


def _check_ends(p, k, printable):
    """Move axis ``k``'s slider to its right end: the fold it gives is within the maximum, no red text, OK enabled."""
    s = p.sliders[k][0]
    lim = p.limit_deg(k)
    # the slider's End key takes it to its right end (the combo view under xvfb leaves it too narrow to drag;
    # the left end is the same fold negated: minimum == -maximum below)
    s.setFocus()
    qtest().keyClick(s, QtCore.Qt.Key.Key_End)
    process()
    assert s.value() == s.maximum() > 0
    f = p.spins[k].value()
    lab = p.problem_label(f"axis{k}")
    assert not lab.isVisible(), lab.text()
    assert f"axis{k}" not in p.problems and abs(f) <= lim + 1e-9, (printable, k, f, lim)
    assert dialog_button("Ok").isEnabled()
    assert s.maximum() * folded_shape.STEP <= lim + 1e-9 and s.minimum() == -s.maximum()
    assert (s.maximum() + 1) * folded_shape.STEP > lim, "the slider ends on the last 0.1 deg step within the maximum"
    assert f"(slider +-{s.maximum() / 10:.1f})" in p.limit_labels[k].text(), p.limit_labels[k].text()


def test_slider_ends_are_allowed_folds(doc):
    open_example("fish_axes")
    p = run_panel("MM_FoldedShape")
    for k in (0, 3):                                   # the kinematic maximum: 97.628 deg on every axis
        _check_ends(p, k, False)
        type_into(p.spins[k], "0")                     # back within the printable maximum
    click(p.printable)
    assert p.printable.isChecked()
    pmx = p.limits[1][2]
    assert pmx is not None and p.limit_deg(1) == pmx
    for k in range(len(p.sliders)):                    # the printable maximum: 15.2522 deg; 15.3 was offered
        _check_ends(p, k, True)
    assert p.spins[1].value() > 0 and p.sliders[1][0].maximum() == folded_shape.slider_span(pmx)
    p.reject()


def _range(text):
    m = re.search(r"allowed range \[-([0-9.]+), ([0-9.]+)\] deg", text)
    assert m, text
    assert m.group(1) == m.group(2)
    return float(m.group(2))


def test_stated_maxima_exclude_the_refused_value(doc):
    open_example("fish_axes")
    p = run_panel("MM_FoldedShape")
    mx, _why, pmx = p.limits[1]
    assert 97.62 < mx < 97.63                        # 97.628...: 97.63 is beyond it
    type_into(p.spins[1], "97.63")
    assert p.spins[1].value() == pytest.approx(97.63)
    lab = p.problem_label("axis1")
    assert lab.isVisible() and "kinematic maximum" in lab.text(), lab.text()
    b = _range(lab.text())
    assert 97.63 > b and b <= mx and mx - b < 1e-3, lab.text()       # the range stated excludes the value refused
    assert not dialog_button("Ok").isEnabled()
    label = p.limit_labels[1].text()
    kin = float(re.search(r"kinematic \+-([0-9.]+) deg", label).group(1))
    pr = float(re.search(r"printable \+-([0-9.]+) deg", label).group(1))
    assert kin <= mx and mx - kin < 1e-3 and pr <= pmx and pmx - pr < 1e-3, label
    type_into(p.spins[1], f"{b:.3f}")               # the stated end is itself allowed
    assert not lab.isVisible(), lab.text()
    assert dialog_button("Ok").isEnabled()
    # the printable maximum: 15.2522 deg -> 15.253 is refused with a range that excludes it
    click(p.printable)
    type_into(p.spins[1], "15.253")
    assert lab.isVisible() and "printable maximum" in lab.text(), lab.text()
    b = _range(lab.text())
    assert 15.253 > b and b <= pmx and pmx - b < 1e-3, lab.text()
    type_into(p.spins[1], f"{b:.3f}")
    assert not lab.isVisible(), lab.text()
    p.reject()


@pytest.mark.parametrize("key", ["Key_Return", "Key_Enter"])
def test_return_in_a_fold_box_stores_once_and_nothing_fails_later(doc, capfd, key):
    sc = open_example("fish_axes")
    before = folds(sc)
    p = run_panel("MM_FoldedShape")
    errors = []
    hook = sys.excepthook

    def record(tp, value, tb):
        errors.append(f"{tp.__name__}: {value}")
        hook(tp, value, tb)

    sys.excepthook = record
    try:
        spin = p.spins[0]
        spin.setFocus()
        line = spin.lineEdit()
        line.selectAll()
        qtest().keyClicks(line, "12.5")
        qtest().keyClick(line, getattr(QtCore.Qt.Key, key))     # as a user: Return also presses the dialog's OK
        process(500)                                            # the late editingFinished and any timer run now
    finally:
        sys.excepthook = hook
    err = capfd.readouterr().err
    assert panels.active() is None, "Return did not confirm the panel"
    assert not errors, errors
    assert "Traceback" not in err and "already deleted" not in err, err[-800:]
    assert folds(sc) == [12.5] + before[1:]
    assert doc.UndoNames.count("Folded shape") == 1, doc.UndoNames
    assert p._closed and not p._preview_timer.isActive()
