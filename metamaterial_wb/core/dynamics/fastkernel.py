"""Compiled kernel for the implicit integrator (forces, Newton matrix, band LU, the Newton loop).

``_kernel.c`` (next to this file) evaluates the same equations as :class:`PlanarSystem` and runs
the Newton loop of :meth:`Simulator.step_implicit` in one call per time step (``mm_step``: the whole step with
its ledger terms, anchors and statistics, driven by ``Simulator._burst`` between the run's checks and
records; only the actuator callback runs in Python between two steps); the numpy code in
``system.py`` / ``integrators.py`` stays the reference and the fallback. The C file is compiled at
first use with the system C compiler (``$CC``, else ``cc`` / ``gcc``; Debian: build-essential)::

    cc -O2 -shared -fPIC -ffp-contract=off _kernel.c -lm -o <cache>/dynkernel-<hash>.so

into a per-user cache directory (``$METAMATERIAL_CACHE_DIR``, else ``$XDG_CACHE_HOME/metamaterial_wb``,
else ``~/.cache/metamaterial_wb``, else the temp dir), named by a hash of the source and the flags,
so an edited source is rebuilt and nothing compiled lives in the repository. It is loaded with
ctypes. Compiling takes about a second, once per user and source version.

**Fallback** (automatic, reported in the summary as ``integrator.kernel`` = ``"numpy"`` with the
reason in ``integrator.kernel_note``): no compiler, a failed build or load, a system layout the
kernel does not handle (neither narrow-banded nor small), or a non-default Newton option. Forcing
the numpy path: environment ``METAMATERIAL_DYNAMICS_KERNEL=numpy`` or ``Simulator.kernel = "numpy"``.

Equivalence: identical equations and decisions (same convergence test, same Jacobian-reuse rule);
the sums run in another order and the LU is a C band LU with partial pivoting (LAPACK's dgbtf2
algorithm), so results agree to round-off (tests/dynamics/test_kernel_fast_path.py).
"""
from __future__ import annotations

import ctypes
import hashlib
import operator
import os
import shutil
import subprocess
import tempfile

import numpy as np

_SRC = os.path.join(os.path.dirname(os.path.abspath(__file__)), "_kernel.c")
_FLAGS = ["-O2", "-shared", "-fPIC", "-ffp-contract=off", "-fno-fast-math"]
ENV_SWITCH = "METAMATERIAL_DYNAMICS_KERNEL"

_state = {"lib": None, "tried": False, "note": None, "path": None, "build_s": 0.0}


def _cache_dirs():
    env = os.environ.get("METAMATERIAL_CACHE_DIR")
    if env:
        yield env
    xdg = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    yield os.path.join(xdg, "metamaterial_wb")
    uid = os.getuid() if hasattr(os, "getuid") else "user"
    yield os.path.join(tempfile.gettempdir(), f"metamaterial_wb-{uid}")


def _compiler():
    for cand in (os.environ.get("CC"), "cc", "gcc"):
        if cand and shutil.which(cand):
            return shutil.which(cand)
    return None


def _build():
    import time
    with open(_SRC, "rb") as f:
        src = f.read()
    cc = _compiler()
    if cc is None:
        raise OSError("no C compiler found (install build-essential, or set CC)")
    tag = hashlib.sha256(src + " ".join(_FLAGS).encode() + cc.encode()).hexdigest()[:16]
    errors = []
    for d in _cache_dirs():
        path = os.path.join(d, f"dynkernel-{tag}.so")
        if os.path.exists(path):
            return path
        try:
            os.makedirs(d, exist_ok=True)
            fd, tmp = tempfile.mkstemp(suffix=".so", dir=d)
            os.close(fd)
            t0 = time.perf_counter()
            r = subprocess.run([cc, *_FLAGS, _SRC, "-o", tmp, "-lm"], capture_output=True, text=True, timeout=120)
            if r.returncode != 0:
                os.unlink(tmp)
                raise OSError(f"{os.path.basename(cc)} failed: {r.stderr.strip()[:300]}")
            os.replace(tmp, path)          # atomic: concurrent builders write the same file
            _state["build_s"] = time.perf_counter() - t0
            return path
        except OSError as e:
            errors.append(f"{d}: {e}")
    raise OSError("; ".join(errors))


