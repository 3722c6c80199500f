"""Two-hysteron sequencing (seed 002, section 2.3) and the direct simulation of mixed rings."""
import numpy as np
import pytest

from metamaterial_wb.core.sleeve.analysis import pressure_control, pv_curve, two_hysteron_sequence
from metamaterial_wb.core.sleeve.cell import CellGeometry
from metamaterial_wb.core.sleeve.pipeline import ring_thresholds, ring_trace, simulated_sequence
from metamaterial_wb.core.sleeve.walker import loop_area, tip_trajectory

L = 18.0


@pytest.mark.parametrize("p1,p2,v1,v2,combo,symmetric", [
    (2.0, 1.0, 0.5, -0.5, 1, True),      # seed: 1) P1 > P2 & V1 > V2
    (2.0, 1.0, -0.5, 0.5, 2, False),     # 2) P1 > P2 & V1 < V2
    (1.0, 2.0, -0.5, 0.5, 3, True),      # 3) mirror image of 1
    (1.0, 2.0, 0.5, -0.5, 4, False),     # 4) mirror image of 2
])
def test_two_hysteron_rule_gives_the_seeds_four_combinations(p1, p2, v1, v2, combo, symmetric):
    s = two_hysteron_sequence([(p1, v1), (p2, v2)])
    assert s["combination"] == combo
    assert s["symmetric"] is symmetric
    first = 0 if p1 < p2 else 1
    assert s["loading"][0] == first                       # lowest forward threshold snaps first
    assert s["unloading"][0] == (0 if v1 > v2 else 1)      # highest backward threshold first


def _mixed(types):
    gs = [CellGeometry(L=L, t=a * L, h=b * L) for a, b in types]
    m, up, down = ring_trace(gs, [[0, 0, 1, 1]], n_el=6, steps=110)
    return m, up, down, simulated_sequence(m, up, down)


