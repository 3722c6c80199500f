"""Calibrating the sleeve beam model on CalculiX (issue 18, item 2c): one root-flexibility length fitted on the
FE unit cell's converged peak, then checked, unfitted, on the cell's valley and on the four-cell ring.

The beam model clamps each free beam half at the faces of its pillars (rigid links to the pillar centre
lines). The printed beam is built into pillars of its own soft material, whose material near the root deforms
too: the beam behaves as if clamped a little inside the support (the classical root-rotation correction of a
cantilever built into an elastic wall). ``root_extension`` (in units of the beam thickness ``t``) lets the
flexible beam continue that far into each pillar (``core/sleeve/model.py``). Its value is the one at which the
beam model's unit-cell peak, extrapolated in its own mesh, equals CalculiX's extrapolated peak; its
uncertainty is the range over which the model stays within the FE's error bar (plus the model's own mesh
error). Everything else the section reports is a check the fit never saw.

Input: the FE study ``benchmarks/results/fe-study.json`` (``bench fidelity --fe --fe-parts sleeve``) and the
long FE ring trace ``benchmarks/results/fe-ring-trace.json`` (``benchmarks/bench_sleeve_calibration.py
--trace``), both written by CalculiX runs; the beam-model runs are redone here (about a minute).
"""
import time

import numpy as np

from metamaterial_wb.bench.measures import convergence_error
from metamaterial_wb.fe.sleeve2d import peak_valley

CELL_MESHES = (8, 16, 32)
RING_MESHES = (6, 12, 24)
MARK_BEGIN, MARK_END = "<!-- fe-calibration:begin -->", "<!-- fe-calibration:end -->"


def _geom():
    from metamaterial_wb.core.sleeve.cell import CellGeometry
    return CellGeometry()


def model_cell_pv(e, n_el, d_max=0.7, steps=140):
    """``(d_peak, F_peak, d_valley, F_valley)`` of the beam model's unit cell at root extension ``e``."""
    from metamaterial_wb.core.sleeve.model import cell_curve
    up, _ = cell_curve(_geom(), n_el=n_el, steps=steps, d_max=d_max, unload=False, root_extension=e)
    return peak_valley(up.d, up.F), up


def model_ring(e, n_el, d_max=0.7, steps=140, curvature=False):
    from metamaterial_wb.core.sleeve.model import SleeveModel
    m = SleeveModel([_geom()], [[0, 0, 0, 0]], n_el, imperfection=1e-4, curvature=curvature, root_extension=e)
    return m.trace(np.linspace(0, d_max, steps + 1))


def extrapolated(meshes, values):
    """``(value, error)`` per column: Richardson in ``h ~ 1/n`` (measures.convergence_error)."""
    ext, err, _ = convergence_error([1.0 / n for n in meshes], np.asarray(values, float))
    return np.atleast_1d(ext), np.atleast_1d(err)


def cell_peak(e, meshes=CELL_MESHES, d_max=0.3, steps=60):
    """The cell's peak at ``e``, extrapolated in the beam mesh: ``(value, mesh error)``."""
    vals = [model_cell_pv(e, n, d_max, steps)[0][1] for n in meshes]
    v, err = extrapolated(meshes, vals)
    return float(v[0]), float(err[0])


def fit_root_extension(target, target_err, lo=0.0, hi=1.5, tol=0.01, meshes=CELL_MESHES):
    """``(e, e_low, e_high)``: the root extension whose extrapolated cell peak equals ``target``, and the ones
    where it reaches ``target +- target_err`` (bisection: the peak falls monotonically with e)."""
    def solve(y):
        a, b = lo, hi
        while b - a > tol:
            m = 0.5 * (a + b)
            a, b = (m, b) if cell_peak(m, meshes)[0] > y else (a, m)
        return 0.5 * (a + b)
    return solve(target), solve(target + target_err), solve(target - target_err)


