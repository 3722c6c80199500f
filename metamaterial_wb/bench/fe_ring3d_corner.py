"""The curved FE ring past its first peak with the beam's corners fully integrated (issue 18): the runs that get
past the all-reduced meshes' stops (``--p1-full-near``, ``--p1-full-low``), and their convergence over the three
in-plane meshes (docs/sleeves.md, "A curved 3-D FE ring"). Reads what ``benchmarks/bench_sleeve_ring3d.py``
stored; the section's other parts are in ``fe_ring3d``."""
import re

import numpy as np

from metamaterial_wb.bench import fe_ring3d_paths as base

#: the family the convergence table uses: every brick fully integrated (C3D20, ``--p1-element C3D20``), the only
#: one that reaches d/L 0.7 on r = 3 (the whole beam fully integrated, ``_full9low``, stops at 0.364, the corners
#: and the edge pillar's strip, ``_full1.5low``, at 0.257: the next reduced bricks fold; docs/sleeves.md)
FAMILY = "_C3D20"
#: where the family's paths are compared (d/L)
FAMILY_D = (0.05, 0.10, 0.14, 0.20, 0.30, 0.40, 0.45, 0.50, 0.60, 0.70)
#: the family's plot, under docs/
IMG = "img/sleeve-fe-ring3d-corner.png"
_KEY = re.compile(r"^p1_(r[1-4])(_full[0-9.]+(?:low)?|_C3D20)$")


def corner_keys(c):
    """The stored static paths with fully integrated corner bricks, ``[(key, mesh, suffix)]`` by mesh then key."""
    out = [(k, m.group(1), m.group(2)) for k in c for m in [_KEY.match(k)] if m]
    return sorted(out, key=lambda t: (t[1], t[0]))


def zone(info):
    """Which bricks a corner run integrated fully, in words."""
    if info.get("element") == "C3D20":
        return f"all {info.get('elements', '?')} bricks"
    s = (f"{info.get('full_elements', '?')} bricks within {info.get('full_near', 0):g} mm of the beam's "
         "re-entrant corners")
    return s + (" and of the edge pillar's side in its strip at the beam's height" if info.get("full_low") else "")


def _short(info):
    """The fully integrated zone in a few words (a plot label)."""
    if info.get("element") == "C3D20":
        return "all bricks C3D20"
    return f"{'beam' if info.get('full_near', 0) >= 9 else 'corners'} C3D20"


def corner_markdown(c):
    """One paragraph per corner-integrated run: how far it gets past its mesh's all-reduced stop and what the ring
    does there, against the all-reduced path on the same mesh."""
    L = []
    for k, mesh, _ in corner_keys(c):
        x, info = c[k], c[k]["info"]
        d, F = np.asarray(x["d"]), np.asarray(x["F"])
        ex = x["extrema"]
        rest = "" if info.get("element") == "C3D20" else "; the rest C3D20R"
        line = (f"**Past the reduced mesh's stop ({base.MESH_NAMES[mesh]}, {zone(info)} fully integrated, C3D20"
                f"{rest}).** `*STATIC`, {info['increments']} increments to d/L {info['d_reached']:.3f} in "
                f"{info['wall_s'] / 60:.1f} min" +
                (f" (ccx stopped there: {info['stopped'].strip().splitlines()[-2].strip()})" if info.get("stopped")
                 else " (the whole range)") +
                f": {base._kinds(ex)}" + (" - " if ex else "") + ", ".join(f"{kd} {1e3 * f:.3f} at d/L {dd:.3f}" for kd, dd, f in ex[:4]) +
                f"; the force at the end {1e3 * F[-1]:.3f}; tilt {base.tilt_facts(x['d'], x['tilt_deg'])}." +
                (f" {info['note']}" if info.get("note") else ""))
        red = base._path(c, mesh)
        if red:
            sd = np.asarray(red["d"])
            m = d <= sd[-1]
            gap = (F[m] - np.interp(d[m], sd, red["F"])) / max(np.asarray(red["F"]).max(), 1e-30)
            j = int(np.argmax(np.abs(gap)))
            line += (f" Against the all-reduced {base.MESH_NAMES[mesh]} path (to its stop at d/L {sd[-1]:.3f}): at "
                     f"most {100 * gap[j]:+.1f} % of its P1 apart (at d/L {d[m][j]:.3f}).")
        L += [line, ""]
    return L


def family_convergence(c, family=FAMILY):
    """``base.path_convergence`` of the corner-integrated paths ``p1_<mesh><family>`` on r = 1, 2, 3 at
    ``FAMILY_D``, with the valley after P1 on each mesh and extrapolated too (``"valley"``, ``"valley_ext"``)."""
    return base.path_convergence(c, family, FAMILY_D)


