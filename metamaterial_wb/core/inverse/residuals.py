"""Residuals of one target frame and their exact Jacobians.

Unknowns of a frame: the actuator values ``v`` (through ``dpos``, ``dR``, ``dF``: derivatives of the
poses along each value's response) and, for ``align`` rigid / similarity, a transform applied to the
sheet, ``q = exp(sigma) exp([w]x) R0 p + t`` (``R0`` the initial Kabsch rotation, ``w = 0`` there;
``sigma`` only with similarity). Residual blocks (all in mm):

* nodes: ``sqrt(weight) (q_i - target_i)``; with ``rotation_weight_mm`` > 0 also
  ``rotation_weight_mm * log(R_target^T R_i)`` (rotation vector);
* surface: ``q_i - closest_point(q_i)``, linearised ``N dq`` (exact almost everywhere);
* folds: ``fold_weight_mm_per_deg * (A fold - target)`` with the smooth signed fold
  ``atan2((n_a x n_b) . F_a f, n_a . n_b)`` (equal to ``kinematics.joint_angles`` when the two
  plates' fold frames turn about one fold vector, the case of every scene without crossing folds).
"""
import itertools
import math

import numpy as np

from metamaterial_wb.core import kinematics as _k
from metamaterial_wb.core.inverse.rotations import kabsch, right_jacobian, right_jacobian_inv, skew, vee


