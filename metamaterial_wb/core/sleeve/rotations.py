"""Rotation vectors and matrices for the 3-D frame (``frame3d_nl``) and its rigid plates (``frame3d_plate``)."""
import numpy as np

from metamaterial_wb.core.lattice.mechanics import skew  # one cross-product matrix for the lattice and the frame


def expm_so3(v):
    """Rotation matrices ``exp(skew(v))`` of rotation vectors ``v`` (..., 3) (Rodrigues)."""
    v = np.asarray(v, float)
    a = np.linalg.norm(v, axis=-1)[..., None, None]
    K = skew(v)
    small = a < 1e-4
    s = np.where(small, 1 - a ** 2 / 6, np.sin(a) / np.where(small, 1, a))
    c = np.where(small, 0.5 - a ** 2 / 24, (1 - np.cos(a)) / np.where(small, 1, a) ** 2)
    return np.eye(3) + s * K + c * (K @ K)


def logm_so3(R):
    """Rotation vectors (..., 3) of rotation matrices ``R`` (..., 3, 3), angles below pi."""
    c = (np.trace(R, axis1=-2, axis2=-1) - 1) / 2
    w = 0.5 * np.stack([R[..., 2, 1] - R[..., 1, 2], R[..., 0, 2] - R[..., 2, 0], R[..., 1, 0] - R[..., 0, 1]], -1)
    s = np.linalg.norm(w, axis=-1)
    a = np.arctan2(s, c)                              # precise near 0, where arccos(c) is not
    small = a < 1e-4
    f = np.where(small, 1 + a ** 2 / 6, a / np.where(small, 1, s))
    return f[..., None] * w