def ring_extrema(d, F):
    """P1, V1, P2, V2 (and where) of a ring curve: its alternating peaks and valleys as the sleeve analysis
    counts them (``core.sleeve.analysis.extrema``: a wiggle smaller than 2 % of the curve's range is none), each
    refined by a parabola through its three points. A list of ``(d, F)``, at most four."""
    from metamaterial_wb.core.sleeve.analysis import extrema
    d, F = np.asarray(d, float), np.asarray(F, float)
    p, v = extrema(F)
    out = []
    for i in sorted(p + v)[:4]:
        if 0 < i < len(F) - 1:
            x, y = d[i - 1:i + 2], F[i - 1:i + 2]
            A = np.polyfit(x, y, 2)
            xv = -A[1] / (2 * A[0]) if A[0] else x[1]
            out.append((float(xv), float(np.polyval(A, xv))) if x[0] <= xv <= x[2] else (float(d[i]), float(F[i])))
        else:
            out.append((float(d[i]), float(F[i])))
    return out


def run(fe_study, trace=None, progress=print, fit=None, bias_trace=None):
    """The calibration and its checks as a plain dict (JSON-able). ``fit``: ``(e, e_low, e_high)`` of an earlier
    :func:`fit_root_extension` on the same FE study (skips the bisection)."""
    cell_fe = fe_study["cell"]["fe_extrapolated"]
    ring_fe = fe_study["ring"].get("fe_extrapolated")
    Fp, eFp = cell_fe["pv"][1], cell_fe["err"][1]
    e, e_lo, e_hi = fit if fit is not None else fit_root_extension(Fp, eFp)
    progress(f"root extension {e:.3f} t (FE peak band: {e_lo:.3f} .. {e_hi:.3f})")
    out = {"root_extension": e, "root_extension_range": [e_lo, e_hi], "fe_cell": cell_fe, "fe_ring": ring_fe,
           "fe_cell_by_mesh": {str(f["r"]): f["pv"] for f in fe_study["cell"]["fe"]},
           "fe_ring_by_mesh": {str(f["r"]): f["pv"][:2] for f in fe_study["ring"]["fe"]},
           "fe_cell_wall_s": {str(f["r"]): f["wall_s"] for f in fe_study["cell"]["fe"]}}
    rows = {}
    for name, ee in (("uncalibrated", 0.0), ("calibrated", e)):
        pvs, walls = [], []
        for n in CELL_MESHES:
            t0 = time.perf_counter()
            pvs.append(model_cell_pv(ee, n)[0])
            walls.append(time.perf_counter() - t0)
        v, err = extrapolated(CELL_MESHES, pvs)
        rows[name] = {"cell_pv": v.tolist(), "cell_err": err.tolist(), "cell_by_mesh": [list(p) for p in pvs],
                      "cell_wall_s": walls}
        rp = [peak_valley(*(lambda p: (p.d, p.F))(model_ring(ee, n, d_max=0.18, steps=36)))[:2] for n in RING_MESHES]
        v, err = extrapolated(RING_MESHES, rp)
        rows[name].update({"ring_p1": v.tolist(), "ring_p1_err": err.tolist()})
        progress(f"{name}: cell {np.round(rows[name]['cell_pv'], 5)}, ring P1 {np.round(rows[name]['ring_p1'], 5)}")
    out["models"] = rows
    if trace is not None:
        n = max(RING_MESHES)
        for name, ee in (("uncalibrated", 0.0), ("calibrated", e)):
            p = model_ring(ee, n, d_max=max(trace["d"][-1], 0.2), steps=140)
            rows[name]["ring_curve"] = {"n_el": n, "d": p.d.tolist(), "F": p.F.tolist(),
                                        "tilt_deg": np.degrees(np.hypot(*np.asarray(p.tilt).T)).tolist(),
                                        "extrema": ring_extrema(p.d, p.F)}
        out["trace"] = {k: trace[k] for k in ("r", "d", "F", "tilt_rad")}
        out["trace"]["info"] = {k: trace["info"].get(k) for k in ("wall_s", "increments", "d_reached", "stopped",
                                                                  "dofs", "elements")}
        out["trace"]["extrema"] = ring_extrema(trace["d"], trace["F"])
        if bias_trace is not None:
            out["trace_bias"] = {k: bias_trace[k] for k in ("r", "bias", "d", "F", "tilt_rad")}
            out["trace_bias"]["info"] = {k: bias_trace["info"].get(k) for k in ("wall_s", "increments", "d_reached",
                                                                                "stopped")}
            out["trace_bias"]["extrema"] = ring_extrema(bias_trace["d"], bias_trace["F"])
    return out


