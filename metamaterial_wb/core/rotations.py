"""Vectorised rotations (SO(3)): about z, axis-angle (Rodrigues), log and exp (re-exported by
:mod:`core.kinematics`)."""
import numpy as np


# ----------------------------------------------------------------------------------------------
# rotations (vectorised)
# ----------------------------------------------------------------------------------------------
def rotation_matrices(phi):
    """(n, 3, 3) rotations about z.

    Parameters
    ----------
    phi : array_like
        Shape ``(n,)``, radians.

    Returns
    -------
    numpy.ndarray
    """
    phi = np.asarray(phi, dtype=float)
    c, s = np.cos(phi), np.sin(phi)
    R = np.zeros((phi.size, 3, 3))
    R[:, 0, 0] = c
    R[:, 0, 1] = -s
    R[:, 1, 0] = s
    R[:, 1, 1] = c
    R[:, 2, 2] = 1.0
    return R


def axis_angle_matrices(axis, angle):
    """Rodrigues: (m, 3, 3) rotations about unit ``axis`` (m, 3) or (3,) by ``angle`` (m,).

    Parameters
    ----------
    axis : array_like
    angle : array_like

    Returns
    -------
    numpy.ndarray
        Shape ``(m, 3, 3)``.
    """
    angle = np.asarray(angle, dtype=float).reshape(-1)
    axis = np.broadcast_to(np.asarray(axis, dtype=float), (angle.size, 3))
    x, y, z = axis[:, 0], axis[:, 1], axis[:, 2]
    c, s = np.cos(angle), np.sin(angle)
    C = 1.0 - c
    R = np.empty((angle.size, 3, 3))
    R[:, 0, 0] = c + x * x * C
    R[:, 0, 1] = x * y * C - z * s
    R[:, 0, 2] = x * z * C + y * s
    R[:, 1, 0] = y * x * C + z * s
    R[:, 1, 1] = c + y * y * C
    R[:, 1, 2] = y * z * C - x * s
    R[:, 2, 0] = z * x * C - y * s
    R[:, 2, 1] = z * y * C + x * s
    R[:, 2, 2] = c + z * z * C
    return R


def rotation_log(R):
    """Rotation vectors (m, 3) of rotations (m, 3, 3) with angles below pi.

    Parameters
    ----------
    R : array_like

    Returns
    -------
    numpy.ndarray
    """
    tr = np.einsum("mii->m", R)
    ang = np.arccos(np.clip(0.5 * (tr - 1.0), -1.0, 1.0))
    v = 0.5 * np.column_stack([R[:, 2, 1] - R[:, 1, 2], R[:, 0, 2] - R[:, 2, 0], R[:, 1, 0] - R[:, 0, 1]])
    s = np.sin(ang)
    small = s < 1e-8
    fac = np.where(small, 1.0 + ang * ang / 6.0, ang / np.where(small, 1.0, s))
    return v * fac[:, None]


def rotation_exp(w):
    """Rotations (m, 3, 3) from rotation vectors (m, 3).

    Parameters
    ----------
    w : array_like

    Returns
    -------
    numpy.ndarray
    """
    w = np.asarray(w, dtype=float).reshape(-1, 3)
    ang = np.linalg.norm(w, axis=1)
    axis = np.where(ang[:, None] > 1e-15, w / np.where(ang > 1e-15, ang, 1.0)[:, None], [0.0, 0.0, 1.0])
    return axis_angle_matrices(axis, ang)


def _matvec(R, v):
    return np.einsum("mij,mj->mi", R, v)
