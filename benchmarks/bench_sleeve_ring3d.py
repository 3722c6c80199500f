#!/usr/bin/env python3
"""The sleeve's four-cell ring as a curved 3-D CalculiX solid (issue 18, item 2c/4), against the flat FE ring and
the beam model's curved ring.

    OMP_NUM_THREADS=1 nice -n 15 /usr/bin/python3 benchmarks/bench_sleeve_ring3d.py [--trace --increments 100]
        [--p1-mesh r2 --p1-dmax 0.3] [--p1-mesh layers2 --p1-dmax 0.14] [--stiffness flat,fixed,free,...] [--no-write]

``--trace`` runs CalculiX's curved ring (``metamaterial_wb/fe/sleeve3d.py``, mesh r = 1, one brick through the
wall, implicit dynamics) to d/L 0.7 in fixed displacement increments, keeping every converged increment if it
stops early (``partial=True``), and stores it in ``benchmarks/results/fe-ring3d.json`` (tens of minutes; needs
``ccx``; the stored trace was stopped by hand inside the snap at d/L 0.151). ``--p1-mesh`` runs a finer mesh
(r = 2, or two bricks through the wall) statically past the first peak (the mesh error of P1, and at r = 2 the
path to d/L 0.3); ``--stiffness`` the initial-stiffness checks (flat ring, wall held at its radius, free).
Without them the stored runs are read. The beam model's curved ring (default and calibrated: root_extension
from ``benchmarks/results/fe-calibration.json``) and the flat FE ring (``fe-ring-trace.json``) are compared; the
section between the ``<!-- fe-ring3d -->`` markers of docs/sleeves.md and ``docs/img/sleeve-fe-ring3d.png`` are
written.
"""
import argparse
import json
import os
import sys
import time

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ["OMP_NUM_THREADS"] = "1"
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)

import numpy as np  # noqa: E402

RESULTS = os.path.join(ROOT, "benchmarks", "results")
STORE = os.path.join(RESULTS, "fe-ring3d.json")
DOC = os.path.join(ROOT, "docs", "sleeves.md")
IMG = "img/sleeve-fe-ring3d.png"
MARK_BEGIN, MARK_END = "<!-- fe-ring3d:begin -->", "<!-- fe-ring3d:end -->"


def _geom():
    from metamaterial_wb.core.sleeve.cell import CellGeometry
    return CellGeometry()


def run_fe(r=1, n_layers=1, d_max=0.7, increments=140, timeout_s=5400.0, radial="free", bias=1e-5, method="dynamic",
           patient=False):
    from metamaterial_wb.fe import sleeve3d
    g = _geom()
    c, info = sleeve3d.solve_ring3d(g, 4, r, n_layers, d_max=d_max * g.L, increments=increments, bias=bias,
                                    timeout_s=timeout_s, partial=True, radial=radial,
                                    method=method, patient=patient)
    info.pop("log_tail", None)
    return {"r": r, "n_layers": n_layers, "radial": radial, "d": c["d"].tolist(), "F": c["F"].tolist(),
            "tilt_rad": c["tilt_rad"].tolist(), "info": info,
            "extrema": sleeve3d.all_extrema(c["d"], c["F"])}


def stiffness_check(kinds=("flat", "fixed", "free", "free_layers2")):
    """Secant stiffness to d/L 0.005 of the flat ring and of the curved one (two increments to d/L 0.01)."""
    from metamaterial_wb.fe import sleeve2d, sleeve3d
    g = _geom()
    out = {}
    for k in kinds:
        if k == "flat":
            c, info = sleeve2d.solve_ring(g, 4, 1, d_max=0.01 * g.L, increments=2, timeout_s=600)
        else:
            nl = 2 if "layers2" in k else 1
            r = 2 if "r2" in k else 1
            c, info = sleeve3d.solve_ring3d(g, 4, r, nl, d_max=0.01 * g.L, increments=2, timeout_s=900,
                                            radial="fixed" if k == "fixed" else "free",
                                            element="C3D20" if "full" in k else "C3D20R")
        out[k] = {"k": float(np.interp(0.005, c["d"], c["F"]) / 0.005), "wall_s": info["wall_s"],
                  "dofs": info["dofs"], "d": c["d"].tolist(), "F": c["F"].tolist()}
        print(k, out[k]["k"], info["wall_s"], flush=True)
    return out


