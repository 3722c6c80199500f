"""Small vectorised rotation helpers for the inverse design (skew, SO(3) Jacobians, Kabsch).

Conventions: ``skew(v) @ x = v x x``; ``vee`` is its inverse on the skew part of a matrix. For
``Q = exp([w]x)``: ``dQ = Q [J_r(w) dw]x`` (right Jacobian), so ``dw = J_r(w)^-1 vee(Q^T dQ)``.
"""
import numpy as np

from metamaterial_wb.core.lattice.mechanics import skew  # noqa: F401  (one cross-product matrix for both)

_SMALL = 1e-6


def vee(A):
    """Axial vector of the skew part of (..., 3, 3)."""
    return 0.5 * np.stack([A[..., 2, 1] - A[..., 1, 2], A[..., 0, 2] - A[..., 2, 0],
                           A[..., 1, 0] - A[..., 0, 1]], axis=-1)


def _coeffs(th):
    """(1 - cos)/th^2, (th - sin)/th^3 and 1/th^2 - (1 + cos)/(2 th sin), with series near 0."""
    small = th < _SMALL
    ts = np.where(small, 1.0, th)
    c, s = np.cos(ts), np.sin(ts)
    a = np.where(small, 0.5 - th ** 2 / 24.0, (1.0 - c) / ts ** 2)
    b = np.where(small, 1.0 / 6.0 - th ** 2 / 120.0, (ts - s) / ts ** 3)
    g = np.where(small, 1.0 / 12.0 + th ** 2 / 720.0, 1.0 / ts ** 2 - (1.0 + c) / (2.0 * ts * s))
    return a, b, g


def right_jacobian(w):
    """J_r(w) (m, 3, 3) of the rotation vectors w (m, 3)."""
    w = np.asarray(w, dtype=float).reshape(-1, 3)
    th = np.linalg.norm(w, axis=1)
    a, b, _ = _coeffs(th)
    W = skew(w)
    return np.eye(3) - a[:, None, None] * W + b[:, None, None] * (W @ W)


def right_jacobian_inv(w):
    """J_r(w)^-1 (m, 3, 3)."""
    w = np.asarray(w, dtype=float).reshape(-1, 3)
    th = np.linalg.norm(w, axis=1)
    _, _, g = _coeffs(th)
    W = skew(w)
    return np.eye(3) + 0.5 * W + g[:, None, None] * (W @ W)


def kabsch(P, Q, weights=None, scale=False):
    """Rigid (or similarity) transform ``(s, R, t)`` minimising ``sum w |s R P + t - Q|^2``.

    P, Q: (n, 3). Returns the scale s (1 unless ``scale``), R (3, 3) proper rotation, t (3,).
    """
    P = np.asarray(P, dtype=float)
    Q = np.asarray(Q, dtype=float)
    w = np.ones(len(P)) if weights is None else np.asarray(weights, dtype=float)
    w = w / w.sum()
    cp, cq = w @ P, w @ Q
    X, Y = P - cp, Q - cq
    C = (X * w[:, None]).T @ Y
    U, S, Vt = np.linalg.svd(C)
    d = np.sign(np.linalg.det(Vt.T @ U.T)) or 1.0
    Dm = np.diag([1.0, 1.0, d])
    R = Vt.T @ Dm @ U.T
    s = 1.0
    if scale:
        var = float(np.sum(w * np.sum(X * X, axis=1)))
        s = float(np.sum(S * np.diag(Dm)) / var) if var > 0 else 1.0
    t = cq - s * R @ cp
    return s, R, t
