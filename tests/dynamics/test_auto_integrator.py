"""The integrator ``auto`` picks (``Simulator.choose``, core/dynamics/autochoice.py): the cheaper run on the path
that will actually run. Before, the rule "an implicit step costs 4-8 explicit steps" ignored that the implicit step
runs in the compiled kernel while the explicit one runs in numpy: every sheet example without
``dynamics.integrator`` ran semi-implicit Euler at its guard (the fish's 0.2 s: 3241 numpy steps, 5.3 s of
integration) instead of the implicit integrator at the sheets' converged 0.25 ms (800 compiled steps, 0.05 s), with
the same answer. No timing is asserted: the choice, that auto's run is the chosen method's run, and the cost model.
"""
import copy
import json

import pytest

from metamaterial_wb import example_path
from metamaterial_wb.core.dynamics import fastkernel
from metamaterial_wb.core.dynamics.builders import build, dynamics_config
from metamaterial_wb.core.dynamics.integrators import Simulator
from metamaterial_wb.core.dynamics.simulate import simulate
from metamaterial_wb.core.scene import Scene


def _scene(name, drop_integrator=False):
    with open(example_path(name), encoding="utf-8") as fh:
        d = json.load(fh)
    if drop_integrator:
        d = copy.deepcopy(d)
        del d["dynamics"]["integrator"]
    return Scene.from_dict(d)


def _simulator(scene):
    """The simulator ``simulate`` builds (its default implicit step: the model's), without settling."""
    model = build(scene, dynamics_config(scene))
    sim = Simulator(model.system, model.q0, actuate=model.actuate)
    sim.default_implicit_dt = getattr(model, "default_dt", None) or sim.default_implicit_dt
    return sim


def _compiled_or_skip():
    if fastkernel.load() is None:
        pytest.skip(f"no compiled kernel here: {fastkernel.note()}")


@pytest.mark.parametrize("name", ["fish", "grid_fold"])
def test_auto_runs_the_compiled_implicit_integrator_on_sheet_examples(name):
    """fish / grid_fold (no dynamics.integrator): the explicit guard is 6.2e-5 / 8.1e-5 s, 4.1 / 3.1 explicit steps
    per implicit 0.25 ms step, and a compiled implicit step costs 0.003-0.07 of a numpy explicit step (measured:
    docs/benchmarks.md); the former rule took the explicit one."""
    _compiled_or_skip()
    scene = _scene(name)
    auto, *_ = simulate(scene, 0.02)
    implicit, *_ = simulate(scene, 0.02, method="implicit")
    it = auto["integrator"]
    assert it["method"] == "implicit" and it["kernel"] == "c", it
    choice = it["auto_choice"]
    assert choice["chose"] == "implicit" and choice["implicit_path"] == "compiled", choice
    assert choice["symplectic_dt_s"] == it["dt_guard_s"] and choice["implicit_dt_s"] == 2.5e-4, choice
    assert choice["cost_ratio_implicit_to_symplectic"] < 1.0, choice
    # auto's run is the implicit run: same steps, same answer
    assert it["steps"] == implicit["integrator"]["steps"] and it["dt_s"] == implicit["integrator"]["dt_s"]
    assert auto["displacement_mm"] == implicit["displacement_mm"]
    assert auto["energy"] == implicit["energy"]
    assert auto["warnings"] == implicit["warnings"] == []


def test_auto_on_the_numpy_path_uses_the_numpy_costs(monkeypatch):
    """Without the compiled kernel (no compiler, failed build, or forced) both integrators run in numpy: an implicit
    numpy step costs 1.3-2.5 explicit steps on the sheets (2.7 modelled), still below the fish's 4.1 guard steps per
    implicit step (measured: 2.9 s against 5.1 s for 0.2 s), so auto still takes the implicit one, on the numpy path."""
    monkeypatch.setenv(fastkernel.ENV_SWITCH, "numpy")
    fastkernel.reset()
    try:
        scene = _scene("fish")
        auto, *_ = simulate(scene, 0.01)
        implicit, *_ = simulate(scene, 0.01, method="implicit")
    finally:
        monkeypatch.delenv(fastkernel.ENV_SWITCH)
        fastkernel.reset()
    it = auto["integrator"]
    assert it["method"] == "implicit" and it["kernel"] == "numpy", it
    assert it["auto_choice"]["implicit_path"] == "numpy", it["auto_choice"]
    assert it["steps"] == implicit["integrator"]["steps"]
    # the same run to round-off: bit for bit when run alone, 3e-12 relative apart once in a full CI run on the host
    # lane (0.008932836714548031 vs ...575787 mm; not understood, see the session 35 note)
    assert auto["displacement_mm"] == pytest.approx(implicit["displacement_mm"], rel=1e-9)


