"""The seed's combinations as two stacked rings on the nonlinear 3-D frame (issue 18): does the frame give the
seed's sequences when each cell type is a hysteron of its own?

The seed's combination 2 (a mixed ring [0, 0, 1, 1]) snaps asymmetrically; on the frame the mixed ring snaps
symmetrically although the two-hysteron rule on the frame's own uniform-ring thresholds gives the seed's order
(``fe_frame3d_plate.sequence_markdown``). Here each type makes a ring of its own, the two stacked
(``RingFrame(pattern=[[0] * 4, [1] * 4])``, the plate between them free to rise, tilt and twist), so the rings
share only their force - two hysterons in series, the rule's own setting. The stack's peaks and valleys against
the uniform rings' (the same force, if they act in series), its order against the rule's and the beam model's
(``pipeline.analyse`` on the same pattern), on two beam meshes. ``bench_sleeve_frame3d.py --stacked``.
"""
import json
import os

import numpy as np

from metamaterial_wb.bench.fe_ring3d_combinations import SEED_COMBINATIONS, combination_cells, order_text, rule, seed_order

IMG = os.path.join("img", "sleeve-frame3d-stack.png")


def stacked_study(meshes=(6, 12, 24), root_extension=0.63, steps=240):
    """Each seed combination's two types as two stacked uniform rings of four cells, loaded to twice the beam
    model's stroke and back in ``steps`` on the frame (free top plate, bias ramped) on each of ``meshes`` (elements
    per beam half), and on the beam model as the ``sleeve`` command runs it: ``{combination: {"frame": {n_el:
    sequence with "peaks", "valleys", "seconds"}, "model": {...}, "paths": the finest mesh's loading and unloading
    (d, F, each ring's rise)}}``."""
    from metamaterial_wb.core.sleeve.analysis import peaks_valleys
    from metamaterial_wb.core.sleeve.frame3d_sequence import frame_sequence
    from metamaterial_wb.core.sleeve.model import default_stroke
    from metamaterial_wb.core.sleeve.pipeline import analyse
    from metamaterial_wb.core.sleeve.spec import SleeveSpec
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    base = json.load(open(os.path.join(root, "examples", "sleeve.json")))
    L = base["L_mm"]
    pattern = [[0] * 4, [1] * 4]
    out = {}
    for key, comb in SEED_COMBINATIONS.items():
        cells = combination_cells(key)
        frames = {}
        for n_el in meshes:
            fs, up, down = frame_sequence(cells, pattern, 2 * default_stroke(cells), steps, n_el, root_extension)
            pv = peaks_valleys(up["d"], up["F"])
            frames[str(n_el)] = dict({k: v for k, v in fs.items() if not k.startswith("events")},
                                     peaks=[p for _, p in pv["peaks"]], valleys=[v for _, v in pv["valleys"]])
        paths = {name: {"d": r["d"].tolist(), "F": r["F"].tolist(), "ring_rises": r["ring_rises"].tolist()}
                 for name, r in (("loading", up), ("unloading", down))}          # the finest mesh's, for the plot
        spec = {k: v for k, v in base.items() if k != "ring"}
        spec.update(cell_types=[{"t_mm": t * L, "h_mm": h * L} for h, t in comb["cells"]], pattern=pattern,
                    walker=False)
        summ, _ = analyse(SleeveSpec(spec, "stacked study"))
        q = summ["sequence"]
        out[key] = {"frame": frames, "paths": paths, "elements_paths": str(meshes[-1]),
                    "model": {k: q[k] for k in ("loading", "unloading", "symmetric", "lean_reverses",
                                                "max_tilt_loading_deg", "max_tilt_unloading_deg")}}
    out["stability_cost"] = stability_cost(root_extension)
    return out


