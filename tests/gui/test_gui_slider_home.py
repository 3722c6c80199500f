"""The Home key on a focused slider goes to the slider (its start), not to FreeCAD's Home shortcut (view home),
as End, the arrows and the Page keys do: the Animate timeline (docs/gui.md: arrow / Page / Home / End scrubbing)
and Simulate's sliders (the global deformation and every motor / constraint slider). Real key presses (QTest) on
the focused slider; the panel's own state (Animate's shown time, Simulate's values) must follow."""
import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

from PySide import QtCore, QtGui  # noqa: E402

from guihelpers import doc, press_ok, process, qtest, run_panel, workbench  # noqa: E402,F401


def open_example(name):
    p = run_panel("MM_OpenExample")
    p.select(name)
    assert press_ok()


def key(slider, name):
    """A real key press on the focused slider."""
    slider.setFocus()
    process(20)
    assert QtGui.QApplication.focusWidget() is slider
    qtest().keyClick(slider, getattr(QtCore.Qt.Key, name))
    process(20)


def test_home_on_the_animate_timeline_goes_to_its_start(doc):
    open_example("worm")
    p = run_panel("MM_Animate")
    s = p.timeline
    key(s, "Key_End")
    assert s.value() == s.maximum() and p.t == pytest.approx(p.duration.value())
    key(s, "Key_Left")
    assert s.value() == s.maximum() - 1
    key(s, "Key_Home")
    assert s.value() == s.minimum(), "Home did not reach the timeline (taken by a shortcut)"
    assert p.t == pytest.approx(0.0) and p.time_label.text() == "t = 0.00 s"
    key(s, "Key_End")                            # and back: the timeline still answers after Home
    assert s.value() == s.maximum()
    key(s, "Key_Home")
    assert s.value() == s.minimum()
    p.reject()


def test_home_on_simulate_sliders_goes_to_their_start(doc):
    open_example("worm")
    p = run_panel("MM_Simulate")
    if p.use_global.isChecked():
        p.use_global.setChecked(False)
    assert p.sliders, "the worm has motors"
    for name, s in p.sliders.items():            # each motor / constraint slider
        assert s.isEnabled()
        key(s, "Key_End")
        assert s.value() == s.maximum() and p.values()[name] == pytest.approx(1.0)
        key(s, "Key_Home")
        assert s.value() == s.minimum(), f"Home did not reach the slider of {name}"
        assert p.values()[name] == pytest.approx(-1.0)
    g = p.global_slider
    key(g, "Key_End")
    assert g.value() == g.maximum() and p.global_value() == pytest.approx(1.0)
    key(g, "Key_Home")
    assert g.value() == g.minimum(), "Home did not reach the global deformation slider"
    assert p.global_value() == pytest.approx(-1.0) and p.global_label.text() == "-1.000"
    p.reject()