def test_the_choice_follows_the_path_that_will_run():
    """The same fish with its implicit step at twice the explicit guard: a compiled implicit step (0.32 explicit
    steps modelled) is cheaper, a numpy one (2.7) is not, so auto takes the implicit integrator with the kernel and
    the explicit one without (the former rule took the explicit one whatever the path); the explicit run it chose
    is the symplectic run, and the statistics keep no trace of the kernel probe."""
    _compiled_or_skip()
    scene = _scene("fish")
    sim = _simulator(scene)
    sim.default_implicit_dt = 2.0 * sim.dt_guard
    assert sim.choose("auto", None, 1.0)[0] == "implicit"
    assert sim.stats["auto_choice"]["implicit_path"] == "compiled"
    numpy_sim = _simulator(scene)
    numpy_sim.default_implicit_dt = 2.0 * numpy_sim.dt_guard
    numpy_sim.kernel = "numpy"
    assert numpy_sim.choose("auto", None, 1.0)[0] == "symplectic"
    assert numpy_sim.stats["auto_choice"]["implicit_path"] == "numpy"
    assert "kernel_note" not in numpy_sim.stats and "kernel" not in numpy_sim.stats
    # burst off: the compiled Newton loop one call per step (1.02 explicit steps modelled) is still cheaper here
    per_step = _simulator(scene)
    per_step.default_implicit_dt = 2.0 * per_step.dt_guard
    per_step.burst = False
    assert per_step.choose("auto", None, 1.0)[0] == "implicit"
    assert per_step.stats["auto_choice"]["implicit_path"] == "compiled_per_step"
    # a given step within the explicit limit: the same number of steps, so the cheaper step decides
    sim2 = _simulator(scene)
    dt = 0.5 * sim2.dt_guard
    assert sim2.choose("auto", dt, 1.0)[:2] == ("implicit", dt)
    numpy2 = _simulator(scene)
    numpy2.kernel = "numpy"
    assert numpy2.choose("auto", dt, 1.0)[:2] == ("symplectic", dt)
    # auto's explicit run is the symplectic run
    runs = []
    for method in ("auto", "symplectic"):
        s = _simulator(scene)
        s.kernel = "numpy"
        s.default_implicit_dt = 2.0 * s.dt_guard
        s.run(0.003, method=method)
        runs.append(s)
    assert runs[0].stats["method"] == "symplectic" and runs[0].stats["steps"] == runs[1].stats["steps"]
    assert (runs[0].q == runs[1].q).all() and runs[0].ledger == runs[1].ledger


def test_implicit_step_cost_model():
    from metamaterial_wb.core.dynamics.autochoice import IMPLICIT_STEP_COST, auto_method, implicit_step_cost

    assert set(IMPLICIT_STEP_COST) == {"compiled", "compiled_per_step", "numpy"}
    for dofs in (21, 48, 900, 3000):
        c, per_step, npy = (implicit_step_cost(p, dofs) for p in ("compiled", "compiled_per_step", "numpy"))
        assert c < per_step < npy, dofs
    # grows with the size (the explicit step is vectorised numpy, the implicit one factors a band matrix)
    assert implicit_step_cost("compiled", 3000) > implicit_step_cost("compiled", 21)
    assert implicit_step_cost("numpy", 3000) > implicit_step_cost("numpy", 21)
    # at or above the upper ends measured (docs/benchmarks.md): compiled 0.07 on the sheets, 0.23 on the 8-cell belt,
    # 0.7 at 900 dofs, 2.6 on the 1000-cell belt; per step 0.8 on the sheets, 3.2 at 3000 dofs; numpy 2.5 on the
    # sheets, 24 at 3000 dofs (the 8-cell belt's numpy path, 2.4-4.4, and the dense 300-dof one, 6.5-9.0, went above
    # it in single runs; there the explicit run needs 28 and more steps per implicit step: no effect on the choice)
    assert 0.07 <= implicit_step_cost("compiled", 27) < 1.0
    assert implicit_step_cost("compiled", 48) >= 0.23 and implicit_step_cost("compiled", 900) >= 0.7
    assert implicit_step_cost("compiled", 3000) >= 2.6
    assert implicit_step_cost("compiled_per_step", 27) >= 0.8 and implicit_step_cost("compiled_per_step", 3000) >= 3.2
    assert 2.5 <= implicit_step_cost("numpy", 27) < 4.05       # below the fish's 4.05 explicit steps per implicit one
    assert implicit_step_cost("numpy", 3000) >= 24
    # the comparison: 1/dt_sym explicit steps against cost/dt_imp
    assert auto_method(6.2e-5, 2.5e-4, 0.32) == "implicit"      # the fish, compiled
    assert auto_method(6.2e-5, 2.5e-4, 2.71) == "implicit"      # the fish, numpy
    assert auto_method(6.2e-5, 2.5e-4, 4.5) == "symplectic"     # an implicit step dearer than 4 explicit ones
    assert auto_method(1e-4, 2e-4, 2.0) == "implicit"           # a tie: the implicit (converged) step
    assert auto_method(1e-4, 1e-4, 1.1) == "symplectic"         # same step, dearer implicit step
    with pytest.raises(ValueError, match="allowed: compiled, compiled_per_step, numpy"):
        implicit_step_cost("gpu", 10)


@pytest.mark.parametrize("path", ["compiled", "numpy"])
@pytest.mark.parametrize("name,dt", [("worm_crawl", 2.5e-4), ("belt8", 2e-3)])
def test_worm_and_belt_keep_the_implicit_integrator_under_auto(name, dt, path):
    """Without their dynamics.integrator the worm (auto at the sheets' 0.25 ms; explicit guard 3.9e-5 s) and the
    8-cell belt (auto at 2 ms; guard 7e-5 s) ran implicit under auto before, and do on either path (their examples
    name the implicit integrator anyway, so the results docs/dynamics.md quotes do not depend on auto)."""
    if path == "compiled":
        _compiled_or_skip()
    sim = _simulator(_scene(name, drop_integrator=True))
    if path == "numpy":
        sim.kernel = "numpy"
    method, step, _ = sim.choose("auto", None, 1.0)
    assert method == "implicit" and step == dt
    assert sim.stats["auto_choice"]["implicit_path"] == path
    assert sim.stats["auto_choice"]["cost_ratio_implicit_to_symplectic"] < 1.0