def stability_cost(root_extension=0.63, n_el=12, steps=160):
    """What checking every state for a saddle costs (``trace_ring(stable=True)``, an LU's pivot signs per
    converged state): combination 1's mixed ring loaded and unloaded with and without, best of two each, and the
    largest force difference between the two cycles: ``{"seconds_stable", "seconds_plain", "max_dF"}``."""
    import time
    from metamaterial_wb.core.sleeve.cell import CellGeometry
    from metamaterial_wb.core.sleeve.frame3d import RingFrame
    from metamaterial_wb.core.sleeve.frame3d_nl import trace_ring
    from metamaterial_wb.core.sleeve.model import default_stroke
    L = CellGeometry().L
    cells = [CellGeometry(t=t * L, h=h * L) for h, t in SEED_COMBINATIONS["1"]["cells"]]
    dm = default_stroke(cells)
    d = np.linspace(0.0, dm, steps + 1)
    best, F = {}, {}
    for stable in (False, True, False, True):
        ring = RingFrame(cells, plane="stress", root_extension=root_extension, n_el=n_el, row=[0, 0, 1, 1])
        t0 = time.perf_counter()
        up = trace_ring(ring, d, plate="free", bias_ramp=dm, stable=stable)
        down = trace_ring(ring, d[::-1], plate="free", start=up, stable=stable)
        best[stable] = min(best.get(stable, np.inf), time.perf_counter() - t0)
        F[stable] = np.concatenate([up["F"], down["F"]])
    return {"seconds_stable": best[True], "seconds_plain": best[False], "elements": n_el, "states": 2 * len(d),
            "max_dF": float(np.abs(F[True] - F[False]).max())}


def stacked_markdown(st, mixed):
    """The table: per combination the seed's (mixed ring) sequence, the rule's on the frame's uniform rings
    (``mixed[key]["uniform"]``, ``fe_frame3d_plate.sequence_study``), the frame's mixed ring (12 elements), the
    stack on the frame per mesh and on the beam model; and the stack's thresholds against the uniform rings'."""
    seq = order_text
    L = ["**The seed's combinations as two stacked rings on the frame** (`bench/fe_frame3d_stack.py`, "
         "`bench_sleeve_frame3d.py --stacked`: each type a uniform ring of four cells, the thinner or lower one "
         "below, the plate between them free to rise, tilt and twist; loaded to twice the beam model's stroke and "
         "back in 240 steps, the free top plate biased as above). Rings in series share only their force - two "
         "hysterons, the two-hysteron rule's own setting:", "",
         "| combination | seed (mixed ring) | rule on the frame's uniform rings | frame, mixed ring (12) | "
         "frame, stacked: elements: sequence | lean (loading / unloading) | time | beam model, stacked |",
         "|---|---|---|---|---|---|---|---|"]
    notes = []
    for key, r in st.items():
        if key not in SEED_COMBINATIONS:
            continue
        seed = seed_order(key)
        u = mixed.get(key, {}).get("uniform")
        ru = rule(u) if u and all(x["P1"] and x["valley"] for x in u) else None
        m12 = mixed.get(key, {}).get("frame", {}).get("12")
        for i, (n_el, f) in enumerate(r["frame"].items()):
            head = (f"| {key} | {seq(seed)} | {seq(ru) if ru else '-'} | {seq(m12) if m12 else '-'} | " if i == 0
                    else "| | | | | ")
            tail = f" {seq(r['model'])} |" if i == 0 else " |"
            lean = (f"{f['max_tilt_loading_deg']:.1f} / {f['max_tilt_unloading_deg']:.1f} deg, "
                    + ("reverses" if f["lean_reverses"] else "the same way"))
            L.append(head + f"{n_el}: {seq(f)} | {lean} | {f['seconds']:.0f} s |" + tail)
        f = r["frame"].get("12")                 # on the uniform rings' mesh
        if u and f:
            first = rule(u)["loading"][0]
            expect = [u[first]["valley"], max(x["valley"] for x in u)]
            if len(f["peaks"]) == 2 and len(f["valleys"]) == 2:
                dp = max(abs(a / b - 1) for a, b in zip(sorted(f["peaks"]), sorted(x["P1"] for x in u)))
                dv = max(abs(a / b - 1) for a, b in zip(f["valleys"], expect))
                notes.append(f"combination {key}: the stack's peaks are the uniform rings' first peaks to "
                             f"{100 * dp:.1f} %, its valleys to {100 * dv:.1f} % the first ring's and the higher of "
                             "the two")
    L += ["", "; ".join(notes) + (" (uniform rings: 12 elements, 160 steps; the stack's sampled at its own "
                                  "steps, 12 elements) - the rings act in series. The second valley is the higher "
                                  "of the two, not the second ring's own: a snapped ring carries no less than its "
                                  "valley, below it it would snap back." if notes else ""), ""]
    c = st.get("stability_cost")
    if c:
        L += [f"Every state of the frame is a minimum: a converged state whose reduced Hessian has a negative pivot "
              f"is a saddle, left down its lowest mode (`trace_ring(stable=True)`, the default). Checking costs one "
              f"LU's pivot signs per state: combination 1's mixed ring ({c['states']} states, {c['elements']} "
              f"elements) takes {c['seconds_stable']:.1f} s with the check and {c['seconds_plain']:.1f} s without "
              f"(x{c['seconds_stable'] / c['seconds_plain']:.2f}, best of two each, the same run), its forces "
              f"{c['max_dF']:.1e} apart (no saddle on that path).", ""]
    two = st.get("2")
    if two:
        agree = all(f["loading"] == SEED_COMBINATIONS["2"]["seed"][0] and
                    f["unloading"] == SEED_COMBINATIONS["2"]["seed"][1] for f in two["frame"].values())
        L += [("Combination 2 stacked gives the seed's asymmetric order on every mesh: the frame's thresholds are "
               "right, and what keeps the mixed ring from that order is the plate its cells share (a type's cells "
               "are not a free hysteron when the other type's cells hold the same plate), not the cells' own "
               "curves." if agree else "Combination 2 stacked does not give the seed's order on every mesh."), ""]
    return "\n".join(L)


