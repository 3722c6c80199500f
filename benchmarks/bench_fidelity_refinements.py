"""Can cheap corrections lift the linear lattice to a third of the quadratic model's error at amplitude 0.5?

    /usr/bin/python3 benchmarks/bench_fidelity_refinements.py [--steps 3]

Measures, on the standard scenes of ``metamaterial_wb/bench/fidelity.py`` (chain, 10 x 10 grid, mixed hinge sizes) at
amplitudes 0.05 and 0.5, the RMS node-angle error (D units, rigid rotation removed) against the nonlinear
reference, divided by the quadratic model's error measured in the same run, for four ways of refining the
linear model's answer (docs/fidelity-models.md, "Why the linear model stays one solve"):

* ``frozen``: k modified-Newton corrections with the linear model's own factorisation (flat-sheet tangent,
  corotational residual of the nonlinear model, contact springs of the hinges in contact by low-rank
  updates), from the linear solution (chain poses);
* ``newton``: k full Newton steps (new tangent and factorisation each), from the linear solution;
* ``lbfgs``: k energy-decreasing L-BFGS steps preconditioned by the flat factorisation (constraints held
  by the projection; planar scenes keep them exactly), from the linear solution;
* ``stepped``: the load in k equal steps, one Newton iteration per step (k factorisations; k = 1 is the
  linear model without contact).

Column k = 0 is the linear model itself. Times are per refinement run (wall clock, one run, this shared
machine). Nothing here is used by the models; it documents what was tried.
"""
import argparse
import os
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))

from metamaterial_wb.bench import fidelity  # noqa: E402
from metamaterial_wb.core.lattice.geometry import LatticeGeometry  # noqa: E402
from metamaterial_wb.core.lattice.solve import LinearLattice, NonlinearLattice, _apply, _kkt_solve, finish  # noqa: E402
from metamaterial_wb.core.models import ModelResult, run_model  # noqa: E402


class Case:
    def __init__(self, scene):
        self.scene = scene
        self.geo = LatticeGeometry(scene)
        self.nl = NonlinearLattice(scene, self.geo)
        self.lin = LinearLattice(scene, self.geo)
        self.ref = run_model("nonlinear", scene, **fidelity.REFERENCE_OPTIONS)
        self.e_quad = fidelity.compare(scene, run_model("quadratic", scene), self.ref)["rms_D"]

    def ratio(self, X, R):
        if not (np.all(np.isfinite(X)) and np.all(np.isfinite(R))):
            return float("inf")
        X2, R2, _phi, D = finish(self.geo, X, R)
        return fidelity.compare(self.scene, ModelResult(D, X2, R2, [], {}, True, {}), self.ref)["rms_D"] / self.e_quad

    def residual(self, X, R, mu, lam=1.0):
        nl, pat = self.nl, self.nl.pattern
        st, E, ge, _ = nl._state(X, R, tangent=False)
        A = st.J[nl.joints, 5, :]
        r = pat.vector(ge) + pat.vector(A * mu[:, None], nl.joints)
        return st, E, r, A, nl._constraint(st, lam)

    def flat_solve(self, rhs, st):
        """The linear model's factorisation plus contact springs (frozen closing rows) on the hinges that
        are in contact at ``st``: a Woodbury update, no new factorisation."""
        lin, nl, pat = self.lin, self.nl, self.nl.pattern
        active = np.flatnonzero(nl.close_sign * st.eps[:, 5] - nl.kappa0 > 0) if st is not None else []
        if len(active) == 0:
            return lin.lu.solve(rhs)
        Ut = np.zeros((pat.N, active.size))
        ed = pat.ed[active]
        cols = np.broadcast_to(np.arange(active.size)[:, None], ed.shape)
        ok = ed >= 0
        np.add.at(Ut, (ed[ok], cols[ok]), (lin.close_sign[active, None] * lin.J5[active])[ok])
        Z = lin.lu.solve(Ut)
        y = lin.lu.solve(rhs)
        return y - Z @ np.linalg.solve(np.diag(1.0 / lin.kc[active]) + Ut.T @ Z, Ut.T @ y)

    def start(self):
        X, R, _q, mu = self.lin.solve()
        return X, R, mu


