"""Animate in a narrow task dock (a combo view of 300 px): the panel needed 474 px on FreeCAD 1.1 (the dock grew
over the 3D view) and was cut off on 0.20; its profile table scrolled sideways (the phase and servo angle range
columns off screen) and range labels were cut ("-27.0 .. +7.3 deg" needed 102 px, got 99). Every value of the
panel must be readable and editable within the dock, at a narrow width and at a normal one."""
import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

from PySide import QtCore, QtGui  # noqa: E402

from test_gui_folded_narrow import narrow  # noqa: E402,F401  (the fixture that narrows the task dock)
from guihelpers import doc, process, press_cancel, run_panel, type_into, workbench  # noqa: E402,F401
from test_gui_panel_details import open_example  # noqa: E402


@pytest.fixture(params=[300, 600], ids=["narrow", "normal"])
def dock_width(request):
    return request.param


def _clipped(w, dock):
    """Where the widget is cut left or right by one of its parents up to the dock (a sideways scroll, the dock's
    edge), or None."""
    x0 = w.mapTo(dock, QtCore.QPoint(0, 0)).x()
    a = w.parentWidget()
    while a is not None:
        ax = a.mapTo(dock, QtCore.QPoint(0, 0)).x() if a is not dock else 0
        if x0 < ax or x0 + w.width() > ax + a.width():
            return (type(a).__name__, a.objectName(), x0, w.width(), ax, a.width())
        if a is dock:
            return None
        a = a.parentWidget()
    return ("no dock",)


def _measure(p, dock):
    from metamaterial_wb.gui.panels.folded_shape import ElidedLabel
    values = []                                      # every widget that shows or edits a value of the panel
    for name in p.shapes:
        values += [p.shapes[name], *p.spins[name], p.amp_deg[name]]
    values += [p.play_btn, p.loop, p.speed, p.duration, p.timeline, p.time_label, p.port, p.connect_btn,
               p.traj_load_btn, p.traj_seconds, p.traj_sim_btn, p.traj_off_btn, p.values_label, p.rate_label]
    cut = []
    for lab in p.form.findChildren(QtGui.QLabel):
        if not lab.isVisible() or lab.wordWrap() or not lab.text():
            continue
        if isinstance(lab, ElidedLabel):             # cut with "...", in full in its tooltip
            assert lab.toolTip() == lab.fullText()
            continue
        if lab.width() < lab.sizeHint().width():
            cut.append((lab.text(), lab.width(), lab.sizeHint().width()))
    return {"dock": dock.width(), "form": p.form.width(), "needs": p.form.minimumSizeHint().width(),
            "table": p.table.isVisible(), "cut": cut,
            "hidden": [type(w).__name__ + ":" + (w.text() if hasattr(w, "text") else "")
                       for w in values if not w.isVisible()],
            "clipped": [(type(w).__name__, w.text() if hasattr(w, "text") else "", _clipped(w, dock))
                        for w in values if w.isVisible() and _clipped(w, dock)],
            "squeezed": [(w.width(), w.minimumSizeHint().width()) for name in p.spins for w in p.spins[name]
                         if w.width() < w.minimumSizeHint().width()]}


@pytest.mark.parametrize("example", ["worm_crawl", "gripper"])
def test_animate_fits_the_dock_and_every_value_stays_editable(doc, narrow, dock_width, example):
    open_example(example)
    p = run_panel("MM_Animate")
    dock = narrow(p, dock_width)
    process(100)
    m = _measure(p, dock)
    print(f"animate at {dock_width} px:", m)
    assert dock.width() <= dock_width + 10, m                 # the dock does not grow over the 3D view
    assert p.form.width() <= dock.width(), m                  # nothing runs off the dock's right edge
    assert not m["hidden"] and not m["clipped"] and not m["cut"] and not m["squeezed"], m
    if p.table.isVisible():                                   # no sideways scroll hides a column
        assert p.table.horizontalScrollBar().maximum() == 0, m
    # every row stays editable: the last motor's amplitude is typed and followed by its angle range
    name = list(p.shapes)[-1]
    if not p.spins[name][0].isEnabled():                      # a motor without a profile: give it a sine first
        p.set_shape(name, "sine")
        process()
    before = p.amp_deg[name].text()
    type_into(p.spins[name][0], "0.35")
    process()
    assert p.spins[name][0].value() == pytest.approx(0.35)
    assert p.profiles()[name]["amplitude"] == pytest.approx(0.35)
    assert p.amp_deg[name].text() != before
    m = _measure(p, dock)
    assert not m["clipped"] and not m["cut"], m
    assert press_cancel()
