"""Issue 18: a mixed ring (two cell types around it) as a curved CalculiX solid, loaded and unloaded.

The seed's mixed combination 2 (examples/sleeve.json, ring [0, 0, 1, 1]) had been run on the solid only as
uniform rings of each type. Its types differ in h (combination 1's in t), so their cells differ in height and in
where the beam meets the edge pillar. The mixed mesh puts a flat top at the taller cell's height and every cell's
side at the thickest beam's end heights, so neighbours share their nodes: checked here against the single cells'
outlines (area), the wrap (volume), the seam, each cell's own beam ends, and a tiny real ccx cycle.
"""
import math

import numpy as np
import pytest

from metamaterial_wb.bench.fe_ring3d_combinations import combination_cells
from metamaterial_wb.fe import ccx, sleeve2d, sleeve3d

needs_ccx = pytest.mark.skipif(not ccx.available()[0],
                               reason="CalculiX (ccx) not installed (Debian calculix-ccx; not in every lane's root)")


def _mixed(key):
    a, b = combination_cells(key)
    return [a, a, b, b]


@pytest.mark.parametrize("key", ["1", "2"])
def test_mixed_outline_is_each_cells_own_outline_meeting_at_a_flat_top(key):
    cells = _mixed(key)
    H = max(g.height for g in cells)
    assert len({g.height for g in cells}) == 2                          # the types' cells differ in height
    m = sleeve2d.cell_mesh(cells, 2, 4)
    assert m.height == pytest.approx(H)
    # each cell is its own outline, its edge pillars (c wide in all) lengthened by the height it lacks; the
    # skewed pillar blocks (combination 1's beam thicknesses differ) must keep the area exactly
    own = sum(sleeve2d.cell_mesh(g, 2, 1).area() + (H - g.height) * g.c for g in cells)
    assert m.area() == pytest.approx(own, rel=1e-12)
    assert m.min_jacobian() > 0
    # conforming: the mixed ring has the uniform ring's node count (no node left unshared along a cell's side)
    assert m.n_nodes == sleeve2d.cell_mesh(cells[0], 2, 4).n_nodes
    bottom, top, pairs = sleeve2d._edges(m)                            # the seam's sides match node for node
    assert len(pairs) == len(sleeve2d._edges(sleeve2d.cell_mesh(cells[0], 2, 4))[2])
    assert np.all(m.nodes[top, 1] == pytest.approx(H))


def test_one_geometry_per_cell_of_one_type_is_the_uniform_ring():
    g = combination_cells("2")[0]
    a, b = sleeve2d.cell_mesh(g, 2, 4), sleeve2d.cell_mesh([g] * 4, 2, 4)
    assert np.array_equal(a.elements, b.elements)
    assert np.abs(a.nodes - b.nodes).max() < 1e-12 * g.L


@pytest.mark.parametrize("key", ["1", "2"])
def test_mixed_ring_wraps_and_each_half_ends_on_its_own_beam(key):
    cells = _mixed(key)
    m = sleeve3d.ring_mesh(cells, 4, 1, 1)
    assert m.volume() == pytest.approx(m.exact_volume(), rel=1e-5)
    assert m.min_jacobian() > 0
    assert m.nodes[:, 2].max() == pytest.approx(max(g.height for g in cells))
    ends = m.beam_ends()
    assert ends["cells"].tolist() == [0, 0, 1, 1, 2, 2, 3, 3]
    for half, k in enumerate(ends["cells"]):
        g = cells[k]
        inner = m.nodes[ends["inner"][half], 2]
        outer = m.nodes[ends["outer"][half], 2]
        assert inner == pytest.approx(float(g.centre_line(0.5 * g.c)), abs=1e-9)    # its own type's beam
        assert outer == pytest.approx(float(g.y_lower), abs=1e-9)
    phi = np.arctan2(m.nodes[:, 1], m.nodes[:, 0]) % (2 * math.pi)
    assert phi.max() - phi.min() > 1.9 * math.pi                        # all the way round


