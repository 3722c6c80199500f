"""The step a sheet scene gets when it asks for none, and the integrator ``auto`` picks for a given step (an audit
of the dynamics journey, session 26): a sheet without ``dynamics.integrator`` ran at the implicit 2 ms, where the
worm crawls 161 mm in 10 s instead of about 60 and neither the ledger nor the dt study (2 ms against 1 ms, both
damping the pads' chatter) says so; ``--dt 0.00025`` with ``auto`` took the explicit integrator, which cannot use
that step, and ran 4x as many steps at its guard."""
import copy
import json

import pytest

from metamaterial_wb import example_path
from metamaterial_wb.core.dynamics.simulate import simulate
from metamaterial_wb.core.scene import Scene


def worm(without_integrator):
    with open(example_path("worm_crawl")) as f:
        d = json.load(f)
    if without_integrator:
        d = copy.deepcopy(d)
        del d["dynamics"]["integrator"]
    return Scene.from_dict(d)


def test_a_sheet_without_a_step_runs_at_the_worms_converged_step():
    s_default, *_ = simulate(worm(True), 2.0)
    s_example, *_ = simulate(worm(False), 2.0)
    assert s_default["integrator"]["dt_s"] <= 2.5e-4 + 1e-12, s_default["integrator"]
    # the example's own 0.25 ms step gives the reference crawl; the default must not be 2.8x off it
    assert s_default["displacement_mm"] == pytest.approx(s_example["displacement_mm"], rel=0.1, abs=1.0)


def test_auto_with_a_step_the_explicit_integrator_cannot_take_runs_implicit():
    scene = Scene.from_dict(json.load(open(example_path("fish"))))
    summary, *_ = simulate(scene, 0.05, method="auto", dt=2.5e-4)
    integ = summary["integrator"]
    assert integ["dt_stability_limit_s"] < 2.5e-4, integ            # (the case: the explicit limit is below it)
    assert integ["method"] == "implicit" and integ["dt_s"] == 2.5e-4, integ
    assert "dt_reduced_from" not in integ


def test_the_energy_warning_of_an_implicit_run_does_not_advise_the_implicit_integrator():
    from metamaterial_wb.core.dynamics.simulate import convergence_warnings
    energy = {"actuator_work_J": 1.0, "damping_dissipated_J": 0.0, "friction_dissipated_J": 0.0, "numerical_J": -0.5}
    implicit = convergence_warnings(energy, 0.0, stats={"method": "symplectic->implicit", "steps": 10})
    explicit = convergence_warnings(energy, 0.0, stats={"method": "symplectic", "steps": 10})
    assert "created" in implicit[0] and "implicit integrator" not in implicit[0], implicit
    assert "or the implicit integrator" in explicit[0], explicit


def test_the_travel_extremes_do_not_depend_on_the_frame_rate():
    """min/max_com_displacement_mm came from the recorded frames: at 1 frame/s the worm's roll-back in its first
    1.5 s read -2.77 mm, at 30 frames/s -2.99; ``belt8`` at 0.2 frames/s showed none at all (the docs say the field
    shows a roll-back even when the belt recovers)."""
    scene = worm(False)
    slow, *_ = simulate(scene, 1.5, record_dt=1.0)
    fast, *_ = simulate(scene, 1.5, record_dt=1.0 / 30.0)
    assert slow["min_com_displacement_mm"] < -2.9, slow["min_com_displacement_mm"]
    assert slow["min_com_displacement_mm"] == fast["min_com_displacement_mm"]
    assert slow["max_com_displacement_mm"] == fast["max_com_displacement_mm"]
