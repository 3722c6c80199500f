"""A failure of the parallel machinery (a pool process killed, a Dask worker that cannot import the package)
is one clear MetamaterialError naming the pool or scheduler and the cause, not a raw traceback; the CLI prints
it as one line and exits 2."""
import os
import signal
import subprocess
import sys
import threading
import time

import pytest

from metamaterial_wb.core.errors import MetamaterialError

HERE = os.path.dirname(os.path.abspath(__file__))


def _nap(problem, seconds):
    time.sleep(seconds)
    return problem, seconds


def test_a_pool_process_killed_mid_run_is_a_clear_error():
    import multiprocessing as mp

    from metamaterial_wb.parallel import make_mapper
    mapper, n = make_mapper(workers=2)
    try:
        assert mapper(_nap, "p", [0.0, 0.0]) == [("p", 0.0), ("p", 0.0)]        # the pool is up
        victim = next(iter(mapper._pool._processes.values()))
        threading.Timer(1.0, os.kill, (victim.pid, signal.SIGKILL)).start()
        t0 = time.time()
        with pytest.raises(MetamaterialError, match=r"^--workers 2: a process of the local process pool ended "
                                                    r"abruptly \(killed by SIGKILL\)") as err:
            mapper(_nap, "p", [3.0] * 4)
        assert time.time() - t0 < 10
        assert "\n" not in str(err.value)
        # a later call starts a new pool
        assert mapper(_nap, "q", [0.0]) == [("q", 0.0)]
    finally:
        mapper.close()
    deadline = time.time() + 5
    while mp.active_children() and time.time() < deadline:
        time.sleep(0.1)
    assert not mp.active_children()


def test_an_error_of_the_function_itself_passes_unchanged():
    from metamaterial_wb.parallel import make_mapper
    mapper, _ = make_mapper(workers=2)
    try:
        with pytest.raises(ZeroDivisionError):
            mapper(_divide, 1.0, [1.0, 0.0])
        assert mapper(_divide, 1.0, [2.0]) == [0.5]        # the pool is still usable
    finally:
        mapper.close()


def _divide(problem, x):
    return problem / x


def test_cli_with_a_pool_process_killed_prints_one_line_and_exits_2(tmp_path):
    sys.path.insert(0, HERE)
    from test_interrupt import session_pids, start_cli
    from inverse_helpers import planted_result, scene_with
    import json
    from metamaterial_wb.core.scene import Scene
    s = scene_with(Scene.grid(12, 12), [("H1,1", 0.6), ("V2,3", 0.5)])
    (tmp_path / "t.json").write_text(json.dumps(planted_result(s)))
    bare = s.to_dict()
    bare["actuators"] = []
    (tmp_path / "s.json").write_text(json.dumps(bare))
    p = start_cli(tmp_path, "out")
    deadline = time.time() + 60
    while len(session_pids(p.pid)) < 3:
        assert p.poll() is None and time.time() < deadline, "the pool never started"
        time.sleep(0.1)
    time.sleep(3.0)
    assert p.poll() is None
    victim = max(pid for pid in session_pids(p.pid) if pid != p.pid)
    os.kill(victim, signal.SIGKILL)
    try:
        _, err = p.communicate(timeout=30)
    except subprocess.TimeoutExpired:
        os.killpg(p.pid, signal.SIGKILL)
        p.communicate()
        pytest.fail("the CLI did not end after a pool process was killed")
    assert p.returncode == 2, err[-3000:]
    assert "Traceback" not in err, err[-3000:]
    last = err.strip().splitlines()[-1]
    assert last.startswith("error: --workers 2: a process of the local process pool ended abruptly"), last
    time.sleep(0.5)
    assert session_pids(p.pid) == []


@pytest.fixture()
def scheduler_with_a_bare_worker(tmp_path):
    """A Dask scheduler (in this process) and one worker started from a folder and an environment where
    metamaterial_wb cannot be imported (as a dask-worker started without the checkout on PYTHONPATH)."""
    distributed = pytest.importorskip("distributed")
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    with distributed.LocalCluster(n_workers=0, processes=True, dashboard_address=None) as cl:
        w = subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_worker", cl.scheduler_address,
                              "--nthreads", "1", "--no-nanny", "--no-dashboard"], cwd=str(tmp_path), env=env,
                             stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        try:
            with distributed.Client(cl.scheduler_address, timeout="10s") as c:
                c.wait_for_workers(1, timeout=30)
            yield cl.scheduler_address
        finally:
            w.terminate()
            try:
                w.wait(10)
            except subprocess.TimeoutExpired:
                w.kill()
                w.wait()


def test_a_dask_worker_that_cannot_import_the_package_is_a_clear_error(scheduler_with_a_bare_worker):
    from metamaterial_wb.core.scene import Scene
    from metamaterial_wb.parallel import make_mapper
    addr = scheduler_with_a_bare_worker
    mapper, n = make_mapper(scheduler=addr)
    try:
        assert n == 1
        with pytest.raises(MetamaterialError, match=rf"^--scheduler {addr}: a worker cannot import metamaterial_wb "
                                                    r"\(start dask-worker with the checkout on PYTHONPATH"):
            mapper(Scene.from_dict, Scene.grid(3, 3), [{}])
    finally:
        mapper.close()


def test_dask_failure_translation():
    """The errors the Dask client raises when its machinery fails (seen in practice) name the scheduler."""
    import concurrent.futures as cf

    from metamaterial_wb.parallel import dask_failure
    where = "--scheduler tcp://h:1"
    e = dask_failure(Exception("ModuleNotFoundError(\"No module named 'metamaterial_wb'\")"), where)
    assert str(e).startswith(f"{where}: a worker cannot import metamaterial_wb (start dask-worker with the "
                             "checkout on PYTHONPATH")
    e = dask_failure(ModuleNotFoundError("No module named 'scipy'", name="scipy"), where)
    assert str(e).startswith(f"{where}: a worker cannot import scipy")
    e = dask_failure(cf.CancelledError("one_blas_thread-de2bfb1e-6"), where)
    assert str(e).startswith(f"{where}: the work was dropped") and "one_blas_thread" not in str(e)
    e = dask_failure(OSError("Timed out trying to connect"), where)
    assert str(e).startswith(f"{where}: lost the connection") and "Timed out" in str(e)
    assert dask_failure(ZeroDivisionError("x"), where) is None        # an error of the function itself
    assert dask_failure(Exception("something else"), where) is None
