"""Issue 18: the sleeve cell's reference checked against its element formulation (``bench/fe_cell_elements.py``):
the table extrapolates each formulation exactly when the error is a known power of h, and the fourth reduced mesh
is judged against the reference's error bar as it is (inside or how far outside)."""
import pytest

from metamaterial_wb.bench import fe_cell_elements as ce


def _runs(scale):
    """Peak 0.6e-3 and valley -0.11e-3 with an h^2 error ``scale / r^2`` (relative), on r = 1..4."""
    return [{"r": r, "pv": [0.13, 0.6e-3 * (1 + scale / r ** 2), 0.6, -0.11e-3 * (1 + scale / r ** 2)]}
            for r in (1, 2, 3, 4)]


def test_each_formulation_is_extrapolated_and_the_fourth_mesh_is_judged_against_the_reference():
    el = {"refinements": [1, 2, 3, 4], "runs": {"reduced": _runs(0.1), "corners": _runs(0.3), "beam": _runs(1.0)}}
    for name in ("reduced", "corners", "beam"):
        p, ep, v, ev = ce.extrapolated(el["runs"][name])
        assert p == pytest.approx(0.6e-3, rel=1e-6) and v == pytest.approx(-0.11e-3, rel=1e-6)
    r4 = el["runs"]["reduced"][-1]["pv"]
    ok = {"pv": [0.13, 0.6e-3, 0.6, -0.11e-3], "err": [0.0, 1.01 * (r4[1] - 0.6e-3), 0.0, 0.5 * abs(r4[3] + 0.11e-3)]}
    text = "\n".join(ce.markdown_lines({"elements": el, "fe_extrapolated": ok}))
    assert "| CPE8R everywhere | 0.660 / -0.1210 |" in text
    assert "| 0.600 +- 0.004 / -0.1100 +- 0.0007 |" in text          # the error: the finest mesh to it
    assert "the peak lies inside its bar, the valley outside its bar by 1.0 bars" in text
    assert "extrapolated, they agree within their error bars" in text
    spread = 100 * (1 + 1.0 / 16) / (1 + 0.1 / 16) - 100
    assert f"still differ by {spread:.1f} % on the peak" in text
    assert ce.markdown_lines({"fe_extrapolated": ok}) == []
    s = ce.reference_sentence({"elements": el, "fe_extrapolated": ok})
    assert "lands outside its error bar on the valley" in s and "within their error bars." in s
    wide = dict(ok, err=[0.0, 1.0, 0.0, 1.0])
    assert "inside its error bars on both the peak and the valley" in ce.reference_sentence(
        {"elements": el, "fe_extrapolated": wide})
    assert ce.reference_sentence({"fe_extrapolated": ok}) == ""
