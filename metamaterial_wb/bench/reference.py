"""The converged lattice reference: the nonlinear model with hinges of n = 1, 2, 4, 8 corotational Timoshenko
elements (option ``hinge_elements``), extrapolated to n -> infinity (Richardson), with its uncertainty.

The reported reference is the extrapolated field (in-plane plate rotations and positions). Its uncertainty is
the correction the extrapolation made to the finest level (``|extrapolated - finest|``, in the same units as
the errors: RMS and max D, max position / cell): by the triangle inequality every model's error against the
unknown converged answer lies within that band of its error against the reference, which is what the error
bars of docs/fidelity.md show. The observed order comes from the last three levels (clipped to [1, 4]); with
fewer converged levels order 2 is assumed and said so. Where the levels are not in the asymptotic range (a
doubling of n does not at least halve the RMS change, e.g. a plate that snaps to another branch between
levels) the uncertainty is the conservative one: the second finest level's distance from the reference.
"""
import time

import numpy as np

from metamaterial_wb.core.models import run_model

HINGE_LEVELS = (1, 2, 4, 8)


class ExtrapolatedReference:
    """What :func:`metamaterial_wb.bench.fidelity.compare` needs of a reference: in-plane plate rotations
    ``phi`` (radians) and ``positions_mm``."""

    def __init__(self, phi, positions_mm):
        self.phi = np.asarray(phi, float)
        self.positions_mm = np.asarray(positions_mm, float)


def _aligned(results):
    """Plate rotations (rigid rotation removed against the finest) and positions (Kabsch onto the finest)."""
    from metamaterial_wb.bench.measures import twist
    from metamaterial_wb.core.lattice.solve import kabsch

    fin = results[-1]
    phi_f = twist(fin.rotations)
    P_f = np.asarray(fin.positions_mm, float)
    phis, Ps = [], []
    for r in results:
        phi = twist(r.rotations)
        phis.append(phi - np.mean(phi - phi_f))
        P = np.asarray(r.positions_mm, float)
        if len(P) > 1:
            Rm, tv = kabsch(P, P_f)
            P = P @ Rm.T + tv
        Ps.append(P)
    return phis, Ps


def observed_order(levels, fields):
    """Order from the RMS changes between the last three levels (doubling n); None with fewer than three."""
    if len(fields) < 3:
        return None
    d1 = np.sqrt(np.mean((fields[-2] - fields[-3]) ** 2))
    d2 = np.sqrt(np.mean((fields[-1] - fields[-2]) ** 2))
    r = levels[-1] / levels[-2]
    if d2 <= 0 or d1 <= 0:
        return None
    return float(np.log(d1 / d2) / np.log(r))


def converged_reference(scene, levels=HINGE_LEVELS, options=None, progress=None):
    """Run the nonlinear model at every level; return ``(reference, study)``.

    ``study``: ``{"levels": [{"n", "time_s", "converged", "info", "result"}], "order", "order_assumed",
    "uncertainty": {"rms_D", "max_D", "max_pos"}, "used_levels"}``.
    """
    from metamaterial_wb.bench.measures import REFERENCE_OPTIONS, compare

    opts = dict(REFERENCE_OPTIONS if options is None else options)
    runs = []
    for n in levels:
        if progress:
            progress(f"reference: nonlinear, {n} element(s) per hinge")
        t = time.perf_counter()
        res = run_model("nonlinear", scene, hinge_elements=n, **opts)
        runs.append({"n": n, "time_s": time.perf_counter() - t, "converged": bool(res.converged),
                     "info": res.info, "result": res})
    ok = [r for r in runs if r["converged"]]
    if not ok:
        ok = runs[:1]
    used = [r["n"] for r in ok]
    phis, Ps = _aligned([r["result"] for r in ok])
    p = observed_order(used, phis)
    assumed = p is None or not np.isfinite(p)
    if assumed:
        p = 2.0
    p = float(np.clip(p, 1.0, 4.0))
    if len(ok) >= 2:
        ratio = used[-1] / used[-2]
        f = 1.0 / (ratio ** p - 1.0)
        phi_ext = phis[-1] + f * (phis[-1] - phis[-2])
        P_ext = Ps[-1] + f * (Ps[-1] - Ps[-2])
    else:
        phi_ext, P_ext = phis[-1], Ps[-1]
    ref = ExtrapolatedReference(phi_ext, P_ext)
    # asymptotic: every doubling of n shrinks the RMS change by at least 2; if not (a branch switch somewhere,
    # or pre-asymptotic levels) the uncertainty is the conservative one: the error of the second finest level
    changes = [float(np.sqrt(np.mean((phis[k + 1] - phis[k]) ** 2))) for k in range(len(phis) - 1)]
    asymptotic = all(changes[k + 1] <= 0.5 * changes[k] for k in range(len(changes) - 1))
    if len(ok) < 2:
        unc = {"rms_D": float("nan"), "max_D": float("nan"), "max_pos": float("nan")}
    else:
        unc = compare(scene, ok[-1 if asymptotic else -2]["result"], ref)
    for r in runs:
        r["error"] = compare(scene, r["result"], ref)
    study = {"levels": runs, "order": p, "order_assumed": assumed, "used_levels": used, "asymptotic": asymptotic,
             "rms_changes_rad": changes,
             "uncertainty": {k: float(unc[k]) for k in ("rms_D", "max_D", "max_pos")}}
    return ref, study


def strip(study):
    """The study without the model results (JSON-able)."""
    out = dict(study)
    out["levels"] = [{k: v for k, v in r.items() if k != "result"} for r in study["levels"]]
    return out