@pytest.mark.parametrize("field,value", [("L", 20.0), ("T", 2.0), ("c", 3.0), ("delta", 0.6)])
def test_cell_types_that_cannot_meet_are_refused_by_name(field, value):
    from dataclasses import replace
    a, b = combination_cells("2")
    with pytest.raises(ValueError, match=rf"{field} takes the values .*allowed: one {field}"):
        sleeve3d.ring_mesh([a, a, replace(b, **{field: value}), b], 4, 1, 1)
    with pytest.raises(ValueError, match=r"3 for a ring of 4 cells; allowed: one, or one per cell"):
        sleeve2d.cell_mesh([a, a, b], 1, 4)


def test_hysterons_snap_each_half_past_its_own_cells_h():
    cells = _mixed("2")
    m = sleeve3d.ring_mesh(cells, 4, 1, 1)
    ends = m.beam_ends()
    watch = np.unique(np.concatenate([ends["outer"].ravel(), ends["inner"].ravel()]))
    L = cells[0].L
    h0, h1 = cells[0].h / L, cells[2].h / L
    rise = h0 + 0.25 * (h1 - h0)            # past type 0's h, short of type 1's and of the two's mean
    u = np.zeros((2, watch.size, 3))
    outer = np.isin(watch, ends["outer"])
    u[1, outer, 2] = rise * L
    r, snapped = sleeve3d.hysterons(m, ends, u, watch)
    assert r[1] == pytest.approx(rise)
    # pillar 0 hangs between two type-0 cells, pillar 2 between two type-1 cells, 1 and 3 between the types
    assert snapped[1].tolist() == [True, False, False, False]
    assert not snapped[0].any()


def test_unloading_runs_on_along_an_amplitude_back_to_the_start():
    """One static step of time 2: the plate's rise follows 0 -> 1 -> 0, the bias moment 0 -> 1 -> 1 (a second
    step from the deformed ring does not converge in ccx)."""
    cells = _mixed("2")
    deck, meta = sleeve3d.ring_deck3d(cells, 4, 1, 1, d_max=0.1 * cells[0].L, increments=5, unload=True,
                                      element="C3D20")
    assert deck.count("*STEP") == 1 and meta["unload"]
    assert "*AMPLITUDE, NAME=UPDOWN\n0,0,1,1,2,0\n" in deck and "*AMPLITUDE, NAME=HOLD\n0,0,1,1,2,1\n" in deck
    assert "*STATIC\n0.2,2.0," in deck
    assert f"*BOUNDARY, AMPLITUDE=UPDOWN\nBOTTOM,1,3,0\n{sleeve3d.REF},1,2,0\n{sleeve3d.REF},3,3,1.8\n" in deck
    assert "*CLOAD, AMPLITUDE=HOLD\n" in deck
    plain, _ = sleeve3d.ring_deck3d(cells, 4, 1, 1, d_max=0.1 * cells[0].L, increments=5, element="C3D20")
    assert "AMPLITUDE" not in plain and "*STATIC\n0.2,1.0," in plain
    assert f"{sleeve3d.REF},0,0,{max(g.height for g in cells):.9g}" in deck          # the plate on the flat top


def test_dynamic_unloading_runs_the_same_amplitude_with_inertia():
    """The seed's FE was dynamic implicit: the same one step of time 2, under ``*DYNAMIC`` with the small density,
    the plate's rise along 0 -> 1 -> 0 (not the loading ramp, which would hold it at the top) and the bias held."""
    cells = _mixed("2")
    deck, meta = sleeve3d.ring_deck3d(cells, 4, 1, 1, d_max=0.1 * cells[0].L, increments=5, unload=True,
                                      element="C3D20", method="dynamic")
    assert deck.count("*STEP") == 1 and meta["unload"] and meta["method"] == "dynamic"
    assert "*DYNAMIC, ALPHA=-0.3\n0.2,2.0," in deck and "*DENSITY\n" in deck
    assert f"*BOUNDARY, AMPLITUDE=UPDOWN\nBOTTOM,1,3,0\n{sleeve3d.REF},1,2,0\n{sleeve3d.REF},3,3,1.8\n" in deck
    assert "*CLOAD, AMPLITUDE=HOLD\n" in deck and "RAMP" not in deck
    up, _ = sleeve3d.ring_deck3d(cells, 4, 1, 1, d_max=0.1 * cells[0].L, increments=5, element="C3D20",
                                 method="dynamic")
    assert "*BOUNDARY, AMPLITUDE=RAMP\n" in up and "*DYNAMIC, ALPHA=-0.3\n0.2,1.0," in up


