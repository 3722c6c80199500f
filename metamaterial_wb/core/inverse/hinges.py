"""Hinge sizes per region as extra unknowns (``inverse --hinges``).

The sheet is split into ``rows x cols`` blocks of cells; every joint whose flat midpoint lies in a
block belongs to its region, and a region's hinges share one flexible length ``L_r`` (mm), bounded by
the calibration table's length range and the scene's hinge rules (``0 < L < cell / 2``,
``width <= (cell - L) / 4``). Joints with a ``k1`` override keep it (they are in no region).

The quadratic model sees a length only through ``k1(L)`` (the table, piecewise linear), which enters
the Hessian's off-diagonal ``H_ab = -2 k1 k2``; so for a fixed placement

    dD_F / dL_r = -H_FF^-1 (dH/dL_r D)_F,   (dH/dL_r D)_a = -2 k2_e k1'(L_r) D_b (and a <-> b)

one back-substitution per region, exact (one-sided at the table's knots). The kinematic model's
geometry uses the sheet's base hinge length (docs/kinematics.md), so poses depend on L only through D;
the lattice models use every joint's real length, and the evaluation under them is what tells.
Values (per keyframe) and lengths (shared by all keyframes) are fitted jointly by the same
box-constrained Gauss-Newton.
"""
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
    def __init__(self, problem, rows=2, cols=2, calibration=None):
        scene = problem.scene
        self.pb = problem
        self.cal = calibration or default_calibration()
        topo = scene.topology
        pos = flat_positions_mm(scene)
        mid = 0.5 * (pos[topo.joint_pairs[:, 0]] + pos[topo.joint_pairs[:, 1]])
        lo, hi = mid.min(axis=0), mid.max(axis=0)
        span = np.maximum(hi - lo, 1e-9)
        ci = np.minimum((cols * (mid[:, 0] - lo[0]) / span[0]).astype(int), cols - 1)
        ri = np.minimum((rows * (hi[1] - mid[:, 1]) / span[1]).astype(int), rows - 1)
        label = ri * cols + ci
        fixed_k1 = np.array([("k1" in scene.joint_overrides.get(n, {})) for n in topo.joint_names], dtype=bool)
        self.regions = [np.flatnonzero((label == k) & ~fixed_k1) for k in range(rows * cols)]
        self.regions = [r for r in self.regions if r.size]
        if not self.regions:
            raise SceneError("--hinges", "every joint has a k1 override: no hinge length to fit")
        cell = scene.cell_size_mm
        tl, th = float(self.cal.len_mm[0]), float(self.cal.len_mm[-1])
        self.bounds = []
        self.start = []
        for js in self.regions:
            w = max(scene.joint_hinge(topo.joint_names[k])["width_mm"] for k in js)
            lo_r, hi_r = tl, min(th, 0.5 * cell * (1 - 1e-9), cell - 4.0 * w)
            if hi_r < lo_r:
                raise SceneError("--hinges", f"no hinge length fits joints like {topo.joint_names[js[0]]}: the "
                                             f"table's range is [{tl}, {th}] mm and the width {w} mm needs L <= "
                                             f"{cell - 4 * w:g} mm")
            L0 = float(np.mean([scene.joint_hinge(topo.joint_names[k])["length_mm"] for k in js]))
            self.bounds.append((lo_r, hi_r))
            self.start.append(min(max(L0, lo_r), hi_r))
        self.k2 = problem.k2

    @property
    def n_unknowns(self):
        return len(self.regions)

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

    def response(self, joints, L):
        """``(D0, G, dD0/dL, dG/dL)``: D = D0 + G v and its derivatives in the region lengths."""
        pb = self.pb
        k1, slope = self.k1_of(L)
        groups = [(name, nodes) for name, nodes, _ in pb.constraints]
        groups += [(f"servo{k}", pb._joint_nodes(j)) for k, j in enumerate(joints)]
        model = QuadraticModel(pb.topo.n_nodes, pb.topo.joint_pairs, k1, self.k2, groups)
        n, nc, ns = pb.topo.n_nodes, len(pb.constraints), len(joints)
        ng = nc + ns
        full = np.zeros((n, ng))
        full[model.fixed, model.fixed_group] = 1.0
        if model.free.size:
            E = np.zeros((ng, ng))
            np.fill_diagonal(E, 1.0)
            full[model.free] = np.asarray(model._factor.solve(-(model.H_FA @ E[model.fixed_group]))).reshape(-1, ng)
        a, b = pb.topo.joint_pairs[:, 0], pb.topo.joint_pairs[:, 1]
        dfull = np.zeros((len(self.regions), n, ng))
        for r, js in enumerate(self.regions):
            w = -2.0 * self.k2[js] * slope[r]
            HD = np.zeros((n, ng))
            np.add.at(HD, a[js], w[:, None] * full[b[js]])
            np.add.at(HD, b[js], w[:, None] * full[a[js]])
            if model.free.size:
                dfull[r][model.free] = -np.asarray(model._factor.solve(HD[model.free])).reshape(-1, ng)
        cvals = np.array([v for _, _, v in pb.constraints])
        D0 = full[:, :nc] @ cvals if nc else np.zeros(n)
        dD0 = np.einsum("rnc,c->rn", dfull[:, :, :nc], cvals) if nc else np.zeros((len(self.regions), n))
        return D0, full[:, nc:], dD0, dfull[:, :, nc:]

    def fit(self, joints, v0=None, max_nfev=80, tol=1e-15):
        """Joint fit of the values (per keyframe) and the region lengths (shared). Returns
        ``(FitResult, lengths)``."""
        pb = self.pb
        joints = tuple(joints)
        pb.check_placement(joints)
        nf, ns, nr = len(pb.frames), len(joints), len(self.regions)
        if v0 is None:
            v0 = pb.fit(joints, starts=(0.5, -0.5)).values
        L0 = np.array(self.start)
        D0, G, _, _ = self.response(joints, L0)
        R0s, xis = [], []
        for fi, fr in enumerate(pb.frames):
            R0, xi = fr.initial_alignment(pb.kin.poses(np.clip(D0 + G @ v0[fi], -1, 1))[0])
            R0s.append(R0)
            xis.append(xi)
        nx = [len(x) for x in xis]
        off = np.cumsum([0, nr] + [ns + k for k in nx])

        def unpack(x):
            return x[:nr], [x[off[f + 1]:off[f + 1] + ns] for f in range(nf)], \
                [x[off[f + 1] + ns:off[f + 2]] for f in range(nf)]

        def fun(x, jac=True):
            L, vs, xs = unpack(x)
            D0, G, dD0, dG = self.response(joints, L)
            rs, rows = [], []
            for f in range(nf):
                Dv = D0 + G @ vs[f]
                dDL = dD0 + np.einsum("rnc,c->rn", dG, vs[f])          # (nr, n)
                dirs = np.vstack([G.T, dDL])
                if jac:
                    pos, R, dpos, dR, F, dF = pb.tangent.poses(Dv, dirs)
                    r, Jd, Jx, _ = pb.frames[f].evaluate(pos, R, xs[f], R0s[f], dpos, dR, F, dF)
                    J = np.zeros((r.size, len(x)))
                    J[:, :nr] = Jd[:, ns:]
                    J[:, off[f + 1]:off[f + 1] + ns] = Jd[:, :ns]
                    J[:, off[f + 1] + ns:off[f + 2]] = Jx
                    rows.append(J)
                else:
                    r = pb.frame_residual(f, vs[f], xs[f], R0s[f], D0, G, want_jac=False)[0]
                rs.append(r)
            return np.concatenate(rs), (np.vstack(rows) if jac else None)

        x0 = np.concatenate([L0] + [np.concatenate([v0[f], xis[f]]) for f in range(nf)])
        lo = np.concatenate([[b[0] for b in self.bounds]] +
                            [np.concatenate([-np.ones(ns), -np.inf * np.ones(nx[f])]) for f in range(nf)])
        hi = np.concatenate([[b[1] for b in self.bounds]] +
                            [np.concatenate([np.ones(ns), np.inf * np.ones(nx[f])]) for f in range(nf)])
        x, nfev = box_gauss_newton(fun, np.clip(x0, lo, hi), lo, hi, max_nfev=max_nfev, tol=tol)
        L, vs, xs = unpack(x)
        D0, G, _, _ = self.response(joints, L)
        frames = []
        for f in range(nf):
            r, _, _, parts = pb.frame_residual(f, vs[f], xs[f], R0s[f], D0, G, want_jac=False)
            frames.append(FrameFit(vs[f], xs[f], 0.5 * float(r @ r), parts, nfev,
                                   pb.frames[f].transform(xs[f], R0s[f]), R0s[f]))
        return FitResult(joints, frames, float(sum(fr.cost for fr in frames)), nfev, 0.0), L

    def overrides(self, L, tol=1e-9):
        """``{joint name: {"length_mm": L}}`` for regions whose length differs from the joint's own."""
        scene = self.pb.scene
        names = scene.topology.joint_names
        out = {}
        for js, Lr in zip(self.regions, L):
            for k in js:
                if abs(scene.joint_hinge(names[k])["length_mm"] - Lr) > tol:
                    out[names[k]] = {"length_mm": float(Lr)}
        return out

    def report(self, L):
        names = self.pb.scene.topology.joint_names
        k1, _ = self.k1_of(L)
        return [{"region": r, "joints": [names[k] for k in js], "length_mm": float(L[r]),
                 "k1": float(k1[js[0]]), "range_mm": list(self.bounds[r])} for r, js in enumerate(self.regions)]
