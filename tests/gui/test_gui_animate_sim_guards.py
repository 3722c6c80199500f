"""Animate: "Simulate" on a belt scene is refused at once, before any simulation (it simulated the whole run in
the background, then refused to load it: the belt has no sheet nodes); a stored animation frame rate outside the
preference page's range (1..120 /s) is refused, naming the preference, rather than used or clamped silently (an
audit, session 29)."""
import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

import FreeCADGui  # noqa: E402,F401

from metamaterial_wb.gui import commands, panels, preferences  # noqa: E402
from guihelpers import click, doc, press_ok, process, run_panel, workbench  # noqa: E402,F401
from test_gui_panel_details import open_example  # noqa: E402


def test_simulate_on_a_belt_scene_is_refused_at_once(doc, monkeypatch):
    open_example("belt8")
    p = run_panel("MM_Animate")
    started = []
    p.sim.start = lambda *a, **k: started.append(a) or True     # no background run may start
    # nor any simulation work in the foreground: the model's build, the integrator, the run (counted, not timed)
    from metamaterial_wb.core import playback
    from metamaterial_wb.core.dynamics import builders, simulate
    work = []
    for mod, name in [(playback, "run_dynamics"), (builders, "build"), (simulate, "simulate"),
                      (simulate, "Simulator")]:
        monkeypatch.setattr(mod, name, lambda *a, _f=getattr(mod, name), _n=name, **k: work.append(_n) or _f(*a, **k))
    click(p.traj_sim_btn)
    process()
    monkeypatch.undo()
    text = p.error.text()
    assert not started, "the background simulation was started for a belt scene"
    assert not work, f"simulation work done before the belt scene was refused: {work}"
    assert p.error.isVisible(), text
    assert "dynamics.model" in text and "only the 'sheet' model maps onto a structure's nodes" in text, text
    assert p.traj_sim_btn.isEnabled() and p.trajectory is None and not p.sim.running
    assert "simulating" not in p.traj_label.text(), p.traj_label.text()
    p.reject()


@pytest.mark.parametrize("fps", [500, 121, 0, -5])
def test_an_animation_frame_rate_preference_out_of_range_is_refused(doc, fps):
    open_example("worm_crawl")
    cmd = commands.INSTANCES["MM_Animate"]
    cmd.last_error = ""
    preferences.params().SetInt("AnimationFps", fps)
    try:
        FreeCADGui.runCommand("MM_Animate")
        process()
        opened = panels.active()
    finally:
        preferences.params().RemInt("AnimationFps")
    assert opened is None, f"Animate opened with AnimationFps {fps} (dt {getattr(opened, 'dt', None)})"
    err = cmd.last_error
    assert "Animation frame rate" in err and "AnimationFps" in err, err
    assert str(fps) in err and "1..120" in err, err


def test_an_animation_frame_rate_in_range_is_used(doc):
    open_example("worm_crawl")
    preferences.params().SetInt("AnimationFps", 120)
    try:
        p = run_panel("MM_Animate")
    finally:
        preferences.params().RemInt("AnimationFps")
    assert p.dt == pytest.approx(1.0 / 120.0)
    p.reject()
