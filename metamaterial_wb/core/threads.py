"""Limit BLAS threads for one block of code, at run time (no environment variable at import).

``OPENBLAS_NUM_THREADS`` only works before numpy loads OpenBLAS, and setting it in a module that the
CLI imports made every command single-threaded (issue 14/19). :func:`blas_threads` instead calls the
loaded OpenBLAS's ``openblas_set_num_threads`` and restores the old count afterwards; where no
OpenBLAS is loaded (MKL, Accelerate, another OS) it does nothing.
"""
import contextlib
import ctypes


def _openblas_libs():
    libs = []
    try:
        with open("/proc/self/maps") as f:
            paths = {line.split()[-1] for line in f if "openblas" in line.lower() and "/" in line}
    except OSError:
        return libs
    for p in sorted(paths):
        try:
            lib = ctypes.CDLL(p)
            lib.openblas_get_num_threads.restype = ctypes.c_int
            lib.openblas_set_num_threads.argtypes = [ctypes.c_int]
            libs.append(lib)
        except (OSError, AttributeError):
            continue
    return libs


def blas_thread_counts():
    """Current thread count of every loaded OpenBLAS (empty when none is loaded)."""
    import numpy  # noqa: F401  (make sure BLAS is loaded)
    return [lib.openblas_get_num_threads() for lib in _openblas_libs()]


@contextlib.contextmanager
def blas_threads(n):
    """``with blas_threads(1): ...`` runs the block with ``n`` BLAS threads."""
    import numpy  # noqa: F401
    libs = _openblas_libs()
    old = [lib.openblas_get_num_threads() for lib in libs]
    for lib in libs:
        lib.openblas_set_num_threads(int(n))
    try:
        yield
    finally:
        for lib, k in zip(libs, old):
            lib.openblas_set_num_threads(k)
