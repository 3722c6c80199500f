"""Export's check of the snap-fit clearance preference only where snap pins are made (session 34 follow-up): with
the "Snap-fit sockets" box unticked, or a scene with ``fabrication.sockets: false``, a clearance at or above the
socket lip was refused although no snap pin is designed and the sheet builds with it; toggling the box did not
re-run the check; and the background export named the scene's socket_lip_mm, not the preference, when the snap pin
refused the preference's clearance."""
import json
import os

import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

from guihelpers import click, doc, process, run_panel, type_into, workbench  # noqa: E402,F401
from test_gui_panel_details import open_example  # noqa: E402
from test_gui_pref_clearance import clearance  # noqa: E402,F401 - PrinterClearance, restored afterwards

REFUSED = "Edit > Preferences > Metamaterial > Snap-fit clearance (mm): 0.6 mm is not below the 0.5 mm socket lip"
PREF = "Edit > Preferences > Metamaterial > Snap-fit clearance (mm) (PrinterClearance)"
SOCKETS_OFF = "modules plug into the node sockets, but fabrication.sockets is false"


def opened(doc, clearance, name, clr, **fabrication):
    """The example ``name`` (its own fabrication section set in SceneJSON, as a user edits it, when given), then the
    clearance preference ``clr`` set by a macro (the page stops at 0.49)."""
    sc = open_example(name)
    if fabrication:
        data = json.loads(sc.SceneJSON)
        data["fabrication"] = fabrication
        sc.SceneJSON = json.dumps(data)
        doc.recompute()
    clearance.SetFloat("PrinterClearance", clr)
    doc.recompute()
    return sc


def export(p, out):
    """Export 3MF only (faster) into ``out`` with the panel's button; returns the files there."""
    p.step.setChecked(False)
    type_into(p.path, str(out))
    click(p.export_btn)
    assert p.wait(300), "export did not finish"
    return sorted(n for n in os.listdir(out) if not n.startswith(".")) if os.path.isdir(out) else []


def preferences_problem(p):
    return p.problem_label("preferences").text()


@pytest.mark.parametrize("how", ["checkbox", "scene"])
def test_the_sheet_without_sockets_exports_with_the_clearance(doc, clearance, tmp_path, how):
    """fish (no module): without sockets (the box unticked, or the scene's own fabrication.sockets) nothing uses the
    clearance against the lip: Export is not refused and writes the sheet."""
    sc = opened(doc, clearance, "fish", 0.6, **({"sockets": False} if how == "scene" else {}))
    p = run_panel("MM_Export")
    assert p.modules.isChecked() and p.sockets.isChecked()
    if how == "checkbox":
        click(p.sockets)
        assert not p.sockets.isChecked()
    process()
    assert preferences_problem(p) == "" and p.export_btn.isEnabled(), preferences_problem(p)
    names = export(p, tmp_path / "out")
    assert p.job.outcome == "done" and p.error.text() == "", p.error.text()
    assert any(n.endswith(".3mf") for n in names) and "manifest.json" in names, names
    assert sc.isValid()
    p.reject()


def test_the_sockets_box_reruns_the_check(doc, clearance, tmp_path):
    """fish_modules: with sockets the preference at the lip is refused naming it; unticking the box clears the
    refusal at once, ticking it again brings it back; without sockets Export is refused up front for the real reason
    (the modules plug into the sockets: test_gui_export_upfront), not the clearance, and writes nothing."""
    opened(doc, clearance, "fish_modules", 0.6)
    p = run_panel("MM_Export")
    assert REFUSED in preferences_problem(p) and not p.export_btn.isEnabled(), preferences_problem(p)
    click(p.sockets)
    assert preferences_problem(p) == "", preferences_problem(p)
    assert "plug into the node sockets" in p.problem_label("modules").text() and not p.export_btn.isEnabled()
    click(p.sockets)
    assert REFUSED in preferences_problem(p) and not p.export_btn.isEnabled(), preferences_problem(p)
    assert p.problem_label("modules").text() == ""
    click(p.sockets)
    out = tmp_path / "out"
    assert export(p, out) == [] and not out.exists()
    assert p.job.outcome is None and "plug into the node sockets" in p.problem_label("modules").text()
    assert "Snap-fit clearance" not in p.problem_text(), p.problem_text()
    p.reject()


def test_a_scene_without_sockets_is_not_refused_the_clearance(doc, clearance, tmp_path):
    """fish_modules with fabrication.sockets false (the box ticked): no clearance refusal; its modules fail for the
    sockets, in the document and in the Export panel (up front); without the modules the sheet is written."""
    sc = opened(doc, clearance, "fish_modules", 0.6, sockets=False)
    sc.touch()
    doc.recompute()
    bad = [m.getStatusString() for m in sc.Modules if not m.isValid()]
    assert len(bad) == 4 and all(SOCKETS_OFF in t and PREF not in t for t in bad), bad
    p = run_panel("MM_Export")
    assert p.sockets.isChecked()
    assert preferences_problem(p) == "", preferences_problem(p)
    assert "fabrication.sockets is false" in p.problem_label("modules").text() and not p.export_btn.isEnabled()
    click(p.modules)
    assert p.problem_label("modules").text() == "" and p.export_btn.isEnabled(), p.problem_text()
    names = export(p, tmp_path / "out")
    assert p.job.outcome == "done" and any(n.endswith(".3mf") for n in names), (p.error.text(), names)
    p.reject()


def test_the_background_export_names_the_preference(doc, clearance, tmp_path):
    """fish_modules with a 2.8 mm socket: the preference's 0.45 mm (below the lip, so Export starts) leaves the pin
    no room for its slot; the background run's error names the preference, and nothing is written."""
    opened(doc, clearance, "fish_modules", 0.45, socket_diameter_mm=2.8)
    p = run_panel("MM_Export")
    assert preferences_problem(p) == "" and p.export_btn.isEnabled(), preferences_problem(p)
    out = tmp_path / "out"
    assert export(p, out) == [] and not out.exists()
    text = p.error.text()
    assert p.job.outcome == "error" and "slot" in text and PREF in text, text
    assert "now 0.45 mm; allowed range [0, 0.5) mm" in text, text
    p.reject()
