"""Issue 18: the mesh error of the sleeve figures (``benchmarks/bench_sleeve_convergence.py``): Richardson over
meshes of n, 2n, 4n elements per beam half on a sequence whose limit is known, the tables it writes into
docs/sleeves.md."""
import math
import os

import pytest
from scriptload import load_script

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def _bench():
    return load_script("benchmarks/bench_sleeve_convergence.py", "bench_sleeve_conv")


def test_figure_row_extrapolates_a_second_order_mesh_sequence():
    b = _bench()
    meshes = (12, 24, 48)
    vals = [3.16 + 40.0 / n ** 2 for n in meshes]          # beam elements converge as h^2 = 1 / n^2
    r = b.figure_row("P1", meshes, vals, 24)
    assert r["extrapolated"] == pytest.approx(3.16) and r["order"] == pytest.approx(2.0)
    assert r["default_value"] == pytest.approx(vals[1])
    # the default mesh's error is its true error plus the (here exact) extrapolation's correction
    assert r["default_error"] == pytest.approx(40.0 / 24 ** 2 + 40.0 / 48 ** 2)
    md = b.table([r], "Error of X")
    assert "+-" in md and "bench_sleeve_convergence.py" in md and "| P1 | " in md


def test_figure_row_on_a_constant_figure_has_zero_error_and_no_order():
    b = _bench()
    r = b.figure_row("lift", (12, 24, 48), [17.13, 17.13, 17.13], 24)
    assert r["default_error"] == 0.0 and r["extrapolated"] == 17.13 and math.isnan(r["order"])


def test_splice_replaces_only_between_its_markers():
    b = _bench()
    doc = "a\n<!-- sleeve-conv:cell:begin -->\nold\n<!-- sleeve-conv:cell:end -->\nb\n"
    out = b.splice(doc, "cell", "new\n")
    assert out == "a\n<!-- sleeve-conv:cell:begin -->\nnew\n<!-- sleeve-conv:cell:end -->\nb\n"


def test_sleeves_doc_figures_carry_their_mesh_error():
    text = open(os.path.join(REPO, "docs", "sleeves.md")).read()
    for key, n in (("cell", 2), ("rings", 22), ("walker", 4)):
        block = text[text.index(f"<!-- sleeve-conv:{key}:begin -->"):text.index(f"<!-- sleeve-conv:{key}:end -->")]
        rows = [ln for ln in block.splitlines() if ln.startswith("| ") and not ln.startswith("| figure")]
        assert len(rows) == n and all("+-" in ln for ln in rows), key


def test_lean_angles_are_compared_modulo_a_turn():
    b = _bench()
    assert b.unwrap_deg([-180.0, 180.0, -179.5]) == pytest.approx([-180.0, -180.0, -179.5])
    r = b.figure_row("lean", (12, 24, 48), b.unwrap_deg([-180.0, 180.0, 180.0]), 24)
    assert r["default_error"] == pytest.approx(0.0)
