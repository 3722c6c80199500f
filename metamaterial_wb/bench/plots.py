"""Work-precision diagrams: error against run time for every rung, with the reference's error bars."""
import io

import numpy as np

FLOOR = 1e-12


def _bar(y, u):
    """Asymmetric error bar for a log axis: the lower bar stops above zero."""
    y = max(y, FLOOR)
    if not np.isfinite(u):
        return [[0.0], [0.0]]
    return [[min(u, 0.95 * y)], [u]]


def work_precision(results, path, fe_study=None):
    """Rows: one per amplitude (and one for the FE hinge if ``fe_study``); columns: angle error, position
    error against run time. Error bars: the converged reference's uncertainty."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from metamaterial_wb.core.fileio import write_atomic

    amps = sorted({r["amplitude"] for r in results})
    has_hinge = bool(fe_study and fe_study.get("bending"))
    has_patch = bool(fe_study and fe_study.get("patch"))
    nrows = len(amps) + int(has_hinge) + int(has_patch)
    fig, axes = plt.subplots(nrows, 2, figsize=(12, 4.6 * nrows), squeeze=False)
    markers = {"quadratic": "s", "linear": "^", "linear_flat": "v", "dr": "x"}
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    keys = []
    for r in results:
        if r["key"] not in keys:
            keys.append(r["key"])
    for ia, amp in enumerate(amps):
        for ic, (metric, bar, ylabel) in enumerate((("rms_D", "ref_rms_D", "RMS node-angle error (D units)"),
                                                    ("max_pos", "ref_max_pos", "max position error / cell size"))):
            ax = axes[ia, ic]
            for r in results:
                if r["amplitude"] != amp:
                    continue
                col = colors[keys.index(r["key"]) % len(colors)]
                nl = [row for row in r["rows"] if row["model"] == "nonlinear"]
                ax.plot([row["time_s"] * 1e3 for row in nl], [max(row[metric], FLOOR) for row in nl], "-o",
                        color=col, ms=3, alpha=0.6)
                nn = [row for row in r["rows"] if row["model"] == "nonlinear_n"]
                one = [row for row in nl if not row["options"]]
                chain = one + nn
                ax.plot([row["time_s"] * 1e3 for row in chain], [max(row[metric], FLOOR) for row in chain], "--D",
                        color=col, ms=5)
                for row in r["rows"]:
                    if row["model"] in markers or row["model"] == "nonlinear_n":
                        mk = markers.get(row["model"], "D")
                        ax.errorbar(row["time_s"] * 1e3, max(row[metric], FLOOR), yerr=_bar(row[metric], row[bar]),
                                    fmt=mk, color=col, ms=8 if mk != "D" else 5, capsize=3,
                                    mfc="none" if row["model"] == "quadratic" else col)
                # the reference's own uncertainty (a band at the right edge)
                u = r["rows"][0][bar]
                if np.isfinite(u) and u > 0:
                    ax.axhline(u, color=col, lw=0.8, ls=":")
            ax.set_xscale("log")
            ax.set_yscale("log")
            ax.set_xlabel("run time (ms)")
            ax.set_ylabel(ylabel)
            ax.set_title(f"actuator amplitude {amp}")
            ax.grid(True, which="both", alpha=0.3)
    from matplotlib.lines import Line2D
    handles = [Line2D([], [], ls="none", marker="s", mfc="none", color="k", label="quadratic (R0)"),
               Line2D([], [], ls="none", marker="^", color="k", label="linear lattice (R1, about the quadratic state)"),
               Line2D([], [], ls="none", marker="v", color="k", label="linear lattice at the flat sheet (about=flat)"),
               Line2D([], [], ls="-", marker="o", ms=3, color="k", label="nonlinear (R2), 1 element/hinge, tol 1e-2 .. 1e-8"),
               Line2D([], [], ls="--", marker="D", ms=5, color="k", label="nonlinear (R2), 1, 2, 4, 8 elements/hinge"),
               Line2D([], [], ls=":", color="k", label="reference uncertainty (= error bar)"),
               Line2D([], [], ls="none", marker="x", color="k", label="dynamic relaxation alone"),
               Line2D([], [], ls="none", marker="P", color="C3", label="CalculiX (mesh study)")]
    handles += [Line2D([], [], ls="-", color=colors[i % len(colors)], label=k) for i, k in enumerate(keys)]
    fig.legend(handles=handles, loc="lower center", ncol=4, fontsize=8, frameon=False)
    if has_hinge:
        _fe_rows(axes[len(amps)], fe_study)
    if has_patch:
        _patch_row(axes[-1], fe_study["patch"])
    fig.suptitle("Error against the converged reference (lattice: hinges of n -> infinity elements; hinge: CalculiX) "
                 "vs run time", fontsize=10)
    fig.tight_layout(rect=(0, 0.07 if nrows > 1 else 0.12, 1, 0.97))
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=100)
    plt.close(fig)
    write_atomic(path, buf.getvalue(), mode="wb")


def fe_hinge_errors(study):
    """Hinge-level work-precision points against the finest/extrapolated FE solution: ``[(label, time_s,
    error, error_bar)]`` for the held-end moment at the largest angle (relative error) and the pure bending
    moment (relative error)."""
    out = {"held": [], "free": []}
    for held, key in ((True, "held"), (False, "free")):
        fe = [r for r in study.get("bending", []) if r["held"] == held]
        if not fe:
            continue
        fe = sorted(fe, key=lambda r: -r["h_mm"])
        m_f = [r["moment_Nmm"][-1] for r in fe]
        ref = m_f[-1]
        # FE mesh error estimate: Richardson from the two finest meshes, their own size ratio and the cautious
        # order of the report's table (fe_study.bending_uncertainty)
        if len(fe) >= 2:
            from metamaterial_wb.bench.fe_study import bending_orders, mesh_size
            r_h = mesh_size(fe[-2]) / mesh_size(fe[-1])
            ref = m_f[-1] + (m_f[-1] - m_f[-2]) / (r_h ** bending_orders(study)[held] - 1.0)
        unc = abs(ref - m_f[-1]) / abs(ref) if len(fe) >= 2 else float("nan")
        for r in fe:
            out[key].append((f"FE h = {r['h_mm']:g} mm", r["wall_s"], abs(r["moment_Nmm"][-1] - ref) / abs(ref), unc))
        for r in [r for r in study.get("lattice", []) if r["held"] == held]:
            out[key].append((f"lattice n = {r['n']}", r["wall_s"], abs(r["moment_Nmm"][-1] - ref) / abs(ref), unc))
    return out


def _fe_rows(axes, study):
    pts = fe_hinge_errors(study)
    for ax, key, title in ((axes[0], "free", "one hinge, pure bending to 45 deg"),
                           (axes[1], "held", "one hinge, end turned in place to 45 deg")):
        lattice = [p for p in pts[key] if not p[0].startswith("FE")]
        same = len(lattice) > 1 and max(p[2] for p in lattice) - min(p[2] for p in lattice) < 1e-3 * max(p[2] for p in lattice)
        for k, (label, t, e, u) in enumerate(pts[key]):
            mk = "P" if label.startswith("FE") else "D"
            if same and mk == "D":
                label = "lattice n = 1 .. 8 (equal)" if k == len(pts[key]) - len(lattice) else ""
            ax.errorbar(t * 1e3, max(e, FLOOR), yerr=_bar(e, u), fmt=mk, ms=8, capsize=3,
                        color="C3" if mk == "P" else "C0")
            if label:
                ax.annotate(label, (t * 1e3, max(e, FLOOR)), textcoords="offset points",
                            xytext=(5, 4 if k % 2 == 0 else -10), fontsize=7)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("run time (ms)")
        ax.set_ylabel("relative moment error vs FE (extrapolated)")
        ax.set_title(title)
        ax.grid(True, which="both", alpha=0.3)


def _patch_row(axes, rows):
    """The 3 x 3 patch: every model and every FE mesh against the extrapolated FE solution."""
    marks = {"quadratic": ("s", "C0"), "linear": ("^", "C1"), "nonlinear (R2), default": ("o", "C4")}
    for ax, r in zip(axes, rows[:2]):
        u = r["fe_uncertainty"]["rms_D"]
        for f in r["fe"]:
            ax.errorbar(f["wall_s"] * 1e3, max(f["rms_D"], FLOOR), yerr=_bar(f["rms_D"], u), fmt="P", color="C3",
                        ms=8, capsize=3)
            ax.annotate(f"CalculiX h = {f['h_mm']:g}", (f["wall_s"] * 1e3, max(f["rms_D"], FLOOR)),
                        textcoords="offset points", xytext=(5, 4), fontsize=7)
        nl = [m for m in r["models"] if "elements/hinge" in m["label"] or "1 element/hinge" in m["label"]]
        ax.plot([m["time_s"] * 1e3 for m in nl], [max(m["rms_D"], FLOOR) for m in nl], "--D", color="C2", ms=5)
        for m in r["models"]:
            mk, col = next((v for k, v in marks.items() if m["label"].startswith(k)), ("D", "C2"))
            ax.errorbar(m["time_s"] * 1e3, max(m["rms_D"], FLOOR), yerr=_bar(m["rms_D"], u), fmt=mk, color=col,
                        ms=7, capsize=3, mfc="none" if mk == "s" else col)
        ax.axhline(u, color="C3", lw=0.8, ls=":")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("run time (ms)")
        ax.set_ylabel("RMS node-angle error vs CalculiX (D units)")
        ax.set_title(f"3 x 3 patch, two actuators, amplitude {r['amplitude']} (no contact)")
        ax.grid(True, which="both", alpha=0.3)
