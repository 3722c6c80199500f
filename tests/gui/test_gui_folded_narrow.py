"""Folded shape in a narrow task dock (the combo view at its usual width, 320 px) with four axes
(fish_axes): every slider keeps a usable width, no label is cut, and a slider can be dragged with the mouse
to change the fold (also with "Limit to printable folds", where a fold beyond the printable maximum is shown
as it is, refused in red, and never clamped by the slider)."""
import json

import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

from PySide import QtCore, QtGui  # noqa: E402

from metamaterial_wb.gui.panels import folded_shape  # noqa: E402
from guihelpers import (click, dialog_button, doc, drag_slider, narrowing, process, press_ok, qtest,  # noqa: E402,F401
                        run_panel, type_into, workbench)
from test_gui_panel_details import open_example  # noqa: E402

DOCK_WIDTH = 320
MIN_SLIDER = 120






@pytest.fixture
def narrow():
    """Make the task dock (the combo view / task view dock holding the panel) DOCK_WIDTH px wide; put it back."""
    yield from narrowing(DOCK_WIDTH)


def _measure(p, dock):
    return {"dock": dock.width(), "form": p.form.width(),
            "sliders": [s.width() for s, _mx in p.sliders], "global": p.global_slider.width(),
            "spins": [(sp.width(), sp.sizeHint().width()) for sp in p.spins],
            "cut": [(lab.text(), lab.width(), lab.sizeHint().width())
                    for lab in p.form.findChildren(QtGui.QLabel)
                    if lab.isVisible() and not lab.wordWrap() and lab.text()
                    and lab.width() < lab.sizeHint().width()]}


def _folds(sc):
    return [a["fold_deg"] for a in json.loads(sc.SceneJSON)["axes"]]


def test_sliders_keep_a_usable_width_in_a_narrow_dock(doc, narrow):
    open_example("fish_axes")
    p = run_panel("MM_FoldedShape")
    assert len(p.sliders) >= 4
    dock = narrow(p)
    m = _measure(p, dock)
    print("narrow folded shape:", m)
    assert p.form.width() <= dock.width(), m                            # nothing runs off the dock's right edge
    assert min(m["sliders"]) >= MIN_SLIDER and m["global"] >= MIN_SLIDER, m
    assert not m["cut"], m
    for sp in p.spins:                                                  # the value is readable in full
        assert sp.width() >= sp.minimumSizeHint().width(), m
    p.reject()


def test_a_slider_is_dragged_by_the_mouse_in_a_narrow_dock(doc, narrow):
    sc = open_example("fish_axes")
    before = _folds(sc)
    p = run_panel("MM_FoldedShape")
    dock = narrow(p)
    s = p.sliders[2][0]
    assert s.width() >= MIN_SLIDER, _measure(p, dock)
    target = s.value() + (200 if s.value() < 0 else -200)              # 20 deg further along
    drag_slider(s, target)
    assert abs(s.value() - target) <= 15, (s.value(), target, s.width())   # within 1.5 deg of where it was let go
    assert p.spins[2].value() == pytest.approx(s.value() * folded_shape.STEP)
    assert "axis2" not in p.problems
    expect = round(p.spins[2].value(), 6)
    assert press_ok()
    after = _folds(sc)
    assert after[2] == pytest.approx(expect) and after[2] != before[2], (before, after)
    assert after[:2] + after[3:] == before[:2] + before[3:]


def test_printable_limit_beyond_fold_is_shown_not_clamped_and_drag_brings_it_back(doc, narrow):
    sc = open_example("fish_axes")
    p = run_panel("MM_FoldedShape")
    dock = narrow(p)
    k = 2
    type_into(p.spins[k], "40")                                         # within the kinematic, beyond the printable max
    assert "axis%d" % k not in p.problems
    click(p.printable)
    assert p.printable.isChecked()
    pmx = p.limit_deg(k)
    assert pmx < 40
    s = p.sliders[k][0]
    lab = p.problem_label(f"axis{k}")
    # the fold is kept as typed and refused in red; the slider sits at its end and says it is pinned there
    assert p.spins[k].value() == pytest.approx(40.0)
    assert lab.isVisible() and "printable maximum" in lab.text(), lab.text()
    assert s.value() == s.maximum()
    assert not dialog_button("Ok").isEnabled()
    assert not press_ok()
    assert _folds(sc)[k] != pytest.approx(40.0)
    # dragging the slider (it is wide enough) brings the fold back within the printable maximum
    assert s.width() >= MIN_SLIDER, _measure(p, dock)
    drag_slider(s, s.maximum() // 2)
    assert abs(s.value() - s.maximum() // 2) <= 15, (s.value(), s.maximum(), s.width())
    assert p.spins[k].value() == pytest.approx(s.value() * folded_shape.STEP)
    assert not lab.isVisible(), lab.text()
    assert dialog_button("Ok").isEnabled()
    p.reject()


def test_tab_follows_the_lines_fold_box_then_its_slider(doc):
    """Each axis shows its fold box above its slider: Tab from the box goes to that axis's slider, then to the next
    axis's box (not up and down the panel)."""
    open_example("fish_axes")
    p = run_panel("MM_FoldedShape")
    app = QtGui.QApplication.instance()
    order = []
    p.spins[0].setFocus()
    process()
    w = app.focusWidget()
    for _ in range(4):
        qtest().keyClick(w, QtCore.Qt.Key.Key_Tab)
        process()
        w = app.focusWidget()
        order.append(w)
    slider0, spin1 = p.sliders[0][0], p.spins[1]
    assert order[0] is slider0, [type(x).__name__ for x in order]
    assert order[1] is spin1 or (order[1] is not None and order[1].parentWidget() is spin1), \
        [type(x).__name__ for x in order]
    p.reject()
