"""Simulate, Fit to target, Sleeve, Place motor and Rotary axes in a narrow task dock (the combo view, ~300 px), as
Folded shape, Export, New structure and Flexibility already fit it: the dock keeps its width (FreeCAD 1.1 grew it to
the panel's width and squeezed the 3D view), the panel's content needs no horizontal scrolling (FreeCAD 0.20 cut it
off at the right), every widget lies within the task view, no label or button is cut (long names are elided with the
full name in their tooltip, long texts wrap), and every slider keeps a width a hand can drag (SLIDER_MIN_WIDTH).
Also the Tab order of Sleeve (the cell-type table's t / h boxes where the table is, not after the export button) and
the name of Simulate's "global deformation" check box."""
import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

from PySide import QtCore, QtGui  # noqa: E402

from metamaterial_wb.gui.panels.folded_shape import SLIDER_MIN_WIDTH  # noqa: E402
from guihelpers import doc, narrowing, process, run_panel, scroll_of, tab_chain, workbench  # noqa: E402,F401
from test_gui_panel_details import open_example  # noqa: E402

DOCK_WIDTH = 300
SLACK = 40                 # px the dock may end up off DOCK_WIDTH (FreeCAD's own minimum of the task view, splitters)

PANELS = [("MM_Simulate", "fish_axes"), ("MM_FitTarget", "fish"), ("MM_Sleeve", None), ("MM_PlaceMotor", "fish"),
          ("MM_RotaryAxes", "fish")]








@pytest.fixture
def narrow():
    """Ask for a DOCK_WIDTH px task dock; put it back after. Returns the dock: its width is what FreeCAD made of
    the request (a panel wider than it makes it grow; the tests measure by how much)."""
    yield from narrowing(DOCK_WIDTH, SLACK, require=False)


def _inside_inner_view(w, form):
    """True for the parts of a compound widget that clip its own content (a table's cells, a spin box's editor)."""
    q = w.parentWidget()
    while q is not None and q is not form:
        if isinstance(q, (QtGui.QAbstractScrollArea, QtGui.QAbstractSpinBox, QtGui.QComboBox)):
            return True
        q = q.parentWidget()
    return False


def _name(w):
    text = w.text() if hasattr(w, "text") and callable(w.text) else ""
    return f"{type(w).__name__}({text[:40]!r})" if text else type(w).__name__


def _elided(lab):
    return bool(lab.toolTip()) and lab.text().endswith("\u2026")


def measure(p, dock):
    form = p.form
    scroll = scroll_of(form)
    assert scroll is not None, "the panel is not in a scroll area"
    vp = scroll.viewport()
    out, cut, small, scrolled = [], [], [], []
    for w in form.findChildren(QtGui.QWidget):
        if not w.isVisible() or _inside_inner_view(w, form):
            continue
        x0 = w.mapTo(vp, QtCore.QPoint(0, 0)).x()
        if x0 < -1 or x0 + w.width() > vp.width() + 1:
            out.append((_name(w), x0, x0 + w.width()))
        if isinstance(w, QtGui.QLabel) and w.text() and not w.wordWrap() and not _elided(w) \
                and w.width() < w.sizeHint().width():
            cut.append((_name(w), w.width(), w.sizeHint().width()))
        if isinstance(w, QtGui.QPushButton) and w.text() \
                and w.width() < w.fontMetrics().boundingRect(w.text()).width() + 6:     # its text in full
            cut.append((_name(w), w.width(), w.fontMetrics().boundingRect(w.text()).width()))
        if isinstance(w, (QtGui.QCheckBox, QtGui.QAbstractSpinBox, QtGui.QComboBox)) \
                and w.width() < w.minimumSizeHint().width():
            cut.append((_name(w), w.width(), w.minimumSizeHint().width()))
        if isinstance(w, QtGui.QSlider) and w.width() < SLIDER_MIN_WIDTH:
            small.append((_name(w), w.width()))
        if isinstance(w, QtGui.QAbstractScrollArea) and w.horizontalScrollBar().maximum() > 0:
            scrolled.append((_name(w), w.horizontalScrollBar().maximum()))
    return {"dock": dock.width(), "viewport": vp.width(), "form": form.width(),
            "form_min": form.minimumSizeHint().width(), "hscroll": scroll.horizontalScrollBar().maximum(),
            "outside": out, "cut": cut, "small_sliders": small, "inner_hscroll": scrolled}


def _open(cmd, example):
    if example:
        open_example(example)
    return run_panel(cmd)


@pytest.mark.parametrize("cmd, example", PANELS, ids=[c for c, _e in PANELS])
def test_the_panel_fits_a_narrow_task_dock(doc, narrow, cmd, example):
    p = _open(cmd, example)
    dock = narrow(p)
    m = measure(p, dock)
    print(cmd, "in a narrow dock:", m)
    assert dock.width() <= DOCK_WIDTH + SLACK, m                   # the dock kept its width (1.1 grew it)
    assert m["hscroll"] == 0 and m["form"] <= m["viewport"], m       # no horizontal scrolling (0.20 cut it off)
    assert not m["outside"], m                                       # every widget within the task view
    assert not m["cut"], m                                           # every text and value shown in full
    assert not m["small_sliders"], m                                 # sliders a hand can drag
    assert not m["inner_hscroll"], m                                 # the sleeve's t / h boxes in full
    if cmd == "MM_Simulate":
        assert len(p.sliders) >= 2
    p.reject()




def _is(w, target):
    return w is target or (w is not None and target.isAncestorOf(w))


def test_sleeve_tab_visits_the_cell_type_boxes_where_the_table_is(doc):
    p = run_panel("MM_Sleeve")
    rows = p.types.rowCount()
    assert rows >= 2
    boxes = [p.types.cellWidget(r, c) for r in range(rows) for c in range(2)]
    chain = tab_chain(p.name, 40)
    names = [_name(w) if w is not None else None for w in chain]

    def where(target):
        return next((k for k, w in enumerate(chain) if _is(w, target)), None)

    at = [where(b) for b in boxes]
    assert None not in at, ("every t / h box is reached by Tab", at, names)
    assert at == sorted(at) and at[-1] - at[0] == len(boxes) - 1, ("t0, h0, t1, h1, ... in a row", at, names)
    export = where(p.export_btn)
    ring = where(p.ring)
    assert ring is not None and at[-1] < ring, ("the boxes come before the ring pattern below the table", at, names)
    assert export is None or at[-1] < export, names
    # a type added by the button is reached where it is shown too
    p.add_type(1.0, 7.0)
    process()
    chain = tab_chain(p.name, 40)
    names = [_name(w) if w is not None else None for w in chain]
    new = [where(p.types.cellWidget(rows, c)) for c in range(2)]
    ring = where(p.ring)
    assert None not in new and new[1] < ring, (new, ring, names)
    p.reject()


def test_simulate_global_check_box_has_a_name(doc):
    open_example("fish")
    p = run_panel("MM_Simulate")
    cb = p.use_global
    assert cb.text().strip() or cb.accessibleName().strip(), "the check box has no text or name"
    assert "global" in (cb.text() + " " + cb.accessibleName()).lower(), (cb.text(), cb.accessibleName())
    p.reject()
