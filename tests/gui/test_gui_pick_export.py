"""Defects 1 and 4 of issue 15, driven through real widgets (QTest clicks on the task dialog and on
the 3D view): export keeps the document active; a click picks the hinge nearest to the click ray on
default 2 mm hinges, with the joint under the cursor highlighted and named before the click."""
import os

import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

import FreeCADGui  # noqa: E402

from metamaterial_wb.gui import commands, panels  # noqa: E402
from metamaterial_wb.objects import structure  # noqa: E402
from metamaterial_wb.core.live import joint_node_indices  # noqa: E402
from guihelpers import (hinge_mid, click, click_view, doc, hover_view, press_ok, process, run_panel,  # noqa: E402,F401
                        screen_point, type_into, workbench)


def new_default_sheet(doc):
    """New structure with the panel's defaults (2 x 6 grid, 2 mm hinges), confirmed with the OK button."""
    run_panel("MM_NewStructure")
    assert press_ok(), panels.active().error.text()
    sc = structure.find_scene_objects(doc)[0]
    FreeCADGui.SendMsgToActiveView("ViewFit")
    process(50)
    return sc


def test_click_picks_a_default_2mm_hinge_with_preselection(doc):
    sc = new_default_sheet(doc)
    assert sc.HingeLength.Value == pytest.approx(2.0)
    p = run_panel("MM_RotaryAxes")
    # the view names the grid lines with the numbers the buttons and messages use
    assert p.overlay.labels == [f"row {r}" for r in range(2)] + [f"col {c}" for c in range(6)]
    pt = screen_point(hinge_mid(sc, "H0,3"))
    hover_view(pt)
    assert p.pick_label.text() == "under the cursor: hinge H0,3 (click to pick it)"
    assert p.picker.switch.whichChild.getValue() == 0, "the joint under the cursor is highlighted"
    click_view(pt)
    assert p.pick_label.text() == "picked hinge H0,3"
    assert p.buttons[("vertical", 3)].isChecked(), "the click toggled the axis crossing H0,3"
    # a few pixels off the 2 mm hinge still picks it (nearest hinge midpoint to the click ray)
    off = pt + type(pt)(4, 3)
    click_view(off)
    assert p.pick_label.text() == "picked hinge H0,3"
    assert not p.buttons[("vertical", 3)].isChecked()
    # a horizontal-axis hinge
    click_view(screen_point(hinge_mid(sc, "V1,2")))
    assert p.pick_label.text() == "picked hinge V1,2"
    assert p.buttons[("horizontal", 1)].isChecked()
    assert press_ok()
    assert [(a.direction, a.line) for a in structure.compose_scene(sc).axes] == [("horizontal", 1)]


def test_export_keeps_an_active_document_and_reports_in_the_panel(doc, tmp_path):
    p = run_panel("MM_OpenExample")
    p.select("fish")
    assert press_ok()
    sc = structure.find_scene_objects(doc)[-1]
    p = run_panel("MM_Export")
    out = str(tmp_path / "fish_export")
    type_into(p.path, out)
    click(p.export_btn)
    assert p.jobbox.progress.isVisible() and p.jobbox.cancel_btn.isVisible(), "progress + Cancel while it runs"
    assert p.wait(300), "export did not finish"
    assert p.job.outcome == "done", p.error.text()
    assert FreeCAD.ActiveDocument is not None and FreeCAD.ActiveDocument.Name == doc.Name
    assert commands.INSTANCES["MM_Export"].IsActive() and commands.INSTANCES["MM_Simulate"].IsActive()
    names = sorted(os.listdir(out))
    assert any(n.endswith(".step") for n in names) and any(n.endswith(".3mf") for n in names), names
    summary = p.jobbox.summary.text()
    assert summary.startswith(f"wrote {len(names)} file(s) to {out}"), summary
    for n in names:
        assert n in summary
    assert not [n for n in os.listdir(tmp_path) if n.startswith(".mm-export-")], "staging folder left behind"
    click(p.export_btn)      # Cancel: nothing written, nothing left behind
    click(p.jobbox.cancel_btn)
    assert p.job.outcome == "cancelled" and "cancelled" in p.jobbox.summary.text()
    assert not [n for n in os.listdir(tmp_path) if n.startswith(".mm-export-")]
    assert sc.isValid()


def test_export_folder_with_a_tilde_is_in_the_home_folder(doc, tmp_path, monkeypatch):
    """'~/fish_export' made a folder named '~' in FreeCAD's working directory."""
    monkeypatch.setenv("HOME", str(tmp_path / "home"))
    cwd = tmp_path / "cwd"
    cwd.mkdir()
    monkeypatch.chdir(cwd)
    p = run_panel("MM_OpenExample")
    p.select("fish")
    assert press_ok()
    p = run_panel("MM_Export")
    type_into(p.path, "~/fish_export")
    click(p.export_btn)
    assert p.wait(300) and p.job.outcome == "done", p.error.text()
    assert any(n.endswith(".step") for n in os.listdir(tmp_path / "home" / "fish_export"))
    assert os.listdir(cwd) == []
