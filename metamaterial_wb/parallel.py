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

Failures of the machinery (a pool process killed, the scheduler gone, a Dask worker that cannot import this
package) become one :class:`MetamaterialError` naming the pool or the scheduler and the cause; errors raised by
the evaluated function itself pass unchanged. Ctrl-C: the pool's workers ignore SIGINT (a terminal sends it to
the whole process group), the parent stops them (:meth:`PoolMapper.terminate`) and re-raises.

Nothing here is home-made distribution: the pool is the standard library's, the cluster Dask's. Lives
above ``core`` (which stays numpy/scipy only and just calls the mapper it is given).
"""
import concurrent.futures as cf
from concurrent.futures.process import BrokenProcessPool
import multiprocessing as mp
import os
import pickle
import re
import shutil
import signal
import sys
import time
import threading
from contextlib import contextmanager

from metamaterial_wb.core.errors import MetamaterialError, SceneError

_PROBLEM = None
_SCHEDULER_RE = re.compile(r"^(?:(tcp|tls|ws|wss|ucx)://)?(\[[0-9A-Fa-f:.]+\]|[A-Za-z0-9_](?:[A-Za-z0-9_.-]*"
                           r"[A-Za-z0-9_])?):([0-9]{1,5})$")       # ASCII digits: int() reads others too
_INPROC_RE = re.compile(r"^inproc://\S+$")      # Dask's in-process transport (a LocalCluster without processes)
SCHEDULER_ALLOWED = ("a Dask scheduler address tcp://HOST:PORT (or tls://, ws://, wss://, ucx://; port 1-65535), "
                     "e.g. tcp://127.0.0.1:8786, or an in-process inproc:// address")


def check_scheduler_address(address, option="--scheduler"):
    """``address`` if it is a Dask scheduler address ``tcp://HOST:PORT`` / ``tls://HOST:PORT`` / ``HOST:PORT``
    (port 1-65535), else a :class:`SceneError` naming ``option``, the value and what is allowed. Only the form
    is checked (no connection, no Dask needed)."""
    if isinstance(address, str) and _INPROC_RE.fullmatch(address):
        return address
    m = _SCHEDULER_RE.fullmatch(address) if isinstance(address, str) else None
    if m is None or not 1 <= int(m.group(3)) <= 65535:
        raise SceneError(option, f"{address!r}; allowed: {SCHEDULER_ALLOWED}")
    return address


def _init_worker(blob):
    global _PROBLEM
    try:
        signal.signal(signal.SIGINT, signal.SIG_IGN)    # Ctrl-C reaches the whole group: only the parent acts
    except (ValueError, OSError):  # pragma: no cover - not the main thread / no such signal
        pass
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


@contextmanager
def _no_sigint():
    """A second Ctrl-C while the pool is being stopped is ignored (the stop takes well under a second)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    try:
        old = signal.signal(signal.SIGINT, signal.SIG_IGN)
    except (ValueError, OSError):  # pragma: no cover
        yield
        return
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, old)


def _exit_text(code):
    if code is None or code == 0:
        return None
    if code < 0:
        try:
            return f"killed by {signal.Signals(-code).name}"
        except ValueError:
            return f"killed by signal {-code}"
    return f"exited with status {code}"


