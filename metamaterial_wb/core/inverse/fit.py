"""Values-only fit: actuator values of a fixed placement that best reach a target.

For a fixed placement the quadratic model's D is affine in the actuator values,
``D = D0 + G v`` (``G`` is the solver's response matrix, :class:`~metamaterial_wb.core.solver.QuadraticModel`),
and the poses are smooth in D (:class:`~metamaterial_wb.core.inverse.tangent.PoseTangent` gives their
exact derivatives), so ``v`` follows from a bounded Gauss-Newton / trust-region least squares
(:func:`box_gauss_newton`: Levenberg-Marquardt-damped Gauss-Newton with an active set for the
bounds [-1, 1]; ``scipy.optimize.least_squares`` is a cross-check in the tests) with the exact Jacobian
``dr/dv = dr/dpose * dpose/dD * G``, jointly with the frame's rigid alignment. Frames (keyframes) are
independent given the placement, so each is fitted on its own.
"""
import time
from dataclasses import dataclass, field

import numpy as np

from metamaterial_wb.core import kinematics as _k
from metamaterial_wb.core.design import joint_tilts_rad
from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.core.inverse.residuals import FrameResidual
from metamaterial_wb.core.inverse.surface import TargetError
from metamaterial_wb.core.inverse.tangent import PoseTangent
from metamaterial_wb.core.scene import joint_nodes, parse_joint
from metamaterial_wb.core.solver import QuadraticModel


@dataclass
class FrameFit:
    values: np.ndarray
    xi: np.ndarray
    cost: float                       # 0.5 |r|^2 (mm^2)
    parts: dict
    nfev: int
    transform: tuple = None           # (scale, R, t) applied to the sheet
    R0: np.ndarray = None


@dataclass
class FitResult:
    joints: tuple
    frames: list
    cost: float
    nfev: int
    seconds: float
    info: dict = field(default_factory=dict)

    @property
    def values(self):
        return np.array([f.values for f in self.frames])


