"""The sleeve model's tangent: Cholesky / symmetric-mode LU with inertia, the smallest eigenpairs of
an indefinite tangent, and the mesh-independent choice of a negative-curvature direction.

A mixin of :class:`metamaterial_wb.core.sleeve.model.SleeveModel` (it uses ``self.sparse``,
``self.tilt_reference`` and ``self._energy``)."""
import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla

DEGENERATE = 0.05       # two lowest eigenvalues within 5 %: one (symmetry-degenerate) mode pair


def symmetric_factor(K):
    """SuperLU's symmetric mode for the sparse symmetric ``K`` (CSC): minimum degree on K + K^T, diagonal pivots
    (``P K P^T = L D L^T`` where the pivots allow). SuperLU's RuntimeError for an exactly singular ``K`` passes."""
    return spla.splu(K, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0, options={"SymmetricMode": True})


def symmetric_lu(K):
    """The symmetric-mode LU of the sparse symmetric ``K`` (CSC; diagonal pivots, ``P K P^T = L D L^T``) and
    the number of its negative eigenvalues by Sylvester's law of inertia (the signs of the pivots): ``(lu,
    negatives)``; ``(None, 1)`` when ``K`` is exactly singular, ``(lu, None)`` when SuperLU had to pivot off the
    diagonal (the inertia is then unknown from U)."""
    try:
        lu = symmetric_factor(K)
    except RuntimeError:
        return None, 1
    if not np.array_equal(lu.perm_r, lu.perm_c):
        return lu, None
    return lu, int(np.sum(lu.U.diagonal() < 0))


def min_eig_sparse(K, k=1):
    """Smallest eigenpair of a sparse symmetric indefinite ``K``: bracket the eigenvalue by
    inertia (signs of the symmetric-mode LU pivots of K - s I, Sylvester), then shift-invert."""
    n = K.shape[0]
    I = sp.identity(n, format="csc")
    absK = abs(K)
    gersh = float(np.min(2 * K.diagonal() - np.asarray(absK.sum(axis=1)).ravel()))
    lo = min(gersh, -1e-300) * 1.01          # below every eigenvalue

    def below(sv):
        """True when some eigenvalue lies below sv (None if the inertia is unknown)."""
        neg = symmetric_lu((K - sv * I).tocsc())[1]
        return None if neg is None else neg > 0

    hi = -abs(lo) * 1e-15
    ok = True
    for _ in range(60):                      # geometric bisection on the magnitude
        if abs(lo) / abs(hi) < 4:
            break
        mid = -np.sqrt(abs(lo) * abs(hi))
        b = below(mid)
        if b is None:
            ok = False
            break
        if b:
            hi = mid
        else:
            lo = mid
    try:
        if not ok:
            raise RuntimeError
        lam, vec = spla.eigsh(K, k=k, sigma=lo, which="LM", tol=1e-8,
                              v0=np.ones(K.shape[0]))      # deterministic start
        return lam, vec
    except Exception:
        return sla.eigh(K.toarray(), subset_by_index=[0, k - 1], check_finite=False)


class TangentSolver:
    def _descent_direction(self, q, d, e, g, K):
        """Negative-curvature direction at an indefinite tangent, chosen independently of the mesh.

        The two lowest eigenpairs are computed; when they are (nearly) degenerate - the two tilt
        modes of a ring with a rotational symmetry - the direction is taken inside their span
        (the part of -g in it, else of the tilt reference), not the combination the eigensolver
        happens to return. The sign is the descending one; when the gradient cannot tell (a
        symmetric state), the one of lower energy a small step away; when both are equal, the
        one along the tilt reference (the imperfection's direction)."""
        if self.sparse:
            lam, vec = min_eig_sparse(K, k=2)
        else:
            lam, vec = sla.eigh(K, subset_by_index=[0, min(1, len(K) - 1)], check_finite=False)
        order = np.argsort(lam)
        lam, vec = np.asarray(lam)[order], vec[:, order]
        V = vec[:, :1]
        if len(lam) > 1 and lam[1] < 0 and (lam[1] - lam[0]) <= DEGENERATE * abs(lam[0]):
            V = vec[:, :2]
        v = V[:, 0]
        gn = float(np.linalg.norm(g))
        if V.shape[1] > 1:
            w = -(V @ (V.T @ g))
            if np.linalg.norm(w) <= 1e-6 * max(gn, 1e-300):
                w = V @ (V.T @ self.tilt_reference)
            if np.linalg.norm(w) > 1e-12:
                v = w
        v = v / max(np.abs(v).max(), 1e-300)
        gv = float(g @ v)
        if abs(gv) <= 1e-6 * max(gn, 1e-300):
            # the gradient does not pick a side: compare the energies a small step either way
            a = 1e-3
            ep, em = self._energy(q + a * v, d), self._energy(q - a * v, d)
            tol_e = 1e-13 * max(abs(e), 1e-30)
            if ep - em > tol_e:
                v = -v
            elif abs(ep - em) <= tol_e:
                r = float(self.tilt_reference @ v)
                if r < -1e-12 or (abs(r) <= 1e-12 and v[np.argmax(np.abs(v))] < 0):
                    v = -v
        elif gv > 0:
            v = -v
        self._last_min_eig = float(lam[0])
        return v

    def _factor(self, K):
        """``(solve, positive_definite)`` for the reduced tangent ``K``."""
        if not self.sparse:
            try:
                C = sla.cho_factor(K, check_finite=False)
            except np.linalg.LinAlgError:
                return None, False
            return (lambda b: sla.cho_solve(C, b, check_finite=False)), True
        lu, neg = symmetric_lu(K)
        if lu is None:                        # exactly singular
            return None, False
        if neg is None:
            # off-diagonal pivoting happened: inertia unknown from U; decide densely
            return self._factor_dense(K.toarray())
        # symmetric permutation P K P^T = L D L^T (Sylvester): positive definite <=> all pivots > 0
        return lu.solve, bool(np.all(lu.U.diagonal() > 0))

    def _factor_dense(self, K):
        try:
            C = sla.cho_factor(K, check_finite=False)
        except np.linalg.LinAlgError:
            return None, False
        return (lambda b: sla.cho_solve(C, b, check_finite=False)), True
