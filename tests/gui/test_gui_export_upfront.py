"""Export refuses up front what the background export would refuse (session 35): with a scene whose modules plug
into the node sockets, "Modules as separate files" ticked and "Snap-fit sockets on the nodes" unticked (or the scene's
own fabrication.sockets false), Export started the background run, which failed ("fabrication.sockets is false") and
wrote nothing. The panel says so before anything starts, naming both options, and Export / a script's accept() are
refused; unticking Modules (the sheet alone) or ticking Sockets again clears it at once."""
import json
import os

import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

from guihelpers import click, doc, process, run_panel, type_into, workbench  # noqa: E402,F401
from test_gui_panel_details import open_example  # noqa: E402
from test_gui_pref_clearance import clearance  # noqa: E402,F401 - PrinterClearance, restored afterwards

MODULES = "Modules as separate files"
SOCKETS = "Snap-fit sockets on the nodes"


def opened(doc, name, **fabrication):
    sc = open_example(name)
    if fabrication:
        data = json.loads(sc.SceneJSON)
        data["fabrication"] = fabrication
        sc.SceneJSON = json.dumps(data)
        doc.recompute()
    return sc


def modules_problem(p):
    return p.problem_label("modules").text()


def refused_up_front(p, out, *names):
    """The panel names the combination (each of ``names``) before anything starts: the Export button is disabled,
    a click and a script's accept() start no background run and write nothing."""
    text = modules_problem(p)
    assert text and all(n in text for n in names), text
    assert p.problem_label("modules").isVisible()
    assert not p.export_btn.isEnabled()
    type_into(p.path, str(out))
    click(p.export_btn)                 # disabled: nothing happens
    assert not p.job.running and p.job.outcome is None, p.job.outcome
    assert p.accept() is False and not p.job.running
    assert all(n in p.error.text() for n in names), p.error.text()
    assert "not exported" in p.error.text(), p.error.text()
    assert not out.exists()
    return text


def test_modules_without_the_sockets_box_are_refused_before_export(doc, clearance, tmp_path):
    opened(doc, "fish_modules")
    p = run_panel("MM_Export")
    assert p.modules.isChecked() and p.sockets.isChecked()
    assert modules_problem(p) == "" and p.export_btn.isEnabled(), modules_problem(p)
    click(p.sockets)
    assert not p.sockets.isChecked()
    text = refused_up_front(p, tmp_path / "out", MODULES, SOCKETS)
    assert "4 module(s)" in text, text
    click(p.sockets)                    # ticked again: the refusal goes at once
    assert modules_problem(p) == "" and p.export_btn.isEnabled(), modules_problem(p)
    click(p.sockets)
    assert modules_problem(p)
    click(p.modules)                    # the sheet alone: no socket needed, exported
    assert modules_problem(p) == "" and p.export_btn.isEnabled(), modules_problem(p)
    p.step.setChecked(False)
    out = tmp_path / "sheet"
    type_into(p.path, str(out))
    click(p.export_btn)
    assert p.wait(300) and p.job.outcome == "done", p.error.text()
    assert any(n.endswith(".3mf") for n in os.listdir(out))
    p.reject()


def test_modules_in_a_scene_without_sockets_are_refused_before_export(doc, clearance, tmp_path):
    """The reverse: the box ticked but the scene's fabrication.sockets false (the box cannot add sockets the scene
    turns off): refused up front naming the scene's setting and Modules; the sheet alone is exported."""
    opened(doc, "fish_modules", sockets=False)
    p = run_panel("MM_Export")
    assert p.modules.isChecked() and p.sockets.isChecked()
    text = refused_up_front(p, tmp_path / "out", MODULES, "fabrication.sockets")
    assert "false" in text, text
    click(p.sockets)                    # unticking the box changes nothing: still no socket
    assert "fabrication.sockets" in modules_problem(p) and not p.export_btn.isEnabled()
    click(p.modules)
    assert modules_problem(p) == "" and p.export_btn.isEnabled(), modules_problem(p)
    p.reject()


def test_a_scene_without_modules_exports_without_sockets(doc, clearance, tmp_path):
    """fish (no module): Modules ticked and Sockets unticked is no refusal (nothing plugs in)."""
    opened(doc, "fish")
    p = run_panel("MM_Export")
    click(p.sockets)
    process()
    assert modules_problem(p) == "" and p.export_btn.isEnabled(), modules_problem(p)
    p.reject()


def test_the_page_takes_a_clearance_a_wider_socket_lip_builds(doc, clearance, tmp_path):
    """The preferences page is global, scenes differ: it allowed 0-0.49 mm (below the DEFAULT 0.5 mm socket lip)
    although a scene with a 1 mm lip builds its modules' snap pins with 0.6 mm. The page takes the fabrication's
    whole clearance range; the scene's own lip is checked where it matters (Export, Add module), naming the
    preference: the lip-1 scene exports its modules with 0.6 mm, the default scene is refused up front."""
    from metamaterial_wb.core.fabrication import FAB_DEFAULTS
    from test_gui_pref_clearance import on_preferences_page
    sc = opened(doc, "fish_modules", socket_lip_mm=1.0, socket_diameter_mm=4.0, socket_inset_mm=4.0)
    seen = on_preferences_page("0.6")
    assert seen["value"] == pytest.approx(0.6) and seen["maximum"] >= 2.0, seen
    assert clearance.GetFloat("PrinterClearance") == pytest.approx(0.6)
    doc.recompute()
    assert all(m.isValid() for m in sc.Modules), [m.getStatusString() for m in sc.Modules]
    p = run_panel("MM_Export")
    assert p.problem_label("preferences").text() == "" and p.export_btn.isEnabled(), \
        p.problem_label("preferences").text()
    p.step.setChecked(False)
    out = tmp_path / "out"
    type_into(p.path, str(out))
    click(p.export_btn)
    assert p.wait(300) and p.job.outcome == "done", p.error.text()
    names = os.listdir(out)
    assert sum(n.endswith(".3mf") for n in names) >= 1 + len(sc.Modules), names
    p.reject()
    assert FAB_DEFAULTS["socket_lip_mm"] == 0.5
    data = json.loads(sc.SceneJSON)               # back to the default 0.5 mm lip: the preference is named up front
    data.pop("fabrication")
    sc.SceneJSON = json.dumps(data)
    doc.recompute()
    p = run_panel("MM_Export")
    text = p.problem_label("preferences").text()
    assert "0.6 mm is not below the 0.5 mm socket lip" in text and not p.export_btn.isEnabled(), text
    p.reject()
