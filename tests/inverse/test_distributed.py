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


def test_cli_on_a_dask_scheduler_equals_the_local_cli(tmp_path):
    """``inverse --scheduler tcp://...`` (a LocalCluster started here) writes the same answer as ``--workers 1``."""
    import json
    import os
    import subprocess
    import sys

    distributed = pytest.importorskip("distributed")
    from metamaterial_wb import REPO_DIR
    s = scene_with(Scene.grid(4, 4), [("H1,1", 0.6), ("V2,3", 0.5)])
    (tmp_path / "t.json").write_text(json.dumps(planted_result(s)))
    bare = s.to_dict()
    bare["actuators"] = []
    (tmp_path / "s.json").write_text(json.dumps(bare))
    env = dict(os.environ, PYTHONPATH=REPO_DIR)

    def cli(out, *extra):
        p = subprocess.run([sys.executable, "-m", "metamaterial_wb", "inverse", str(tmp_path / "s.json"), "--target",
                            str(tmp_path / "t.json"), "--servos", "2", "--out", str(tmp_path / out), "--evaluate",
                            "quadratic", "--no-picture", *extra], capture_output=True, text=True, env=env, timeout=600)
        assert p.returncode == 0, p.stderr
        return json.loads((tmp_path / out / "report.json").read_text())

    local = cli("local")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cl:
        remote = cli("remote", "--scheduler", cl.scheduler_address)
    assert remote["scheduler"] == cl.scheduler_address and remote["workers"] == 2
    assert remote["placement"] == local["placement"]
    assert remote["errors"]["quadratic"]["rms_mm"] == local["errors"]["quadratic"]["rms_mm"]
    assert (tmp_path / "local" / "scene.json").read_text() == (tmp_path / "remote" / "scene.json").read_text()


def test_unreachable_scheduler_is_a_clear_error(tmp_path):
    from metamaterial_wb.core.errors import MetamaterialError
    from metamaterial_wb.parallel import make_mapper
    pytest.importorskip("distributed")
    with pytest.raises(MetamaterialError, match="cannot connect"):
        make_mapper(scheduler="tcp://127.0.0.1:1")


def test_pool_is_spawned_on_a_python_interpreter_from_a_threaded_program(problem_and_local, monkeypatch):
    """The GUI runs the search on a background thread inside FreeCAD, whose ``sys.executable`` is FreeCAD:
    the pool must not fork a threaded program (Python 3.12+ warns, it can deadlock) and must start its
    workers on a real Python interpreter."""
    import sys
    import threading
    import warnings
    from metamaterial_wb import parallel
    pb, local = problem_and_local
    monkeypatch.setattr(sys, "executable", "/usr/bin/freecadcmd")      # as inside FreeCAD
    assert parallel.python_executable().rsplit("/", 1)[-1].startswith("python")
    out = {}

    def run():
        with warnings.catch_warnings():
            warnings.simplefilter("error", DeprecationWarning)
            mapper, n = parallel.make_mapper(workers=2)
            try:
                out["res"] = search_placement(pb, 2, strategy="greedy", screen=6, mapper=mapper, workers=n)
                out["method"] = mapper._pool._mp_context.get_start_method()
            except BaseException as exc:          # noqa: BLE001 - reported below
                out["exc"] = exc
            finally:
                mapper.close()

    idle = threading.Event()
    other = threading.Thread(target=idle.wait, daemon=True)             # the program is multi-threaded
    other.start()
    t = threading.Thread(target=run)
    t.start()
    t.join(300)
    idle.set()
    assert "exc" not in out, repr(out.get("exc"))
    assert out["method"] == "spawn"
    _same(out["res"], local)


def test_pool_without_an_interpreter_says_to_use_one_worker(monkeypatch):
    import shutil
    import sys
    from metamaterial_wb import parallel
    from metamaterial_wb.core.errors import MetamaterialError
    monkeypatch.setattr(sys, "executable", "/nonexistent/freecad")
    monkeypatch.setattr(sys, "base_exec_prefix", "/nonexistent")
    monkeypatch.setattr(shutil, "which", lambda name: None)
    with pytest.raises(MetamaterialError, match="use 1 worker"):
        parallel.python_executable()