def _rel(m, em, f, ef):
    r = m / f - 1.0
    return r, abs(m / f) * np.hypot(em / abs(m), ef / abs(f))


def fe_order_note(cal):
    """``extrapolation.order_note`` of the CalculiX column of :func:`markdown`'s table, from the stored meshes
    (``fe_cell_by_mesh``, ``fe_ring_by_mesh``: what ``fe_sleeve.summarise`` extrapolated): ``""`` when every order
    was observed inside the range."""
    from metamaterial_wb.core.extrapolation import order_note
    figs = []
    for key, names in (("fe_cell_by_mesh", ("cell peak at d/L", "cell peak (fitted)", "cell valley at d/L",
                                            "cell valley")),
                       ("fe_ring_by_mesh", ("four-cell ring P1 at d/L", "four-cell ring P1 (flat)"))):
        by = cal.get(key) or {}
        if key == "fe_ring_by_mesh" and not cal.get("fe_ring"):
            continue
        rs = sorted(by, key=int)
        figs.append(([f"CalculiX, extrapolated: {n}" for n in names], [1.0 / int(r) for r in rs],
                     [by[r][:len(names)] for r in rs]))
    return order_note(figs)


def markdown(cal, img=None):
    e, (elo, ehi) = cal["root_extension"], cal["root_extension_range"]
    fc, fr = cal["fe_cell"], cal["fe_ring"]
    L = [MARK_BEGIN, "", "### Calibrating the beam model on CalculiX (issue 18)", "",
         "Regenerated by `benchmarks/bench_sleeve_calibration.py` (`metamaterial_wb/bench/fe_sleeve_calibration.py`). "
         "**Physical reason.** The beam model clamps each free beam half at its pillars' faces. The printed beam is "
         "built into pillars of the same soft material, which deform near the root too: the beam turns at its root "
         "as if clamped a little inside the support (the root-rotation correction of a cantilever built into an "
         "elastic wall). `root_extension` (units of `t`; `SleeveModel(..., root_extension=...)`, "
         "`core/sleeve/model.py`) continues the flexible beam that far into each pillar. **Fit**: one number, on "
         "one figure - the unit cell's peak, the beam model extrapolated in its mesh (8, 16, 32 elements per half) "
         f"against CalculiX extrapolated: **root_extension = {e:.2f} t** (the FE's error bar on the peak maps to "
         f"{elo:.2f} .. {ehi:.2f} t). **Checks** (not fitted): the cell's valley and both positions, and the "
         "four-cell ring (flat, as the 2-D FE ring).", "",
         "| figure (forces x1e-3) | CalculiX, extrapolated | beam model as documented (root_extension 0) | "
         f"calibrated ({e:.2f} t) | calibrated against CalculiX |", "|---|---|---|---|---|"]
    mu, mc = cal["models"]["uncalibrated"], cal["models"]["calibrated"]
    fig = [("cell peak (fitted)", 1, fc["pv"], fc["err"], "cell_pv", "cell_err", 1e3),
           ("cell peak at d/L", 0, fc["pv"], fc["err"], "cell_pv", "cell_err", 1.0),
           ("cell valley", 3, fc["pv"], fc["err"], "cell_pv", "cell_err", 1e3),
           ("cell valley at d/L", 2, fc["pv"], fc["err"], "cell_pv", "cell_err", 1.0)]
    if fr:
        fig += [("four-cell ring P1 (flat)", 1, fr["pv"], fr["err"], "ring_p1", "ring_p1_err", 1e3),
                ("four-cell ring P1 at d/L", 0, fr["pv"], fr["err"], "ring_p1", "ring_p1_err", 1.0)]
    for name, j, fv, fe, kv, ke, s in fig:
        cells = [f"{s * fv[j]:.3f} +- {s * fe[j]:.3f}"]
        for m in (mu, mc):
            cells.append(f"{s * m[kv][j]:.3f} +- {s * m[ke][j]:.3f}")
        if s != 1.0:
            r, u = _rel(mc[kv][j], mc[ke][j], fv[j], fe[j])
            ok = "within" if abs(r) <= u else "outside"
            cells.append(f"{100 * r:+.1f} % +- {100 * u:.1f} % ({ok} the error)")
        else:
            cells.append(f"{mc[kv][j] - fv[j]:+.3f} +- {np.hypot(mc[ke][j], fe[j]):.3f}")
        L.append(f"| {name} | " + " | ".join(cells) + " |")
    L.append("")
    note = fe_order_note(cal)
    L += [note, ""] if note else []
    if "trace" in cal:
        L += trace_lines(cal)
    if img:
        L += [f"![calibrated beam model against CalculiX]({img})", ""]
    L.append(MARK_END)
    return "\n".join(L) + "\n"