def test_mixed_ring_sequence_and_lean():
    """Seed combination 1 geometry (t/L 0.055 and 0.065 at h/L 0.372): the thinner type snaps
    first on loading (lower first peak, as the rule says); the lean reverses exactly when the
    simulated sequence is asymmetric; the mixed ring's first peak lies between the uniform rings'."""
    types = [(0.055, 0.372), (0.065, 0.372)]
    thr = []
    for a, b in types:
        _, up, _ = ring_trace([CellGeometry(L=L, t=a * L, h=b * L)], [[0] * 4], n_el=6, steps=110, unload=False)
        thr.append(ring_thresholds(up)[:2])
    rule = two_hysteron_sequence(thr)
    m, up, down, sim = _mixed(types)
    assert sim["loading"] == rule["loading"] == [0, 1]
    assert sim["lean_reverses"] == (not sim["symmetric"])
    assert sim["max_tilt_loading_deg"] > 5 and sim["max_tilt_unloading_deg"] > 5
    p1 = float(np.max(up.F[: len(up.F) // 3]))
    assert min(thr[0][0], thr[1][0]) < p1 < max(thr[0][0], thr[1][0])


def test_seed_combination_1_is_symmetric():
    """Seed combination 1 (h/L 0.372, t/L 0.055 and 0.065): the thinner type has the lower first
    peak (snaps first) and - on the curved ring - the lower second valley, so the thicker type
    snaps back first: a symmetric sequence, the lean kept on unloading (seed section 2.3, fig. 3B).
    The rule's thresholds from the uniform rings and the direct simulation of the mixed ring agree."""
    types = [(0.055, 0.372), (0.065, 0.372)]
    thr = []
    for a, b in types:
        _, up, _ = ring_trace([CellGeometry(L=L, t=a * L, h=b * L)], [[0] * 4], n_el=6, steps=110, unload=False)
        thr.append(ring_thresholds(up)[:2])
    assert thr[0][0] < thr[1][0]            # P1 rises with t
    assert thr[0][1] < thr[1][1]            # V2 rises with t on the ring (unlike the flat cell's valley)
    rule = two_hysteron_sequence(thr)
    assert rule["symmetric"] is True and rule["loading"] == [0, 1] and rule["unloading"] == [1, 0]
    m, up, down, sim = _mixed(types)
    assert sim["symmetric"] is True
    assert sim["loading"] == [0, 1] and sim["unloading"] == [1, 0]
    assert sim["lean_reverses"] is False


def test_seed_combination_2_is_asymmetric_and_bends_both_ways():
    """Seed combination 2 (t/L 0.061, h/L 0.394 and 0.416): asymmetric sequence; the actuator leans
    one way on loading and the other way on unloading (checked robust for 12-32 elements per
    segment; 6 are too few for this pair, whose first peaks differ by only 0.2 %)."""
    gs = [CellGeometry(L=L, t=0.061 * L, h=b * L) for b in (0.394, 0.416)]
    m, up, down = ring_trace(gs, [[0, 0, 1, 1]], n_el=12, steps=110)
    sim = simulated_sequence(m, up, down)
    assert sim["symmetric"] is False
    assert sim["loading"] == sim["unloading"]
    assert sim["lean_reverses"] is True
    assert sim["max_tilt_loading_deg"] > 5 and sim["max_tilt_unloading_deg"] > 5


def test_pressure_control_jumps_on_a_cubic():
    """p(V) = V^3 - 3V + 3 has a local max p=5 at V=-1 and a local min p=1 at V=1 (closed form):
    under increasing pressure the state jumps at p=5 to V=2; under decreasing pressure at p=1 to V=-2."""
    V = np.linspace(-2.5, 2.5, 50001)
    p = V ** 3 - 3 * V + 3
    Vp, pp, jumps = pressure_control(V, p, loading=True)
    assert len(jumps) == 1
    assert jumps[0][0] == pytest.approx(5, abs=1e-3)
    assert jumps[0][1] == pytest.approx(-1, abs=1e-3) and jumps[0][2] == pytest.approx(2, abs=1e-3)
    assert np.all(np.diff(pp) >= -1e-12)
    Vu, pu, ju = pressure_control(V[::-1], p[::-1], loading=False)
    assert len(ju) == 1 and ju[0][0] == pytest.approx(1, abs=1e-3)
    assert ju[0][2] == pytest.approx(-2, abs=1e-3)


def test_pv_is_fd_rescaled_by_cap_area():
    d = np.array([0.0, 1.0, 2.0])         # mm
    F = np.array([0.0, 10.0, 5.0])        # N
    A = 100.0                             # mm^2
    V, p = pv_curve(d, F, A)
    assert np.allclose(V, [0, 0.1, 0.2])                 # mL
    assert np.allclose(p, [0, 100.0, 50.0])              # kPa (10 N / 100 mm^2 = 0.1 MPa)
    V2, p2 = pv_curve(d, F, A, membrane_kPa_per_mL=10.0)
    assert np.allclose(p2 - p, 10.0 * V)


def test_walker_geometry():
    sq = [[0, 0], [1, 0], [1, 1], [0, 1]]
    assert loop_area(sq) == pytest.approx(1.0)
    assert loop_area(sq[::-1]) == pytest.approx(-1.0)
    d = np.array([0.0, 2.0])
    tip, _ = tip_trajectory(d, np.zeros((2, 2)), 30.0, 10.0, direction=[1.0, 0.0])
    assert np.allclose(tip, [[0, 40], [0, 42]])
    # constant-curvature bend by psi: tip of a foot-less leg lies on the circle arc
    psi = 0.4
    tip, _ = tip_trajectory(np.zeros(1), np.array([[0.0, psi]]), 30.0, 0.0, direction=[1.0, 0.0])
    R = 30.0 / psi
    assert tip[0, 0] == pytest.approx(R * (1 - np.cos(psi)))
    assert tip[0, 1] == pytest.approx(R * np.sin(psi))


# --- an incomplete order is neither symmetric nor asymmetric (audit) -----------------------------------------------
# A synthetic single-layout ring of four cells: beam halves 2k, 2k + 1 of cell k; edge pillar k (a hysteron) carries
# half 2k + 1 and half 2k + 2 (mod 8). Rises over h (/ L) below zero before a hysteron snaps, above after.
SYN_H = 0.4


def _syn_ring(pattern):
    from types import SimpleNamespace
    types = [pattern[j // 2] for j in range(8)]
    units = [(j - 1) % 8 // 2 for j in range(8)]                  # half 1, 2 -> pillar 0; ... half 7, 0 -> pillar 3
    g = SimpleNamespace(h=SYN_H, L=1.0)
    return SimpleNamespace(state_types=types, state_geoms=[g] * 8, state_units=units, N=4,
                           cell_index=[(0, k, t) for k, t in enumerate(pattern)])


def _syn_path(groups, units, loading=True, drop=True):
    """A path of 7 states on which the hysterons of ``groups[0]`` change state at the 3rd, ``groups[1]`` at the 5th
    (all snapped at the end of loading, none at the end of unloading); its force has a peak (``drop``) or rises
    monotonically along d."""
    from types import SimpleNamespace
    n = 7
    d = np.linspace(0.0, 1.0, n)
    rises = np.full((n, 8), SYN_H - 0.1)
    for k0, grp in zip((2, 4), groups):
        for j, u in enumerate(units):
            if u in grp:
                rises[k0:, j] = SYN_H + 0.1
    F = np.array([0.0, 1.0, 2.0, 1.0, 0.5, 1.5, 3.0]) if drop else d.copy()
    if not loading:                         # traced from d_max back to 0: the states' order runs the other way
        d, F, rises = d[::-1], F[::-1], rises[::-1]
    return SimpleNamespace(d=d, F=F, states=rises, jumps=[], noise=0.0, tilt=np.full((n, 2), 1e-3))


def _syn_sequence(pattern, load_groups, unload_groups, unload_drop=True):
    """``simulated_sequence`` of the synthetic ring: the hysterons of ``load_groups`` snap in that order on loading,
    those of ``unload_groups`` snap back in that order on unloading."""
    m = _syn_ring(pattern)
    up = _syn_path(load_groups, m.state_units)
    # unloading traced from d_max down: the group that snaps back first changes at the path's start
    down = _syn_path(unload_groups[::-1], m.state_units, loading=False, drop=unload_drop)
    return simulated_sequence(m, up, down)


def test_complete_orders_keep_their_verdict():
    """[0, 0, 1, 1]: pillar 0 is type 0's, pillar 2 type 1's; the order is read from them (the mixed pillars 1
    and 3 go with either group). Unloading that reverses loading is symmetric, one that repeats it asymmetric."""
    sim = _syn_sequence([0, 0, 1, 1], [{0, 1}, {2, 3}], [{2, 3}, {0, 1}])
    assert sim["loading"] == [0, 1] and sim["unloading"] == [1, 0] and sim["symmetric"] is True
    assert not sim.get("note")
    sim = _syn_sequence([0, 0, 1, 1], [{2, 3}, {0, 1}], [{2, 3}, {0, 1}])
    assert sim["loading"] == [1, 0] and sim["unloading"] == [1, 0] and sim["symmetric"] is False
    assert not sim.get("note")


def test_a_type_without_a_pillar_of_its_own_leaves_the_symmetry_undetermined():
    """The audit's ring [0, 0, 0, 1]: pillars 0 and 1 sit between type-0 cells, 2 and 3 between the types, so type
    1 has no pillar to be read from; the order was [0] | [0] and called symmetric although the first pillars to snap
    (2, 3 here) were the first to snap back. Now symmetric is None with a note naming type 1 and why."""
    sim = _syn_sequence([0, 0, 0, 1], [{2, 3}, {0, 1}], [{2, 3}, {0, 1}])
    assert sim["loading"] == [0] and sim["unloading"] == [0]
    assert sim["events_loading"] and sim["events_unloading"]
    assert sim["symmetric"] is None
    assert "type 1 has no pillar between two cells of its own type" in sim["note"]
    assert "type 0" not in sim["note"]


def test_a_ring_of_mixed_pillars_only_has_no_order():
    """[0, 1, 0, 1]: every pillar sits between the two types; the order used to fall back to all pillars, whose
    types come out sorted ([0, 1] | [0, 1], "asymmetric", whatever the path did)."""
    from metamaterial_wb.core.sleeve.analysis import snap_order
    m = _syn_ring([0, 1, 0, 1])
    up = _syn_path([{2, 3}, {0, 1}], m.state_units)
    order, events = snap_order(up, m.state_types, m.state_geoms, m.state_units)
    assert order == [] and [e[2] for e in events] == [[2, 3], [0, 1]]
    sim = _syn_sequence([0, 1, 0, 1], [{2, 3}, {0, 1}], [{0, 1}, {2, 3}])
    assert sim["symmetric"] is None
    assert "type 0 has no pillar" in sim["note"] and "type 1 has no pillar" in sim["note"]


def test_a_path_without_a_snap_leaves_the_symmetry_undetermined():
    """The frame's 40-step cycle: loading [0, 1], unloading [] (no force drop on the coarse unloading path) was
    called asymmetric."""
    sim = _syn_sequence([0, 0, 1, 1], [{0, 1}, {2, 3}], [{2, 3}, {0, 1}], unload_drop=False)
    assert sim["loading"] == [0, 1] and sim["unloading"] == [] and sim["events_unloading"] == []
    assert sim["symmetric"] is None
    assert "the unloading path showed no snap" in sim["note"] and "model.steps" in sim["note"]


def test_a_type_that_does_not_snap_on_a_path_leaves_the_symmetry_undetermined():
    """Type 1's pillars never change on loading (the stroke ends first): [0] | [0] is no evidence of symmetry."""
    sim = _syn_sequence([0, 0, 1, 1], [{0}, set()], [set(), {0}])
    assert sim["loading"] == [0] and sim["unloading"] == [0]
    assert sim["symmetric"] is None
    assert "on the loading path no pillar of type 1 changed state" in sim["note"]
    assert "on the unloading path no pillar of type 1 changed state" in sim["note"]


def test_the_words_for_a_sequence():
    """stdout and the plot's title: "undetermined" for an incomplete order, "nothing snapped" without events."""
    from metamaterial_wb.cli.sleeve import symmetry_word
    ev = [{"d": 0.2, "cells": [0], "snapped": True}]
    assert symmetry_word({"symmetric": None, "events_loading": ev, "events_unloading": []}) == "undetermined"
    assert symmetry_word({"symmetric": None, "events_loading": [], "events_unloading": []}) == "nothing snapped"
    assert symmetry_word({"symmetric": True, "events_loading": ev, "events_unloading": ev}) == "symmetric"
    assert symmetry_word({"symmetric": False, "events_loading": ev, "events_unloading": ev}) == "asymmetric"


def test_the_frames_cycle_reads_the_order_the_same_way():
    """``frame3d_sequence.sequence`` (``model.frame_nonlinear``): the same verdict and note on the frame's paths."""
    from types import SimpleNamespace
    from metamaterial_wb.core.sleeve.frame3d_sequence import sequence
    m = _syn_ring([0, 0, 0, 1])
    ring = SimpleNamespace(cells=m.state_geoms[:2], state_types=m.state_types, units=m.state_units, rings=1)
    up = _syn_path([{2, 3}, {0, 1}], m.state_units)
    down = _syn_path([{0, 1}, {2, 3}], m.state_units, loading=False)

    def as_frame(p):
        return {"d": p.d, "F": p.F, "rises": p.states, "tilt": np.column_stack([p.tilt, np.zeros(len(p.d))])}
    s = sequence(ring, as_frame(up), as_frame(down))
    assert s["loading"] == [0] and s["unloading"] == [0] and s["symmetric"] is None
    assert "type 1 has no pillar between two cells of its own type" in s["note"]
    ring.state_types = [[0, 0, 1, 1][j // 2] for j in range(8)]
    ring.cells = m.state_geoms[:2]
    s = sequence(ring, as_frame(up), as_frame(_syn_path([{0, 1}, {2, 3}], m.state_units, loading=False, drop=False)))
    assert s["loading"] == [1, 0] and s["unloading"] == [] and s["symmetric"] is None
    assert "the unloading path showed no snap" in s["note"]


def test_accuracy_note_calls_an_incomplete_frame_order_undetermined():
    """The accuracy line on the nonlinear frame's sequence: a path without its snap (events on the other path) is
    an incomplete order, not 'nothing snapped' (before: 'unloading [] (nothing snapped)' for a 40-step frame)."""
    from metamaterial_wb.core.sleeve.accuracy import frame_sequence_note
    fs = {"elements": 6, "seconds": 3.0, "loading": [0, 1], "unloading": [], "symmetric": None,
          "events_loading": [{"d": 0.1, "units": [0], "snapped": True}], "events_unloading": [],
          "max_tilt_loading_deg": 2.0, "max_tilt_unloading_deg": 1.0, "lean_reverses": False,
          "agrees_with_model": False}
    beam = {"loading": [0, 1], "unloading": [1, 0], "symmetric": True, "frame3d_nl": fs}
    note = frame_sequence_note(beam)
    assert "unloading [] (undetermined)" in note and "nothing snapped" not in note, note
    fs.update(events_loading=[], loading=[])
    assert "loading [], unloading [] (nothing snapped)" in frame_sequence_note(beam)