def load():
    """The ctypes library, or None (then ``note()`` says why)."""
    if os.environ.get(ENV_SWITCH, "").lower() == "numpy":
        _state["note"] = f"numpy path forced by {ENV_SWITCH}=numpy"
        return None
    if _state["tried"]:
        return _state["lib"]
    _state["tried"] = True
    try:
        path = _build()
        lib = ctypes.CDLL(path)
        P, D, I = ctypes.c_void_p, ctypes.c_double, ctypes.c_int64
        lib.mm_forces.argtypes = [P, P, P, P, P]
        lib.mm_forces.restype = D
        lib.mm_assemble.argtypes = [P, P, P, D, P]
        lib.mm_assemble.restype = None
        lib.mm_gbtrf.argtypes = [I, I, I, P, I, P]
        lib.mm_gbtrf.restype = I
        lib.mm_gbtrs.argtypes = [I, I, I, P, I, P, P]
        lib.mm_gbtrs.restype = None
        lib.mm_newton.argtypes = [P, P, P, P, P, D, P, I, D, D, I, I, P]
        lib.mm_newton.restype = None
        lib.mm_update_anchors.argtypes = [P, P, P, P, P, P]
        lib.mm_update_anchors.restype = None
        lib.mm_actuation_jump.argtypes = [P, P, P, P, P]
        lib.mm_actuation_jump.restype = D
        lib.mm_contact_damping.argtypes = [P, P, P, P, P, P, D]
        lib.mm_contact_damping.restype = D
        lib.mm_step.argtypes = [P, P]
        lib.mm_step.restype = None
        lib.mm_save_actuation.argtypes = [P, P]
        lib.mm_save_actuation.restype = None
        lib.mm_sheet_steps.argtypes = [P, P, I, P]
        lib.mm_sheet_steps.restype = None
        lib.mm_sheet_actuate.argtypes = [P, P]
        lib.mm_sheet_actuate.restype = None
        _state["lib"], _state["path"] = lib, path
    except Exception as e:        # no compiler, build or load failure: the numpy path is used
        _state["note"] = f"compiled kernel unavailable ({e}); numpy path used"
        _state["lib"] = None
    return _state["lib"]


def note():
    return _state["note"]


def reset():
    """Forget the loaded state (tests: re-evaluate the environment switch)."""
    _state.update({"lib": None, "tried": False, "note": None, "path": None})


class _Sys(ctypes.Structure):
    _fields_ = ([(k, ctypes.c_int64) for k in ("n", "m", "p")]
                + [(k, ctypes.c_void_p) for k in ("M", "gravity", "free_dof", "ha", "hb", "cb", "ra", "rb", "kp", "cp",
                                                  "kr", "cr", "theta0", "rc", "mu", "kn", "cn", "kt", "ct")]
                + [(k, ctypes.c_int64) for k in ("N", "kl", "ku", "ldab")]
                + [(k, ctypes.c_void_p) for k in ("hmap", "cmap", "dmap", "perm", "Q", "R", "dv", "x", "cth", "sth", "ux", "uy", "fn",
                                                  "ft", "sgn", "inside", "stick", "pushing", "lu", "ipiv", "f_push",
                                                  "f_stick")]
                + [("f_valid", ctypes.c_int64), ("f_age", ctypes.c_int64), ("f_singular", ctypes.c_int64),
                   ("f_h", ctypes.c_double)])


class _Step(ctypes.Structure):
    """``Step`` of _kernel.c: one whole implicit step (``mm_step``), driven by ``Simulator._burst`` (burst.py)."""
    _fields_ = ([(k, ctypes.c_void_p) for k in ("q", "v", "qp", "vp", "out", "anchors", "inside", "th_old", "ra_old",
                                                 "rb_old", "w", "qh", "vh", "v1", "q1", "ns")]
                + [(k, ctypes.c_double) for k in ("aw", "damp", "cdamp", "fric", "pen", "com_min", "com_max")]
                + [(k, ctypes.c_int64) for k in ("fe", "jac", "nit", "unconv", "bdf2_steps")]
                + [(k, ctypes.c_double) for k in ("dt", "tol_abs", "tol_rel")]
                + [(k, ctypes.c_int64) for k in ("bdf2", "use_bdf2", "max_it", "max_age", "refactor")])


