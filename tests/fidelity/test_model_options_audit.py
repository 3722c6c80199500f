"""Simulation-model audit: poses past the scene's rotation limits are flagged, options that would be ignored or
misread are refused or warned about, and the live solver checks its global deformation (audit of the
simulation core, defects 1, 3 and 4)."""
import math

import numpy as np
import pytest

from metamaterial_wb.bench.fidelity import standard_scenes
from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.core.live import LiveSolver
from metamaterial_wb.core.models import run_model
from metamaterial_wb.core.scene import Scene


def _std(key, amplitude):
    return dict((k, s) for k, _, s in standard_scenes(amplitude))[key]


def _chain(value=0.3):
    return Scene.from_dict({"format": "metamaterial-scene", "version": 1, "layout": {"grid": [1, 6]},
                            "actuators": [{"name": "m1", "joint": "V0,0", "value": value}]})


# -- defect 1: about=flat past the hinge limits is flagged, naming the joint, its angle and the limit ----------
def test_linear_flat_folding_through_is_warned():
    # the auditor's case: H10,2 turns ~173 deg (plates fold through each other), |D| up to 10
    res = run_model("linear", _std("grid10", 0.9), about="flat")
    hits = [w for w in res.warnings if "past the scene's rotation limits" in w]
    assert hits, res.warnings
    w = hits[0]
    assert "H10,2 turns 17" in w and "folding through" in w and "not a valid pose" in w, w
    rec = res.info["hinge_limit_exceeded"]
    assert rec and rec[0]["joint"] == "H10,2" and rec[0]["angle_deg"] > 170.0
    # the D range warning no longer explains it as physics
    assert not [x for x in res.warnings if "free-edge amplification" in x], res.warnings


def test_linear_flat_past_the_opening_limit_is_warned():
    res = run_model("linear", _std("grid10", 0.5), about="flat")
    hits = [w for w in res.warnings if "past the scene's rotation limits" in w]
    assert hits, res.warnings
    assert "H10,2" in hits[0] and "opening limit 90.0 deg" in hits[0] and "not a valid pose" in hits[0], hits[0]
    assert res.info["hinge_limit_exceeded"][0]["sense"] == "opening"


def test_linear_flat_within_its_range_is_not_warned():
    res = run_model("linear", _std("grid10", 0.3), about="flat")
    assert not [w for w in res.warnings if "past the scene's" in w], res.warnings
    assert res.info["hinge_limit_exceeded"] == []


def test_nonlinear_reference_within_the_limits_is_not_warned():
    res = run_model("nonlinear", _std("grid10", 0.7), hinge_elements=2)
    assert res.converged and not [w for w in res.warnings if "past the scene's" in w], res.warnings


# -- defect 3: predictor=true where it cannot run is refused; whether it ran is recorded ------------------------
@pytest.mark.parametrize("opts, needle", [
    ({"hinge_elements": 2}, "hinge_elements"),
    ({"planar": False}, "planar"),
    ({"method": "dynamic_relaxation"}, "method"),
])
def test_predictor_where_it_cannot_run_is_refused(opts, needle):
    with pytest.raises(SceneError) as exc:
        run_model("nonlinear", _chain(), predictor=True, **opts)
    msg = str(exc.value)
    assert "predictor" in msg and needle in msg, msg


def test_predictor_used_is_recorded():
    on = run_model("nonlinear", _chain(), predictor=True)
    off = run_model("nonlinear", _chain())
    assert on.converged and on.info["predictor_used"] is True
    assert off.info["predictor_used"] is False
    assert np.allclose(on.D, off.D, atol=1e-6)


# -- defect 4: hinge_elements=true, the live global deformation, planar=true on tilted hinges -------------------
@pytest.mark.parametrize("bad", [True, False])
def test_hinge_elements_boolean_is_refused(bad):
    with pytest.raises(SceneError, match="hinge_elements"):
        run_model("nonlinear", _chain(), hinge_elements=bad)


@pytest.mark.parametrize("g", [float("nan"), 7.0, -1.5, float("inf"), True])
def test_live_global_deformation_is_checked(g):
    live = LiveSolver(_chain())
    with pytest.raises(SceneError, match="global_deformation"):
        live.solve(global_deformation=g)
    with pytest.raises(SceneError, match="global_deformation"):
        live.frame(global_deformation=g)


def test_live_global_deformation_in_range_is_kept():
    live = LiveSolver(_chain())
    assert np.all(live.solve(global_deformation=-1.0) == -1.0)
    assert np.all(live.frame(global_deformation=0.4).D == 0.4)


@pytest.mark.parametrize("model", ["linear", "nonlinear"])
def test_planar_true_on_tilted_hinges_is_warned(model):
    sc = _std("bending", 0.3)
    res = run_model(model, sc, planar=True)
    hits = [w for w in res.warnings if "planar" in w and "tilted" in w]
    assert hits, res.warnings
    free = run_model(model, sc)
    assert not [w for w in free.warnings if "planar" in w and "tilted" in w], free.warnings


def test_planar_true_on_a_flat_scene_is_not_warned():
    res = run_model("linear", _chain(), planar=True)
    assert not [w for w in res.warnings if "tilted" in w], res.warnings
    assert math.isfinite(res.D[0])