def _store(key, value):
    data = json.load(open(STORE)) if os.path.exists(STORE) else {}
    data[key] = value
    with open(STORE + ".tmp", "w") as f:
        json.dump(data, f, indent=1)
    os.replace(STORE + ".tmp", STORE)


def model_curve(e, curvature, n_el=24, d_max=0.7, steps=140):
    """The beam model's four-cell ring (as in fe_sleeve_calibration: imperfection 1e-4), root extension ``e``."""
    from metamaterial_wb.bench.fe_sleeve_calibration import model_ring
    from metamaterial_wb.fe.sleeve3d import all_extrema
    t0 = time.perf_counter()
    p = model_ring(e, n_el, d_max=d_max, steps=steps, curvature=curvature)
    return {"n_el": n_el, "root_extension": e, "curvature": curvature, "d": p.d.tolist(), "F": p.F.tolist(),
            "tilt_deg": np.degrees(np.hypot(*np.asarray(p.tilt).T)).tolist(), "extrema": all_extrema(p.d, p.F),
            "wall_s": time.perf_counter() - t0}


def compare(data):
    """Everything the section shows, from the stored FE runs and fresh beam-model runs."""
    from metamaterial_wb.fe.sleeve3d import all_extrema
    cal = json.load(open(os.path.join(RESULTS, "fe-calibration.json")))
    flat = json.load(open(os.path.join(RESULTS, "fe-ring-trace.json")))
    e = cal["root_extension"]
    out = {"root_extension": e, "flat_fe": {"r": flat["r"], "d": flat["d"], "F": flat["F"],
                                            "tilt_deg": np.degrees(np.hypot(*np.asarray(flat["tilt_rad"]).T)).tolist(),
                                            "extrema": all_extrema(flat["d"], flat["F"]),
                                            "info": {k: flat["info"].get(k) for k in ("wall_s", "increments",
                                                                                     "d_reached", "dofs")}}}
    out.update({"curved": model_curve(0.0, True), "curved_calibrated": model_curve(e, True),
                "flat_calibrated": model_curve(e, False)})
    if "stiffness" in data:
        out["stiffness"] = data["stiffness"]
    for k in ["trace", "p1_r2", "p1_layers2", "radial_fixed"] + [k for k in data if k.startswith("attempt_")]:
        if k in data:
            out[k] = dict(data[k], tilt_deg=np.degrees(np.hypot(*np.asarray(data[k]["tilt_rad"]).T)).tolist())
    return out


STIFF = {"flat": "flat 2-D ring (plane strain)", "fixed": "curved 3-D ring, wall held at its radius",
         "free": "curved 3-D ring", "free_layers2": "curved 3-D ring, two bricks through the wall",
         "free_r2": "curved 3-D ring, mesh r = 2", "free_full": "curved 3-D ring, fully integrated C3D20",
         "free_layers2_r2": "curved 3-D ring, r = 2 and two bricks through the wall"}
METHOD = {"static": "`*STATIC`",
          "dynamic": "implicit dynamics (`*DYNAMIC`, HHT alpha -0.3) with the displacement ramped over the step and "
                     "a small density (1e-10 t/mm^3 with G = 1 MPa and a step of time 1, a tenth of rubber's pulled at "
                     "0.7 L per second; the ring's lowest period a few thousandths of the step) so that inertia regularises the soft tilt mode "
                     "and carries the ring over a snap (the seed's FE used the dynamic implicit method, loading "
                     "slowly, too)"}
NAMES = {"trace": "CalculiX, curved 3-D, r = 1 (dynamic, this section)", "flat_fe": "CalculiX, flat 2-D (above)",
         "curved": "beam model, curved (default)", "curved_calibrated": "beam model, curved, calibrated",
         "flat_calibrated": "beam model, flat, calibrated", "radial_fixed": "CalculiX, curved 3-D, wall held at its radius"}


