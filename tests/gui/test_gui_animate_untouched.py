"""Animate: an OK that changes nothing writes nothing, also for motors without a motion profile (the gripper's
motors: ProfileShape 'none'). OK rewrote each of them as a sine of amplitude 0 (Amplitude 0.5 -> 0.0), added an
undo step "Animate: motion profiles" and marked the saved document modified. Such a row shows "none" and keeps
the motor as it is until the user edits that row."""
import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

import FreeCADGui  # noqa: E402

from guihelpers import doc, press_ok, process, qtest, run_panel, type_into, workbench  # noqa: E402,F401
from test_gui_panel_details import open_example  # noqa: E402


def motors(sc):
    return [it for it in sc.Items if it.Kind == "actuator"]


def _value(v):
    """A property's value to compare: its repr, or the public fields of an object shown by address (a material)."""
    r = repr(v)
    if " at 0x" not in r:
        return r
    fields = {}
    for k in dir(v):
        if not k.startswith("_"):
            try:
                x = getattr(v, k)
            except Exception:  # noqa: BLE001 - a field that cannot be read is left out
                continue
            r = repr(x)
            if not callable(x) and " at 0x" not in r:
                fields[k] = r
    return type(v).__name__, fields


def motor_properties(sc):
    """Every property of every motor (the shape by its bounding box and volume)."""
    out = {}
    for it in motors(sc):
        props = {}
        for name in it.PropertiesList:
            v = getattr(it, name)
            if name == "Shape":
                v = (repr(v.BoundBox), round(v.Volume, 9) if not v.isNull() else None)
            props[name] = _value(v)
        out[it.Name] = props
    return out


def saved_gripper(doc, tmp_path):
    sc = open_example("gripper")
    assert any(m.ProfileShape == "none" for m in motors(sc)), [m.ProfileShape for m in motors(sc)]
    doc.saveAs(str(tmp_path / "gripper.FCStd"))      # names the file; Std_Save then saves as the user does
    FreeCADGui.runCommand("Std_Save")
    process(50)
    gd = FreeCADGui.getDocument(doc.Name)
    assert not gd.Modified
    return sc, gd


def test_untouched_ok_keeps_motors_without_a_profile(doc, tmp_path):
    sc, gd = saved_gripper(doc, tmp_path)
    before = motor_properties(sc)
    undo0 = list(doc.UndoNames)
    p = run_panel("MM_Animate")
    for m in motors(sc):
        if m.ProfileShape == "none":                  # the row says so, its wave boxes do not apply
            combo = p.shapes[m.ItemName]
            assert combo.currentText() == "none", combo.currentText()
            assert not any(w.isEnabled() for w in p.spins[m.ItemName])
    assert press_ok()
    process(50)
    after = motor_properties(sc)
    changed = {n: {k: (before[n][k], after[n][k]) for k in before[n] if before[n][k] != after[n][k]} for n in before}
    assert not any(changed.values()), changed
    assert list(doc.UndoNames) == undo0, doc.UndoNames
    assert not gd.Modified, "an untouched OK marked the saved document modified"


def test_a_motor_without_a_profile_gets_one_when_its_row_is_edited(doc, tmp_path):
    sc, gd = saved_gripper(doc, tmp_path)
    none = [m for m in motors(sc) if m.ProfileShape == "none"]
    first, rest = none[0], none[1:]
    before = motor_properties(sc)
    p = run_panel("MM_Animate")
    p.set_shape(first.ItemName, "sine")
    process()
    amp, freq, _phase = p.spins[first.ItemName]
    assert amp.isEnabled() and freq.isEnabled()
    if amp.isVisible():
        type_into(amp, "0.25")
    else:
        amp.setValue(0.25)
    process()
    f = freq.value()
    assert press_ok(), p.error.text()
    process(50)
    assert first.ProfileShape == "sine" and first.Amplitude == pytest.approx(0.25)
    assert first.FrequencyHz == pytest.approx(f)
    after = motor_properties(sc)
    for m in rest:                                    # the rows not edited keep their motors as they were
        assert after[m.Name] == before[m.Name], m.Name
    assert doc.UndoNames[0] == "Animate: motion profiles", doc.UndoNames
