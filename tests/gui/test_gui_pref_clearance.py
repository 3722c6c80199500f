"""The snap-fit clearance on Edit > Preferences > Metamaterial (audit aud_gui10): a changed clearance left the
modules' old solids and Recompute did not rebuild them; the page accepted up to 2 mm, but a clearance at or above the
0.5 mm socket lip makes every module unbuildable, refused only after OK, five times, naming
fabrication.socket_lip_mm, not the preference."""
import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

import FreeCADGui  # noqa: E402
from PySide import QtCore, QtGui  # noqa: E402

from metamaterial_wb import PREFS_PATH  # noqa: E402
from metamaterial_wb.objects import structure  # noqa: E402
from guihelpers import dialog_button, doc, process, run_panel, type_into, workbench  # noqa: E402,F401
from test_gui_panel_details import open_example  # noqa: E402


@pytest.fixture
def clearance():
    prm = FreeCAD.ParamGet(PREFS_PATH)
    had = "PrinterClearance" in prm.GetFloats()
    old = prm.GetFloat("PrinterClearance")
    prm.RemFloat("PrinterClearance")
    yield prm
    if had:
        prm.SetFloat("PrinterClearance", old)
    else:
        prm.RemFloat("PrinterClearance")


def on_preferences_page(text):
    """Open Edit > Preferences > Metamaterial, type ``text`` into the clearance spin box and press OK; returns what
    the spin box showed and its maximum."""
    seen = {}

    def drive(tries=[0]):
        dlg = QtGui.QApplication.activeModalWidget()
        spin = dlg.findChild(QtGui.QDoubleSpinBox, "PrinterClearance") if dlg is not None else None
        if spin is None:
            tries[0] += 1
            if tries[0] < 100:
                QtCore.QTimer.singleShot(100, drive)
            elif dlg is not None:
                dlg.reject()
            return
        try:
            type_into(spin, text)
            seen["value"], seen["maximum"] = spin.value(), spin.maximum()
            box = dlg.findChild(QtGui.QDialogButtonBox)
            ok = getattr(QtGui.QDialogButtonBox, "Ok", None) or QtGui.QDialogButtonBox.StandardButton.Ok
            box.button(ok).click()
        finally:
            if dlg.isVisible():
                dlg.reject()
    QtCore.QTimer.singleShot(200, drive)
    FreeCADGui.showPreferences("Metamaterial", 0)
    process()
    assert "value" in seen, "the clearance spin box of the Metamaterial page was not found"
    return seen


def test_ok_on_the_page_makes_recompute_rebuild_the_modules(doc, clearance):
    sc = open_example("fish_modules")
    m = sc.Modules[0]
    v0 = m.Shape.Volume
    seen = on_preferences_page("0.4")
    assert clearance.GetFloat("PrinterClearance") == pytest.approx(0.4), seen
    assert m.Name in [o.Name for o in doc.Objects if "Touched" in o.State]   # Recompute has something to do
    FreeCADGui.runCommand("Std_Refresh")
    process()
    assert m.isValid(), m.getStatusString()
    assert abs(m.Shape.Volume - v0) > 1.0
    fresh = structure.build_module_shape(m, structure.compose_scene(sc))[0].Volume
    assert abs(m.Shape.Volume - fresh) < 1e-6 * fresh


def test_the_page_takes_the_fabrications_clearance_range(doc, clearance):
    """The page is global and scenes differ (a wider fabrication.socket_lip_mm takes a wider clearance: session 35):
    it allows the fabrication's clearance_mm range, 0-2 mm; the scene's own lip is checked by Add module and Export
    (test_a_clearance_at_the_socket_lip_is_named_before_ok, test_gui_export_upfront)."""
    open_example("fish_modules")
    seen = on_preferences_page("0.6")
    assert seen["maximum"] == pytest.approx(2.0) and seen["value"] == pytest.approx(0.6), seen
    assert clearance.GetFloat("PrinterClearance") == pytest.approx(0.6)


def test_a_clearance_at_the_socket_lip_is_named_before_ok(doc, clearance):
    sc = open_example("fish_modules")
    clearance.SetFloat("PrinterClearance", 0.6)      # a macro or the parameter editor: not limited by the page
    want = "Edit > Preferences > Metamaterial > Snap-fit clearance (mm): 0.6 mm is not below the 0.5 mm socket lip"
    p = run_panel("MM_AddModule")
    p.set_type("friction_pad")
    p.target.setCurrentText("N0,0")
    process()
    text = p.problem_label("preferences").text()
    assert want in text and "allowed range [0, 0.5) mm" in text and text.count(want) == 1, text
    assert not dialog_button("Ok").isEnabled()
    p.reject()
    p = run_panel("MM_Export")
    text = p.problem_label("preferences").text()
    assert want in text and not p.export_btn.isEnabled(), text
    p.reject()
    doc.recompute()
    bad = [m.getStatusString() for m in sc.Modules if not m.isValid()]
    assert bad and all("Snap-fit clearance (mm) (PrinterClearance): 0.6 mm" in t for t in bad), bad