def _tilt_facts(d, deg):
    d, deg = np.asarray(d, float)[:len(deg)], np.asarray(deg, float)
    on = np.nonzero(deg > 1.0)[0]
    k = int(np.argmax(deg))
    return (f"{deg[k]:.1f} deg at d/L {d[k]:.3f}, above 1 deg from d/L {d[on[0]]:.3f}" if len(on)
            else f"at most {deg[k]:.2f} deg")


def _kinds(ex):
    p = sum(1 for k in ex if k[0] == "peak")
    v = len(ex) - p
    return f"{p} peak{'s' if p != 1 else ''}, {v} valle{'ys' if v != 1 else 'y'}"


def snap(x, drop=0.05, window=0.0005):
    """The first place where the force falls by more than ``drop`` of its maximum so far within ``window`` of d/L
    (a dynamic snap in a displacement-controlled run), or None: {"i", "d0", "F0", "Fmin", "dd", "tilt0", "tilt1"}."""
    d, F = np.asarray(x["d"], float), np.asarray(x["F"], float)
    deg = np.asarray(x["tilt_deg"], float)
    for i in range(1, len(F)):
        j = np.flatnonzero((d > d[i]) & (d <= d[i] + window))
        if j.size and F[i] - F[j].min() > drop * F[:i + 1].max():
            k = i
            m = int(j[np.argmin(F[j])])
            return {"i": k, "d0": float(d[k]), "F0": float(F[k]), "Fmin": float(F[m]), "dd": float(d[m] - d[k]),
                    "tilt0": float(deg[min(k, len(deg) - 1)]), "tilt1": float(deg[-1])}
    return None


def beyond(x):
    """What a mesh-check run did after its first peak (when it went on past it)."""
    from metamaterial_wb.fe.sleeve2d import peak_valley
    d, F = np.asarray(x["d"], float), np.asarray(x["F"], float)
    deg = np.degrees(np.hypot(*np.asarray(x["tilt_rad"], float).T))
    dp = peak_valley(d, F)[0]
    if not np.isfinite(dp) or d[-1] < dp + 0.03:
        return ""
    sn = snap({"d": d, "F": F, "tilt_deg": deg})
    after = d > dp
    k = int(np.argmin(F[after])) + int(np.flatnonzero(after)[0])
    stop = x["info"].get("stopped")
    return (f" Past it, to d/L {d[-1]:.3f}, the force falls to {1e3 * F[-1]:.3f} (lowest {1e3 * F[k]:.3f} at d/L "
            f"{d[k]:.3f})" +
            (f" with a snap at d/L {sn['d0']:.3f}" if sn else
             f" without a snap (largest fall between two increments {1e3 * max(0.0, -np.diff(F[after]).min()):.3f})") +
            f"; the tilt stays at most {deg.max():.2f} deg." +
            (f" ccx stopped at d/L {d[-1]:.3f}: {stop.strip().splitlines()[-2].strip()}" if stop else ""))


