"""Exact directional derivatives of the kinematic poses (``core/kinematics.py``) with respect to D.

:class:`PoseTangent` reproduces ``Kinematics.poses_from_angles`` step by step and carries, for k
directions ``dD`` (k, n) at once, the forward-mode derivative of every intermediate:

1. ``phi = parity * D * limit(sign D)``: ``dphi = parity * limit * dD`` (one-sided at D = 0, where
   the closing and the opening limit differ; the D = +0 side is taken, as ``node_angles`` does);
2. folds ``gamma = -2 atan(tan(alpha) sin(phi_A))``: chain rule;
3. fold fields ``theta``: the same sparse least-squares solve (linear) applied to ``dgamma``;
4. fold frames ``F = prod_g Rot(f_g, theta_g)``: product rule with ``dRot = [f]x Rot dtheta``;
5. rotations ``R = F Rz(phi)``; chord frames ``M = mid(F_A, F_B)`` through the SO(3) right
   Jacobians (exact ``Rot(f, mean theta)`` for one fold direction);
6. positions: the hinge-closure least squares is linear in the chords, so ``dpos`` is the same
   back-substitution of ``dchord``, centred like ``pos``.

No finite differences anywhere; ``tests/inverse/test_tangent.py`` checks every output against
central differences of ``Kinematics.poses``.
"""
import numpy as np

from metamaterial_wb.core import kinematics as _k
from metamaterial_wb.core.inverse.rotations import right_jacobian, right_jacobian_inv, skew, vee

_KZ = skew(np.array([0.0, 0.0, 1.0]))


def _mv(R, v):
    """Batched matrix-vector product over matching leading axes."""
    return np.einsum("...ij,...j->...i", R, v)


class PoseTangent:
    """Poses and their derivatives for one :class:`~metamaterial_wb.core.kinematics.Kinematics`."""

    def __init__(self, kin):
        self.kin = kin
        self.closing, self.opening = kin.limits

    def phi_rate(self, D):
        """d phi / d D per node (diagonal)."""
        D = np.asarray(D, dtype=float)
        return self.kin.parity * np.where(D >= 0, self.closing, self.opening)

    def poses(self, D, dD):
        """``(pos (n,3), R (n,3,3), dpos (k,n,3), dR (k,n,3,3), F, dF)`` for directions dD (k, n)."""
        kin = self.kin
        D = np.asarray(D, dtype=float)
        dD = np.atleast_2d(np.asarray(dD, dtype=float))
        phi = kin.angles(D)
        dphi = dD * self.phi_rate(D)[None, :]
        return self.poses_from_angles(phi, dphi)

    def poses_from_angles(self, phi, dphi):
        kin = self.kin
        n, m = kin.n, kin.m
        k = dphi.shape[0]
        a, b = kin.a, kin.b
        Rz = _k.rotation_matrices(phi)
        dRz = (_KZ @ Rz)[None] * dphi[:, :, None, None]          # (k, n, 3, 3)

        theta = dtheta = None
        if kin.planar:
            F = np.broadcast_to(np.eye(3), (n, 3, 3))
            dF = None
            R = Rz
            dR = dRz
        else:
            G = len(kin.groups)
            t = kin.tilted
            phi_a = 0.5 * (phi[a[t]] - phi[b[t]])
            dphi_a = 0.5 * (dphi[:, a[t]] - dphi[:, b[t]])
            ta = np.tan(kin.tilt[t])
            u = ta * np.sin(phi_a)
            gamma = np.zeros(m)
            gamma[t] = -2.0 * np.arctan(u)
            dgamma = np.zeros((k, m))
            dgamma[:, t] = -2.0 * ta * np.cos(phi_a) / (1.0 + u * u) * dphi_a
            E = np.zeros((m, G))
            dE = np.zeros((m, k, G))
            for g, (_d, _f, js) in enumerate(kin.groups):
                E[js, g] = gamma[js]
                dE[js, :, g] = dgamma[:, js].T
            theta = kin._solve_edges(E)                                           # (n, G)
            dtheta = kin._solve_edges(dE.reshape(m, k * G)).reshape(n, k, G).transpose(1, 0, 2)
            Rg = [_k.axis_angle_matrices(f, theta[:, g]) for g, (_d, f, _js) in enumerate(kin.groups)]
            dRg = [(skew(f) @ Rg[g])[None] * dtheta[:, :, g, None, None]
                   for g, (_d, f, _js) in enumerate(kin.groups)]
            # prefix / suffix products for the product rule
            pre = [np.broadcast_to(np.eye(3), (n, 3, 3))]
            for g in range(G):
                pre.append(pre[-1] @ Rg[g])
            F = pre[-1]
            suf = [None] * (G + 1)
            suf[G] = np.broadcast_to(np.eye(3), (n, 3, 3))
            for g in range(G - 1, -1, -1):
                suf[g] = Rg[g] @ suf[g + 1]
            dF = np.zeros((k, n, 3, 3))
            for g in range(G):
                dF += pre[g][None] @ dRg[g] @ suf[g + 1][None]
            R = F @ Rz
            dR = dF @ Rz[None] + F[None] @ dRz

        # chords
        mean = 0.5 * (phi[a] + phi[b])
        dmean = 0.5 * (dphi[:, a] + dphi[:, b])
        c, s = np.cos(mean), np.sin(mean)
        d0 = kin.d0
        cp = np.column_stack([c * d0[:, 0] - s * d0[:, 1], s * d0[:, 0] + c * d0[:, 1], np.zeros(m)])
        dcp = np.cross(np.array([0.0, 0.0, 1.0]), cp)[None] * dmean[:, :, None]   # (k, m, 3)
        if kin.planar:
            chord, dchord = cp, dcp
        else:
            if len(kin.groups) == 1:
                f = kin.groups[0][1]
                M = _k.axis_angle_matrices(f, 0.5 * (theta[a, 0] + theta[b, 0]))
                dM = (skew(f) @ M)[None] * (0.5 * (dtheta[:, a, 0] + dtheta[:, b, 0]))[:, :, None, None]
            else:
                Fa, Fb = F[a], F[b]
                dFa, dFb = dF[:, a], dF[:, b]
                Q = np.swapaxes(Fa, 1, 2) @ Fb
                w = _k.rotation_log(Q)
                N = _k.rotation_exp(0.5 * w)
                M = Fa @ N
                dQ = np.swapaxes(dFa, 2, 3) @ Fb[None] + np.swapaxes(Fa, 1, 2)[None] @ dFb
                dw = _mv(right_jacobian_inv(w)[None], vee(np.swapaxes(Q, 1, 2)[None] @ dQ))
                dN = N[None] @ skew(_mv(right_jacobian(0.5 * w)[None], 0.5 * dw))
                dM = dFa @ N[None] + Fa[None] @ dN
            chord = _mv(M, cp)
            dchord = _mv(dM, cp[None]) + _mv(M[None], dcp)
        e = chord + _mv(R[a], kin.ra) - _mv(R[b], kin.rb)
        de = dchord + _mv(dR[:, a], kin.ra[None]) - _mv(dR[:, b], kin.rb[None])
        pos = kin._solve_edges(e)
        pos += kin.flat.mean(axis=0) - pos.mean(axis=0)
        dpos = kin._solve_edges(de.transpose(1, 0, 2).reshape(m, 3 * k)).reshape(n, k, 3).transpose(1, 0, 2)
        dpos -= dpos.mean(axis=1, keepdims=True)
        return pos, R, dpos, dR, F, dF
