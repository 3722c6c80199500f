"""Issue 18: the reference error of the long-horizon travel figures (``bench_dynamics.py dtstudy``): the same
run at dt, dt/2, dt/4, ... and Richardson; checked here on travel sequences whose limit is known."""
import math
import os

import pytest
from scriptload import load_script

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def _bench():
    return load_script("benchmarks/bench_dynamics.py", "bench_dynamics_dt")


def test_dt_study_of_a_second_order_sequence_finds_its_limit():
    b = _bench()
    out = b.dt_study_rows(lambda dt: 180.0 + 2e4 * dt * dt, (0.004, 0.002, 0.001))
    assert out["extrapolated_mm"] == pytest.approx(180.0) and out["order"] == pytest.approx(2.0)
    finest = out["rows"][-1]
    assert out["error_mm"] == pytest.approx(finest["travel_mm"] - 180.0)
    # a coarser step's error covers its true error (distance to the finest plus the finest's own)
    for r in out["rows"]:
        assert r["error_mm"] >= abs(r["travel_mm"] - 180.0) - 1e-9


def test_dt_study_of_a_non_monotone_sequence_reports_at_least_the_last_difference():
    b = _bench()
    seq = {0.004: 181.15, 0.002: 181.20, 0.001: 180.90, 0.0005: 180.89, 0.00025: 180.85}   # measured belt8, 10 s
    out = b.dt_study_rows(seq.get, tuple(seq))
    assert math.isnan(out["order"])                       # no asymptotic order: nothing is extrapolated
    assert out["extrapolated_mm"] == pytest.approx(180.85)
    assert out["error_mm"] >= 0.04 - 1e-9
    assert out["rows"][1]["error_mm"] >= abs(181.20 - 180.85)      # the documented 2 ms figure's error


def test_dtstudy_command_is_wired():
    b = _bench()
    assert b.DT_STUDY_STEPS == tuple(sorted(b.DT_STUDY_STEPS, reverse=True))
    assert all(abs(a / c - 2.0) < 1e-12 for a, c in zip(b.DT_STUDY_STEPS, b.DT_STUDY_STEPS[1:]))
    assert callable(b.run_dtstudy)


def test_dt_study_table_prints_every_step_with_its_error():
    b = _bench()
    out = b.dt_study_rows(lambda dt: 180.0 + 2e4 * dt * dt, (0.004, 0.002, 0.001))
    out.update({"scene": "belt8.json", "seconds": 10.0, "method": "implicit (BDF2)", "start": "as_built"})
    md = b.dt_study_markdown(out, "observed order 2")
    rows = [ln for ln in md.splitlines() if ln.startswith("| ") and ln[2].isdigit()]
    assert len(rows) == 3 and all("+-" in ln for ln in rows)
    assert "Finest step: 180.02 +- 0.02 mm" in md


def test_dynamics_fidelity_doc_holds_the_measured_dt_tables():
    text = open(os.path.join(REPO, "docs", "dynamics-fidelity.md")).read()
    for key in ("flat", "incline10", "worm_crawl"):
        block = text[text.index(f"<!-- dt-study:{key}:begin -->"):text.index(f"<!-- dt-study:{key}:end -->")]
        rows = [ln for ln in block.splitlines() if ln.startswith("| ") and ln[2].isdigit()]
        assert len(rows) >= 5 and all("+-" in ln for ln in rows), key