def markdown(c, img=None):
    from metamaterial_wb.fe.sleeve3d import all_extrema
    L = [MARK_BEGIN, "", "### A curved 3-D FE ring (issue 18)", ""]
    tr = c.get("trace")
    if tr is None:
        return "\n".join(L + ["(no curved FE run stored)", "", MARK_END]) + "\n"
    info = tr["info"]
    L += [f"Regenerated by `benchmarks/bench_sleeve_ring3d.py` (model: `metamaterial_wb/fe/sleeve3d.py`). The same "
          "structured mesh of the printed outline as the flat ring (mesh r = %d), wrapped onto the cylinder at the "
          "beam model's mid radius R = N W / 2 pi = %.2f mm (the wall's mid surface keeps the 2-D lengths) and "
          "extruded radially through the wall T = %.1f mm, %d brick%s through it: %d C3D20R elements, %d DOFs; the "
          "ring is closed by merging the seam's nodes. Same neo-Hooke solid (K = 500 G), but no plane-strain "
          "restraint: the wall may bulge and thin. Bottom edge clamped (3 DOFs); the top edge on a rigid plate "
          "(`*RIGID BODY`) that rises by d, tilts freely about both in-plane axes and twists freely, its in-plane "
          "translation fixed (neither the beam model's plate nor the flat ring has one); a bias moment 1e-5 G L^2 R "
          "towards the beam model's imperfection direction. Displacement control, `NLGEOM`, %d fixed increments to "
          "d/L 0.7 (ccx cuts back by itself), %s; force = the clamped bottom's axial reaction." %
          (tr["r"], info["radius_mm"], _geom().T, tr["n_layers"], "s" if tr["n_layers"] > 1 else "",
           info["elements"], info["dofs"], info.get("increments_asked", 140), METHOD[info.get("method", "static")]), ""]
    L.append(f"Run: {info['increments']} converged increments to d/L {info['d_reached']:.3f} in "
             f"{info['wall_s'] / 60:.1f} min (one core, niced, on a shared 2-core machine)" +
             (f"; **the run stopped there**: {info.get('stopped_by') or info['stopped'].splitlines()[0]}"
              if info.get("stopped") else ", the whole range") + ".")
    sn = snap(tr)
    if sn:
        L += ["", f"**A snap at d/L {sn['d0']:.4f}**: there the quasi-static path ends (force {1e3 * sn['F0']:.3f}, tilt "
              f"{sn['tilt0']:.2f} deg); within d/L {sn['dd']:.4f} the force falls to "
              f"{1e3 * sn['Fmin']:.3f} (the ring moving dynamically, the force oscillating: bottom reaction including "
              f"inertia), the tilt reaching {sn['tilt1']:.2f} deg at the end of the run. Its extrema below are counted on "
              f"the quasi-static part before the snap only (d/L < {sn['d0']:.4f})."]
    L += ["", "Extrema of the four-cell ring, forces F / (G L^2) x1e-3 (at d/L); every local maximum and minimum "
          "that rises or falls by more than 2 % of the curve's range (`sleeve3d.all_extrema`):", "",
          "| model | extrema (2 %) | with a 0.5 % threshold | P1 | V1 | P2 | V2 | largest tilt |",
          "|---|---|---|---|---|---|---|---|---|"]
    for k in ("trace", "radial_fixed", "flat_fe", "curved", "curved_calibrated", "flat_calibrated"):
        if k not in c:
            continue
        x = c[k]
        ex = x["extrema"]
        sn = snap(x) if k == "trace" else None
        if sn:
            x = dict(x, d=x["d"][:sn["i"] + 1], F=x["F"][:sn["i"] + 1], tilt_deg=x["tilt_deg"][:sn["i"] + 1])
            ex = all_extrema(x["d"], x["F"])
        cells = [f"{1e3 * f:.3f} ({dd:.3f})" for _, dd, f in ex[:4]] + ["-"] * (4 - min(4, len(ex)))
        deg = np.asarray(x["tilt_deg"])
        fine = all_extrema(x["d"], x["F"], 0.005)
        L.append(f"| {NAMES[k]} | {_kinds(ex)} | {_kinds(fine)} | " + " | ".join(cells) +
                 f" | {deg.max():.1f} deg ({np.asarray(x['d'])[:len(deg)][int(np.argmax(deg))]:.3f}) |")
    L.append("")
    L.append("Tilt of the top plate: " + "; ".join(f"{NAMES[k]} {_tilt_facts(c[k]['d'], c[k]['tilt_deg'])}"
                                                    for k in ("trace", "flat_fe", "curved", "curved_calibrated")
                                                    if k in c) + ".")
    L.append("")
    att = [(k, c[k]) for k in sorted(c) if k.startswith("attempt_")]
    if att:
        L.append("**Earlier attempts** (kept in `benchmarks/results/fe-ring3d.json`): " + "; ".join(
            f"{x['info'].get('method', 'static')}" + (f", density {x['info']['density']:.0e}" if 'density' in x['info'] else "") +
            f", tilt bias {x['info']['bias']:.0e} G L^2: {x['info']['increments']} increments to d/L "
            f"{x['info']['d_reached']:.3f} in {x['info']['wall_s'] / 60:.1f} min, highest force "
            f"{1e3 * max(x['F']):.3f} at d/L {x['d'][int(np.argmax(x['F']))]:.3f}, tilt {x['tilt_deg'][-1]:.2f} deg at "
            f"the end - {x['info'].get('note', '')}" for k, x in att) + ".")
        L.append("")
    if "stiffness" in c:
        sc = c["stiffness"]
        L.append("**Initial stiffness** (secant to d/L 0.005, F / (G L^2) per d/L x1e-3; two increments to d/L 0.01 "
                 "each, the CI case `tests/fe/test_sleeve3d.py`): " + "; ".join(
                     f"{STIFF[k]} {1e3 * v['k']:.1f} ({v['k'] / sc['flat']['k']:.2f} of the flat ring's)"
                     for k, v in sc.items()) + ".")
        L.append("")
    from metamaterial_wb.fe.sleeve2d import peak_valley
    for k in ("p1_r2", "p1_layers2"):
        if k in c:
            x = c[k]
            p = peak_valley(x["d"], x["F"])[:2]
            p1 = peak_valley(tr["d"], tr["F"])[:2]
            if np.isfinite(p[1]) and np.isfinite(p1[1]):
                L.append(f"**Second mesh on P1** ({'r = 2' if k == 'p1_r2' else 'two bricks through the wall'}, "
                         f"{x['info']['elements']} elements, {x['info']['dofs']} DOFs, `*STATIC` in "
                         f"{x['info']['increments']} increments to d/L {x['info']['d_reached']:.3f}, "
                         f"{x['info']['wall_s'] / 60:.1f} min; " + (
                             "the same ramped tilt bias as the trace)" if abs(info['d_max_mm'] / x['info']['d_max_mm'] - 1) < 0.01
                             else f"its tilt bias ramps over a shorter step, so it is "
                             f"{info['d_max_mm'] / x['info']['d_max_mm']:.1f} times the trace's at a given d)") +
                         f": P1 {1e3 * p[1]:.3f} at d/L {p[0]:.3f}, against "
                         f"{1e3 * p1[1]:.3f} at {p1[0]:.3f} on the trace's mesh (r = 1, one brick through the wall), "
                         f"{100 * (p1[1] / p[1] - 1):+.1f} % off the finer mesh's value." + beyond(x))
                L.append("")
    if img:
        L += [f"![curved FE ring against the flat FE ring and the beam model]({img})", ""]
    L.append(MARK_END)
    return "\n".join(L) + "\n"


