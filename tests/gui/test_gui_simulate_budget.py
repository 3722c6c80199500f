"""Animate's background dynamics run (the GUI's only path that records simulated frames, through
core.playback.run_dynamics) is held to the command line's frames x bodies size budget: belt1000 for 600 s at the
animation's 30 frames/s is 18000 frames x 1000 bodies, 1.8e7 body poses (``simulate`` refuses more than 1e7); the
panel ran it (hours, gigabytes) with nothing checked (an audit, session 29). A run within the budget still simulates:
tests/gui/test_gui_trajectory_sleeve.py."""
import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

import FreeCADGui  # noqa: E402,F401

from metamaterial_wb.objects import structure  # noqa: E402
from guihelpers import click, doc, press_ok, process, run_panel, type_into, workbench  # noqa: E402,F401


def open_example(name):
    p = run_panel("MM_OpenExample")
    p.select(name)
    assert press_ok()
    return structure.find_scene_objects(FreeCAD.ActiveDocument)[-1]


def test_animate_refuses_a_simulation_over_the_pose_budget(doc):
    open_example("belt1000")
    p = run_panel("MM_Animate")
    assert p.dt == pytest.approx(1.0 / 30.0)       # the test preferences' frame rate
    type_into(p.traj_seconds, "600")
    assert p.traj_seconds.value() == 600.0
    click(p.traj_sim_btn)
    try:
        assert p.wait_simulation(30.0), "the run was not refused before the work: it is still simulating"
    finally:
        if p.sim.running:                           # today's code: stop the 600 s run
            p.sim.cancel()
            p.wait_simulation(600.0)
    process()
    text = p.error.text()
    assert p.error.isVisible(), text
    assert "simulation failed" in text and "18000 frames" in text and "1000 bodies" in text, text
    assert "at most 10000000 are allowed" in text and "at most 10000 frames for this scene" in text, text
    assert p.trajectory is None and p.traj_sim_btn.isEnabled()
    p.reject()

