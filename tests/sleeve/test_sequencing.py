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