class Problem:
    """A scene (its constraints stay fixed), a target, and everything reused across placements."""

    def __init__(self, scene, target, keep_actuators=False, calibration=None):
        from metamaterial_wb.core import design
        from metamaterial_wb.core.calibration import joint_stiffness

        scene = scene.copy()
        design.ensure_configured(scene)
        self.scene = scene
        self.target = target
        topo = scene.topology
        self.topo = topo
        self.k1, self.k2 = joint_stiffness(scene, calibration)
        self.kin = _k.Kinematics(scene, joint_tilts_rad(scene))
        self.tangent = PoseTangent(self.kin)
        self.frames = [FrameResidual(scene, fr) for fr in target.frames]
        flat = self.kin.poses(np.zeros(topo.n_nodes))[0]
        for fr in self.frames:                       # global starts of surface alignments (flat sheet)
            fr.prepare_global(flat)
        self.constraints = [(c.name, self._joint_nodes(c.joint), c.value) for c in scene.constraints]
        self.fixed_nodes = set()
        for _, nodes, _ in self.constraints:
            self.fixed_nodes.update(nodes)
        self.existing = [(a.name, a.joint) for a in scene.actuators] if keep_actuators else []

    def _joint_nodes(self, joint):
        kind, i, j = parse_joint(joint)
        return [self.topo.node_id(*n) for n in joint_nodes(kind, i, j)]

    # -- response ---------------------------------------------------------------------------
    def response(self, joints):
        """``(D0 (n,), G (n, len(joints)))`` with ``D = D0 + G v`` for servos on ``joints``."""
        groups = [(name, nodes) for name, nodes, _ in self.constraints]
        groups += [(f"servo{k}", self._joint_nodes(j)) for k, j in enumerate(joints)]
        model = QuadraticModel(self.topo.n_nodes, self.topo.joint_pairs, self.k1, self.k2, groups)
        nc, ns = len(self.constraints), len(joints)
        ng = nc + ns
        full = np.zeros((self.topo.n_nodes, ng))
        full[model.fixed, model.fixed_group] = 1.0
        if model.free.size:
            if model.G is not None:
                full[model.free] = model.G
            else:
                for g in range(ng):
                    e = np.zeros(ng)
                    e[g] = 1.0
                    full[model.free, g] = model._factor.solve(-(model.H_FA @ e[model.fixed_group]))
        cvals = np.array([v for _, _, v in self.constraints])
        D0 = full[:, :nc] @ cvals if nc else np.zeros(self.topo.n_nodes)
        return D0, full[:, nc:]

    def base_state(self, joints):
        """A factored model of the constraints plus servos on ``joints`` (for rank-2 additions)."""
        groups = [(name, nodes) for name, nodes, _ in self.constraints]
        groups += [(f"servo{k}", self._joint_nodes(j)) for k, j in enumerate(joints)]
        model = QuadraticModel(self.topo.n_nodes, self.topo.joint_pairs, self.k1, self.k2, groups)
        D0, G = self.response(joints)
        where = -np.ones(self.topo.n_nodes, dtype=np.int64)
        where[model.free] = np.arange(model.free.size)
        return {"model": model, "D0": D0, "G": G, "where": where}

    def added_response(self, state, joint):
        """``(D0, G)`` of the placement plus a servo on ``joint`` by a rank-2 update (two
        back-substitutions): fixing nodes a, b of a free SPD system conditions its solution,
        ``x' = x + X S^-1 (value - x_ab)`` with ``X = H_FF^-1 E_ab``, ``S = X_ab``. ``None`` when a node
        of the joint is not a free node of the base (fixed, or in a part without any fixed node)."""
        model, where = state["model"], state["where"]
        a, b = self._joint_nodes(joint)
        ia, ib = where[a], where[b]
        if ia < 0 or ib < 0:
            return None
        nf = model.free.size
        E = np.zeros((nf, 2))
        E[ia, 0] = E[ib, 1] = 1.0
        X = np.asarray(model._factor.solve(E)).reshape(nf, 2)
        s00, s01, s10, s11 = X[ia, 0], X[ia, 1], X[ib, 0], X[ib, 1]
        det = s00 * s11 - s01 * s10
        K = X @ (np.array([[s11, -s01], [-s10, s00]]) / det)   # X S^-1
        Kfull = np.zeros((self.topo.n_nodes, 2))
        Kfull[model.free] = K
        M = np.column_stack([state["D0"], state["G"]])
        M = M - Kfull @ M[[a, b]]
        M[[a, b]] = 0.0
        col = Kfull @ np.ones(2)
        col[[a, b]] = 1.0
        return M[:, 0], np.column_stack([M[:, 1:], col])

    # -- the free field (every node's D an unknown): a lower bound and a metric for the search --
    def free_field(self, fi, reg=1e-6, max_nfev=40):
        """``(D*, W, cost*, converged)`` of frame ``fi``: the D field (every node free in [-1, 1]) that best
        reaches the target, the Gauss-Newton metric ``W = B^T B`` of the residual in D there (alignment
        projected out), the reached cost, and whether its fit converged within ``max_nfev`` evaluations (only
        then is ``cost*`` a lower bound of every placement's cost). A small multiple ``reg`` of the quadratic energy keeps
        directions the target does not see at the smoothest field."""
        from metamaterial_wb.core.solver import assemble_hessian
        n = self.topo.n_nodes
        eye = np.eye(n)
        zero = np.zeros(n)
        fr = self.frames[fi]
        pos0 = self.kin.poses(zero)[0]
        aligns = fr.initial_alignments(pos0)
        R0, xi0 = aligns[0]
        nx = fr.n_xi
        pairs = self.topo.joint_pairs
        m = len(pairs)
        rows = np.concatenate([np.arange(m), np.arange(m), m + np.arange(m), 2 * m + np.arange(m)])
        cols = np.concatenate([pairs[:, 0], pairs[:, 1], pairs[:, 0], pairs[:, 1]])
        a1 = np.sqrt(self.k2 * self.k1)
        a2 = np.sqrt(self.k2 * (1.0 - self.k1))
        L = np.zeros((3 * m, n))
        np.add.at(L, (rows, cols), np.concatenate([a1, -a1, a2, a2]))
        r0 = fr.evaluate(pos0, self.kin.poses(zero)[1], xi0, R0, want_jac=False)[0]
        lam = np.sqrt(reg * max(float(r0 @ r0), 1e-12) / max(1.0, float(np.abs(assemble_hessian(
            n, pairs, self.k1, self.k2)).sum())))

        def make(R0):
            def both(x, jac=True):
                if not jac:
                    r = self.frame_residual(fi, x[:n], x[n:], R0, zero, eye, want_jac=False)[0]
                    return np.concatenate([r, lam * (L @ x[:n])]), None
                r, Jv, Jx, _ = self.frame_residual(fi, x[:n], x[n:], R0, zero, eye)
                return (np.concatenate([r, lam * (L @ x[:n])]),
                        np.vstack([np.hstack([Jv, Jx]), np.hstack([lam * L, np.zeros((3 * m, nx))])]))
            return both

        lo = np.concatenate([-np.ones(n), -np.inf * np.ones(nx)])
        best = None
        for R0, xi0 in aligns:                     # the local and (surfaces) the global alignment start
            both = make(R0)
            for start in ((0.0, 0.5, -0.5) if n <= 400 else (0.0,)):   # the kink at D = 0: try both sides
                x, nfev = box_gauss_newton(both, np.concatenate([np.full(n, start), xi0]), lo, -lo,
                                           max_nfev=max_nfev, tol=1e-12)
                c = float(np.sum(both(x, False)[0] ** 2))
                if best is None or c < best[0]:
                    best = (c, x, R0, nfev < max_nfev)
        R0 = best[2]
        x = best[1]
        r, Jv, Jx, _ = self.frame_residual(fi, x[:n], x[n:], R0, zero, eye)
        if nx:
            Q, _ = np.linalg.qr(Jx)
            B = Jv - Q @ (Q.T @ Jv)
        else:
            B = Jv
        return x[:n], B.T @ B, 0.5 * float(r @ r), best[3]

    # pickling for process pools and Dask: the factorisations are rebuilt on arrival
    def __getstate__(self):
        d = dict(self.__dict__)
        d.pop("kin", None)
        d.pop("tangent", None)
        return d

    def __setstate__(self, d):
        self.__dict__.update(d)
        self.kin = _k.Kinematics(self.scene, joint_tilts_rad(self.scene))
        self.tangent = PoseTangent(self.kin)

    def check_placement(self, joints):
        used = {}
        for j in joints:
            nodes = self._joint_nodes(j)
            for n in nodes:
                if n in self.fixed_nodes:
                    raise SceneError(f"servo {j}", "shares a node with an angular constraint (a node takes one value)")
                if n in used:
                    raise SceneError(f"servo {j}", f"shares a node with servo {used[n]} (a node takes one value)")
                used[n] = j

    # -- one frame ---------------------------------------------------------------------------
    def frame_residual(self, fi, v, xi, R0, D0, G, want_jac=True):
        D = D0 + G @ v
        if want_jac:
            pos, R, dpos, dR, F, dF = self.tangent.poses(D, G.T)
        else:
            phi = self.kin.angles(D)
            F = self.kin.fold_frames(phi) if self.frames[fi].frame.folds is not None else None
            pos, R = self.kin.poses_from_angles(phi)
            dpos = dR = dF = None
        return self.frames[fi].evaluate(pos, R, xi, R0, dpos, dR, F, dF, want_jac=want_jac)

    def fit_frame(self, fi, D0, G, v0=None, max_nfev=60, tol=1e-15):
        fr = self.frames[fi]
        ns = G.shape[1]
        v0 = np.zeros(ns) if v0 is None else np.clip(np.asarray(v0, dtype=float), -1, 1)
        pos0, _R, _ = self.kin.poses(np.clip(D0 + G @ v0, -1, 1))
        best = None
        for R0, xi0 in fr.initial_alignments(pos0):       # the local and (surfaces) the global start
            ff = self._fit_frame_from(fi, D0, G, v0, R0, xi0, max_nfev, tol)
            if best is None or ff.cost < best.cost - 1e-15:
                best = ff
        return best

    def _fit_frame_from(self, fi, D0, G, v0, R0, xi0, max_nfev, tol):
        fr = self.frames[fi]
        ns = G.shape[1]
        nx = fr.n_xi

        def both(x, jac=True):
            if not jac:
                return self.frame_residual(fi, x[:ns], x[ns:], R0, D0, G, want_jac=False)[0], None
            r, Jv, Jx, parts = self.frame_residual(fi, x[:ns], x[ns:], R0, D0, G)
            return r, np.hstack([Jv, Jx])

        x0 = np.concatenate([v0, xi0])
        if ns + nx == 0:
            r, _, _, parts = self.frame_residual(fi, v0, xi0, R0, D0, G, want_jac=False)
            return FrameFit(v0, xi0, 0.5 * float(r @ r), parts, 1, fr.transform(xi0, R0), R0)
        lo = np.concatenate([-np.ones(ns), -np.inf * np.ones(nx)])
        hi = np.concatenate([np.ones(ns), np.inf * np.ones(nx)])
        x, nfev = box_gauss_newton(both, np.clip(x0, lo, hi), lo, hi, max_nfev=max_nfev, tol=tol)
        v, xi = x[:ns], x[ns:]
        r, _, _, parts = self.frame_residual(fi, v, xi, R0, D0, G, want_jac=False)
        return FrameFit(v, xi, 0.5 * float(r @ r), parts, nfev, fr.transform(xi, R0), R0)

    # -- a placement --------------------------------------------------------------------------
    def fit(self, joints, v0=None, starts=None, max_nfev=60, tol=1e-15):
        """Fit every frame for servos on ``joints``. ``v0``: (frames, servos) warm start;
        ``starts``: extra start vectors tried per frame (the best is kept)."""
        t0 = time.perf_counter()
        joints = tuple(joints)
        self.check_placement(joints)
        D0, G = self.response(joints)
        frames, nfev = [], 0
        for fi in range(len(self.frames)):
            cands = [None if v0 is None else np.asarray(v0)[fi]]
            if fi and frames:
                cands.append(frames[-1].values)            # previous keyframe's answer
            for s in starts or ():
                cands.append(np.full(len(joints), float(s)) if np.isscalar(s) else np.asarray(s))
            best = None
            for c in cands:
                ff = self.fit_frame(fi, D0, G, c, max_nfev=max_nfev, tol=tol)
                nfev += ff.nfev
                if best is None or ff.cost < best.cost - 1e-15:
                    best = ff
            frames.append(best)
        return FitResult(joints, frames, float(sum(f.cost for f in frames)), nfev, time.perf_counter() - t0)


