"""Animate's background dynamics run (``core.playback.run_dynamics``, the panel's "Simulate"): a belt scene is
refused before any simulation work (it ran the whole simulation, then refused to load it: only the sheet model
maps onto a structure's nodes), and the run is held to the command line's step limit, which lives in core
(``core.dynamics.simulate.MAX_STEPS``; the GUI used simulate()'s 50 M default, the CLI 20 M) (an audit, session 29)."""
import inspect
import os

import pytest

from metamaterial_wb.core.errors import MetamaterialError, SceneError
from metamaterial_wb.core.scene import Scene
from test_simulate_budget_numbers import no_work  # noqa: F401 (the fixture: no simulation work may start)

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
EX = os.path.join(ROOT, "examples")
WORM = os.path.join(EX, "worm_crawl.json")
BELT8 = os.path.join(EX, "belt8.json")


def test_a_belt_scene_is_refused_before_any_simulation_work(no_work):
    from metamaterial_wb.core.playback import run_dynamics
    calls = []
    with pytest.raises(SceneError) as e:
        run_dynamics(Scene.load(BELT8), 1.0, fps=30.0, progress=calls.append)
    msg = str(e.value)
    assert "dynamics.model" in msg and "'belt'" in msg, msg
    assert "only the 'sheet' model maps onto a structure's nodes" in msg, msg
    assert calls == []                                     # nothing reported: nothing ran


def test_the_playback_check_is_callable_before_the_run(no_work):
    """The panel asks core before it starts its background thread (the refusal shows at once)."""
    from metamaterial_wb.core.playback import check_run_dynamics
    with pytest.raises(SceneError) as e:
        check_run_dynamics(Scene.load(BELT8), 1.0, 30.0)
    assert "only the 'sheet' model maps onto a structure's nodes" in str(e.value)


def _worm_with_dt(dt):
    scene = Scene.load(WORM)
    dyn = dict(scene.extra.get("dynamics", {}))
    dyn["integrator"] = dict(dyn.get("integrator") or {}, dt_s=dt)
    scene.extra["dynamics"] = dyn
    return scene


def test_the_guis_run_uses_the_cli_step_limit(no_work):
    """600 s at the scene's dt_s 2e-5 s is 3e7 time steps: the CLI refuses it (more than 20 M), the GUI's run
    (simulate()'s default of 50 M steps) simulated it."""
    from metamaterial_wb.core.playback import run_dynamics
    with pytest.raises(MetamaterialError) as e:
        run_dynamics(_worm_with_dt(2e-5), 600.0, fps=30.0, progress=lambda f: None)
    msg = str(e.value)
    assert "3e+07 time steps" in msg and "at most 20000000 are allowed" in msg, msg


def test_the_one_step_limit_is_core_s_and_both_use_it():
    from metamaterial_wb.cli import simulate as C
    from metamaterial_wb.core.dynamics import simulate as S
    assert S.MAX_STEPS == 20_000_000
    assert C.MAX_STEPS is S.MAX_STEPS
    assert inspect.signature(S.simulate).parameters["max_steps"].default == S.MAX_STEPS


def test_a_run_within_the_limits_still_passes_the_check():
    from metamaterial_wb.core.playback import check_run_dynamics
    check_run_dynamics(_worm_with_dt(2e-5), 400.0, 30.0)      # 2e7 steps: at the limit, allowed
    check_run_dynamics(Scene.load(WORM), 4.0, 30.0)
