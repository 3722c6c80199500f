"""Placement search (core/inverse/search.py): planted placements recovered, exhaustive optimum found."""
import numpy as np
import pytest

from inverse_helpers import planted_result, scene_with
from metamaterial_wb.core.errors import MetamaterialError
from metamaterial_wb.core.inverse.fit import Problem
from metamaterial_wb.core.inverse.search import exhaustive, search_placement
from metamaterial_wb.core.inverse.targets import parse_target
from metamaterial_wb.core.scene import Scene


def _problem(n, acts, noise=0.0, seed=0):
    s = scene_with(Scene.grid(n, n), acts)
    nodes = planted_result(s)["nodes"]
    if noise:
        rng = np.random.default_rng(seed)
        nodes = [dict(nd, position_mm=list(np.array(nd["position_mm"]) + rng.normal(0, noise, 3))) for nd in nodes]
    return Problem(s, parse_target(s, {"nodes": nodes}))


@pytest.mark.parametrize("n,acts", [
    (4, [("H1,1", 0.6), ("V2,3", 0.5)]),
    (5, [("H0,1", 0.8), ("V3,3", -0.6), ("H4,0", 0.5)]),
    (6, [("V1,0", 0.9), ("H3,4", 0.7)]),
])
def test_planted_placement_recovered(n, acts):
    pb = _problem(n, acts)
    res = search_placement(pb, len(acts))
    assert set(res.joints) == {j for j, _ in acts}
    assert res.fit.cost < 1e-16
    want = dict(acts)
    assert np.allclose(res.fit.values[0], [want[j] for j in res.joints], atol=1e-6)


def test_forbidden_joint_is_never_used():
    pb = _problem(4, [("H1,1", 0.6), ("V2,3", 0.5)])
    res = search_placement(pb, 2, forbidden=["H1,1"])
    assert "H1,1" not in res.joints and res.fit.cost > 1e-12
    with pytest.raises(MetamaterialError, match="H9,9"):
        search_placement(pb, 2, forbidden=["H9,9"])
    with pytest.raises(MetamaterialError, match="servos"):
        search_placement(pb, 40)


@pytest.fixture(scope="module")
def unreachable_4x4():
    # three planted servos plus noise: two servos cannot reach it, the optimum is not planted
    pb = _problem(4, [("H0,0", 0.7), ("V2,1", -0.5), ("H3,2", 0.6)], noise=0.05, seed=1)
    return pb, exhaustive(pb, 2)


@pytest.mark.parametrize("strategy", ["linearised", "greedy"])
def test_4x4_two_servos_finds_the_exhaustive_optimum_of_an_unreachable_target(unreachable_4x4, strategy):
    pb, (best, best_cost, costs) = unreachable_4x4
    assert len(costs) > 200
    res = search_placement(pb, 2, strategy=strategy)
    assert res.fit.cost <= best_cost * (1 + 1e-6)
    assert set(res.joints) == set(best)


def test_round_off_costs_do_not_unseat_the_free_field_bound():
    """Two exact fits (costs at round-off, 7.4e-12 and 8.5e-12 mm^2 on the fish's tail target) do not make the
    free-field lower bound "no bound" (the progress line said the free field had not converged); a placement
    that is really below it does."""
    from metamaterial_wb.core.inverse.search import COST_FLOOR, at_bound, below_bound
    assert not below_bound(7.37086e-12, 8.4932e-12) and at_bound(7.37086e-12, 8.4932e-12)
    assert below_bound(0.5, 1.0) and not below_bound(1.0 - 5e-7, 1.0)
    assert at_bound(1.0 + 5e-7, 1.0) and not at_bound(1.0 + 1e-5, 1.0)
    assert below_bound(0.0, 10 * COST_FLOOR) and not below_bound(0.0, 0.5 * COST_FLOOR)