def box_gauss_newton(fun, x0, lo, hi, max_nfev=60, tol=1e-15, radius=0.25):
    """Minimise ``0.5 |r(x)|^2`` over the box [lo, hi]. ``fun(x, jac) -> (r, J or None)``.
    Returns ``(x, nfev)``.

    Gauss-Newton steps on the free variables (those not at a bound with the gradient pushing out),
    inside a trust region on the bounded variables (the actuator values; the alignment is nearly
    linear and unlimited) that grows on a good step and shrinks on a failed one, plus Levenberg-
    Marquardt damping after failures; the step is projected onto the box. Trial points cost a
    residual only. Quadratic convergence on zero-residual problems (planted targets).
    """
    x = np.asarray(x0, dtype=float).copy()
    r, J = fun(x, True)
    cost = 0.5 * float(r @ r)
    nfev, mu = 1, 0.0
    floor = 0.5 * r.size * 1e-24          # rms residual below 1e-12 mm: round-off level
    bounded_all = np.isfinite(lo) | np.isfinite(hi)
    while nfev < max_nfev and cost > floor:
        g = J.T @ r
        active = ((x <= lo) & (g > 0)) | ((x >= hi) & (g < 0))
        free = ~active
        if not np.any(free):
            break
        Jf = J[:, free]
        A = Jf.T @ Jf
        scale = np.maximum(np.diag(A), 1e-300)
        try:
            dx = np.linalg.solve(A + (mu + 1e-13) * np.diag(scale), -g[free])
        except np.linalg.LinAlgError:
            dx = np.full(int(free.sum()), np.nan)
        if not np.all(np.isfinite(dx)):
            dx = np.linalg.lstsq(A, -g[free], rcond=1e-12)[0]
        if not np.all(np.isfinite(dx)):
            break
        bnd = bounded_all[free]
        big = float(np.abs(dx[bnd]).max()) if np.any(bnd) else 0.0
        if big > radius:
            dx *= radius / big
        xn = x.copy()
        xn[free] += dx
        np.clip(xn, lo, hi, out=xn)
        rn, _ = fun(xn, False)
        nfev += 1
        cn = 0.5 * float(rn @ rn)
        if not np.isfinite(cn):
            cn = np.inf
        d = (xn - x)[free]
        pred = -float(g[free] @ d + 0.5 * d @ (A @ d))
        step = float(np.abs(xn - x).max())
        if cn < cost:
            rho = (cost - cn) / pred if pred > 0 else 0.0
            rel = (cost - cn) / max(cost, 1e-300)
            x, cost = xn, cn
            r, J = fun(x, True)
            if rho > 0.75:
                radius = min(2.0 * radius, 2.0)
                mu *= 0.1
            elif rho < 0.25:
                radius *= 0.5
            if step <= tol * (1.0 + float(np.abs(x).max())) or rel <= tol:
                break
        else:
            dbig = float(np.abs(d[bnd]).max()) if np.any(bnd) else 0.0
            radius = 0.25 * (dbig if dbig > 0 else radius)
            mu = max(4.0 * mu, 1e-6)
            if step <= tol * (1.0 + float(np.abs(x).max())) or mu > 1e12:
                break
    return x, nfev


def frame_errors(parts):
    """``{rms_mm, max_mm, rms_deg, max_deg}`` of one frame's residual parts (None where absent)."""
    d = np.concatenate([parts[k] for k in ("node_dist_mm", "surface_dist_mm") if k in parts] or [np.zeros(0)])
    f = parts.get("fold_err_deg")
    out = {"rms_mm": float(np.sqrt(np.mean(d ** 2))) if d.size else None,
           "max_mm": float(d.max()) if d.size else None,
           "rms_deg": float(np.sqrt(np.mean(f ** 2))) if f is not None else None,
           "max_deg": float(np.abs(f).max()) if f is not None else None}
    return out


def combined_errors(parts_list):
    d = [np.concatenate([p[k] for k in ("node_dist_mm", "surface_dist_mm") if k in p] or [np.zeros(0)])
         for p in parts_list]
    d = np.concatenate(d) if d else np.zeros(0)
    f = [p["fold_err_deg"] for p in parts_list if "fold_err_deg" in p]
    f = np.concatenate(f) if f else None
    return frame_errors({"node_dist_mm": d, **({"fold_err_deg": f} if f is not None else {})})


__all__ = ["Problem", "FitResult", "FrameFit", "frame_errors", "combined_errors", "TargetError"]
