"""Linear algebra of the lattice models: the symmetric KKT solves (sparse LU with the multiplier shift, or
CHOLMOD + a dense Schur complement for a few constraints), the held plate and the DOF map, and the switch
between the fast paths and the plain reference computations (:func:`reference_paths`).

``_cholmod`` (CHOLMOD's factoriser or None) and ``_FAST`` are this module's state; the other lattice modules
read them as ``linalg._cholmod`` / ``linalg._FAST`` so that :func:`reference_paths` (and a test that patches
``_cholmod``) switches every path at once.
"""
import contextlib

import numpy as np
import scipy.sparse.linalg as spla

# symmetric KKT matrices: symmetric fill-reducing ordering, diagonal preferred, threshold pivoting only
# where the diagonal is too small (the zero multiplier block); measured 4x faster than partial pivoting
_SPLU = {"permc_spec": "MMD_AT_PLUS_A", "diag_pivot_thresh": 0.01, "options": {"SymmetricMode": True}}


def _support_node(geo):
    X0 = geo.X0[:getattr(geo, "n_plates", geo.n)]          # a plate, never a hinge-internal node
    c = X0.mean(axis=0)
    return int(np.argmin(np.linalg.norm(X0 - c, axis=1)))


def _dofmap(geo, planar):
    n = geo.n
    keep = np.ones((n, 6), dtype=bool)
    if planar:
        keep[:, [2, 3, 4]] = False
    keep[_support_node(geo), :] = False
    dm = -np.ones(6 * n + 1, dtype=np.int64)       # last slot: "no DOF"
    flat = keep.ravel()
    dm[:6 * n][flat] = np.arange(int(flat.sum()))
    return dm, int(flat.sum())


def _kkt_solve(pat, He, A, reg, rhs):
    """Solve the KKT system; only if it is singular (redundant constraints) with the multiplier shift."""
    try:
        return spla.splu(pat.matrix(He, A, 0.0), **_SPLU).solve(rhs)
    except RuntimeError:
        return spla.splu(pat.matrix(He, A, reg), **_SPLU).solve(rhs)


try:                                     # CHOLMOD (scikit-sparse, optional: tools/pip-optional.txt)
    from sksparse.cholmod import cholesky as _cholmod
except Exception:  # pragma: no cover - depends on the machine
    _cholmod = None
# the Schur-complement KKT solve keeps the multipliers' block dense: only for a few constraints
SCHUR_MAX_CONSTRAINTS = 64
_FAST = True          # the fast paths (False inside reference_paths(): the plain reference computations)


class SchurKKT:
    """Solver of the KKT system ``[[H, A^T], [A, -reg I]] [x; y] = [f; g]`` for a positive definite ``H``
    (the material tangent ``J^T K J`` with one plate held): a sparse Cholesky factorisation of ``H``
    (CHOLMOD) and the small dense Schur complement ``S = A H^-1 A^T`` of the few actuator constraints:
    ``y = S^-1 (A H^-1 f - g)``, ``x = H^-1 (f - A^T y)`` (``reg = 0``). Same answer as a sparse LU of the KKT
    matrix (to rounding), with a cheaper factorisation and much cheaper back-substitutions (the contact
    updates need one per hinge in contact). Redundant constraints (``S`` singular): pseudo-inverse of ``S``
    (the plates' motion is unique, the multipliers are the least-norm ones). ``build`` returns None where it
    does not apply (no CHOLMOD, too many constraints, ``H`` not positive definite); the caller then factors
    the KKT matrix by LU.

    Parameters
    ----------
    F : callable
        CHOLMOD factor of ``H``.
    A : scipy.sparse matrix
        Constraint rows.
    HA : numpy.ndarray
        ``H^-1 A^T``.
    S_factor : numpy.ndarray or None
        Pseudo-inverse of the Schur complement.
    na : int
        Number of DOFs.
    """

    def __init__(self, F, A, HA, S_factor, na):
        self._F, self.A, self.HA, self._S, self.na = F, A, HA, S_factor, na

    @classmethod
    def build(cls, H, A):
        """Factor ``H`` and the Schur complement of ``A``, or None where this path does not apply.

        Parameters
        ----------
        H : scipy.sparse matrix
            Symmetric positive definite tangent.
        A : scipy.sparse matrix
            Constraint rows.

        Returns
        -------
        SchurKKT or None
            None where the Schur path does not apply.
        """
        if _cholmod is None or A.shape[0] > SCHUR_MAX_CONSTRAINTS or H.shape[0] == 0:
            return None
        import warnings
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("error")          # CHOLMOD warns (not raises) on a non-definite matrix
                F = _cholmod(H, mode="supernodal") if H.shape[0] > 20000 else _cholmod(H)
                Ld = F.D() if hasattr(F, "D") else None
        except Exception:
            return None
        if Ld is not None and not (np.all(Ld > 0) and np.all(np.isfinite(Ld))):
            return None                                  # indefinite tangent: the LU path pivots
        HA = F(np.ascontiguousarray(A.T)) if A.shape[0] else np.zeros((H.shape[0], 0))
        S = A @ HA
        Sinv = None
        if A.shape[0]:
            # S is symmetric positive semi-definite; redundant constraints (e.g. every joint around a cell
            # actuated) make it singular. Its null directions v have A^T v = 0 (H is definite), so they do
            # not move the plates: leave them out (pseudo-inverse) rather than amplify rounding along them.
            w, V = np.linalg.eigh(0.5 * (S + S.T))
            keep = w > 1e-10 * max(float(w.max()), 1e-300)
            Sinv = (V[:, keep] / w[keep]) @ V[:, keep].T
        return cls(F, A, HA, Sinv, H.shape[0])

    def solve(self, rhs):
        """Solve the KKT system for ``rhs``.

        Parameters
        ----------
        rhs : numpy.ndarray
            ``[f; g]``.

        Returns
        -------
        numpy.ndarray
            ``[x; y]``.
        """
        na = self.na
        f, g = rhs[:na], rhs[na:]
        u = self._F(np.ascontiguousarray(f))
        if self._S is None:
            return np.concatenate([u, g * 0.0])
        y = self._S @ (self.A @ u - g)
        return np.concatenate([u - self.HA @ y, y])


@contextlib.contextmanager
def reference_paths():
    """Within the block, the linear model runs its plain reference paths (sparse LU of the whole KKT
    matrix, LU for the hinge-chain positions, no CHOLMOD): for tests that the fast paths agree with it.

    Returns
    -------
    contextlib context manager
    """
    global _cholmod, _FAST
    saved = _cholmod, _FAST
    _cholmod, _FAST = None, False
    try:
        yield
    finally:
        _cholmod, _FAST = saved


class _Cholesky:
    """CHOLMOD factor of an SPD matrix with the ``solve(rhs)`` interface of SuperLU."""

    def __init__(self, M):
        self.solve = _cholmod(M)


def kkt_regularisation(geo):
    """Multiplier-block shift of the KKT matrix (1/rad units: 1e-10 of the softest hinge compliance).

    Parameters
    ----------
    geo : LatticeGeometry

    Returns
    -------
    float
    """
    return 1e-10 / float(geo.K[:, 5, 5].max())
