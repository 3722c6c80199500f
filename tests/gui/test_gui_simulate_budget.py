"""Animate's background dynamics run (the GUI's only path that records simulated frames, through
core.playback.run_dynamics) is held to the command line's frames x bodies size budget: a 1 x 600 strip (the sheet
model's side view has 601 bodies) for 600 s at the animation's 30 frames/s is 18000 frames x 601 bodies, 1.08e7 body
poses (``simulate`` refuses more than 1e7); the panel ran it with nothing checked (an audit, session 29). The refusal
comes at once, before the background thread. A run within the budget still simulates:
tests/gui/test_gui_trajectory_sleeve.py; a belt is refused as no sheet: test_gui_animate_sim_guards.py."""
import json

import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

import FreeCADGui  # noqa: E402,F401

from guihelpers import click, doc, press_ok, process, run_panel, type_into, workbench  # noqa: E402,F401


def test_animate_refuses_a_simulation_over_the_pose_budget(doc, tmp_path):
    strip = tmp_path / "long_strip.json"
    strip.write_text(json.dumps({"format": "metamaterial-scene", "version": 1, "name": "long_strip",
                                 "layout": {"grid": [1, 600]},
                                 "actuators": [{"name": "m", "joint": "H0,1", "value": 0.5}]}), encoding="utf-8")
    p = run_panel("MM_NewStructure")
    type_into(p.file, str(strip))
    assert press_ok(), p.error.text()
    p = run_panel("MM_Animate")
    assert p.dt == pytest.approx(1.0 / 30.0)       # the test preferences' frame rate
    type_into(p.traj_seconds, "600")
    assert p.traj_seconds.value() == 600.0
    click(p.traj_sim_btn)
    try:
        assert not p.sim.running, "the run was not refused before the work: it is simulating"
    finally:
        if p.sim.running:                           # the code before the fix: stop the 600 s run
            p.sim.cancel()
            p.wait_simulation(600.0)
    process()
    text = p.error.text()
    assert p.error.isVisible(), text
    assert "simulation failed" in text and "18000 frames" in text and "601 bodies" in text, text
    assert "at most 10000000 are allowed" in text and "at most 16638 frames for this scene" in text, text
    assert p.trajectory is None and p.traj_sim_btn.isEnabled()
    p.reject()
