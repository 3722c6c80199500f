"""Issue 18: the machinery that gives reference figures their own error (Richardson on refinement sequences,
the hinge aspect-ratio table's FE mesh error) on sequences whose limit is known."""
import os

import numpy as np
import pytest

from metamaterial_wb.bench import fe_study
from metamaterial_wb.bench.measures import convergence_error
from scriptload import load_script

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def test_convergence_error_recovers_a_known_limit_and_order():
    h = [0.4, 0.2, 0.1]
    for p in (1.0, 2.0, 3.0):
        ext, err, order = convergence_error(h, [5.0 + 0.7 * x ** p for x in h])
        assert ext == pytest.approx(5.0, abs=1e-12) and order == pytest.approx(p)
        # the error is the correction to the finest value, i.e. that value's true error
        assert err == pytest.approx(0.7 * 0.1 ** p)


def test_convergence_error_with_two_values_assumes_the_given_order():
    ext, err, p = convergence_error([2.0, 1.0], [1.0 + 4.0, 1.0 + 1.0])      # 1 + h^2
    assert (ext, err, p) == pytest.approx((1.0, 1.0, 2.0))
    ext, err, p = convergence_error([2.0, 1.0], [3.0, 2.0], order=1)          # 1 + h
    assert (ext, err) == pytest.approx((1.0, 1.0))


def test_convergence_error_does_not_extrapolate_an_oscillating_sequence():
    # 180.9 / 181.2 / 181.1-like: the differences change sign, so no order is observed and the error is
    # at least the last difference, the value is not moved
    ext, err, p = convergence_error([4, 2, 1], [181.1, 181.2, 180.9])
    assert ext == pytest.approx(180.9) and err == pytest.approx(0.3) and np.isnan(p)


def test_convergence_error_on_arrays_and_bad_input():
    ext, err, _ = convergence_error([0.4, 0.2, 0.1], [np.array([1 + x * x, 2 - x]) for x in (0.4, 0.2, 0.1)])
    assert ext == pytest.approx([1.0, 2.0]) and err == pytest.approx([0.01, 0.1])
    with pytest.raises(ValueError):
        convergence_error([1.0], [1.0])


def _row(L, beam, fe_of_h, sizes):
    return {"length_mm": L, "aspect": L / 0.8, "h_mm": sizes[-1], "wall_s": 1.0, "beam_diag": list(beam),
            "beam_bending": 2.0, "fe_diag": list(fe_of_h(sizes[-1])[:6]), "fe_bending": fe_of_h(sizes[-1])[6],
            "meshes": [{"h_mm": h, "wall_s": 1.0, "fe_diag": list(fe_of_h(h)[:6]), "fe_bending": fe_of_h(h)[6]}
                       for h in sizes]}


def test_aspect_table_rows_carry_their_fe_mesh_error():
    beam = np.arange(1.0, 7.0)
    true = 1.2 * np.concatenate([beam, [2.0]])                    # FE converges to 1.2 x beam, as h^2
    fe = lambda h: true * (1.0 + 0.5 * h * h)                      # noqa: E731
    row = _row(2.0, beam, fe, (0.4, 0.283))
    ratios, err = fe_study.aspect_uncertainty(row)
    assert ratios == pytest.approx(1.2 * (1 + 0.5 * 0.283 ** 2))
    # two meshes, order 2 assumed: the correction lands on the true limit (mesh ratio 0.4 / 0.283)
    assert ratios - err == pytest.approx(np.full(7, 1.2), rel=1e-9)
    md = fe_study.aspect_markdown([row])
    assert "+-" in md and "bench_fidelity_aspect_error.py" in md and "0.4, 0.283" in md
    # a study of one mesh says it has no error of its own instead of printing one
    one = dict(row)
    one.pop("meshes")
    assert np.all(np.isnan(fe_study.aspect_uncertainty(one)[1]))
    assert "+-" not in fe_study.aspect_markdown([one]) and "no error of its own" in fe_study.aspect_markdown([one])


def test_aspect_script_splices_only_its_section():
    mod = load_script("benchmarks/bench_fidelity_aspect_error.py", "bfae")
    doc = "# T\n\n### A\n\nkeep\n\n### Beam law against FE by hinge aspect ratio\n\nold | table\n\n### B\n\nkeep too\n"
    out = mod.splice(doc, "### Beam law against FE by hinge aspect ratio\n\nnew\n")
    assert "old" not in out and "new" in out
    assert out.startswith("# T\n\n### A\n\nkeep") and out.endswith("### B\n\nkeep too\n")


def test_fidelity_doc_aspect_table_has_errors():
    text = open(os.path.join(REPO, "docs", "fidelity.md")).read()
    sec = text[text.index("### Beam law against FE by hinge aspect ratio"):]
    sec = sec[:sec.index("\n#", 10)]
    rows = [ln for ln in sec.splitlines() if ln.startswith("| ") and ln[2].isdigit()]
    assert len(rows) == 4 and all(ln.count("+-") == 7 for ln in rows)