class _SheetAct(ctypes.Structure):
    """``SheetAct`` of _kernel.c: a sheet's servo actuation per step, rows of (n, m) arrays (``mm_sheet_steps``)."""
    _fields_ = [(k, ctypes.c_void_p) for k in ("ra", "rb", "th")]


_SYS_ARRAYS = ("M", "gravity", "ha", "hb", "cb", "ra", "rb", "kp", "cp", "kr", "cr", "theta0", "rc", "mu", "kn",
               "cn", "kt", "ct")
_INT_ARRAYS = ("ha", "hb", "cb")


def _ptr(a):
    return a.ctypes.data


class Kernel:
    """The compiled kernel bound to one :class:`PlanarSystem` (its arrays are read in place, so
    actuators that change ``theta0`` / ``ra`` / ``rb`` in place are seen; a replaced array makes
    ``matches`` false and the caller rebuilds)."""

    def __init__(self, lib, system, layout):
        s = system
        self.lib = lib
        self.sys = s
        self.refs = tuple(getattr(s, k) for k in _SYS_ARRAYS) + (s.free_dof,)
        self._ids = tuple(map(id, self.refs))      # held in refs, so no other array can take these ids
        self._get = operator.attrgetter(*_SYS_ARRAYS, "free_dof")
        for k, a in zip(_SYS_ARRAYS, self.refs):
            want = np.int64 if k in _INT_ARRAYS else np.float64
            if a.dtype != want or not a.flags.c_contiguous:
                raise ValueError(f"array {k} is not contiguous {want.__name__}")
        perm, kl, ku = layout
        n, m, p = s.n, s.ha.size, s.cb.size
        N = 3 * n
        ldab = 2 * kl + ku + 1
        kv = kl + ku
        pos = np.empty(N, np.int64)
        pos[perm] = np.arange(N)
        free = s.free_dof

        def bandidx(r, c):
            i, j = pos[r], pos[c]
            out = kv + i - j + j * ldab
            return np.where(free[r] & free[c], out, -1).astype(np.int64)

        dh = np.column_stack([3 * s.ha, 3 * s.ha + 1, 3 * s.ha + 2, 3 * s.hb, 3 * s.hb + 1, 3 * s.hb + 2]).reshape(m, 6)
        dc = np.column_stack([3 * s.cb, 3 * s.cb + 1, 3 * s.cb + 2]).reshape(p, 3)
        self.hmap = np.ascontiguousarray(bandidx(dh[:, :, None], dh[:, None, :]).reshape(-1))
        self.cmap = np.ascontiguousarray(bandidx(dc[:, :, None], dc[:, None, :]).reshape(-1))
        self.dmap = (kv + pos * ldab).astype(np.int64)
        self.perm = np.ascontiguousarray(perm, np.int64)
        self.pos = pos
        self.free_u8 = np.ascontiguousarray(free, bool).view(np.uint8)
        self.N, self.kl, self.ku, self.ldab = N, kl, ku, ldab
        f = lambda k: np.zeros(k)
        self.Q, self.R, self.dv, self.x = f(N), f(N), f(N), f(N)
        self.q1 = f(N)
        self.cth, self.sth = f(n), f(n)
        self.ux, self.uy, self.fn, self.ft, self.sgn = f(p), f(p), f(p), f(p), f(p)
        self.inside, self.stick, self.pushing = (np.zeros(p, np.uint8) for _ in range(3))
        self.lu = f(ldab * N)
        self.ab = f(ldab * N)
        self.ipiv = np.zeros(N, np.int64)
        self.f_push, self.f_stick = np.zeros(p, np.uint8), np.zeros(p, np.uint8)
        self.stats = f(5)
        self.acc = f(2)
        S = _Sys()
        S.n, S.m, S.p = n, m, p
        for k, a in zip(_SYS_ARRAYS, self.refs):
            setattr(S, k, _ptr(a))
        S.free_dof = _ptr(self.free_u8)
        S.N, S.kl, S.ku, S.ldab = N, kl, ku, ldab
        for k in ("hmap", "cmap", "dmap", "perm", "Q", "R", "dv", "x", "cth", "sth", "ux", "uy", "fn", "ft", "sgn", "inside",
                  "stick", "pushing", "lu", "ipiv", "f_push", "f_stick"):
            setattr(S, k, _ptr(getattr(self, k)))
        S.f_valid = 0
        self.S = S
        self.Sp = ctypes.addressof(S)
        self._stats_p = _ptr(self.stats)
        self._acc_p = _ptr(self.acc)
        self._q1_p = _ptr(self.q1)
        # mm_step's workspace and saved actuation (Simulator._burst)
        m = s.ha.size
        self.qh, self.vh, self.v1 = f(N), f(N), f(N)
        self.th_old, self.ra_old, self.rb_old = f(m), f(2 * m), f(2 * m)
        T = _Step()
        for k in ("qh", "vh", "v1", "q1", "th_old", "ra_old", "rb_old"):
            setattr(T, k, _ptr(getattr(self, k)))
        T.ns = self._stats_p
        self.T = T
        self.Tp = ctypes.addressof(T)

    def matches(self, system):
        """True while ``system`` is the bound one with the same array objects (by identity)."""
        return system is self.sys and tuple(map(id, self._get(system))) == self._ids

    def invalidate(self):
        """Forget the factorisation (the numpy path's ``Simulator._fact = None``)."""
        self.S.f_valid = 0

    # -- the pieces, for tests -----------------------------------------------------------------
    def forces(self, q, v, anchors):
        q = np.ascontiguousarray(q, float)
        v = np.ascontiguousarray(v, float)
        anchors = np.ascontiguousarray(anchors, float)
        Q = np.zeros(self.N)
        dp = self.lib.mm_forces(self.Sp, _ptr(q), _ptr(v), _ptr(anchors), _ptr(Q))
        st = {"ux": self.ux.copy(), "uy": self.uy.copy(), "inside": self.inside.astype(bool),
              "fn": self.fn.copy(), "ft": self.ft.copy(), "stick": self.stick.astype(bool),
              "sgn": self.sgn.copy(), "pushing": self.pushing.astype(bool)}
        return Q.reshape(-1, 3), st, dp

    def matrix(self, q, v, anchors, h):
        """Dense Newton matrix (natural dof order) at (q, v), after a force evaluation there."""
        q = np.ascontiguousarray(q, float)
        v = np.ascontiguousarray(v, float)
        self.forces(q, v, anchors)
        self.lib.mm_assemble(self.Sp, _ptr(q), _ptr(v), h, _ptr(self.ab))
        return self._dense(self.ab)

    def _dense(self, abflat):
        ab = abflat.reshape(self.N, self.ldab)              # column-major band: ab[col, row in band]
        kv = self.kl + self.ku
        Ap = np.zeros((self.N, self.N))                     # permuted order
        j = np.arange(self.N)
        for d in range(self.ldab):
            i = j + d - kv
            ok = (i >= 0) & (i < self.N)
            Ap[i[ok], j[ok]] = ab[j[ok], d]
        return Ap[np.ix_(self.pos, self.pos)]

    def solve(self, A, b):
        """Solve with the kernel's band LU (A dense, natural order), for tests."""
        kv = self.kl + self.ku
        ab = np.zeros((self.N, self.ldab))      # column j at ab[j]
        r, c = np.nonzero(A)
        i, j = self.pos[r], self.pos[c]
        if np.any((j - i > self.ku) | (i - j > self.kl)):
            raise ValueError("matrix outside the kernel's band")
        ab[j, kv + i - j] = A[r, c]
        ab = np.ascontiguousarray(ab.ravel())
        ipiv = np.zeros(self.N, np.int64)
        info = self.lib.mm_gbtrf(self.N, self.kl, self.ku, _ptr(ab), self.ldab, _ptr(ipiv))
        x = np.ascontiguousarray(np.asarray(b, float)[self.perm])
        self.lib.mm_gbtrs(self.N, self.kl, self.ku, _ptr(ab), self.ldab, _ptr(ipiv), _ptr(x))
        out = np.empty_like(x)
        out[self.perm] = x
        return out, int(info)

    def _sheet_act(self, block):
        """The ``SheetAct`` of a block ``(ra, rb, th)`` (``SheetController.block_actuation``: (n, m) each, C-contiguous
        float64, kept alive by the caller during the call)."""
        A = getattr(self, "_sheet", None)
        if A is None:
            A = self._sheet = _SheetAct()
            self._sheet_p = ctypes.addressof(A)
        for name, a in zip(("ra", "rb", "th"), block):
            if not (a.dtype == np.float64 and a.flags.c_contiguous and a.shape[-1] == self.sys.ha.size):
                raise ValueError(f"sheet actuation {name}: expected C-contiguous float64 rows of "
                                 f"{self.sys.ha.size}, got {a.dtype} {a.shape}")
            setattr(A, name, a.ctypes.data)
        return self._sheet_p

    def sheet_steps(self, n, block):
        """``n`` steps (``mm_step``, set up by ``Simulator._burst``), each after copying the actuation of its row of
        ``block`` = ``(ra, rb, th)`` ((n, m) each) into the system."""
        if any(a.shape[0] < n for a in block):
            raise ValueError(f"sheet actuation: {n} steps, rows {[a.shape[0] for a in block]}")
        self.lib.mm_sheet_steps(self.Sp, self.Tp, n, self._sheet_act(block))

    def sheet_actuate(self, block):
        """Copy the first row of ``block`` = ``(ra, rb, th)`` into the system's actuation (tests)."""
        self.lib.mm_sheet_actuate(self.Sp, self._sheet_act(block))

    # -- the hot calls -------------------------------------------------------------------------
    def newton(self, qh, vh, v1, h, anchors, max_it, tol_abs, tol_rel, max_age, refactor_on_contact_change=True):
        """Newton loop of one implicit step; ``v1`` (contiguous, N) is overwritten by the solution.
        Returns the stats array [force evaluations, Jacobians, Newton iterations, converged, damper power]."""
        self.lib.mm_newton(self.Sp, qh.ctypes.data, vh.ctypes.data, v1.ctypes.data, self._q1_p, h,
                           anchors.ctypes.data, max_it, tol_abs, tol_rel, max_age,
                           int(bool(refactor_on_contact_change)), self._stats_p)
        return self.stats

    def actuation_jump(self, q, old):
        """``Simulator._actuation_jump``: the elastic energy at ``q`` with the system's current actuation minus
        that with ``old`` (theta0, ra, rb), in one call."""
        q = np.ascontiguousarray(q, float)
        th, ra, rb = (np.ascontiguousarray(a, float) for a in old)
        return self.lib.mm_actuation_jump(self.Sp, q.ctypes.data, th.ctypes.data, ra.ctypes.data, rb.ctypes.data)

    def contact_damping(self, q, v, q0, v0, anchors, dt):
        """``PlanarSystem.dissipation_power(q, v, anchors, dt, q_start=q0, v_start=v0, hinges=False)``'s contact
        part (W), in one call."""
        q, v, q0, v0, anchors = (np.ascontiguousarray(a, float) for a in (q, v, q0, v0, anchors))
        return self.lib.mm_contact_damping(self.Sp, q.ctypes.data, v.ctypes.data, q0.ctypes.data, v0.ctypes.data,
                                           anchors.ctypes.data, dt)

    def update_anchors(self, q, v, anchors, inside, friction_J, max_pen_mm):
        acc = self.acc
        acc[0] = friction_J
        acc[1] = max_pen_mm
        self.lib.mm_update_anchors(self.Sp, q.ctypes.data, v.ctypes.data, anchors.ctypes.data, inside.ctypes.data,
                                   self._acc_p)
        return acc[0], acc[1]


def layout_for(system, band_max=64, dense_max=300):
    """(perm, kl, ku) for the kernel: the system's reverse Cuthill-McKee band when it is narrow,
    the natural order as a full band for small systems, else None (the numpy path is used)."""
    s = system
    N = 3 * s.n
    b = s.band_layout()
    if b is not None:
        return b["perm"], b["kl"], b["ku"]
    perm, _pos, _r, _c, kl, ku = s.rcm_order()
    if max(kl, ku) <= band_max:
        return perm, kl, ku
    if N <= dense_max:
        return np.arange(N, dtype=np.int64), N - 1, N - 1
    return None
