"""The search on a process pool and on a Dask LocalCluster gives exactly the local answer."""
import numpy as np
import pytest

from inverse_helpers import planted_result, scene_with
from metamaterial_wb.core.inverse.fit import Problem
from metamaterial_wb.core.inverse.search import search_placement
from metamaterial_wb.core.inverse.targets import parse_target
from metamaterial_wb.core.scene import Scene


@pytest.fixture(scope="module")
def problem_and_local():
    s = scene_with(Scene.grid(5, 5), [("H0,1", 0.8), ("V3,3", -0.6), ("H4,0", 0.5)])
    rng = np.random.default_rng(4)
    nodes = [dict(n, position_mm=list(np.array(n["position_mm"]) + rng.normal(0, 0.05, 3)))
             for n in planted_result(s)["nodes"]]
    pb = Problem(s, parse_target(s, {"nodes": nodes}))
    return pb, search_placement(pb, 2, strategy="greedy", screen=6)


def _same(a, b):
    assert a.joints == b.joints
    assert a.fit.cost == b.fit.cost
    assert np.array_equal(a.fit.values, b.fit.values)
    assert (a.fits, a.screened) == (b.fits, b.screened)


def test_process_pool_equals_local(problem_and_local):
    from metamaterial_wb.parallel import make_mapper
    pb, local = problem_and_local
    mapper, n = make_mapper(workers=2)
    try:
        res = search_placement(pb, 2, strategy="greedy", screen=6, mapper=mapper, workers=n)
    finally:
        mapper.close()
    _same(res, local)


def test_dask_local_cluster_equals_local(problem_and_local):
    distributed = pytest.importorskip("distributed")
    from metamaterial_wb.parallel import make_mapper
    pb, local = problem_and_local
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cl:
        mapper, n = make_mapper(scheduler=cl.scheduler_address)
        try:
            assert n == 2
            res = search_placement(pb, 2, strategy="greedy", screen=6, mapper=mapper, workers=n)
        finally:
            mapper.close()
    _same(res, local)
