"""Unit-cell trends and the cylindrical ring (seed 002, figures 2B-2F)."""
import numpy as np
import pytest

from metamaterial_wb.core.sleeve.analysis import extrema, snapped
from metamaterial_wb.core.sleeve.cell import CellGeometry, polygon_area
from metamaterial_wb.core.sleeve.pipeline import ring_thresholds, ring_trace, unit_cell_result

L = 18.0


def cell(tl, hl):
    return CellGeometry(L=L, t=tl * L, h=hl * L)


def test_unit_cell_is_bistable_with_one_peak_and_one_valley():
    res, up, down = unit_cell_result(cell(1 / 18, 7.5 / 18), n_el=8, steps=120)
    p, v = extrema(up.F)
    assert len(p) == 1 and len(v) == 1
    assert res["peak_force"] > 0 > res["valley_force"]
    assert res["bistable"] and res["zero_crossings"] >= 2     # three zeros incl. the origin


def test_thickness_dominates_peak_force_amplitude_changes_it_little():
    """Seed section 2.1 over its design ranges t/L 0.045-0.072, h/L 0.30-0.42."""
    def peak(tl, hl):
        return unit_cell_result(cell(tl, hl), n_el=6, steps=90)[0]
    a, b = peak(0.045, 0.36), peak(0.072, 0.36)
    c, d = peak(0.058, 0.30), peak(0.058, 0.42)
    ratio_t = b["peak_force"] / a["peak_force"]
    ratio_h = d["peak_force"] / c["peak_force"]
    assert ratio_t > 3.0                           # ~ (0.072/0.045)^3 = 4.1
    assert abs(np.log(ratio_h)) < 0.25 * abs(np.log(ratio_t))
    assert abs(ratio_h - 1) < 0.2
    assert b["valley_force"] < a["valley_force"] < 0   # thicker: lower valley


def test_uniform_four_cell_ring_has_two_peaks_two_valleys_second_peak_lower():
    m, up, down = ring_trace([cell(1 / 18, 7.5 / 18)], [[0, 0, 0, 0]], n_el=6, steps=120)
    p, v = extrema(up.F)
    assert len(p) == 2 and len(v) == 2
    assert up.F[p[1]] < up.F[p[0]]                 # destructive coupling
    assert up.F[v[0]] > up.F[v[1]]
    # between the first peak and the second valley the ring tilts and half the cells are snapped
    mid = (p[0] + v[1]) // 2
    assert np.degrees(np.linalg.norm(up.tilt[mid])) > 5
    s = snapped(up.states, m.state_geoms)          # one column per beam half
    n = s.shape[1]
    at_v1 = s[v[0]]
    assert at_v1.sum() == n // 2                    # two of the four edge pillars' beams inverted
    assert s[0].sum() == 0 and s[-1].sum() == n
    # untilted outside that window
    assert np.linalg.norm(up.tilt[p[0] // 2]) < 1e-3
    # unloading with the same imperfection keeps the tilt direction (seed section 2.2)
    k = int(np.argmax(np.linalg.norm(down.tilt, axis=1)))
    kk = int(np.argmax(np.linalg.norm(up.tilt, axis=1)))
    assert np.dot(down.tilt[k], up.tilt[kk]) > 0


def test_second_peak_is_lost_for_thick_low_beams():
    """Seed section 2.2: thick, low beams give one peak and one valley (in our model from t/L ~0.075
    at h/L 0.30, just past the seed's range; the seed's ring also stops tilting there, ours still
    tilts: docs/sleeves.md)."""
    _, up, _ = ring_trace([cell(0.09, 0.28)], [[0] * 4], n_el=6, steps=90, unload=False)
    P1, V2, n_p, n_v = ring_thresholds(up)
    assert n_p == 1 and n_v == 1
    _, up, _ = ring_trace([cell(0.072, 0.30)], [[0] * 4], n_el=6, steps=90, unload=False)
    assert ring_thresholds(up)[2] == 2           # still two peaks at the seed's corner


def test_second_peak_is_lost_with_three_cells_around():
    """Seed SI S4.1: with 2 or 3 cells around, the second peak disappears (four cells: two peaks,
    tested above). On the tighter ring the beams' arcs are more curved, their ends are pushed out
    more and the tilted bar swings the pillar tips further: the snap weakens. (Two cells: one main
    peak after a small shoulder where the ring starts to tilt, too small to call robustly: not
    tested; docs/sleeves.md.)"""
    _, up, _ = ring_trace([cell(1 / 18, 7.5 / 18)], [[0] * 3], n_el=6, steps=120, unload=False)
    P1, V2, n_p, n_v = ring_thresholds(up)
    assert n_p == 1 and n_v == 1
    _, up4, _ = ring_trace([cell(1 / 18, 7.5 / 18)], [[0] * 4], n_el=6, steps=120, unload=False)
    assert ring_thresholds(up4)[2] == 2


def test_ring_curvature_is_what_changes_the_trends():
    """Without the ring's curvature (flat cells side by side) the second valley falls with t like
    the unit cell's valley and a three-cell ring keeps two peaks; with it, the valley rises (seed
    figure 2F) and the second peak goes (test above)."""
    def v2(tl, curvature):
        _, up, _ = ring_trace([cell(tl, 0.372)], [[0] * 4], n_el=6, steps=110, unload=False,
                              curvature=curvature)
        return ring_thresholds(up)[1]
    assert v2(0.065, False) < v2(0.055, False)
    assert v2(0.065, True) > v2(0.055, True)
    # and it is what removes the second peak of a three-cell ring
    _, up, _ = ring_trace([cell(1 / 18, 7.5 / 18)], [[0] * 3], n_el=6, steps=120, unload=False, curvature=False)
    assert ring_thresholds(up)[2] == 2


def test_rings_in_series_share_the_force():
    """Two identical rings in series: before any snapping each carries the force of one ring at
    half the displacement (independent check of the series coupling)."""
    g = cell(1 / 18, 7.5 / 18)
    _, one, _ = ring_trace([g], [[0] * 4], n_el=6, steps=40, d_max=0.04, unload=False)
    _, two, _ = ring_trace([g], [[0] * 4, [0] * 4], n_el=6, steps=40, d_max=0.08, unload=False)
    assert np.allclose(two.F, one.F, rtol=1e-5, atol=1e-9)


@pytest.mark.parametrize("layout,n_beams", [("single", 1), ("double", 2)])
def test_cell_outline_areas_add_up(layout, n_beams):
    g = CellGeometry(layout=layout)
    holes = g.holes()
    void = sum(polygon_area(p) for p in holes.values())
    # material = bars + pillars + beams, estimated independently from the dimensions
    beams = n_beams * 2 * g.t * (g.L - g.c) / 2 * 1.25      # arc length ~1.25 x chord for h/L = 0.42
    bars = g.width * g.c
    assert 0 < g.width * g.height - void
    assert g.width * g.height - void > bars + 0.8 * beams
    assert g.width * g.height - void < bars + g.c * g.height * 2 + 1.6 * beams