def plot(c, path):
    from metamaterial_wb.fe.sleeve3d import all_extrema
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (ax, ax2) = plt.subplots(2, 1, figsize=(7.5, 7.5), dpi=110, sharex=True, height_ratios=(2, 1))
    style = {"trace": ("k-", 1.8), "radial_fixed": ("-", 1.0), "flat_fe": ("-", 1.4), "curved": ("C0--", 1.1),
             "curved_calibrated": ("C3-", 1.1), "flat_calibrated": ("C3:", 1.0)}
    colour = {"radial_fixed": "0.6", "flat_fe": "C2"}
    for k, (st, lw) in style.items():
        if k not in c:
            continue
        x = c[k]
        kw = {"color": colour[k]} if k in colour else {}
        lab = NAMES[k] + (f", root_extension {c['root_extension']:.2f} t" if "calibrated" in k else "")
        ax.plot(x["d"], 1e3 * np.asarray(x["F"]), st, lw=lw, label=lab, **kw)
        ax2.plot(np.asarray(x["d"])[:len(x["tilt_deg"])], x["tilt_deg"], st, lw=lw, label=lab, **kw)
        ex = x["extrema"]
        sn = snap(x) if k == "trace" else None
        if sn:
            ex = all_extrema(x["d"][:sn["i"] + 1], x["F"][:sn["i"] + 1])
            ax.plot([sn["d0"]], [1e3 * sn["F0"]], "kx", ms=7, label=f"snap at d/L {sn['d0']:.3f} (run stopped in it)")
        for kind, dd, f in ex[:4]:
            ax.plot([dd], [1e3 * f], "^" if kind == "peak" else "v", ms=4, color=kw.get("color", st[:2] if st[0] == "C" else "k"))
    for k in ("p1_r2", "p1_layers2"):
        if k in c:
            lab = "CalculiX, curved 3-D, " + ("r = 2 (static)" if k == "p1_r2" else "2 bricks through the wall (static)")
            col = "C1" if k == "p1_r2" else "C4"
            ax.plot(c[k]["d"], 1e3 * np.asarray(c[k]["F"]), "-", color=col, lw=1.2, label=lab)
            ax2.plot(np.asarray(c[k]["d"])[:len(c[k]["tilt_deg"])], c[k]["tilt_deg"], "-", color=col, lw=1.2, label=lab)
    ax.axhline(0, color="k", lw=0.5)
    ax.set_ylabel("F / (G L^2) x1e-3")
    ax.set_title("four-cell ring: curved 3-D FE against the flat FE and the beam model", fontsize=9)
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    ax2.set_xlabel("d / L")
    ax2.set_ylabel("tilt of the top plate (deg)")
    ax2.legend(fontsize=6)
    ax2.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def write(c):
    from metamaterial_wb.bench.fe_sleeve import write_section
    section = markdown(c, IMG)
    plot(c, os.path.join(ROOT, "docs", IMG))
    text = write_section(DOC, section, MARK_BEGIN, MARK_END)
    with open(DOC + ".tmp", "w") as f:
        f.write(text)
    os.replace(DOC + ".tmp", DOC)
    return section


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--trace", action="store_true", help="run the curved FE ring over the working range (ccx)")
    ap.add_argument("--increments", type=int, default=140)
    ap.add_argument("--timeout", type=float, default=5400.0)
    ap.add_argument("--bias", type=float, default=1e-5, help="tilt bias (G L^2) of the trace")
    ap.add_argument("--method", default="dynamic", choices=("static", "dynamic"))
    ap.add_argument("--patient", action="store_true", help="longer Newton before cut-backs (*CONTROLS)")
    ap.add_argument("--key", default="trace", help="where the trace is stored in fe-ring3d.json")
    ap.add_argument("--p1-mesh", default=None, help="a second mesh on the first peak: 'r2' or 'layers2'")
    ap.add_argument("--stiffness", default=None, help="comma list of initial-stiffness runs: flat,fixed,free,"
                    "free_layers2,free_r2 (stored under 'stiffness', merged)")
    ap.add_argument("--p1-dmax", type=float, default=0.17, help="d/L of the P1 mesh run (static, 0.01 per increment)")
    ap.add_argument("--radial-fixed", action="store_true", help="the check with the wall held at its radius")
    ap.add_argument("--no-write", action="store_true")
    a = ap.parse_args(argv)
    if a.trace:
        t0 = time.time()
        tr = run_fe(increments=a.increments, timeout_s=a.timeout, bias=a.bias, method=a.method,
                    patient=a.patient)
        tr["info"]["increments_asked"] = a.increments
        print(f"trace: {tr['info']['increments']} increments to d/L {tr['info']['d_reached']:.3f} in "
              f"{time.time() - t0:.0f} s; extrema {tr['extrema']}", flush=True)
        _store(a.key, tr)
    if a.p1_mesh:
        r, nl = {"r2": (2, 1), "layers2": (1, 2)}[a.p1_mesh]
        tr = run_fe(r, nl, d_max=a.p1_dmax, increments=int(round(100 * a.p1_dmax)), timeout_s=a.timeout,
                    method="static")
        print(f"P1 mesh {a.p1_mesh}: {tr['extrema']} ({tr['info']['wall_s']:.0f} s)", flush=True)
        _store("p1_" + a.p1_mesh, tr)
    if a.stiffness:
        old = (json.load(open(STORE)) if os.path.exists(STORE) else {}).get("stiffness", {})
        old.update(stiffness_check(a.stiffness.split(",")))
        _store("stiffness", old)
    if a.radial_fixed:
        tr = run_fe(d_max=0.7, increments=a.increments, timeout_s=a.timeout, radial="fixed")
        print(f"radial fixed: {tr['extrema']} ({tr['info']['wall_s']:.0f} s)", flush=True)
        _store("radial_fixed", tr)
    data = json.load(open(STORE)) if os.path.exists(STORE) else {}
    c = compare(data)
    c["increments_asked"] = a.increments
    with open(os.path.join(RESULTS, "fe-ring3d-comparison.json"), "w") as f:
        json.dump({k: v for k, v in c.items()}, f, indent=1)
    print(markdown(c, IMG))
    if not a.no_write:
        write(c)
        print("wrote docs/sleeves.md and docs/" + IMG)


if __name__ == "__main__":
    main()