def test_a_uniform_ring_stands_at_a_mixed_rings_top():
    a, b = combination_cells("2")
    plain, raised = sleeve2d.cell_mesh(a, 1, 4), sleeve2d.cell_mesh(a, 1, 4, top=b.height)
    assert raised.height == pytest.approx(b.height) and raised.n_nodes == plain.n_nodes
    assert raised.area() - plain.area() == pytest.approx(4 * (b.height - a.height) * a.c, rel=1e-12)
    assert sleeve3d.ring_mesh(a, 4, 1, 1, top=b.height).nodes[:, 2].max() == pytest.approx(b.height)
    for bad in (a.height - 0.1, a.height + 1.5 * a.L):
        with pytest.raises(ValueError, match=r"top: .* mm; allowed: from the tallest cell's height"):
            sleeve2d.cell_mesh(a, 1, 4, top=bad)


@needs_ccx
def test_tiny_mixed_cycle_comes_back_and_lies_between_its_uniform_rings():
    """Up to d/L 0.01 and back in two increments each (about 40 s): the unloading points are flagged, d falls back
    to 0 and the force with it (an elastic solid), and the mixed ring's first secant stiffness lies between the
    uniform rings' of its two types as they stand in it (each type's cells springs in parallel under one plate;
    the shorter type's at the mixed ring's flat top, its edge pillars lengthened: at its own lower top that ring is
    stiffer than the mixed one, measured)."""
    a, b = combination_cells("2")
    d_max = 0.01 * a.L
    c, info = sleeve3d.solve_ring3d([a, a, b, b], 4, 1, 1, d_max=d_max, increments=2, element="C3D20",
                                    partial=False, unload=True)
    down = c["unloading"]
    assert not down[0] and down[-1] and info["d_reached"] == pytest.approx(0.0, abs=1e-12)
    k = int(np.argmax(down))
    assert c["d"][k - 1] == pytest.approx(0.01) and np.all(np.diff(c["d"][k - 1:]) < 0)
    peak = np.abs(c["F"]).max()
    assert abs(c["F"][-1]) < 1e-3 * peak
    stiff = c["F"][k - 1] / c["d"][k - 1]
    uniform = []
    for g in (a, b):
        u, _ = sleeve3d.solve_ring3d(g, 4, 1, 1, d_max=d_max, increments=2, element="C3D20", partial=False,
                                     top=b.height)
        uniform.append(u["F"][-1] / u["d"][-1])
    assert min(uniform) < stiff < max(uniform)


def test_a_bad_bias_is_refused_with_its_allowed_range():
    """The plate's bias moment is an imperfection: a non-finite, negative or ring-sized one (above 1e-3 G L^2 R, the
    ring's first peak force times its radius) is refused before any deck is written, as a non-finite direction."""
    cells = _mixed("2")
    for bad in (float("nan"), -1e-5, 2e-3, float("inf")):
        with pytest.raises(ValueError, match=r"bias: .*; allowed: 0 to 0.001 \(G L\^2"):
            sleeve3d.ring_deck3d(cells, 4, 1, 1, bias=bad)
    with pytest.raises(ValueError, match=r"bias_angle: inf; allowed: a finite number"):
        sleeve3d.ring_deck3d(cells, 4, 1, 1, bias_angle=float("inf"))
    deck, meta = sleeve3d.ring_deck3d(cells, 4, 1, 1, bias=0.0)
    assert "*CLOAD" not in deck and meta["bias"] == 0.0
    with pytest.raises(ValueError, match=r"bias: nan; allowed: 0 to 0.001 \(G L\^2; a force bias"):   # the flat ring
        sleeve2d.ring_deck(cells[0], 4, 1, bias=float("nan"))
