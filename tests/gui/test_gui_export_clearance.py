"""Export's up-front check of the snap-fit clearance preference uses the scene's own socket lip, as Add module and
the modules' build do (session 34): it compared the preference with the default 0.5 mm lip, so a scene with a
smaller lip passed and then every module failed in the background export, and one with a larger lip was refused
although it builds."""
import json
import os

import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

from guihelpers import click, doc, press_cancel, process, run_panel, type_into, workbench  # noqa: E402,F401
from test_gui_panel_details import open_example  # noqa: E402
from test_gui_pref_clearance import clearance  # noqa: E402,F401 - PrinterClearance, restored afterwards

WANT = "Edit > Preferences > Metamaterial > Snap-fit clearance (mm): {clr} mm is not below the {lip} mm socket lip"
# (socket lip, clearance preference, other fabrication) as in tests/fc/test_fc_clearance_lip.py: a lip below the
# default that the clearance reaches, one above it that the clearance does not (the scene builds)
LIPS = [(0.4, 0.45, {}), (0.8, 0.6, {"socket_diameter_mm": 4.0, "socket_inset_mm": 4.0, "module_material": "PETG"})]


def fish_with_lip(doc, clearance, lip, clr, more):
    """fish_modules opened from the examples, its own fabrication section set in SceneJSON (as a user edits it),
    built with the scene's clearance, then the clearance preference ``clr`` set (a macro; the page stops at 0.49)."""
    sc = open_example("fish_modules")
    data = json.loads(sc.SceneJSON)
    data["fabrication"] = dict(more, socket_lip_mm=lip)
    sc.SceneJSON = json.dumps(data)
    doc.recompute()
    assert all(m.isValid() for m in sc.Modules), [m.getStatusString() for m in sc.Modules]
    clearance.SetFloat("PrinterClearance", clr)
    doc.recompute()
    return sc


def add_module_says():
    p = run_panel("MM_AddModule")
    p.set_type("friction_pad")
    p.target.setCurrentText("N0,0")
    process()
    text = p.problem_label("preferences").text()
    assert press_cancel()
    return text


@pytest.mark.parametrize("lip, clr, more", LIPS)
def test_export_agrees_with_add_module_and_the_build(doc, clearance, tmp_path, lip, clr, more):
    sc = fish_with_lip(doc, clearance, lip, clr, more)
    builds = all(m.isValid() for m in sc.Modules)
    assert builds == (clr < lip), [m.getStatusString() for m in sc.Modules]
    said = add_module_says()
    want = WANT.format(clr=f"{clr:g}", lip=f"{lip:g}")
    assert (want in said and f"allowed range [0, {lip:g}) mm" in said) == (not builds), said
    p = run_panel("MM_Export")
    text = p.problem_label("preferences").text()
    assert text == said, (text, said)
    assert p.export_btn.isEnabled() == builds, text
    if builds:      # the background export builds the modules with the preference's clearance
        p.step.setChecked(False)                      # 3MF only (faster)
        type_into(p.path, str(tmp_path / "out"))
        click(p.export_btn)
        assert p.wait(300), "export did not finish"
        assert p.job.outcome == "done" and p.error.text() == "", p.error.text()
        names = os.listdir(tmp_path / "out")
        assert len([n for n in names if n.endswith(".3mf")]) > len(sc.Modules), names
    p.modules.setChecked(False)                       # the sheet alone: no snap pin, no clearance check
    assert p.problem_label("preferences").text() == "" and p.export_btn.isEnabled()
    p.reject()
