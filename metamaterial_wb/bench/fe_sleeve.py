"""The sleeve's FE rung (issue 18, item 2c): the unit cell and the four-cell ring in CalculiX (2-D plane strain,
``metamaterial_wb/fe/sleeve2d.py``) against our beam model (``core/sleeve/model.py``), each under mesh
refinement with a Richardson estimate, run times side by side. Returns plain dicts (JSON-able), renders the
Markdown section of docs/sleeves.md and its plot.
"""
import time

import numpy as np

from metamaterial_wb.core.extrapolation import order_note, richardson3
from metamaterial_wb.fe import sleeve2d

CELL_REFINEMENTS = (1, 2, 3)          # elements through the beam's thickness (nested counts, h ~ 1 / r)
RING_REFINEMENTS = (1, 2, 3)
CELL_INCREMENTS = 40                  # to d = 0.7 L: past the valley (d/L 0.55-0.6)
RING_INCREMENTS = 12                  # to d = 0.18 L: past the first peak (d/L 0.11-0.13)
RING_D_MAX = 0.18
MODEL_CELL_ELEMENTS = (8, 16, 32)     # beam elements per free half (cell default 16)
MODEL_RING_ELEMENTS = (6, 12, 24)     # (ring default 24)
MARK_BEGIN, MARK_END = "<!-- fe-sleeve:begin -->", "<!-- fe-sleeve:end -->"


def _geom():
    from metamaterial_wb.core.sleeve.cell import CellGeometry
    return CellGeometry()


def _extrapolate(refinements, values):
    """Richardson in the element size ``h ~ 1 / r``: ``(values, error estimates, orders)`` per column."""
    return richardson3([1.0 / r for r in refinements], values)


def figures(rows, size, width, model, names):
    """One :func:`order_note` entry of what :func:`summarise` extrapolates: the first ``width`` figures of each
    row's ``pv`` at ``h ~ 1 / row[size]``, named ``"<model>, extrapolated: <name>"`` (a ``None`` name: a figure
    the table does not show)."""
    return ([None if n is None else f"{model}, extrapolated: {n}" for n in names[:width]],
            [1.0 / r[size] for r in rows], [r["pv"][:width] for r in rows])


PV_NAMES = ("peak at d/L", "peak", "valley at d/L", "valley")
P1_NAMES = ("P1 at d/L", "P1")


def order_notes(study):
    """``{"cell": note, "ring": note}``: :func:`order_note` of each table's extrapolations (``""`` when every order
    was observed inside the range)."""
    c, r_ = study["cell"], study["ring"]
    ring = [figures(r_["fe"], "r", 2, "CalculiX", P1_NAMES)]
    for curv in (False, True):
        ring.append(figures([m for m in r_["model"] if m["curvature"] == curv], "n_el", 2,
                            f"beam model, {'curved' if curv else 'flat'}", P1_NAMES))
    return {"cell": order_note([figures(c["fe"], "r", 4, "CalculiX", PV_NAMES),
                                figures(c["model"], "n_el", 4, "beam model", PV_NAMES)]),
            "ring": order_note(ring)}


def model_cell(geom, n_el, d_max=0.7, steps=140):
    from metamaterial_wb.core.sleeve.model import cell_curve
    t0 = time.perf_counter()
    up, _ = cell_curve(geom, n_el=n_el, steps=steps, d_max=d_max, unload=False)
    wall = time.perf_counter() - t0
    return {"n_el": n_el, "wall_s": wall, "pv": list(sleeve2d.peak_valley(up.d, up.F)), "d": up.d.tolist(),
            "F": up.F.tolist(), "jumps": list(up.jumps)}


def model_ring(geom, n_el, curvature, d_max=RING_D_MAX, steps=40):
    from metamaterial_wb.core.sleeve.model import SleeveModel
    t0 = time.perf_counter()
    m = SleeveModel([geom], [[0, 0, 0, 0]], n_el, imperfection=1e-4, curvature=curvature)
    up = m.trace(np.linspace(0, d_max, steps + 1))
    wall = time.perf_counter() - t0
    return {"n_el": n_el, "curvature": curvature, "wall_s": wall, "pv": list(sleeve2d.peak_valley(up.d, up.F)),
            "d": up.d.tolist(), "F": up.F.tolist()}


