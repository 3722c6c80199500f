"""Thin distribution layer for the inverse design's independent candidate evaluations.

``make_mapper(workers, scheduler)`` returns a callable ``mapper(fn, problem, batches)`` with the
semantics of ``[fn(problem, b) for b in batches]`` (the order is kept):

* ``workers`` > 1: a local ``concurrent.futures.ProcessPoolExecutor``; the problem is sent once per
  worker (its initializer), not once per batch;
* ``scheduler`` ``tcp://HOST:PORT`` (``tls://`` too; a bare ``HOST:PORT`` is tcp; or a
  ``distributed.Client`` / ``LocalCluster``): Dask ``distributed`` (an address is checked by
  :func:`check_scheduler_address` first, a failed connection is a :class:`SceneError` too); the problem
  is scattered once to every worker (``broadcast=True``) and the batches are mapped over it
  (``pure=False``: every batch runs).

Nothing here is home-made distribution: the pool is the standard library's, the cluster Dask's. Lives
above ``core`` (which stays numpy/scipy only and just calls the mapper it is given).
"""
import concurrent.futures as cf
import multiprocessing as mp
import os
import pickle
import re
import shutil
import sys

from metamaterial_wb.core.errors import MetamaterialError, SceneError

_PROBLEM = None
_SCHEDULER_RE = re.compile(r"^(?:(tcp|tls|ws|wss|ucx)://)?(\[[0-9A-Fa-f:.]+\]|[A-Za-z0-9_](?:[A-Za-z0-9_.-]*"
                           r"[A-Za-z0-9_])?):(\d{1,5})$")
_INPROC_RE = re.compile(r"^inproc://\S+$")      # Dask's in-process transport (a LocalCluster without processes)
SCHEDULER_ALLOWED = ("a Dask scheduler address tcp://HOST:PORT (or tls://, ws://, wss://, ucx://; port 1-65535), "
                     "e.g. tcp://127.0.0.1:8786, or an in-process inproc:// address")


def check_scheduler_address(address, option="--scheduler"):
    """``address`` if it is a Dask scheduler address ``tcp://HOST:PORT`` / ``tls://HOST:PORT`` / ``HOST:PORT``
    (port 1-65535), else a :class:`SceneError` naming ``option``, the value and what is allowed. Only the form
    is checked (no connection, no Dask needed)."""
    if isinstance(address, str) and _INPROC_RE.match(address):
        return address
    m = _SCHEDULER_RE.match(address) if isinstance(address, str) else None
    if m is None or not 1 <= int(m.group(3)) <= 65535:
        raise SceneError(option, f"{address!r}; allowed: {SCHEDULER_ALLOWED}")
    return address


def _init_worker(blob):
    global _PROBLEM
    _PROBLEM = pickle.loads(blob)


def _run_in_worker(fn, batch):
    return fn(_PROBLEM, batch)


def python_executable():
    """The Python interpreter the pool's workers run on.

    Inside FreeCAD ``sys.executable`` is FreeCAD itself (``freecad`` / ``freecadcmd``), which cannot run a
    worker; the interpreter of the same version beside it (``python3.11`` ...) can. Raises
    :class:`MetamaterialError` when none is found.
    """
    exe = sys.executable or ""
    if os.path.basename(exe).lower().startswith("python"):
        return exe
    version = "python%d.%d" % sys.version_info[:2]
    for cand in (os.path.join(sys.base_exec_prefix, "bin", version),
                 os.path.join(os.path.dirname(exe), version), os.path.join(os.path.dirname(exe), "python"),
                 os.path.join(os.path.dirname(exe), "python.exe"), shutil.which(version)):
        if cand and os.path.isfile(cand) and os.access(cand, os.X_OK):
            return cand
    raise MetamaterialError(f"workers > 1: no {version} interpreter found beside {exe or 'this program'} to run "
                            "the process pool's workers; use 1 worker (or a Dask scheduler)")


def spawn_context():
    """A ``spawn`` multiprocessing context on :func:`python_executable`.

    Not ``fork``: the GUI runs the search from a background thread of a multi-threaded program, where a
    forked child can deadlock on a lock held by another thread (Python 3.14 warns about exactly this).
    """
    ctx = mp.get_context("spawn")
    ctx.set_executable(python_executable())
    return ctx


class PoolMapper:
    def __init__(self, workers):
        self.workers = int(workers)
        self._pool = None
        self._problem = None

    def __call__(self, fn, problem, batches):
        if self._pool is None or problem is not self._problem:
            self.close()
            blob = pickle.dumps(problem)
            self._pool = cf.ProcessPoolExecutor(self.workers, mp_context=spawn_context(),
                                                initializer=_init_worker, initargs=(blob,))
            self._problem = problem
        return list(self._pool.map(_run_in_worker, [fn] * len(batches), batches))

    def close(self):
        if self._pool is not None:
            self._pool.shutdown(wait=True, cancel_futures=True)
        self._pool = None
        self._problem = None


class DaskMapper:
    def __init__(self, scheduler):
        if isinstance(scheduler, str):
            check_scheduler_address(scheduler)
        try:
            from distributed import Client
        except ImportError:
            raise MetamaterialError("--scheduler needs dask.distributed (Debian: python3-distributed)") from None
        self._own = False
        if isinstance(scheduler, str):
            try:
                self.client = Client(scheduler, timeout="10s")
            except Exception as exc:  # noqa: BLE001 - OSError, TimeoutError, Dask's ValueError / TypeError ...
                reason = " ".join(str(exc).split())[:300] or type(exc).__name__
                raise SceneError("--scheduler", f"{scheduler!r}: cannot connect to a Dask scheduler ({reason}); "
                                                f"allowed: the address of a running scheduler, tcp://HOST:PORT") \
                    from None
            self._own = True
        elif hasattr(scheduler, "scatter"):
            self.client = scheduler
        else:
            self.client = Client(scheduler)
            self._own = True
        self._problem = None
        self._future = None
        self.workers = max(1, len(self.client.scheduler_info().get("workers", {})))

    def __call__(self, fn, problem, batches):
        if problem is not self._problem:
            self._future = self.client.scatter(problem, broadcast=True, hash=False)
            self._problem = problem
        futs = self.client.map(fn, [self._future] * len(batches), batches, pure=False)
        return self.client.gather(futs)

    def close(self):
        if self._own:
            self.client.close()


def make_mapper(workers=1, scheduler=None):
    """``(mapper or None, n_workers)``."""
    if scheduler is not None:
        m = DaskMapper(scheduler)
        return m, m.workers
    if workers is not None and int(workers) > 1:
        return PoolMapper(workers), int(workers)
    return None, 1