def family_markdown(c, family=FAMILY):
    """The corner-integrated path on three meshes: the force at fixed d/L, extrapolated, P1 and the valley ([] until
    r = 3 of the family is stored)."""
    if "p1_r3" + family not in c:
        return []
    pc = family_convergence(c, family)
    info = c["p1_r3" + family]["info"]
    head = [base.MESH_NAMES[m] for m in pc["meshes"]]
    if info.get("element") == "C3D20":
        which = "every brick, `--p1-element C3D20"
    else:
        which = (f"the beam's within {info['full_near']:g} mm of its corners"
                 + (" and the edge pillar's strip next to the pillar's side" if info.get("full_low") else "") +
                 f"; `--p1-full-near {info['full_near']:g}" + (" --p1-full-low" if info.get("full_low") else ""))
    nm = base.NUMBER[len(pc["meshes"])]
    L = [f"**The path past P1 with fully integrated bricks, on {nm} meshes.** With the same bricks fully integrated "
         f"on every in-plane mesh ({which}`), the static path's force at fixed d/L, extrapolated in the element size as above (x1e-3):", "",
         "| d/L | " + " | ".join(head) + " | extrapolated | finest mesh off by |",
         "|---|" + "---|" * len(head) + "---|---|"]
    for d, vals, ext, err, n in pc["rows"]:
        fine = next((v for v in vals[::-1] if v is not None), None)
        L.append(f"| {d:.2f} | " + " | ".join("-" if v is None else f"{1e3 * v:.3f}" for v in vals) + " | " +
                 ("-" if ext is None else f"{1e3 * ext:.3f} +- {1e3 * err:.3f}" + (" (2 meshes)" if n == 2 else ""))
                 + " | " + ("-" if ext is None or not fine else f"{100 * err / abs(ext):.1f} %") + " |")
    L.append("")
    note = base.order_note(pc)
    L += [note, ""] if note else []
    ex = "; ".join(f"{base.MESH_NAMES[m]}: {base._kinds(c['p1_' + m + family]['extrema'])} to d/L "
                   f"{c['p1_' + m + family]['info']['d_reached']:.3f}" for m in pc["meshes"])
    p1 = "; ".join(f"{base.MESH_NAMES[m]} {1e3 * q[1]:.3f} at d/L {q[0]:.3f}" for m, q in zip(pc["meshes"], pc["p1"]))
    va = "; ".join(f"{base.MESH_NAMES[m]} " + (f"{1e3 * q[1]:.3f} at d/L {q[0]:.3f}" if np.isfinite(q[1]) else "-")
                   for m, q in zip(pc["meshes"], pc["valley"]))
    L.append(f"Extrema on each mesh: {ex}. P1: {p1}" + _ext(pc["p1_ext"]) + f". The valley after it: {va}" +
             _ext(pc["valley_ext"]) + ".")
    return L + ["", f"![the fully integrated curved FE ring on {nm} meshes]({IMG})", ""]


def _ext(e):
    if not e:
        return ""
    dx, fx, ef, ed = e
    return f"; extrapolated {1e3 * fx:.3f} +- {1e3 * ef:.3f} at d/L {dx:.3f} +- {ed:.3f}"


def plot_family(c, path, family=FAMILY):
    """The corner-integrated paths on r = 1, 2, 3 (4) and their extrapolation with its error band (False when r = 3 of
    the family is not stored)."""
    if "p1_r3" + family not in c:
        return False
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    pc = family_convergence(c, family)
    fig, ax = plt.subplots(figsize=(7.0, 4.2), dpi=110)
    for m, col in zip(pc["meshes"], ("C0", "C1", "C3", "C2")):
        x = c["p1_" + m + family]
        ax.plot(x["d"], 1e3 * np.asarray(x["F"]), "-", color=col, lw=1.3,
                label=f"CalculiX, curved 3-D, {base.MESH_NAMES[m]} ({_short(x['info'])})")
    rows = [(d, ext, err) for d, _, ext, err, n in pc["rows"] if ext is not None and n >= 2]
    if rows:
        d, ext, err = (np.array(v) for v in zip(*rows))
        ax.errorbar(d, 1e3 * ext, yerr=1e3 * err, fmt="ks", ms=3, capsize=3, label="extrapolated, with its error")
    red = base._path(c, "r2")
    if red:
        ax.plot(red["d"], 1e3 * np.asarray(red["F"]), ":", color="0.4", lw=1.0, label="r = 2, all reduced (stops)")
    ax.axhline(0, color="k", lw=0.5)
    ax.set_xlabel("d / L")
    ax.set_ylabel("F / (G L^2) x1e-3")
    ax.set_title(f"four-cell curved FE ring: one stage on {base.NUMBER[len(pc['meshes'])]} meshes", fontsize=9)
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
    return True