def run_sleeve_study(cell_refinements=CELL_REFINEMENTS, ring_refinements=RING_REFINEMENTS, timeout_s=7200.0,
                     progress=None):
    g = _geom()
    say = progress or (lambda m: None)
    out = {"geometry": g.as_dict(), "bulk_ratio": sleeve2d.BULK_RATIO, "cell": {"fe": [], "model": []},
           "ring": {"fe": [], "model": []}}
    for r in cell_refinements:
        c, info = sleeve2d.solve_cell(g, r, increments=CELL_INCREMENTS, timeout_s=timeout_s)
        out["cell"]["fe"].append({"r": r, "elements": info["elements"], "dofs": info["dofs"], "wall_s": info["wall_s"],
                                  "increments": info["increments"], "pv": list(sleeve2d.peak_valley(c["d"], c["F"])),
                                  "d": c["d"].tolist(), "F": c["F"].tolist()})
        say(f"FE sleeve cell r = {r}: {info['dofs']} DOFs, {info['wall_s']:.1f} s")
    for n in MODEL_CELL_ELEMENTS:
        out["cell"]["model"].append(model_cell(g, n))
    for r in ring_refinements:
        c, info = sleeve2d.solve_ring(g, 4, r, d_max=RING_D_MAX * g.L, increments=RING_INCREMENTS, timeout_s=timeout_s)
        out["ring"]["fe"].append({"r": r, "elements": info["elements"], "dofs": info["dofs"], "wall_s": info["wall_s"],
                                  "increments": info["increments"], "pv": list(sleeve2d.peak_valley(c["d"], c["F"])),
                                  "d": c["d"].tolist(), "F": c["F"].tolist(), "tilt_rad": c["tilt_rad"].tolist()})
        say(f"FE sleeve ring r = {r}: {info['dofs']} DOFs, {info['wall_s']:.1f} s")
    for curv in (False, True):
        for n in MODEL_RING_ELEMENTS:
            out["ring"]["model"].append(model_ring(g, n, curv))
    summarise(out)
    return out


def summarise(study):
    """Richardson estimates of every compared figure (in place)."""
    c = study["cell"]
    if len(c["fe"]) >= 2:
        v, e, p = _extrapolate([r["r"] for r in c["fe"]], [r["pv"] for r in c["fe"]])
        c["fe_extrapolated"] = {"pv": v, "err": e, "order": p}
    if len(c["model"]) >= 2:
        ns = [r["n_el"] for r in c["model"]]
        v, e, p = _extrapolate(ns, [r["pv"] for r in c["model"]])
        c["model_extrapolated"] = {"pv": v, "err": e, "order": p}
    r_ = study["ring"]
    if len(r_["fe"]) >= 2:
        v, e, p = _extrapolate([r["r"] for r in r_["fe"]], [r["pv"][:2] for r in r_["fe"]])
        r_["fe_extrapolated"] = {"pv": v, "err": e, "order": p}
    for curv in (False, True):
        rows = [r for r in r_["model"] if r["curvature"] == curv]
        if len(rows) >= 2:
            v, e, p = _extrapolate([r["n_el"] for r in rows], [r["pv"][:2] for r in rows])
            r_[f"model_extrapolated_{'curved' if curv else 'flat'}"] = {"pv": v, "err": e, "order": p}
    return study


def _x3(v):
    return f"{1e3 * v:.3f}"