class FrameResidual:
    def __init__(self, scene, frame):
        self.scene = scene
        self.frame = frame
        self.fold_vectors = _k.joint_fold_vectors(scene)
        topo = scene.topology
        self.pairs = topo.joint_pairs
        self.align = frame.align if frame.has_positions else "none"
        self.n_xi = {"none": 0, "rigid": 6, "similarity": 7}[self.align]

    # -- alignment -------------------------------------------------------------------------
    def prepare_global(self, pos, keep=8, iterations=10):
        """Global starts of a surface-only frame's alignment (a target surface may be turned any way):
        the 24 proper rotations that map the sheet's principal axes onto the surface's (every signed
        permutation), plus the identity, each followed by ``iterations`` ICP steps on the poses ``pos``
        (the flat sheet, at construction: the same for every worker); the ``keep`` best distinct ones are
        kept as extra starts of :meth:`initial_alignment`."""
        self.global_starts = []
        fr = self.frame
        if self.n_xi == 0 or fr.surface is None or fr.nodes is not None:
            return self.global_starts       # node targets: Kabsch is already the global optimum
        sim = self.align == "similarity"
        ps = pos[fr.surface.idx]
        surf = fr.surface.surface
        tri = surf.tri
        area = 0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1)
        Y, w = surf.centroids, area / area.sum()
        cy = w @ Y
        cx = ps.mean(axis=0)
        _, Ex = np.linalg.eigh(np.cov((ps - cx).T, bias=True) + 1e-12 * np.eye(3))
        _, Ey = np.linalg.eigh(((Y - cy) * w[:, None]).T @ (Y - cy) + 1e-12 * np.eye(3))
        starts = [(1.0, np.eye(3), cy - cx)]
        for perm in itertools.permutations(range(3)):
            for signs in itertools.product((1.0, -1.0), repeat=3):
                S = np.zeros((3, 3))
                S[list(range(3)), list(perm)] = signs
                R = Ey @ S @ Ex.T
                if np.linalg.det(R) > 0:
                    starts.append((1.0, R, cy - R @ cx))
        runs = [self._icp(ps, [], [], [], s0, R0, t0, sim, iterations, surf) for s0, R0, t0 in starts]
        order = sorted(range(len(runs)), key=lambda k: (runs[k][3], k))
        for k in order:
            s0, R0, t0, c = runs[k]
            if all(np.abs(R0 - R1).max() > 1e-3 or np.abs(t0 - t1).max() > 1e-3 for _s, R1, t1 in self.global_starts):
                self.global_starts.append((s0, R0, t0))
            if len(self.global_starts) >= keep:
                break
        return self.global_starts

    @staticmethod
    def _icp(ps, P, Q, W, s, R, t, sim, iterations, surface=None):
        """ICP steps (closest points, then Kabsch on nodes + closest points): ``(s, R, t, mean sq. dist)``."""
        surf = surface
        cost = np.inf
        for _ in range(max(1, iterations)):
            q = s * ps @ R.T + t
            cp, _N = surf.closest(q)
            cost = float(np.mean(np.sum((q - cp) ** 2, axis=1)))
            s2, R2, t2 = kabsch(np.vstack(P + [ps]), np.vstack(Q + [cp]), np.concatenate(W + [np.ones(len(ps))]), sim)
            done = abs(s2 - s) + np.abs(R2 - R).max() + np.abs(t2 - t).max() < 1e-12
            s, R, t = s2, R2, t2
            if done:
                break
        q = s * ps @ R.T + t
        cost = float(np.mean(np.sum((q - surf.closest(q)[0]) ** 2, axis=1)))
        return s, R, t, cost

    def initial_alignment(self, pos, iterations=30):
        """``(R0, xi0)``: the best (smallest ICP cost) of :meth:`initial_alignments`."""
        return self.initial_alignments(pos, iterations)[0]

    def initial_alignments(self, pos, iterations=30):
        """Starts ``[(R0, xi0), ...]`` of the alignment, best first: Kabsch on the target nodes, then ICP
        steps for a surface, from there (the local start) and, for a surface-only frame, from the best
        of the global starts (:meth:`prepare_global`) when that ends elsewhere. Both are returned because
        the ICP cost at the start pose does not tell which basin the joint fit ends in."""
        if self.n_xi == 0:
            return [(np.eye(3), np.zeros(0))]
        fr = self.frame
        P, Q, W = [], [], []
        if fr.nodes is not None:
            P.append(pos[fr.nodes.idx])
            Q.append(fr.nodes.pos)
            W.append(fr.nodes.weight)
        sim = self.align == "similarity"
        s, R, t = (kabsch(np.vstack(P), np.vstack(Q), np.concatenate(W), sim) if P else
                   (1.0, np.eye(3), np.zeros(3)))
        found = [(s, R, t, 0.0)]
        if fr.surface is not None:
            ps = pos[fr.surface.idx]
            surf = fr.surface.surface
            found = [self._icp(ps, P, Q, W, s, R, t, sim, iterations, surf)]
            glob = list(getattr(self, "global_starts", []))
            if glob:
                runs = sorted((self._icp(ps, P, Q, W, *st, sim, 10, surf) for st in glob), key=lambda r: r[3])
                for st in runs[:2]:                  # the two best global starts (symmetric sheets tie)
                    g = self._icp(ps, P, Q, W, *st[:3], sim, iterations, surf)
                    if all(np.abs(g[1] - f[1]).max() > 1e-6 or np.abs(g[2] - f[2]).max() > 1e-6 for f in found):
                        found.append(g)
                found.sort(key=lambda r: r[3])
        out = []
        for s, R, t, _c in found:
            xi = np.zeros(self.n_xi)
            xi[3:6] = t
            if sim:
                xi[6] = math.log(s)
            out.append((R, xi))
        return out

    def transform(self, xi, R0):
        """``(s, R, t)`` of the alignment parameters ``xi`` about ``R0``."""
        if self.n_xi == 0:
            return 1.0, np.eye(3), np.zeros(3)
        Rw = _k.rotation_exp(xi[None, :3])[0]
        s = math.exp(xi[6]) if self.n_xi == 7 else 1.0
        return s, Rw @ R0, xi[3:6]

    # -- residuals ---------------------------------------------------------------------------
    def evaluate(self, pos, R, xi, R0, dpos=None, dR=None, F=None, dF=None, fold_deg=None, want_jac=True):
        """``(r, Jv, Jxi, parts)``; ``parts`` holds the per-node distances and fold errors."""
        fr = self.frame
        k = 0 if dpos is None else dpos.shape[0]
        s, RA, t = self.transform(xi, R0)
        rs, Jv, Jx = [], [], []
        parts = {}
        if self.n_xi:
            w = xi[:3]
            JlT = right_jacobian(w)[0]          # J_l(w) = J_r(w)^T; d(exp(w) y) = -[exp(w) y]x J_l dw

        def pos_block(idx):
            p = pos[idx]
            q = s * p @ RA.T + t
            dq = None if k == 0 else s * np.einsum("ij,knj->kni", RA, dpos[:, idx])
            dxi = None
            if self.n_xi and want_jac:
                y = s * p @ RA.T                                  # exp(sigma) Rw R0 p
                dxi = np.zeros((len(idx), 3, self.n_xi))
                dxi[:, :, :3] = -skew(y) @ JlT.T
                dxi[:, :, 3:6] = np.eye(3)
                if self.n_xi == 7:
                    dxi[:, :, 6] = y
            return q, dq, dxi

        if fr.nodes is not None:
            nt = fr.nodes
            q, dq, dxi = pos_block(nt.idx)
            sw = np.sqrt(nt.weight)[:, None]
            diff = q - nt.pos
            parts["node_dist_mm"] = np.linalg.norm(diff, axis=1)
            rs.append((sw * diff).ravel())
            if want_jac:
                Jv.append(np.zeros((diff.size, k)) if k == 0 else (sw[None] * dq).reshape(k, -1).T)
                if self.n_xi:
                    Jx.append((sw[:, :, None] * dxi).reshape(-1, self.n_xi))
            if nt.rot is not None:
                Rq = RA @ R[nt.idx]                                # (p, 3, 3)
                Qm = np.swapaxes(nt.rot, 1, 2) @ Rq
                wv = _k.rotation_log(Qm)
                parts["node_rot_err_rad"] = np.linalg.norm(wv, axis=1)
                rs.append((nt.rot_weight_mm * wv).ravel())
                if want_jac:
                    Ji = right_jacobian_inv(wv)
                    if k:
                        dQ = np.einsum("pji,jl,kplm->kpim", nt.rot, RA, dR[:, nt.idx])
                        g = np.einsum("pij,kpjl->kpil", np.swapaxes(Qm, 1, 2), dQ)
                        dw = np.einsum("pij,kpj->kpi", Ji, vee(g))
                        Jv.append(nt.rot_weight_mm * dw.reshape(k, -1).T)
                    else:
                        Jv.append(np.zeros((wv.size, 0)))
                    if self.n_xi:
                        dxi = np.zeros((len(nt.idx), 3, self.n_xi))
                        dxi[:, :, :3] = np.einsum("pij,pkj,kl->pil", Ji, Rq, JlT.T)  # Ji Rq^T J_l
                        Jx.append(nt.rot_weight_mm * dxi.reshape(-1, self.n_xi))
        if fr.surface is not None:
            st = fr.surface
            q, dq, dxi = pos_block(st.idx)
            cp, N = st.surface.closest(q)
            diff = q - cp
            parts["surface_dist_mm"] = np.linalg.norm(diff, axis=1)
            rs.append(diff.ravel())
            if want_jac:
                Jv.append(np.zeros((diff.size, 0)) if k == 0 else
                          np.einsum("nij,knj->kni", N, dq).reshape(k, -1).T)
                if self.n_xi:
                    Jx.append(np.einsum("nij,njl->nil", N, dxi).reshape(-1, self.n_xi))
        if fr.folds is not None:
            ft = fr.folds
            if fold_deg is None:
                fold, dfold = self.smooth_folds(R, F, dR, dF, ft.joints)
            else:
                fold, dfold = np.asarray(fold_deg, dtype=float), None
            err = ft.A @ fold - ft.target_deg
            parts["fold_err_deg"] = err
            rs.append(ft.weight_mm_per_deg * err)
            if want_jac:
                Jv.append(np.zeros((err.size, k)) if k == 0 else ft.weight_mm_per_deg * (ft.A @ dfold.T))
                if self.n_xi:
                    Jx.append(np.zeros((err.size, self.n_xi)))
        r = np.concatenate(rs)
        if not want_jac:
            return r, None, None, parts
        return r, np.vstack(Jv), (np.vstack(Jx) if self.n_xi else np.zeros((r.size, 0))), parts

    def smooth_folds(self, R, F, dR, dF, joints):
        """Signed folds (deg) of all joints (computed on ``joints`` only) and their derivatives (k, m)."""
        m = len(self.pairs)
        fold = np.zeros(m)
        k = 0 if dR is None else dR.shape[0]
        dfold = np.zeros((k, m))
        if len(joints) == 0:
            return fold, dfold
        a, b = self.pairs[joints, 0], self.pairs[joints, 1]
        f = self.fold_vectors[joints]
        na, nb = R[a][:, :, 2], R[b][:, :, 2]
        Fa = np.broadcast_to(np.eye(3), (len(a), 3, 3)) if F is None else F[a]
        u = np.einsum("jik,jk->ji", Fa, f)
        c = np.cross(na, nb)
        y = np.einsum("ji,ji->j", c, u)
        x = np.einsum("ji,ji->j", na, nb)
        fold[joints] = np.degrees(np.arctan2(y, x))
        if k:
            dna, dnb = dR[:, a][..., 2], dR[:, b][..., 2]
            dc = np.cross(dna, nb[None]) + np.cross(na[None], dnb)
            du = 0.0 if dF is None else np.einsum("kjil,jl->kji", dF[:, a], f)
            dy = np.einsum("kji,ji->kj", dc, u) + (0.0 if dF is None else np.einsum("ji,kji->kj", c, du))
            dx = np.einsum("kji,ji->kj", dna, nb) + np.einsum("ji,kji->kj", na, dnb)
            dfold[:, joints] = np.degrees((x * dy - y * dx) / (x * x + y * y))
        return fold, dfold