def trace_lines(cal):
    tr = cal["trace"]
    info = tr["info"]
    names = ("P1", "V1", "P2", "V2")
    out = ["**The FE ring over the working range.** CalculiX's four-cell ring at mesh r = "
           f"{tr['r']} ({info.get('elements')} elements, {info.get('dofs')} DOFs), displacement control in "
           f"{info.get('increments')} converged increments to d/L {info.get('d_reached', float('nan')):.3f} "
           f"({info.get('wall_s', float('nan')) / 60:.0f} min)" +
           (f"; **it stopped there**: {info['stopped'].splitlines()[0]}" if info.get("stopped") else ", the whole range") +
           ". Its extrema against the beam model's flat ring (24 elements per half), forces x1e-3 (d/L):", "",
           "| extremum | CalculiX r = %d | beam model as documented | calibrated |" % tr["r"], "|---|---|---|---|"]
    ex = [tr["extrema"], cal["models"]["uncalibrated"]["ring_curve"]["extrema"],
          cal["models"]["calibrated"]["ring_curve"]["extrema"]]
    ends = [tr["d"][-1], cal["models"]["uncalibrated"]["ring_curve"]["d"][-1],
            cal["models"]["calibrated"]["ring_curve"]["d"][-1]]
    # the error of the r-mesh trace: at its first peak, its distance to the ring's extrapolated P1 (plus that
    # extrapolation's error); at the valleys (no ring mesh study there), the unit cell's valley at the same mesh
    r = str(tr["r"])
    fp = fv = None
    if cal.get("fe_ring") and r in cal.get("fe_ring_by_mesh", {}):
        P, eP = cal["fe_ring"]["pv"][1], cal["fe_ring"]["err"][1]
        fp = (abs(cal["fe_ring_by_mesh"][r][1] - P) + eP) / abs(P)
    if r in cal.get("fe_cell_by_mesh", {}):
        V, eV = cal["fe_cell"]["pv"][3], cal["fe_cell"]["err"][3]
        fv = (abs(cal["fe_cell_by_mesh"][r][3] - V) + eV) / abs(V)
    for k, nm in enumerate(names):
        f = fp if k % 2 == 0 else fv
        cells = []
        for i, x in enumerate(ex):
            if len(x) <= k:
                cells.append(f"none (to d/L {ends[i]:.3f})")
                continue
            err = f" +- {1e3 * abs(x[k][1]) * f:.3f}" if i == 0 and f is not None else ""
            cells.append(f"{1e3 * x[k][1]:.3f}{err} ({x[k][0]:.3f})")
        out.append(f"| {nm} | " + " | ".join(cells) + " |")
    out.append("")
    from metamaterial_wb.bench.fe_ring3d import tilt_facts
    ft = np.degrees(np.hypot(*np.asarray(tr["tilt_rad"]).T))
    mu = cal["models"]["uncalibrated"]["ring_curve"]
    mc = cal["models"]["calibrated"]["ring_curve"]
    out += [f"Tilt of the top plate: CalculiX {tilt_facts(tr['d'], ft)}; beam model as documented "
            f"{tilt_facts(mu['d'], mu['tilt_deg'])}; calibrated {tilt_facts(mc['d'], mc['tilt_deg'])}.", ""]
    if "trace_bias" in cal:
        tb = cal["trace_bias"]
        ib = tb["info"]
        exb = tb["extrema"]
        tiltb = np.degrees(np.hypot(*np.asarray(tb["tilt_rad"]).T))
        listed = ", ".join(f"{nm} {1e3 * x[1]:.3f} ({x[0]:.3f})" for nm, x in zip(names, exb)) or "none"
        out += [f"**Branch check**: the same FE ring with a {tb['bias'] / 1e-5:.0f} times larger tilt bias "
                f"({tb['bias']:.0e} G L^2; {ib.get('increments')} increments to d/L {ib.get('d_reached', float('nan')):.3f}"
                + (f", stopped: {ib['stopped'].splitlines()[0]}" if ib.get("stopped") else "") +
                f"): extrema {listed}; tilt {tilt_facts(tb['d'], tiltb)}.", ""]
    if fp is not None and fv is not None:
        out += [f"The FE trace's error (mesh r = {r}) is estimated, not extrapolated (one mesh over the whole range): "
                f"at the peaks its first peak's distance to the ring's three-mesh extrapolation ({100 * fp:.0f} %), "
                f"at the valleys the unit cell's valley error at the same mesh ({100 * fv:.0f} %).", ""]
    return out


