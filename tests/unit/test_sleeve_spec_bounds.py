"""Issue 19: every numeric field of a sleeve spec has a physical range. Just outside each bound the spec is
refused with an error that names the field, the value and the allowed range; at the bound it loads.

The out-of-range cases are the hostile corpus's (``hostile_corpus.SLEEVE_BOUNDS``; the corpus also runs
them through the ``sleeve`` command); the in-range ones below sit exactly on a bound each."""
import math
import os
import sys

import pytest

from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.core.sleeve.spec import SleeveSpec

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import hostile_corpus as hc  # noqa: E402


@pytest.mark.parametrize("cid,changes,field", hc.SLEEVE_BOUNDS, ids=[b[0] for b in hc.SLEEVE_BOUNDS])
def test_just_outside_a_bound_is_refused_naming_field_value_and_range(cid, changes, field):
    with pytest.raises(SceneError) as ei:
        SleeveSpec(hc.sleeve_with(changes))
    e = ei.value
    assert e.field == field, (e.field, e.message)
    assert "allowed" in e.message, e.message
    leaf = list(changes.values())[-1]
    value = leaf if not isinstance(leaf, dict) else list(leaf.values())[-1]
    if isinstance(value, list):
        value = {"ring-short": 1, "ring-long": 33}.get(cid, value)
    if not isinstance(value, list) and cid not in ("ring-bed", "rings-height", "T-tube"):
        assert repr(value) in e.message, e.message     # the value the user wrote
    if "[" in e.message or "(" in e.message:
        assert "]" in e.message or ")" in e.message


SMALLEST = {("L_mm",): 2, ("c_mm",): 0.4, ("delta_mm",): 0.2, ("T_mm",): 0.4,
            ("cell_types",): [{"t_mm": 0.4, "h_mm": 1.2}], ("ring",): [0, 0, 0, 0],
            ("actuator",): {}}       # 2.7 mm inside: the cap is the default, which follows the inner diameter

AT_BOUND = [
    ("smallest printable cell", SMALLEST),
    ("L max, 2 cells", {("L_mm",): 200, ("ring",): [0, 1]}),
    ("c max", {("c_mm",): 10.8}),
    ("delta max", {("delta_mm",): 18}),
    ("T max, 8 cells", {("T_mm",): 36, ("ring",): [0, 1] * 4, ("actuator",): {}}),
    ("G max", {("shear_modulus_MPa",): 5000}),
    ("t max", {("cell_types", 0, "t_mm"): 4.5}),
    ("h max", {("cell_types", 1, "h_mm"): 10.8}),
    ("rings max", {("rings",): 12}),
    ("ring max", {("ring",): [0, 1] * 16}),
    ("model max", {("model",): {"elements_cell": 80, "elements_ring": 80, "steps": 2000, "imperfection": 0.1,
                                "pillar_tip": 12, "max_displacement_mm": 180}}),
    ("model min", {("model",): {"elements_cell": 2, "elements_ring": 2, "steps": 20, "imperfection": 0,
                                "pillar_tip": 3}}),
    ("integral floats", {("model",): {"elements_cell": 16.0, "steps": 160.0}}),
    # the cap at most the sleeve's inner diameter N (L + c) / pi - T (26.21 mm for the base's four cells) less two
    # 0.4 mm walls of the end ring it sits in
    ("actuator max", {("actuator",): {"core_diameter_mm": 4 * 22 / math.pi - 1.8 - 0.8, "membrane_kPa_per_mL": 10000}}),
    ("design map bounds", {("design_map",): {"t_over_L": [0.01, 0.25, 40], "h_over_L": [0.6, 0.6, 1],
                                             "elements": 80}}),
    ("walker bounds", {("walker",): {"foot_length_mm": 300, "body_length_mm": 1000, "contact_band_mm": 100}}),
    ("walker foot zero", {("walker",): {"foot_length_mm": 0}}),
    ("walker all defaults", {("walker",): {}}),
    ("design map all defaults", {("design_map",): {}}),
]


def test_a_cap_just_wider_than_its_end_ring_holds_is_refused():
    top = 4 * 22 / math.pi - 1.8 - 0.8
    with pytest.raises(SceneError) as ei:
        SleeveSpec(hc.sleeve_with({("actuator", "core_diameter_mm"): top + 1e-6}))
    assert ei.value.field == "actuator.core_diameter_mm" and f"(0, {top:.6g}]" in ei.value.message


@pytest.mark.parametrize("name,changes", AT_BOUND, ids=[a[0] for a in AT_BOUND])
def test_on_the_bound_loads(name, changes):
    spec = SleeveSpec(hc.sleeve_with(changes))
    assert spec.N >= 2


def test_integer_fields_are_integers_never_truncated():
    spec = SleeveSpec(hc.sleeve_with({("model",): {"elements_cell": 16.0, "steps": 160.0}}))
    assert spec.n_el_cell == 16 and isinstance(spec.n_el_cell, int) and spec.steps == 160
