"""A sleeve spec's ``design_map`` range ``[min, max, count]`` with count 1 and min != max silently mapped min
alone (``"t_over_L": [0.045, 0.072, 1]`` dropped 0.072; session 35 audit). The rule now: count 1 is one value,
``[v, v, 1]``; a count of 2 to 40 spans min to max, so min < max (``[v, v, 3]`` would compute the same curves
three times). Anything else is refused naming the field and the values, before any work."""
import os
import sys

import pytest

from clihelpers import one_line_error, run_cli
from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.core.sleeve.spec import SleeveSpec

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import hostile_corpus as hc  # noqa: E402


def _spec(key, value):
    return SleeveSpec(hc.sleeve_with({("design_map",): {key: value}}))


@pytest.mark.parametrize("key, value", [("t_over_L", [0.045, 0.072, 1]), ("h_over_L", [0.3, 0.42, 1]),
                                        ("t_over_L", [0.05, 0.05, 2]), ("h_over_L", [0.4, 0.4, 40])])
def test_a_count_that_does_not_fit_min_and_max_is_refused(key, value):
    with pytest.raises(SceneError) as ei:
        _spec(key, value)
    assert ei.value.field == f"design_map.{key}"
    assert f"{value[0]:g}" in ei.value.message and f"{value[1]:g}" in ei.value.message
    assert "count" in ei.value.message


@pytest.mark.parametrize("key, value", [("t_over_L", [0.05, 0.05, 1]), ("h_over_L", [0.3, 0.42, 2]),
                                        ("h_over_L", [0.6, 0.6, 1])])
def test_one_value_or_a_span_loads(key, value):
    assert _spec(key, value).design_map[key] == tuple(value)


def test_the_audit_spec_is_refused_by_the_command(tmp_path):
    p = tmp_path / "sl_dm_n1.json"
    p.write_text('{"format": "metamaterial-sleeve", "version": 1, "name": "seed combination 2 (asymmetric)", '
                 '"L_mm": 18, "c_mm": 4, "delta_mm": 0.5, "T_mm": 1.8, "shear_modulus_MPa": 28, '
                 '"cell_types": [{"t_mm": 1.098, "h_mm": 7.092}, {"t_mm": 1.098, "h_mm": 7.488}], '
                 '"ring": [0, 0, 1, 1], "actuator": {"core_diameter_mm": 24.6, "membrane_kPa_per_mL": 0}, '
                 '"design_map": {"t_over_L": [0.045, 0.072, 1], "h_over_L": [0.3, 0.42, 5]}}', encoding="utf-8")
    r = run_cli("sleeve", p, "--out", tmp_path / "x", "--no-plots", "--quiet")
    one_line_error(r, "design_map.t_over_L")
    assert "0.045" in r.stderr and "0.072" in r.stderr
    assert not (tmp_path / "x").exists()