def markdown(study, img=None):
    """The section between the markers in docs/sleeves.md."""
    c, r_ = study["cell"], study["ring"]
    notes = order_notes(study)
    L = [MARK_BEGIN, "", "### CalculiX check of the cell and the four-cell ring (issue 18)", ""]
    L.append("Our beam model against a solid 2-D model in CalculiX (`metamaterial_wb/fe/sleeve2d.py`, run by "
             "`python3 -m metamaterial_wb bench fidelity --fe --fe-parts sleeve`): the printed outline of the seed's "
             "cell (the same `CellGeometry`), plane strain, 8-node quadrilaterals with reduced integration (CPE8R) "
             "on a structured mesh of our own (nine mapped blocks per half cell, the beam's curved surfaces exact), "
             f"neo-Hooke rubber (shear modulus G, bulk modulus {study['bulk_ratio']:g} G: nearly incompressible, as the "
             "seed's), out-of-plane thickness T. The bottom edge is clamped, the left and right edges periodic "
             "(node to node), the top edge pulled up by `d` with a free common horizontal shift (the seed's kinematic "
             "coupling). Displacement control, `*STATIC` with `NLGEOM`, fixed increments (ccx cuts them back by "
             "itself where Newton struggles; no `*CONTROLS` were needed: the cell's path has no snap-back, the "
             "negative stiffness is followed continuously). Meshes: `r` elements through the beam's thickness "
             "(r = 1 is the seed's choice, SI S3.3), every block's counts times `r`: nested meshes, Richardson in "
             "`h ~ 1/r`. Forces `F / (G L^2)` x1e-3, displacements `d / L`.")
    L.append("")
    L.append("**Unit cell** (t 1, h 7.5, L 18, c 4, delta 0.5, T 1.8 mm):")
    L.append("")
    L.append("| model | mesh | DOFs | peak | at d/L | valley | at d/L | run time (s) |")
    L.append("|---|---|---|---|---|---|---|---|")
    for f in c["fe"]:
        dp, Fp, dv, Fv = f["pv"]
        L.append(f"| CalculiX CPE8R | r = {f['r']} ({f['elements']} elements) | {f['dofs']} | {_x3(Fp)} | {dp:.3f} | "
                 f"{_x3(Fv)} | {dv:.3f} | {f['wall_s']:.1f} |")
    if "fe_extrapolated" in c:
        v, e = c["fe_extrapolated"]["pv"], c["fe_extrapolated"]["err"]
        L.append(f"| CalculiX, extrapolated | | | **{_x3(v[1])} +- {_x3(e[1])}** | {v[0]:.3f} | **{_x3(v[3])} +- "
                 f"{_x3(e[3])}** | {v[2]:.3f} | |")
    for m in c["model"]:
        dp, Fp, dv, Fv = m["pv"]
        L.append(f"| beam model | {m['n_el']} elements per half | | {_x3(Fp)} | "
                 f"{dp:.3f} | {_x3(Fv)} | {dv:.3f} | {m['wall_s']:.2f} |")
    if "model_extrapolated" in c:
        v, e = c["model_extrapolated"]["pv"], c["model_extrapolated"]["err"]
        L.append(f"| beam model, extrapolated | | | {_x3(v[1])} +- {_x3(e[1])} | {v[0]:.3f} | {_x3(v[3])} +- {_x3(e[3])} | "
                 f"{v[2]:.3f} | |")
    L.append("")
    L += [notes["cell"], ""] if notes["cell"] else []
    from metamaterial_wb.bench.fe_cell_elements import markdown_lines
    L += markdown_lines(c)
    L.append("**Four-cell ring, first peak** (the same cells unrolled side by side and closed on themselves, the top "
             "edge on a rigid plate that rises by `d` and tilts freely, `v = d + R (psi_x sin phi - psi_y cos phi)`, the "
             "beam model's ring kinematics; a bias force of 1e-5 G L^2 on the tilt towards the model's imperfection "
             "direction). A flat 2-D ring has no curvature: it is compared with the beam model's flat ring "
             "(`ring_curvature: false`); the default (curved) model is listed beside it:")
    L.append("")
    L.append("| model | mesh | DOFs | first peak P1 | at d/L | run time (s) |")
    L.append("|---|---|---|---|---|---|")
    for f in r_["fe"]:
        dp, Fp = f["pv"][:2]
        L.append(f"| CalculiX CPE8R | r = {f['r']} ({f['elements']} elements) | {f['dofs']} | {_x3(Fp)} | {dp:.3f} | "
                 f"{f['wall_s']:.1f} |")
    if "fe_extrapolated" in r_:
        v, e = r_["fe_extrapolated"]["pv"], r_["fe_extrapolated"]["err"]
        L.append(f"| CalculiX, extrapolated | | | **{_x3(v[1])} +- {_x3(e[1])}** | {v[0]:.3f} | |")
    for curv in (False, True):
        for m in [m for m in r_["model"] if m["curvature"] == curv]:
            dp, Fp = m["pv"][:2]
            L.append(f"| beam model, {'curved (default)' if curv else 'flat'} | {m['n_el']} elements per half | | "
                     f"{_x3(Fp)} | {dp:.3f} | {m['wall_s']:.2f} |")
        key = f"model_extrapolated_{'curved' if curv else 'flat'}"
        if key in r_:
            v, e = r_[key]["pv"], r_[key]["err"]
            L.append(f"| beam model, {'curved' if curv else 'flat'}, extrapolated | | | {_x3(v[1])} +- {_x3(e[1])} | "
                     f"{v[0]:.3f} | |")
    L.append("")
    L += [notes["ring"], ""] if notes["ring"] else []
    L += comparison_lines(study)
    if img:
        L.append(f"![FE against the beam model]({img})")
        L.append("")
    L.append(MARK_END)
    return "\n".join(L) + "\n"


