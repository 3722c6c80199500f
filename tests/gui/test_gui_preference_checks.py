"""A material or servo typed on the Preferences page that the fabrication does not know is shown in the Export and
Add module panels before anything runs, naming the preference (audit, session 28): the page takes free text, and
the error came after OK (Add module, whose panel has no servo field) or from the background export, naming no
preference."""
import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

from metamaterial_wb.gui import preferences  # noqa: E402
from guihelpers import dialog_button, doc, run_panel, workbench  # noqa: E402,F401
from test_gui_panel_details import open_example  # noqa: E402


@pytest.fixture
def stored():
    """Set preferences for one test; the earlier values (or none) come back afterwards."""
    grp = FreeCAD.ParamGet(preferences.PATH)
    before = {k: (grp.GetString(k) if k in grp.GetStrings() else None) for k in ("RigidMaterial", "DefaultServo")}

    def put(key, value):
        grp.SetString(key, value)
    yield put
    for k, v in before.items():
        if v is None:
            grp.RemString(k)
        else:
            grp.SetString(k, v)


def test_an_unknown_material_is_shown_in_the_export_panel(doc, stored):
    open_example("fish")
    stored("RigidMaterial", "Wood")
    p = run_panel("MM_Export")
    text = p.problem_label("preferences").text()
    assert "Preferences > Metamaterial > Rigid material (nodes): 'Wood' is not a known material" in text, text
    assert "PLA" in text and not p.export_btn.isEnabled()
    stored("RigidMaterial", "petg")                 # the fabrication upper-cases it
    p._check()
    assert p.problem_label("preferences").text() == "" and p.export_btn.isEnabled()
    p.reject()


def test_an_unknown_servo_is_shown_in_the_add_module_panel(doc, stored):
    open_example("fish")
    stored("DefaultServo", "XYZ")
    p = run_panel("MM_AddModule")
    p.set_type("servo_housing")
    text = p.problem_label("preferences").text()
    assert "Default servo: 'XYZ' is not a known servo" in text and "MG996R" in text, text
    assert not dialog_button("Ok").isEnabled()
    p.set_type("friction_pad")                      # a pad needs no servo
    p.target.setCurrentText("N0,0")                 # the user chooses the target (the panel opens with none)
    assert p.problem_label("preferences").text() == "" and dialog_button("Ok").isEnabled()
    p.reject()