class PoolMapper:
    def __init__(self, workers):
        self.workers = int(workers)
        self._pool = None
        self._problem = None
        self._procs = []

    def __call__(self, fn, problem, batches):
        if self._pool is None or problem is not self._problem:
            self.close()
            blob = pickle.dumps(problem)
            self._pool = cf.ProcessPoolExecutor(self.workers, mp_context=spawn_context(),
                                                initializer=_init_worker, initargs=(blob,))
            self._problem = problem
        pool, futs = self._pool, []
        try:
            futs = [pool.submit(_run_in_worker, fn, b) for b in batches]
            self._procs = list((pool._processes or {}).values())     # the pool's processes, for terminate()
            return [f.result() for f in futs]
        except BrokenProcessPool:
            # the executor's own thread reaps the dead process (and stops the rest) while we read its exit code:
            # wait for every code (at most a second) so that the cause is the real one, not a guess
            deadline = time.monotonic() + 1.0
            while any(p.exitcode is None for p in self._procs) and time.monotonic() < deadline:
                time.sleep(0.02)
            causes = sorted({t for t in (_exit_text(p.exitcode) for p in self._procs) if t and "SIGTERM" not in t})
            self.terminate()
            cause = ", ".join(causes) if causes else "killed, or out of memory"
            raise MetamaterialError(f"--workers {self.workers}: a process of the local process pool ended abruptly "
                                    f"({cause}); the search stopped. Run again, or with --workers 1") from None
        except Exception:                  # raised by fn in a worker: the pool stays usable
            for f in futs:
                f.cancel()
            raise
        except BaseException:              # Ctrl-C (KeyboardInterrupt), SIGTERM (the CLI's _Signalled): stop now
            self.terminate()
            raise

    def terminate(self):
        """Stop the pool at once: pending batches are cancelled, the workers killed (no waiting for them)."""
        pool, self._pool, self._problem = self._pool, None, None
        if pool is None:
            return
        with _no_sigint():
            procs = list(set(self._procs) | set((getattr(pool, "_processes", None) or {}).values()))
            self._procs = []
            for p in procs:
                try:
                    p.terminate()
                except (OSError, AttributeError, ValueError):  # pragma: no cover - already gone / closed
                    pass
            pool.shutdown(wait=False, cancel_futures=True)
            for p in procs:
                try:
                    p.join(2.0)
                    if p.exitcode is None:
                        p.kill()
                        p.join(2.0)
                except (OSError, AttributeError, ValueError, AssertionError):  # pragma: no cover
                    pass
            manager = getattr(pool, "_executor_manager_thread", None)
            if manager is not None and manager is not threading.current_thread():
                manager.join(5.0)          # nothing left for the interpreter's exit to wait for

    def close(self):
        pool = self._pool
        if pool is None:
            return
        try:
            pool.shutdown(wait=True, cancel_futures=True)
        except BaseException:              # interrupted while waiting: stop the workers, not wait for them
            self.terminate()
            raise
        self._pool = None
        self._problem = None
        self._procs = []


class DaskMapper:
    def __init__(self, scheduler):
        if isinstance(scheduler, str):
            check_scheduler_address(scheduler)
        try:
            from distributed import Client
        except ImportError:
            raise MetamaterialError("--scheduler needs dask.distributed (Debian: python3-distributed)") from None
        self._own = False
        self._address = scheduler if isinstance(scheduler, str) else None
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

    @property
    def label(self):
        if self._address:
            return self._address
        return getattr(getattr(self.client, "scheduler", None), "address", None) or "the Dask scheduler"

    def __call__(self, fn, problem, batches):
        try:
            if problem is not self._problem:
                self._problem = None
                self._future = self.client.scatter(problem, broadcast=True, hash=False)
                self._problem = problem
            futs = self.client.map(fn, [self._future] * len(batches), batches, pure=False)
            return self.client.gather(futs)
        except KeyboardInterrupt:
            raise
        except BaseException as exc:       # noqa: BLE001 - asyncio's CancelledError is a BaseException
            err = dask_failure(exc, f"--scheduler {self.label}")
            if err is None:
                raise
            raise err from None

    def close(self):
        if self._own:
            self.client.close()


_NO_MODULE_RE = re.compile(r"No module named '([A-Za-z0-9_.]+)'")


def dask_failure(exc, where):
    """A :class:`MetamaterialError` for a failure of the Dask machinery (``where`` names the scheduler), or None
    when ``exc`` is an error of the evaluated function itself (it is passed on unchanged)."""
    import asyncio
    text = " ".join(str(exc).split())
    m = _NO_MODULE_RE.search(text)
    if isinstance(exc, ImportError) or (m is not None and type(exc) is Exception):
        # a worker could not unpickle the problem or the function (Dask sends the worker's error back as text)
        name = (getattr(exc, "name", None) or (m.group(1) if m else "") or "a module").split(".")[0]
        if name == "metamaterial_wb":
            return MetamaterialError(f"{where}: a worker cannot import metamaterial_wb (start dask-worker with the "
                                     "checkout on PYTHONPATH, or install the workbench where the workers run; "
                                     "docs/inverse.md)")
        return MetamaterialError(f"{where}: a worker cannot import {name} (install it where the workers run)")
    if isinstance(exc, (cf.CancelledError, asyncio.CancelledError)):
        return MetamaterialError(f"{where}: the work was dropped by the cluster (the scheduler or its workers "
                                 "stopped?); the search stopped. Check the scheduler and run again")
    if type(exc).__name__ == "KilledWorker":
        return MetamaterialError(f"{where}: workers died evaluating a batch (killed, or out of memory?); "
                                 "the search stopped")
    if isinstance(exc, (OSError, TimeoutError)):     # CommClosedError is an OSError
        reason = text[:200] or type(exc).__name__
        return MetamaterialError(f"{where}: lost the connection to the scheduler ({reason}); the search stopped")
    return None


def make_mapper(workers=1, scheduler=None):
    """``(mapper or None, n_workers)``."""
    if scheduler is not None:
        m = DaskMapper(scheduler)
        return m, m.workers
    if workers is not None and int(workers) > 1:
        return PoolMapper(workers), int(workers)
    return None, 1