def frozen(case, k):
    X, R, mu = case.start()
    for _ in range(k):
        st, _E, r, _A, c = case.residual(X, R, mu)
        x = case.flat_solve(np.concatenate([-r, -c]), st)
        X, R = _apply(X, R, x[:case.lin.na], case.lin.dofmap, case.geo.n)
        mu = mu + x[case.lin.na:]
    return X, R


def newton(case, k):
    X, R, mu = case.start()
    nl = case.nl
    for _ in range(k):
        st, _E, r, A, c = case.residual(X, R, mu)
        x = _kkt_solve(nl.pattern, nl._tangent(st, mu), A, nl.reg, np.concatenate([-r, -c]))
        X, R = _apply(X, R, x[:nl.na], nl.dofmap, case.geo.n)
        mu = mu + x[nl.na:]
    return X, R


def lbfgs(case, k, memory=8):
    X, R, _mu = case.start()
    lin, na = case.lin, case.lin.na

    def fg(X, R):
        st, E, ge, _ = case.nl._state(X, R, tangent=False)
        return E, case.nl.pattern.vector(ge)

    def precond(g):
        rhs = np.zeros(case.nl.pattern.N)
        rhs[:na] = g
        return lin.lu.solve(rhs)[:na]

    E, g = fg(X, R)
    S, Y = [], []
    for _ in range(k):
        qv, alphas = g.copy(), []
        for s, y in reversed(list(zip(S, Y))):
            a = (s @ qv) / (y @ s)
            alphas.append(a)
            qv -= a * y
        d = precond(qv)
        for (s, y), a in zip(zip(S, Y), reversed(alphas)):
            d += s * (a - (y @ d) / (y @ s))
        d = -d
        if g @ d >= 0:
            d, S, Y = -precond(g), [], []
        step = 1.0
        for _ in range(30):
            X2, R2 = _apply(X, R, step * d, lin.dofmap, case.geo.n)
            E2, g2 = fg(X2, R2)
            if E2 <= E + 1e-4 * step * (g @ d):
                break
            step *= 0.5
        s, y = step * d, g2 - g
        if y @ s > 0:
            S, Y = (S + [s])[-memory:], (Y + [y])[-memory:]
        X, R, E, g = X2, R2, E2, g2
    return X, R


def stepped(case, k):
    geo, nl = case.geo, case.nl
    if k == 0:
        return case.start()[:2]
    X, R, mu = geo.X0.copy(), np.broadcast_to(np.eye(3), (geo.n, 3, 3)).copy(), np.zeros(nl.joints.size)
    for i in range(1, k + 1):
        st, _E, r, A, c = case.residual(X, R, mu, i / k)
        x = _kkt_solve(nl.pattern, nl._tangent(st, mu), A, nl.reg, np.concatenate([-r, -c]))
        X, R = _apply(X, R, x[:nl.na], nl.dofmap, geo.n)
        mu = mu + x[nl.na:]
    return X, R


VARIANTS = [("frozen", frozen), ("newton", newton), ("lbfgs", lbfgs), ("stepped", stepped)]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--steps", type=int, default=3, help="largest k")
    ap.add_argument("--load-steps", type=int, default=6, help="also run 'stepped' with this many load steps")
    args = ap.parse_args()
    ks = list(range(args.steps + 1))
    print("RMS node-angle error / the quadratic model's, after k refinements (k = 0: the linear model)\n")
    print("| scene | amplitude | refinement | " + " | ".join(f"k={k}" for k in ks) + " | ms at k=max |")
    print("|---|---|---|" + "---|" * len(ks) + "---|")
    for amp in (0.05, 0.5):
        for key, _title, scene in fidelity.standard_scenes(amp):
            if key not in ("chain", "grid10", "mixed"):
                continue
            case = Case(scene)
            rows = [(name, fn, ks) for name, fn in VARIANTS]
            rows.append((f"stepped, k={args.load_steps}", stepped, [args.load_steps]))
            for name, fn, kk in rows:
                cells, dt = [], 0.0
                for k in kk:
                    t = time.perf_counter()
                    with np.errstate(all="ignore"):
                        X, R = fn(case, k)
                    dt = time.perf_counter() - t
                    r = case.ratio(X, R)
                    cells.append(f"{r:.2f}" if r < 1e3 else "diverged")
                cells += [""] * (len(ks) - len(cells))
                print(f"| {key} | {amp} | {name} | " + " | ".join(cells) + f" | {dt * 1e3:.1f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