def _rel(model, e_model, fe, e_fe):
    """Relative error of the model against the FE, and its uncertainty from both references' errors."""
    r = model / fe - 1.0
    u = abs(model / fe) * np.hypot(e_model / abs(model), e_fe / abs(fe))
    return r, u


def comparison_lines(study):
    """The beam model's error against the converged FE, each with the error of both extrapolations."""
    c, r_ = study["cell"], study["ring"]
    out = []
    if "fe_extrapolated" in c and "model_extrapolated" in c:
        fe, efe = c["fe_extrapolated"]["pv"], c["fe_extrapolated"]["err"]
        mo, emo = c["model_extrapolated"]["pv"], c["model_extrapolated"]["err"]
        rp, up = _rel(mo[1], emo[1], fe[1], efe[1])
        rv, uv = _rel(mo[3], emo[3], fe[3], efe[3])
        out.append(f"Beam model (extrapolated in its mesh) against CalculiX (extrapolated): unit-cell peak "
                   f"**{100 * rp:+.0f} % +- {100 * up:.1f} %** (at d/L {mo[0]:.3f} against {fe[0]:.3f}), valley "
                   f"depth **{100 * rv:+.0f} % +- {100 * uv:.1f} %** (at d/L {mo[2]:.3f} against {fe[2]:.3f}); the uncertainty "
                   "combines both Richardson corrections.")
    for curv in (False, True):
        key = f"model_extrapolated_{'curved' if curv else 'flat'}"
        if "fe_extrapolated" in r_ and key in r_:
            fe, efe = r_["fe_extrapolated"]["pv"], r_["fe_extrapolated"]["err"]
            mo, emo = r_[key]["pv"], r_[key]["err"]
            rp, up = _rel(mo[1], emo[1], fe[1], efe[1])
            out.append(f"Four-cell ring, first peak, {'curved (default) ' if curv else 'flat '}beam model against the "
                       f"flat FE ring: **{100 * rp:+.0f} % +- {100 * up:.1f} %**.")
    if out:
        out.append("")
    return out


def plot(study, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axs = plt.subplots(1, 2, figsize=(10, 3.8), dpi=110)
    ax = axs[0]
    for f in study["cell"]["fe"]:
        ax.plot(f["d"], 1e3 * np.asarray(f["F"]), "-", lw=1.2, label=f"CalculiX r = {f['r']}")
    for m in study["cell"]["model"]:
        ax.plot(m["d"], 1e3 * np.asarray(m["F"]), "--", lw=1, label=f"beam model, {m['n_el']} el.")
    ax.axhline(0, color="k", lw=0.6)
    ax.set_xlabel("d / L")
    ax.set_ylabel("F / (G L^2) x1e-3")
    ax.set_title("unit cell (periodic, plane strain)", fontsize=9)
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    ax = axs[1]
    for f in study["ring"]["fe"]:
        ax.plot(f["d"], 1e3 * np.asarray(f["F"]), "-", lw=1.2, label=f"CalculiX r = {f['r']} (flat)")
    for m in study["ring"]["model"]:
        if m["n_el"] == max(MODEL_RING_ELEMENTS):
            ax.plot(m["d"], 1e3 * np.asarray(m["F"]), "--", lw=1,
                    label=f"beam model, {'curved' if m['curvature'] else 'flat'}, {m['n_el']} el.")
    ax.set_xlabel("d / L")
    ax.set_title("four-cell ring to past the first peak", fontsize=9)
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def write_section(doc_path, section, begin=MARK_BEGIN, end=MARK_END):
    """The text of ``doc_path`` with the section between ``begin`` and ``end`` replaced (inserted before
    "## Sequencing" the first time, or appended)."""
    with open(doc_path) as f:
        text = f.read()
    if begin in text and end in text:
        a = text.index(begin)
        b = text.index(end) + len(end) + 1
        return text[:a] + section + text[b:]
    anchor = "## Sequencing"
    i = text.index(anchor) if anchor in text else len(text)
    return text[:i] + section + "\n" + text[i:]


def ci_case(timeout_s=300.0):
    """The smallest case (CI): the unit cell at r = 1 to past the peak (d = 0.2 L in 16 increments)."""
    g = _geom()
    return sleeve2d.solve_cell(g, 1, d_max=0.2 * g.L, increments=16, timeout_s=timeout_s)