def _logbars(y, e):
    """Error bars for a log axis: the upper one ``e``, the lower one cut where it would cross zero (drawn to the
    axis' floor, 1e-3)."""
    y = np.asarray(y, float)
    return np.vstack([np.minimum(e, y - 1e-3 * 0.999), np.full_like(y, e)]).clip(min=0)


def plot(cal, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (ax, ax2, ax3) = plt.subplots(1, 3, figsize=(14, 3.8), dpi=110)
    if "trace" in cal:
        tr = cal["trace"]
        ax.plot(tr["d"], 1e3 * np.asarray(tr["F"]), "k-", lw=1.6, label=f"CalculiX ring, r = {tr['r']}")
        tilt = np.degrees(np.hypot(*np.asarray(tr["tilt_rad"]).T))
        ax2.plot(tr["d"][:len(tilt)], tilt, "k-", lw=1.6, label=f"CalculiX ring, r = {tr['r']}")
        if "trace_bias" in cal:
            tb = cal["trace_bias"]
            lab = f"CalculiX ring, r = {tb['r']}, tilt bias {tb['bias']:.0e}"
            ax.plot(tb["d"], 1e3 * np.asarray(tb["F"]), "-", color="0.55", lw=1.3, label=lab)
            tt = np.degrees(np.hypot(*np.asarray(tb["tilt_rad"]).T))
            ax2.plot(tb["d"][:len(tt)], tt, "-", color="0.55", lw=1.3, label=lab)
        for name, st in (("uncalibrated", "C0--"), ("calibrated", "C3-")):
            c = cal["models"][name]["ring_curve"]
            lab = (f"beam model, flat, root_extension {cal['root_extension']:.2f} t" if name == "calibrated"
                   else "beam model, flat, as documented")
            ax.plot(c["d"], 1e3 * np.asarray(c["F"]), st, lw=1.1, label=lab)
            ax2.plot(c["d"], c["tilt_deg"], st, lw=1.1, label=lab)
    fr = cal["fe_ring"]
    if fr:
        ax.errorbar([fr["pv"][0]], [1e3 * fr["pv"][1]], yerr=[1e3 * fr["err"][1]], fmt="ks", ms=4, capsize=3,
                    label="CalculiX P1, extrapolated (r = 1, 2, 3)")
    ax.axhline(0, color="k", lw=0.5)
    ax.set_xlabel("d / L")
    ax.set_ylabel("F / (G L^2) x1e-3")
    ax.set_title("four-cell ring: force", fontsize=9)
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    ax2.set_xlabel("d / L")
    ax2.set_ylabel("tilt of the top plate (deg)")
    ax2.set_title("four-cell ring: tilt", fontsize=9)
    ax2.legend(fontsize=7)
    ax2.grid(alpha=0.3)
    # work-precision of the unit cell's peak: every rung's error against CalculiX extrapolated, +- that error
    fc = cal["fe_cell"]
    P, eP = fc["pv"][1], fc["err"][1]
    rs = sorted(cal.get("fe_cell_by_mesh", {}), key=int)
    if rs:
        x = [cal["fe_cell_wall_s"][r] for r in rs]
        y = [abs(cal["fe_cell_by_mesh"][r][1] / P - 1) for r in rs]
        ax3.errorbar(x, y, yerr=_logbars(y, eP / abs(P)), fmt="P-", color="C3", capsize=3, label="CalculiX r = 1, 2, 3")
    for name, st in (("uncalibrated", "o--"), ("calibrated", "s-")):
        m = cal["models"][name]
        if "cell_by_mesh" in m:
            y = [abs(p[1] / P - 1) for p in m["cell_by_mesh"]]
            ax3.errorbar(m["cell_wall_s"], y, yerr=_logbars(y, eP / abs(P)), fmt=st, capsize=3,
                         label=f"beam model {'calibrated' if name == 'calibrated' else 'as documented'}, "
                               f"{', '.join(map(str, CELL_MESHES))} el.")
    ax3.set_xscale("log")
    ax3.set_yscale("log")
    ax3.set_ylim(bottom=1e-3)
    ax3.set_xlabel("run time (s)")
    ax3.set_ylabel("|peak / CalculiX extrapolated - 1|")
    ax3.set_title("unit cell peak: error against run time", fontsize=9)
    ax3.legend(fontsize=7)
    ax3.grid(alpha=0.3, which="both")
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def write_section(doc_path, section):
    """Replace the marked calibration section (inserted before "## Sequencing" the first time)."""
    from metamaterial_wb.bench.fe_sleeve import write_section as write_marked
    return write_marked(doc_path, section, MARK_BEGIN, MARK_END)


def fidelity_markdown(sleeve, calibration=None, curved=None):
    """The sleeve part of docs/fidelity.md's FE section: where the sleeve beam model can be trusted, measured
    against CalculiX (``sleeve``: the FE sleeve study, ``calibration``: :func:`run`'s result or None, ``curved``:
    the curved 3-D FE ring's summary from ``benchmarks/bench_sleeve_ring3d.py`` or None)."""
    from metamaterial_wb.bench.fe_cell_elements import reference_sentence
    from metamaterial_wb.bench.fe_sleeve import figures, summarise
    from metamaterial_wb.core.extrapolation import order_note
    sl = summarise(sleeve)
    c, r_ = sl["cell"], sl["ring"]
    L = ["### Sleeve cell and ring: the beam model against CalculiX\n",
         "The sleeve's beam model (`core/sleeve/model.py`) against a plane-strain CPE8R model of the same printed "
         "outline (three nested meshes each, Richardson; details, run times and the curves in "
         "[sleeves.md](sleeves.md#calculix-check-of-the-cell-and-the-four-cell-ring-issue-18)). Forces x1e-3 G L^2, "
         "every figure +- the error of both extrapolations.\n"]
    if "fe_extrapolated" not in c or "model_extrapolated" not in c:
        return "\n".join(L + ["(the FE sleeve study has fewer than two meshes)\n"])
    fe, efe = c["fe_extrapolated"]["pv"], c["fe_extrapolated"]["err"]
    mo, emo = c["model_extrapolated"]["pv"], c["model_extrapolated"]["err"]
    rows = [("unit cell, peak", mo[1], emo[1], fe[1], efe[1]), ("unit cell, valley", mo[3], emo[3], fe[3], efe[3])]
    if "fe_extrapolated" in r_ and "model_extrapolated_flat" in r_:
        rows.append(("four-cell ring (flat), P1", r_["model_extrapolated_flat"]["pv"][1],
                     r_["model_extrapolated_flat"]["err"][1], r_["fe_extrapolated"]["pv"][1],
                     r_["fe_extrapolated"]["err"][1]))
    cal = {}
    if calibration:
        mc = calibration["models"]["calibrated"]
        cal = {"unit cell, peak": (mc["cell_pv"][1], mc["cell_err"][1]),
               "unit cell, valley": (mc["cell_pv"][3], mc["cell_err"][3]),
               "four-cell ring (flat), P1": (mc["ring_p1"][1], mc["ring_p1_err"][1])}
    if curved and curved.get("p1_fe"):
        fx, fe_err = curved["p1_fe"]
        rows.append(("four-cell ring (curved 3-D), P1", curved["p1_model"], 0.0, fx, fe_err))
        cal["four-cell ring (curved 3-D), P1"] = (curved["p1_model_calibrated"], 0.0)
    head = "| figure | CalculiX | beam model | beam model / CalculiX - 1 |"
    if cal:
        head += f" calibrated (root_extension {calibration['root_extension']:.2f} t) | calibrated / CalculiX - 1 |"
    L += [head, "|" + "---|" * (head.count("|") - 1)]
    def pm(v, e):                                  # a model figure with its mesh error, if it has one
        return f"{1e3 * v:.3f}" + (f" +- {1e3 * e:.3f}" if e else " (default mesh)")
    for name, m, em, f, ef in rows:
        r, u = _rel(m, em, f, ef)
        row = f"| {name} | {1e3 * f:.3f} +- {1e3 * ef:.3f} | {pm(m, em)} | {100 * r:+.0f} % +- {100 * u:.0f} % |"
        if cal:
            mcv, mce = cal[name]
            rc, uc = _rel(mcv, mce, f, ef)
            row += (f" {pm(mcv, mce)} | {100 * rc:+.1f} % +- {100 * uc:.1f} %"
                    f"{' (fitted)' if name == 'unit cell, peak' else ''} |")
        L.append(row)
    pv = (None, "peak", None, "valley")                 # the figures the table shows
    note = order_note([figures(c["fe"], "r", 4, "CalculiX, unit cell", pv),
                       figures(c["model"], "n_el", 4, "beam model, unit cell", pv)] +
                      ([figures(r_["fe"], "r", 2, "CalculiX, four-cell ring (flat)", (None, "P1")),
                        figures([m for m in r_["model"] if not m["curvature"]], "n_el", 2,
                                "beam model, four-cell ring (flat)", (None, "P1"))]
                       if "fe_extrapolated" in r_ and "model_extrapolated_flat" in r_ else []))
    L += ["", note] if note else []
    ratio_fe = r_["fe_extrapolated"]["pv"][1] / fe[1] if "fe_extrapolated" in r_ else float("nan")
    ratio_mo = r_["model_extrapolated_flat"]["pv"][1] / mo[1] if "model_extrapolated_flat" in r_ else float("nan")
    rp, _ = _rel(mo[1], emo[1], fe[1], efe[1])
    rv, _ = _rel(mo[3], emo[3], fe[3], efe[3])
    L += ["", "**Where the sleeve beam model can be trusted (measured).** As documented (no root flexibility) its "
          f"absolute forces are not: {100 * rp:+.0f} % on the cell's peak, {100 * rv:+.0f} % on its valley depth. "
          "What it gets right against CalculiX: the kind of curve (peak, negative stiffness, bistable valley), the "
          f"ring-to-cell force ratio (first peak / cell peak {ratio_mo:.2f} against the FE's {ratio_fe:.2f}), the "
          f"snapping positions within {abs(mo[0] - fe[0]):.3f} d/L (peak) and {abs(mo[2] - fe[2]):.3f} d/L (valley)."
          + (" With the root-flexibility length fitted on the FE cell's peak, the four-cell ring's first peak, which "
             "the fit never saw, is the flat ring's row; the valley is the table's second." if cal else "") +
          " The beam model's own mesh error at its defaults is in sleeves.md's convergence tables (a few per cent at "
          "most, far below these gaps)." + reference_sentence(c) + (curved["sentence"] if curved and curved.get("sentence") else
          " The ring's curvature is checked by a curved 3-D FE ring (sleeves.md, \"A curved 3-D FE ring\").")]
    if calibration and "trace" in calibration:
        tr = calibration["trace"]
        info = tr["info"]

        def kinds(ex):
            n = len(ex)
            return f"{(n + 1) // 2} peak{'s' if (n + 1) // 2 != 1 else ''} and {n // 2} valley{'s' if n // 2 != 1 else ''}"
        mex = calibration["models"]["uncalibrated"].get("ring_curve", {}).get("extrema")
        cex = calibration["models"]["calibrated"].get("ring_curve", {}).get("extrema")
        L.append(f"Over the working range: the FE ring (mesh r = {tr['r']} only, traced to d/L "
                 f"{info.get('d_reached', float('nan')):.2f}"
                 f"{'; ' + info['stopped'].splitlines()[0] if info.get('stopped') else ''}) shows "
                 f"{kinds(tr.get('extrema', []))}" +
                 (f", the flat beam model {kinds(mex)} (calibrated: {kinds(cex)})" if mex is not None and cex is not None
                  else "") + "; the values, their estimated errors and the tilt are in sleeves.md. Beyond the first "
                 "peak the ring's shape is therefore trusted only as far as that comparison goes.")
    L.append("")
    return "\n".join(L) + "\n"