def plot(st, path):
    """Combination 2 stacked on the frame: force and each ring's rise against the stack's rise, on loading and
    unloading."""
    plot_paths(st["2"]["paths"], path, "combination 2 as two stacked rings")


def plot_paths(r, path, title):
    """A stack's cycle ``r`` (``{"loading", "unloading"}``, each ``{"d", "F", "ring_rises"}``): force and each
    ring's rise against the stack's rise, the plots titled ``title``."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from metamaterial_wb.bench.plotting import finish
    fig, ax = plt.subplots(1, 2, figsize=(10.5, 3.9), dpi=100)
    for name, style in (("loading", "-"), ("unloading", "--")):
        p = r[name]
        ax[0].plot(p["d"], 1e3 * np.asarray(p["F"]), style, color="k", lw=1.3, label=name)
        rr = np.asarray(p["ring_rises"])
        for j, col in enumerate(("C0", "C3")):
            ax[1].plot(p["d"], rr[:, j], style, color=col, lw=1.3, label=f"ring of type {j}, {name}")
    F = np.asarray(r["loading"]["F"])
    inner = [i for i in range(1, len(F) - 1) if F[i - 1] < F[i] >= F[i + 1]]
    if inner:                                       # the snapping range, not the stiff rise after it
        top = 1.6e3 * max(F[i] for i in inner)
        ax[0].set_ylim(-0.05 * top, top)
        if np.any(F > top / 1e3):
            ax[0].set_xlim(0, 1.05 * r["loading"]["d"][int(np.argmax(F > top / 1e3))])
            ax[1].set_xlim(ax[0].get_xlim())
    ax[0].set_ylabel("F / (G L^2) x1e-3")
    ax[0].set_title(f"{title}: force", fontsize=9)
    ax[1].set_ylabel("ring's own rise / L")
    ax[1].set_title("each ring's own rise (type 0, the lower h, below)", fontsize=9)
    finish(fig, ax, "stack's rise d / L", path)
