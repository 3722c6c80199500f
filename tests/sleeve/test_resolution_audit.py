"""Defects found by an audit of the sleeve's summary, each reported on a sleeve the validator accepts:

* ``pv.needs_vacuum_to_reset`` was true for sleeves whose valley is positive or that have none: the unloading
  force at d = 0 is solver round-off (-1e-14 .. -1e-11 G L^2), and any negative number counted;
* a near-zero ``model.max_displacement_mm`` gave the unit cell a "peak" of solver noise, ``bistable`` true and
  twenty zero crossings;
* a monostable sleeve (no peak, no force drop) was given snapping events and a "symmetric" sequence;
* ``accuracy.ring_first_peak`` was missing (not null) for curved rings of other than four cells;
* ``"version": true`` was read as version 1.

Small models (6-8 elements, 40-60 steps): every case reproduces on them."""
import numpy as np
import pytest

from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.core.sleeve.accuracy import accuracy
from metamaterial_wb.core.sleeve.cell import CellGeometry
from metamaterial_wb.core.sleeve.pipeline import analyse, unit_cell_result
from metamaterial_wb.core.sleeve.spec import SleeveSpec

SEED_TYPE = {"t_mm": 1.0, "h_mm": 7.5}
COARSE = {"elements_cell": 6, "elements_ring": 8, "steps": 60}


def _spec(ring, types=(SEED_TYPE,), **model):
    return SleeveSpec({"format": "metamaterial-sleeve", "version": 1, "cell_types": list(types), "ring": ring,
                       "model": dict(COARSE, **model)})


# --- needs_vacuum_to_reset (defect 1) -----------------------------------------------------------
@pytest.mark.parametrize("ring, types, model", [
    ([0, 0, 0, 0], (SEED_TYPE,), {"pillar_tip": "free", "elements_ring": 12}),   # valley +3.2e-4
    ([0, 0], (SEED_TYPE,), {}),                                                    # valley +1.5e-4
    ([0, 0, 0, 0], ({"t_mm": 1.0, "h_mm": 0.5},), {}),                             # monostable: no valley
])
def test_no_vacuum_is_needed_without_a_valley_below_zero(ring, types, model):
    s, curves = analyse(_spec(ring, types, **model))
    pv = s["pv"]
    assert all(v > 0 for v in pv["valleys_kPa"]), pv["valleys_kPa"]
    pu = curves["pv"]["unload"][1]
    assert pu.min() < 0            # the round-off that used to count: the unloading curve's last point
    assert pv["needs_vacuum_to_reset"] is False


def test_a_valley_below_zero_still_needs_a_vacuum():
    s, _ = analyse(_spec([0, 0, 0, 0]))
    assert min(s["pv"]["valleys_kPa"]) < -1.0
    assert s["pv"]["needs_vacuum_to_reset"] is True


# --- a stroke at the solver's noise (defect 5) --------------------------------------------------
def test_a_stroke_at_the_noise_level_gives_the_unit_cell_no_peak():
    g = CellGeometry()
    res, up, _ = unit_cell_result(g, 8, 40, d_max=1e-9 / g.L)
    assert np.abs(up.F).max() < 1e-9          # nothing but solver noise
    assert res["peak_force"] is None and res["valley_force"] is None
    assert res["bistable"] is False and res["zero_crossings"] == 0
    assert "no peak within the stroke" in res["note"]


def test_a_nanometre_stroke_through_the_pipeline():
    s, _ = analyse(_spec([0, 0, 0, 0], max_displacement_mm=1e-9))
    u = s["unit_cells"][0]
    assert u["peak_force"] is None and u["bistable"] is False and u["zero_crossings"] == 0
    assert s["uniform_rings"][0]["P1"] is None
    assert s["ring"]["peaks"] == [] and s["ring"]["valleys"] == []
    assert s["pv"]["needs_vacuum_to_reset"] is False
    # a real stroke still finds the seed cell's peak, valley and its two sign changes (down past the peak, up past
    # the valley; the start at zero is none): bistable
    res, _, _ = unit_cell_result(CellGeometry(), 8, 60)
    assert res["peak_force"] > 0 > res["valley_force"] and res["bistable"] and res["zero_crossings"] == 2


# --- no snap without a force drop (defect 6) ----------------------------------------------------
@pytest.mark.parametrize("h", [0.5, 1e-9])
def test_a_monostable_sleeve_has_no_snapping_events(h):
    s, _ = analyse(_spec([0, 0, 0, 0], ({"t_mm": 1.0, "h_mm": h},)))
    assert "no peak within the stroke" in s["uniform_rings"][0]["note"]
    seq = s["sequence"]
    assert seq["events_loading"] == [] and seq["events_unloading"] == []
    assert seq["loading"] == [] and seq["unloading"] == []
    assert seq["symmetric"] is None and "nothing snapped" in seq["note"]


def test_a_bistable_sleeve_keeps_its_snapping_events():
    s, _ = analyse(_spec([0, 0, 0, 0]))
    seq = s["sequence"]
    assert seq["loading"] == [0] and seq["unloading"] == [0] and seq["symmetric"] is True
    assert any(e["snapped"] for e in seq["events_loading"])


# --- accuracy.ring_first_peak (defect 3) --------------------------------------------------------
@pytest.mark.parametrize("n", [2, 3, 6])
def test_ring_first_peak_is_null_not_missing_for_curved_rings_of_other_sizes(n):
    acc = accuracy([CellGeometry()], n)
    assert "ring_first_peak" in acc and acc["ring_first_peak"] is None
    assert set(acc) >= {"cell_peak", "cell_valley_depth", "ring_initial_stiffness", "ring_first_peak"}
    assert accuracy([CellGeometry()], 4)["ring_first_peak"] is not None      # measured at four cells
    assert accuracy([CellGeometry()], n, curvature=False)["ring_first_peak"] is None


# --- "version": true (defect 4) -----------------------------------------------------------------
@pytest.mark.parametrize("ver", [True, False, 2, "1"])
def test_version_must_be_the_number_one(ver):
    with pytest.raises(SceneError) as ei:
        SleeveSpec({"format": "metamaterial-sleeve", "version": ver, "cell_types": [SEED_TYPE], "ring": [0, 0]})
    assert ei.value.field == "version"
    assert repr(ver) in ei.value.message and "supported: 1" in ei.value.message
    assert SleeveSpec({"format": "metamaterial-sleeve", "version": 1, "cell_types": [SEED_TYPE],
                       "ring": [0, 0]}).N == 2


def test_the_frames_cycle_of_a_monostable_ring_has_no_snapping_events_either():
    """The same rule on the nonlinear 3-D frame's cycle (``model.frame_nonlinear``, ``frame3d_sequence``)."""
    from metamaterial_wb.core.sleeve.frame3d_sequence import frame_sequence
    out, _, _ = frame_sequence([CellGeometry(t=1.0, h=0.5)], [0, 0, 0, 0], 0.2, 40, 4, 0.0)
    assert out["events_loading"] == [] and out["events_unloading"] == []
    assert out["loading"] == [] and out["unloading"] == [] and out["symmetric"] is None
