"""Hinge sizes per region as extra unknowns (``inverse --hinges``).

The sheet is split into ``rows x cols`` blocks of cells; every joint whose flat midpoint lies in a
block belongs to its region. A region's hinges share one flexible length ``L_r`` (mm) and, when the
calibration table has a width law (``k2_vs_width``, the default table does), one width ``w_r`` (mm), all
bounded by the table's ranges and the scene's hinge rules (``0 < L <= lh`` the sheet's hinge length,
which sets the plate gap: shorter hinges get rigid stubs; ``width <= (cell - L) / 4``). Joints with a
``k1`` (``k2``) override keep their length (width) and are in no region for it.

What the quadratic model sees:

* a length through ``k1(L)`` (the table, piecewise linear; ``H_ab = -2 k1 k2``) and through the poses: a
  joint of flexible length ``L < lh`` has rigid stubs of ``(lh - L) / 2`` on both plates
  (``core/kinematics.py``), so its hinge-closure chord changes with ``L`` even at a fixed D;
* a width through ``k2(w) = factor(w) t / t_ref`` (the table, log-log linear; ``H_aa += 2 k2``,
  ``H_ab = -2 k1 k2``). D is invariant to scaling every ``k2`` at once, so the first region's width is
  the reference and stays fixed unless some joints are in no width region; thickness enters ``k2``
  exactly like the width factor (``t / t_ref``), so it is not a separate unknown (it could not be told
  from the width).

For a fixed placement ``D = D0 + G v`` and ``dD/dp = -H_FF^-1 (dH/dp D)_F`` (one back-substitution per
size, exact, one-sided at the table's knots); the pose derivative along a length adds the stub
geometry's ``dpos/dL`` (the closure least squares is linear in the chords). Values (per keyframe) and
sizes (shared by all keyframes) are fitted jointly by the same box-constrained Gauss-Newton. The
rotation limits are the starting sizes'; the answer's re-evaluation under every model is what tells.
"""
import copy

import numpy as np

from metamaterial_wb.core.calibration import default_calibration
from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.core.inverse.fit import FitResult, FrameFit, box_gauss_newton
from metamaterial_wb.core.kinematics import flat_positions_mm
from metamaterial_wb.core.solver import QuadraticModel


def parse_regions(text):
    try:
        r, c = (int(x) for x in str(text).lower().split("x"))
    except ValueError:
        raise SceneError("--hinge-regions", f"{text!r}: expected ROWSxCOLS, e.g. 2x2") from None
    if not (1 <= r <= 20 and 1 <= c <= 20):
        raise SceneError("--hinge-regions", f"{text!r}: rows and columns must be in [1, 20]")
    return r, c


