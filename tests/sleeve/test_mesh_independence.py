"""Issue 18, item 4: the sleeve's lean (tilt direction) and snapping count do not depend on the mesh.

Before, the imperfection pushed the top plate towards an edge pillar, i.e. along a mirror axis of
the ring: which neighbour joined that pillar in the first-snapping group was a symmetric
bifurcation decided by round-off (and the eigensolver's arbitrary vector in a degenerate pair), so
the lean turned by 45-90 degrees between meshes and between loading and unloading. Now the bias
points between a cell and a pillar (on no mirror axis), degenerate eigenpairs are resolved inside
their span, and the same lean comes out at every mesh."""
import numpy as np
import pytest

from metamaterial_wb.core.sleeve.analysis import extrema, snapped
from metamaterial_wb.core.sleeve.cell import CellGeometry
from metamaterial_wb.core.sleeve.pipeline import ring_trace, simulated_sequence

L = 18.0


def _run(gs, pattern, n_el):
    m, up, down = ring_trace(gs, pattern, n_el=n_el, steps=110)
    sim = simulated_sequence(m, up, down)
    p, v = extrema(up.F)
    s = snapped(up.states, m.state_geoms)
    return sim, [int(s[i].sum()) for i in v], len(p)


def _angle(a, b):
    return abs((a - b + 180.0) % 360.0 - 180.0)


@pytest.mark.parametrize("case", ["uniform", "combination 2"])
def test_lean_and_snapping_count_are_the_same_at_two_meshes(case):
    if case == "uniform":
        gs, pattern, meshes = [CellGeometry(L=L, t=1.0, h=7.5)], [[0] * 4], (6, 16)
    else:
        gs, pattern, meshes = [CellGeometry(L=L, t=0.061 * L, h=b * L) for b in (0.394, 0.416)], [[0, 0, 1, 1]], (6, 12)
    (a, na, pa), (b, nb, pb) = (_run(gs, pattern, n) for n in meshes)
    assert pa == pb == 2 and na == nb == [4, 8]          # two of four pillars (4 of 8 halves), then all
    assert _angle(a["lean_loading_deg"], b["lean_loading_deg"]) < 2.0
    assert _angle(a["lean_unloading_deg"], b["lean_unloading_deg"]) < 2.0
    assert a["lean_reverses"] == b["lean_reverses"] == (case != "uniform")
    if case == "uniform":                                 # the tilt kept on unloading (seed 2.2)
        assert _angle(a["lean_loading_deg"], a["lean_unloading_deg"]) < 2.0
    assert a["loading"] == b["loading"] and a["unloading"] == b["unloading"]


def test_eight_cell_ring_first_valley_half_the_ring_at_the_chord():
    """Eight cells around: at the first valley two adjacent pillars have inverted (rise 1.38 h) and
    their two neighbours sit just below the chord (0.95 h): four adjacent pillars, half the ring, at
    or past inversion - the seed's "half of the unit cells" (SI S4.1) - although a strict rise > h
    counts only 4 of 16 halves. The same at 12 and 16 elements (8 are too few: three pillars)."""
    g = [CellGeometry(L=L, t=1.0, h=7.5)]
    states = []
    for n in (12, 16):
        m, up, _ = ring_trace(g, [[0] * 8], n_el=n, steps=110, unload=False)
        p, v = extrema(up.F)
        assert len(p) == 2 and len(v) == 2
        units = np.array(m.state_units)
        h = np.array([c.h / c.L for c in m.state_geoms])
        r = np.array([np.mean(up.states[v[0], units == u] / h[units == u]) for u in range(8)])
        states.append(r)
        order = np.sort(r)[::-1]
        assert order[1] > 1.2 and 0.85 < order[3] < 1.0 and order[4] < 0.5
        top = np.nonzero(r > 0.85)[0]
        gaps = np.diff(np.sort(np.concatenate([top, top + 8])))
        assert len(top) == 4 and np.sum(gaps == 1) >= 3          # four adjacent pillars around the ring
    assert np.allclose(np.sort(states[0]), np.sort(states[1]), atol=0.05)