class HingeRegions:
    def __init__(self, problem, rows=2, cols=2, calibration=None, widths=True):
        scene = problem.scene
        self.pb = problem
        self.cal = calibration or default_calibration()
        topo = scene.topology
        names = topo.joint_names
        pos = flat_positions_mm(scene)
        mid = 0.5 * (pos[topo.joint_pairs[:, 0]] + pos[topo.joint_pairs[:, 1]])
        lo, hi = mid.min(axis=0), mid.max(axis=0)
        span = np.maximum(hi - lo, 1e-9)
        ci = np.minimum((cols * (mid[:, 0] - lo[0]) / span[0]).astype(int), cols - 1)
        ri = np.minimum((rows * (hi[1] - mid[:, 1]) / span[1]).astype(int), rows - 1)
        label = ri * cols + ci
        fixed_k1 = np.array([("k1" in scene.joint_overrides.get(n, {})) for n in names], dtype=bool)
        fixed_k2 = np.array([("k2" in scene.joint_overrides.get(n, {})) for n in names], dtype=bool)
        keep = [k for k in range(rows * cols) if np.any((label == k) & ~fixed_k1)]
        self.regions = [np.flatnonzero((label == k) & ~fixed_k1) for k in keep]
        if not self.regions:
            raise SceneError("--hinges", "every joint has a k1 override: no hinge length to fit")
        cell = scene.cell_size_mm
        lh = float(scene.hinge["length_mm"])
        tl, th = float(self.cal.len_mm[0]), float(self.cal.len_mm[-1])
        self.bounds, self.start = [], []
        for js in self.regions:
            w = max(scene.joint_hinge(names[k])["width_mm"] for k in js)
            lo_r, hi_r = tl, min(th, lh, 0.5 * cell * (1 - 1e-9), cell - 4.0 * w)
            if hi_r < lo_r:
                raise SceneError("--hinges", f"no hinge length fits joints like {names[js[0]]}: the table's range is "
                                             f"[{tl}, {th}] mm, the plate gap {lh} mm and the width {w} mm needs L <= "
                                             f"{cell - 4 * w:g} mm")
            L0 = float(np.mean([scene.joint_hinge(names[k])["length_mm"] for k in js]))
            self.bounds.append((lo_r, hi_r))
            self.start.append(min(max(L0, lo_r), hi_r))
        # widths: per region (joints without a k2 override), the first one the reference unless some
        # joints keep their k2 (then every region's width is seen)
        self.wregions = []
        if widths and getattr(self.cal, "w_mm", None) is not None and len(self.cal.w_mm) > 1:
            wr = [np.flatnonzero((label == k) & ~fixed_k2) for k in keep]
            wr = [r for r in wr if r.size]
            outside = bool(np.any(fixed_k2))
            self.wregions = wr if outside else wr[1:]
        wl, wh = (float(self.cal.w_mm[0]), float(self.cal.w_mm[-1])) if self.wregions else (0.0, 0.0)
        for js in self.wregions:
            Lmax = max(b[1] for b in self.bounds)
            w0 = float(np.mean([scene.joint_hinge(names[k])["width_mm"] for k in js]))
            hi_w = min(wh, (cell - Lmax) / 4.0)
            self.bounds.append((wl, hi_w))
            self.start.append(min(max(w0, wl), hi_w))
        self.nL, self.nW = len(self.regions), len(self.wregions)
        self.thick = np.array([scene.joint_hinge(n)["thickness_mm"] for n in names], dtype=float)
        self.k2 = problem.k2.copy()
        self.lh = lh
        kin = problem.kin
        self.u = kin.d0 / np.linalg.norm(kin.d0, axis=1)[:, None]
        lj = np.linalg.norm(kin.d0, axis=1)
        self.ra_c = kin.ra - 0.5 * (lh - lj)[:, None] * self.u        # the plate corners (no stubs)
        self.rb_c = kin.rb + 0.5 * (lh - lj)[:, None] * self.u
        self.lj0 = lj

    @property
    def n_unknowns(self):
        return self.nL + self.nW

    def start_sizes(self):
        return np.array(self.start, dtype=float)

    def k1_of(self, L):
        k1 = self.pb.k1.copy()
        slope = np.zeros(len(self.regions))
        x, y = self.cal.len_mm, self.cal.k1_tab
        for r, (js, Lr) in enumerate(zip(self.regions, L)):
            k1[js] = np.interp(Lr, x, y)
            seg = min(max(int(np.searchsorted(x, Lr, side="right")) - 1, 0), len(x) - 2)
            slope[r] = (y[seg + 1] - y[seg]) / (x[seg + 1] - x[seg])
        return k1, slope

    def k2_of(self, W):
        """``(k2, dlog k2 / dw per width region)``: the table's log-log law times t / t_ref."""
        k2 = self.k2.copy()
        g = np.zeros(self.nW)
        lx, ly = np.log(self.cal.w_mm), np.log(self.cal.w_fac)
        for r, (js, w) in enumerate(zip(self.wregions, W)):
            k2[js] = np.exp(np.interp(np.log(w), lx, ly)) * self.thick[js] / self.cal.t_ref
            seg = min(max(int(np.searchsorted(lx, np.log(w), side="right")) - 1, 0), len(lx) - 2)
            g[r] = (ly[seg + 1] - ly[seg]) / (lx[seg + 1] - lx[seg]) / w
        return k2, g

    def split(self, p):
        p = np.asarray(p, dtype=float)
        return p[:self.nL], p[self.nL:self.nL + self.nW]

    def lengths(self, L):
        lj = self.lj0.copy()
        for js, Lr in zip(self.regions, L):
            lj[js] = Lr
        return lj

    def kinematics(self, L):
        """The problem's kinematics with the region lengths' stubs (a shallow copy)."""
        kin = copy.copy(self.pb.kin)
        lj = self.lengths(L)
        stub = 0.5 * (self.lh - lj)[:, None] * self.u
        kin.ra, kin.rb, kin.d0 = self.ra_c + stub, self.rb_c - stub, lj[:, None] * self.u
        return kin

    def geometry_dpos(self, kin, D):
        """``dpos/dL_r`` (nL, n, 3) at a fixed D: the stub geometry (the closure is linear in the chords)."""
        phi = kin.angles(D)
        F, theta = kin._fold_state(phi)
        R = kin.rotations(phi, F)
        out = np.zeros((self.nL, kin.n, 3))
        for r, js in enumerate(self.regions):
            k = copy.copy(kin)
            mask = np.zeros((kin.m, 1))
            mask[js] = 1.0
            k.d0, k.ra, k.rb = mask * self.u, -0.5 * mask * self.u, 0.5 * mask * self.u
            de = k._chords(phi, F, R, theta)
            x = kin._solve_edges(de)
            out[r] = x - x.mean(axis=0)
        return out

    def response(self, joints, p):
        """``(D0, G, dD0/dp, dG/dp)``: D = D0 + G v and its derivatives in the sizes ``p``."""
        pb = self.pb
        L, W = self.split(p) if len(p) == self.n_unknowns else (np.asarray(p, dtype=float), np.zeros(0))
        k1, slope = self.k1_of(L)
        k2, g = self.k2_of(W) if self.nW and len(W) else (self.k2, np.zeros(0))
        groups = [(name, nodes) for name, nodes, _ in pb.constraints]
        groups += [(f"servo{k}", pb._joint_nodes(j)) for k, j in enumerate(joints)]
        model = QuadraticModel(pb.topo.n_nodes, pb.topo.joint_pairs, k1, k2, groups)
        n, nc, ns = pb.topo.n_nodes, len(pb.constraints), len(joints)
        ng = nc + ns
        full = np.zeros((n, ng))
        full[model.fixed, model.fixed_group] = 1.0
        if model.free.size:
            E = np.zeros((ng, ng))
            np.fill_diagonal(E, 1.0)
            full[model.free] = np.asarray(model._factor.solve(-(model.H_FA @ E[model.fixed_group]))).reshape(-1, ng)
        a, b = pb.topo.joint_pairs[:, 0], pb.topo.joint_pairs[:, 1]
        npar = len(L) + len(W)
        dfull = np.zeros((npar, n, ng))

        def back(r, HD):
            if model.free.size:
                dfull[r][model.free] = -np.asarray(model._factor.solve(HD[model.free])).reshape(-1, ng)

        for r, js in enumerate(self.regions):
            w = -2.0 * k2[js] * slope[r]                               # d(-2 k1 k2)/dL
            HD = np.zeros((n, ng))
            np.add.at(HD, a[js], w[:, None] * full[b[js]])
            np.add.at(HD, b[js], w[:, None] * full[a[js]])
            back(r, HD)
        for r, js in enumerate(self.wregions[:len(W)]):
            dk2 = k2[js] * g[r]
            HD = np.zeros((n, ng))
            np.add.at(HD, a[js], (2.0 * dk2)[:, None] * full[a[js]] - (2.0 * k1[js] * dk2)[:, None] * full[b[js]])
            np.add.at(HD, b[js], (2.0 * dk2)[:, None] * full[b[js]] - (2.0 * k1[js] * dk2)[:, None] * full[a[js]])
            back(len(L) + r, HD)
        cvals = np.array([v for _, _, v in pb.constraints])
        D0 = full[:, :nc] @ cvals if nc else np.zeros(n)
        dD0 = np.einsum("rnc,c->rn", dfull[:, :, :nc], cvals) if nc else np.zeros((npar, n))
        return D0, full[:, nc:], dD0, dfull[:, :, nc:]

    def _frame(self, kin, tangent, f, p, v, xi, R0, D0, G, dD0=None, dG=None, jac=True):
        fr = self.pb.frames[f]
        Dv = D0 + G @ v
        if not jac:
            phi = kin.angles(Dv)
            F = kin.fold_frames(phi) if fr.frame.folds is not None else None
            pos, R = kin.poses_from_angles(phi)
            return fr.evaluate(pos, R, xi, R0, None, None, F, None, want_jac=False)
        dDp = dD0 + np.einsum("rnc,c->rn", dG, v)
        pos, R, dpos, dR, F, dF = tangent.poses(Dv, np.vstack([G.T, dDp]))
        ns = G.shape[1]
        dpos = np.array(dpos)
        dpos[ns:ns + self.nL] += self.geometry_dpos(kin, Dv)
        return fr.evaluate(pos, R, xi, R0, dpos, dR, F, dF)

    def fit(self, joints, v0=None, max_nfev=80, tol=1e-15):
        """Joint fit of the values (per keyframe) and the region sizes (shared). Returns
        ``(FitResult, sizes)`` (sizes: the region lengths, then the fitted widths)."""
        from metamaterial_wb.core.inverse.tangent import PoseTangent
        pb = self.pb
        joints = tuple(joints)
        pb.check_placement(joints)
        nf, ns, npar = len(pb.frames), len(joints), self.n_unknowns
        if v0 is None:
            v0 = pb.fit(joints, starts=(0.5, -0.5)).values
        p0 = self.start_sizes()
        D0, G, _, _ = self.response(joints, p0)
        kin0 = self.kinematics(p0[:self.nL])
        R0s, xis = [], []
        for fi, fr in enumerate(pb.frames):
            R0, xi = fr.initial_alignment(kin0.poses(np.clip(D0 + G @ v0[fi], -1, 1))[0])
            R0s.append(R0)
            xis.append(xi)
        nx = [len(x) for x in xis]
        off = np.cumsum([0, npar] + [ns + k for k in nx])

        def unpack(x):
            return x[:npar], [x[off[f + 1]:off[f + 1] + ns] for f in range(nf)], \
                [x[off[f + 1] + ns:off[f + 2]] for f in range(nf)]

        def fun(x, jac=True):
            p, vs, xs = unpack(x)
            D0, G, dD0, dG = self.response(joints, p)
            kin = self.kinematics(p[:self.nL])
            tangent = PoseTangent(kin)
            rs, rows = [], []
            for f in range(nf):
                r, Jd, Jx, _ = self._frame(kin, tangent, f, p, vs[f], xs[f], R0s[f], D0, G, dD0, dG, jac)
                if jac:
                    J = np.zeros((r.size, len(x)))
                    J[:, :npar] = Jd[:, ns:]
                    J[:, off[f + 1]:off[f + 1] + ns] = Jd[:, :ns]
                    J[:, off[f + 1] + ns:off[f + 2]] = Jx
                    rows.append(J)
                rs.append(r)
            return np.concatenate(rs), (np.vstack(rows) if jac else None)

        self._fun = fun
        x0 = np.concatenate([p0] + [np.concatenate([v0[f], xis[f]]) for f in range(nf)])
        lo = np.concatenate([[b[0] for b in self.bounds]] +
                            [np.concatenate([-np.ones(ns), -np.inf * np.ones(nx[f])]) for f in range(nf)])
        hi = np.concatenate([[b[1] for b in self.bounds]] +
                            [np.concatenate([np.ones(ns), np.inf * np.ones(nx[f])]) for f in range(nf)])
        x, nfev = box_gauss_newton(fun, np.clip(x0, lo, hi), lo, hi, max_nfev=max_nfev, tol=tol)
        p, vs, xs = unpack(x)
        D0, G, _, _ = self.response(joints, p)
        kin = self.kinematics(p[:self.nL])
        frames = []
        for f in range(nf):
            r, _, _, parts = self._frame(kin, None, f, p, vs[f], xs[f], R0s[f], D0, G, jac=False)
            frames.append(FrameFit(vs[f], xs[f], 0.5 * float(r @ r), parts, nfev,
                                   pb.frames[f].transform(xs[f], R0s[f]), R0s[f]))
        return FitResult(joints, frames, float(sum(fr.cost for fr in frames)), nfev, 0.0), p

    def overrides(self, p, tol=1e-9):
        """``{joint name: {"length_mm": L, "width_mm": w}}`` for joints whose sizes differ from their own."""
        scene = self.pb.scene
        names = scene.topology.joint_names
        L, W = self.split(p)
        out = {}
        for js, Lr in zip(self.regions, L):
            for k in js:
                if abs(scene.joint_hinge(names[k])["length_mm"] - Lr) > tol:
                    out.setdefault(names[k], {})["length_mm"] = float(Lr)
        for js, wr in zip(self.wregions, W):
            for k in js:
                if abs(scene.joint_hinge(names[k])["width_mm"] - wr) > tol:
                    out.setdefault(names[k], {})["width_mm"] = float(wr)
        return out

    def report(self, p):
        names = self.pb.scene.topology.joint_names
        L, W = self.split(p)
        k1, _ = self.k1_of(L)
        rows = [{"region": r, "joints": [names[k] for k in js], "length_mm": float(L[r]),
                 "k1": float(k1[js[0]]), "range_mm": list(self.bounds[r])} for r, js in enumerate(self.regions)]
        if self.nW:
            k2, _ = self.k2_of(W)
            for r, js in enumerate(self.wregions):
                rows.append({"width_region": r, "joints": [names[k] for k in js], "width_mm": float(W[r]),
                             "k2": float(k2[js[0]]), "range_mm": list(self.bounds[self.nL + r])})
        return rows
