"""The seed's combinations' thresholds on the curved solid (issue 18): each cell type of a combination as a
uniform four-cell ring in CalculiX (``fe/sleeve3d.py``, every brick C3D20, static to d/L 0.7 in steps of 0.01,
the tilting top plate under the default bias), its first peak and first valley, and the two-hysteron rule on
them (``rule``) beside the frame's. The seed's combinations (``SEED_COMBINATIONS``, ``combination_cells``)
and the rule live here, below the frame's studies (``fe_frame3d_plate``, ``fe_frame3d_stack``) that use them too.

Rings stacked in series share only their force: the frame's stacked rings (``fe_frame3d_stack``) put the stack's
peaks on the uniform rings' first peaks and its valleys on the first ring's and the higher of the two, to 0.0 %,
so the rule on a model's uniform rings is that model's order for the stack. The stacked solid itself runs by
implicit dynamics (its snaps under displacement control are dynamic): ``fe_ring3d_stack``. On the solid's
coarse meshes each P1 is some per cent high (the seed's type: +16 % on r = 1, +7 % on r = 2 against the
four-mesh extrapolation), alike for types this close, so the order rests on their differences: given on each
mesh and extrapolated over r = 1, 2, 3 (``extrapolated``) for combination 2, whose types lie within a few per
cent; combination 1's, 20 % and more apart, over the same three meshes (its differences moved by about 1 %).
"""
import concurrent.futures

import numpy as np

# the seed's two combinations (h/L, t/L of its two cell types; the seed's sequence, types in its order)
SEED_COMBINATIONS = {
    "1": {"cells": ((0.372, 0.055), (0.372, 0.065)), "seed": ([0, 1], [1, 0]), "lean": "the same way"},
    "2": {"cells": ((0.394, 0.061), (0.416, 0.061)), "seed": ([0, 1], [0, 1]), "lean": "the other way"}}


def combination_cells(key):
    """The cell types of seed combination ``key`` (``SEED_COMBINATIONS``) on examples/sleeve.json's cell (L, c,
    delta, T): a list of ``CellGeometry``."""
    import json
    import os
    from metamaterial_wb.core.sleeve.cell import CellGeometry
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    base = json.load(open(os.path.join(root, "examples", "sleeve.json")))
    L = base["L_mm"]
    return [CellGeometry(L=L, c=base["c_mm"], delta=base["delta_mm"], T=base["T_mm"], t=t * L, h=h * L)
            for h, t in SEED_COMBINATIONS[key]["cells"]]


def rule(uniform):
    """The two-hysteron order on a model's uniform-ring thresholds (``[{"P1", "valley"}, ...]``): loading by
    rising P1, unloading by falling valley."""
    load = sorted(range(len(uniform)), key=lambda k: uniform[k]["P1"])
    unload = sorted(range(len(uniform)), key=lambda k: -uniform[k]["valley"])
    return {"loading": load, "unloading": unload, "symmetric": unload == load[::-1]}


def seed_order(key):
    """The seed's sequence of combination ``key`` as ``rule`` gives orders: ``{"loading", "unloading",
    "symmetric"}``."""
    load, unload = SEED_COMBINATIONS[key]["seed"]
    return {"loading": load, "unloading": unload, "symmetric": load[::-1] == unload}


def symmetry_text(s):
    """``symmetric`` / ``asymmetric`` of a sequence, or, its ``symmetric`` null, ``undetermined`` / ``nothing
    snapped`` (``analysis.symmetry_word``, from its events); a record stored without its events (the frame's
    ``model`` entries) is ``undetermined``: null is neither symmetric nor asymmetric."""
    from metamaterial_wb.core.sleeve.analysis import symmetry_word
    if s.get("symmetric") is None and "events_loading" not in s and "events_unloading" not in s:
        return "undetermined"
    return symmetry_word(s)


def order_text(s):
    """A sequence in the docs' words: ``[0, 1] \\| [1, 0] (symmetric)`` (:func:`symmetry_text`)."""
    return f"{s['loading']} \\| {s['unloading']} ({symmetry_text(s)})"


MESH_R = {"r1": 1, "r2": 2, "r3": 3}
BIAS = 1e-5                 # the plate's tilt bias moment, G L^2 (sleeve3d.ring_deck3d's default)
D_MAX = 0.7                 # d/L: past the first valley of every seed type (the seed's cell: 0.45)


def solid_ring(g, r, d_max=D_MAX, timeout_s=5400.0, top=None):
    """One uniform four-cell ring of cell ``g`` on mesh ``r`` (one brick through the wall, every brick C3D20,
    static, 0.01 d/L per increment): ``{"P1", "P1_d", "valley", "valley_d", "d", "F", "tilt_deg_max", "wall_s",
    "d_reached", "stopped"}`` (``None`` for an extremum the run did not reach). ``top`` (mm): the ring's top
    raised there (``sleeve3d.ring_mesh``: the shorter type as it stands in a mixed ring, ``"top_mm"``)."""
    from metamaterial_wb.fe import sleeve3d
    c, info = sleeve3d.solve_ring3d(g, 4, r, 1, d_max=d_max * g.L, increments=int(round(100 * d_max)),
                                    timeout_s=timeout_s, partial=True, element="C3D20", top=top)
    ext = sleeve3d.all_extrema(c["d"], c["F"])
    peak = next(((x, y) for k, x, y in ext if k == "peak"), (None, None))
    valley = next(((x, y) for k, x, y in ext if k == "valley" and peak[0] is not None and x > peak[0]), (None, None))
    tilt = np.degrees(np.hypot(*np.asarray(c["tilt_rad"]).T))
    return {"P1_d": peak[0], "P1": peak[1], "valley_d": valley[0], "valley": valley[1], "extrema": ext,
            "d": np.round(c["d"], 6).tolist(), "F": c["F"].tolist(), "tilt_deg_max": float(tilt.max()),
            "wall_s": info["wall_s"], "d_reached": info["d_reached"], "stopped": info.get("stopped", "")[:300],
            "top_mm": g.height if top is None else float(top)}


MIXED_ROW = (0, 0, 1, 1)     # the seed's mixed ring (the frame's and the beam model's)


def solid_cycle(key, r=1, d_max=D_MAX, row=MIXED_ROW, timeout_s=7200.0, method="static", bias=BIAS):
    """The seed's combination ``key`` as one mixed four-cell ring ``row`` on the curved solid (``fe/sleeve3d.py``:
    one brick through the wall, every brick C3D20, a flat top at the taller type's height; ``method`` static or
    implicit dynamics as the seed's FE, 0.01 d/L per increment at most; the plate's tilt bias moment ``bias``,
    ``sleeve3d.ring_deck3d``'s) raised to ``d_max`` and lowered back, the beams' ends watched: ``{"d", "F",
    "tilt_rad", "unloading", "rises" (k, halves), "cells", "units", "wall_s", "d_reached", "stopped", "method",
    "bias", ...}`` (``cycle_sequence`` reads the order off it)."""
    from metamaterial_wb.fe import sleeve3d
    types = combination_cells(key)
    cells = [types[t] for t in row]
    mesh = sleeve3d.ring_mesh(cells, len(row), r, 1)
    ends = mesh.beam_ends()
    watch = np.unique(np.concatenate([ends["outer"].ravel(), ends["inner"].ravel()]))
    n = int(round(100 * d_max))
    c, info = sleeve3d.solve_ring3d(cells, len(row), r, 1, d_max=d_max * cells[0].L, increments=n,
                                    timeout_s=timeout_s, partial=True, element="C3D20", watch=watch, unload=True,
                                    method=method, bias=bias)
    rise, _ = sleeve3d.hysterons(mesh, ends, c["u_watch"], watch)
    return {"combination": key, "row": list(row), "r": int(r), "d_max": float(d_max),
            "d": np.round(c["d"], 6).tolist(), "F": c["F"].tolist(), "tilt_rad": c["tilt_rad"].tolist(),
            "unloading": c["unloading"].astype(int).tolist(), "rises": np.round(rise, 7).tolist(),
            "cells": ends["cells"].tolist(), "units": ends["units"].tolist(), "wall_s": info["wall_s"],
            "d_reached": info["d_reached"], "stopped": info.get("stopped", "")[:300], "method": method,
            "bias": float(bias)}


def shorter(key):
    """The index of combination ``key``'s shorter cell type (the one a mixed ring's flat top raises)."""
    types = combination_cells(key)
    return min(range(2), key=lambda k: types[k].height)


def standing(key, raised, uniform):
    """Combination ``key``'s two types' uniform rings as they stand in its mixed ring: the shorter type's raised to
    the flat top (``raised``, ``solid_ring(top=...)``), the taller type's own (``uniform``, its two types' rows)."""
    return [raised if k == shorter(key) else uniform[k] for k in range(2)]


def turn(run):
    """The index of a ``solid_cycle`` run's last loading point, where its unloading path starts."""
    return int(np.argmax(np.asarray(run["unloading"], bool))) - 1


def legs(run):
    """A stored cycle's two paths as slices of its points: ``{"loading": ..., "unloading": ...}``, both holding the
    turn (``turn``); a run that did not come back down is all loading."""
    first = turn(run) if np.asarray(run["unloading"], bool).any() else len(run["d"]) - 1
    return {"loading": slice(0, first + 1), "unloading": slice(first, None)}


def cycle_sequence(run):
    """The snapping order of a ``solid_cycle`` run's cell types on loading and unloading, by the frame's own reading
    (``frame3d_sequence.sequence``: ``analysis.snap_order`` on the beams' rises, the plate's largest lean on each
    path), or ``None`` when the run did not come back down (``run["stopped"]``)."""
    return path_sequence(run, [run["row"][k] for k in run["cells"]], rings=1)


def path_sequence(run, state_types, rings):
    """``frame3d_sequence.sequence`` on a stored solid cycle ``run`` (``"d"``, ``"rises"`` per beam half, their
    ``"units"``, ``"tilt_rad"``, ``"unloading"``) whose halves are of the cell types ``state_types``, or ``None``
    when the run did not come back down: it did not unload, or it stopped (``run["stopped"]``) before every type
    that snapped on loading had snapped back."""
    from types import SimpleNamespace
    from metamaterial_wb.core.sleeve.frame3d_sequence import sequence
    down = np.asarray(run["unloading"], bool)
    if not down.any():
        return None
    ring = SimpleNamespace(cells=combination_cells(run["combination"]), state_types=list(state_types),
                           units=run["units"], rings=rings)
    d, rises = np.asarray(run["d"]), np.asarray(run["rises"])
    tilt = np.column_stack([np.asarray(run["tilt_rad"]), np.zeros(len(d))])
    up, back = ({"d": d[sl], "rises": rises[sl], "tilt": tilt[sl]} for sl in legs(run).values())
    out = sequence(ring, up, back)
    if run["stopped"] and sorted(out["unloading"]) != sorted(out["loading"]):
        return None
    return out


# mixed_study's variants of the cycle: where each is stored and how it is run (solid_cycle's keywords); "unbiased":
# static without the plate's bias moment (the mixed ring's own asymmetry the only one)
CYCLE_KEYS = {"static": "cycle", "dynamic": "cycle_dynamic", "unbiased": "cycle_unbiased"}
VARIANTS = {"static": {}, "dynamic": {"method": "dynamic"}, "unbiased": {"bias": 0.0}}


def mixed_study(runs=(("2", "r1"),), workers=2, timeout_s=7200.0, done=None):
    """For each (combination, mesh) or (combination, mesh, variant) of ``runs`` (``VARIANTS``, ``"static"`` by
    default): the mixed ring's cycle (``solid_cycle``) and, for the static one, the shorter type's uniform ring
    at the mixed ring's flat top (``solid_ring(top=...)``: with the taller type's stored uniform ring, the
    two-hysteron rule for the cells as they stand in the mixed ring), ``workers`` ccx runs at a time.
    ``done(key, mesh, what, result)`` as each ends (``what``: "raised" or the variant's ``CYCLE_KEYS``)."""
    full = []
    for run in runs:
        run = tuple(run)
        key, mesh, variant = run + ("static",) if len(run) == 2 else run if len(run) == 3 else (None,) * 3
        if key not in SEED_COMBINATIONS or mesh not in MESH_R or variant not in CYCLE_KEYS:
            raise ValueError(f"run {run!r}; allowed: a combination of {sorted(SEED_COMBINATIONS)} on a mesh of "
                             f"{sorted(MESH_R)}, as a variant of {sorted(CYCLE_KEYS)} (default static)")
        full.append((key, mesh, variant))
    out = {}
    with concurrent.futures.ThreadPoolExecutor(workers) as pool:
        futures = {}
        for key, mesh, variant in full:
            types = combination_cells(key)
            short = types[shorter(key)]
            top = max(g.height for g in types)
            futures[pool.submit(solid_cycle, key, MESH_R[mesh], timeout_s=timeout_s, **VARIANTS[variant])] = \
                (key, mesh, CYCLE_KEYS[variant])
            if top > short.height and variant == "static":
                futures[pool.submit(solid_ring, short, MESH_R[mesh], timeout_s=timeout_s, top=top)] = \
                    (key, mesh, "raised")
        for f in concurrent.futures.as_completed(futures):
            key, mesh, what = futures[f]
            out.setdefault(key, {}).setdefault(mesh, {})[what] = f.result()
            if done:
                done(key, mesh, what, out[key][mesh][what])
    return out


def solid_thresholds(runs=(("2", "r1"), ("2", "r2"), ("2", "r3"), ("1", "r1")), workers=2, timeout_s=5400.0,
                     done=None):
    """Every cell type of each (combination, mesh) of ``runs`` as a uniform solid ring (``solid_ring``), ``workers``
    ccx runs at a time (each on one core): ``{combination: {mesh: [type 0's row, type 1's row]}}``. ``done(key,
    mesh, k, row)`` is called as each run ends (to store it at once)."""
    for key, mesh in runs:
        if key not in SEED_COMBINATIONS or mesh not in MESH_R:
            raise ValueError(f"run ({key!r}, {mesh!r}); allowed: a combination of {sorted(SEED_COMBINATIONS)} "
                             f"on a mesh of {sorted(MESH_R)}")
    jobs = [(key, mesh, k, g) for key, mesh in runs for k, g in enumerate(combination_cells(key))]
    out = {}
    with concurrent.futures.ThreadPoolExecutor(workers) as pool:
        futures = {pool.submit(solid_ring, g, MESH_R[mesh], timeout_s=timeout_s): (key, mesh, k)
                   for key, mesh, k, g in jobs}
        for f in concurrent.futures.as_completed(futures):
            key, mesh, k = futures[f]
            row = f.result()
            out.setdefault(key, {}).setdefault(mesh, [None, None])[k] = row
            if done:
                done(key, mesh, k, row)
    return out


def solid_rule(rows):
    """The two-hysteron order on the solid's uniform rings of one combination and mesh, or ``None`` if a run
    missed a threshold."""
    if not rows or any(r is None or r["P1"] is None or r["valley"] is None for r in rows):
        return None
    return rule(rows)


def differences(rows):
    """Type 1's thresholds against type 0's, in per cent: ``(P1, valley)``."""
    return tuple(100.0 * (rows[1][k] / rows[0][k] - 1.0) for k in ("P1", "valley"))


def extrapolated(meshes):
    """Richardson over the solid's meshes r = 1, 2, 3 (``extrapolation.richardson3``, element size 1 / r, observed
    order) of one combination's runs ``{mesh: [row, row]}``: each type's ``P1`` and ``valley`` and type 1's
    differences from type 0 (per cent), each ``(value, error)``; ``None`` until all three meshes are stored with
    both thresholds."""
    from metamaterial_wb.core.extrapolation import richardson3
    figs = extrapolation_figures(meshes)
    if figs is None:
        return None
    out = {}
    for key, (_, h, values) in zip((0, 1, "differences"), figs):
        ext, err, _ = richardson3(h, values)
        out[key] = {"P1": (ext[0], err[0]), "valley": (ext[1], err[1])}
    return out


def extrapolation_figures(meshes, label=""):
    """What :func:`extrapolated` extrapolates, as ``extrapolation.order_note`` takes it: ``(names, h, values)`` for
    type 0's and type 1's P1 and valley and their differences (names prefixed by ``label``), ``None`` until all
    three meshes are stored with both thresholds."""
    names = ("r1", "r2", "r3")
    if not all(solid_rule(meshes.get(m)) for m in names):
        return None
    h = [1.0 / MESH_R[m] for m in names]
    return [([f"{label}type {k}'s P1", f"{label}type {k}'s valley"], h,
             [[meshes[m][k]["P1"], meshes[m][k]["valley"]] for m in names]) for k in range(2)] + \
        [([f"{label}type 1 against type 0, P1", f"{label}type 1 against type 0, valley"], h,
          [list(differences(meshes[m])) for m in names])]


def order_note(figures):
    """``extrapolation.order_note`` of ``figures`` (:func:`extrapolation_figures` entries; ``None`` ones left out)."""
    from metamaterial_wb.core.extrapolation import order_note as note
    return note([f for f in figures if f is not None])


def extrapolated_rule(ex):
    """The two-hysteron order on the extrapolated thresholds (``extrapolated``)."""
    return rule([{"P1": ex[k]["P1"][0], "valley": ex[k]["valley"][0]} for k in range(2)])


def _row(r):
    """One type's cell: P1 (d/L), valley (d/L), x1e-3; ``+-`` errors for extrapolated ``(value, error)`` pairs."""
    if r is None or r.get("P1") is None or r.get("valley") is None:
        return "-"
    out = []
    for k in ("P1", "valley"):
        v = r[k]
        out.append(f"{1e3 * v[0]:.3f} +- {1e3 * v[1]:.3f}" if isinstance(v, tuple) else f"{1e3 * v:.3f}"
                   + (f" ({r[k + '_d']:.3f})" if r.get(k + "_d") is not None else ""))
    return ", ".join(out)


def hysteresis(run):
    """A ``solid_cycle`` run's largest gap between its loading and unloading forces at the same rise (the unloading
    path interpolated at the loading rises it spans), over its first peak on loading: 0 for a reversible path."""
    d, F = np.asarray(run["d"]), np.asarray(run["F"])
    first = turn(run)
    du, Fu = d[first:][::-1], F[first:][::-1]            # rising d for the interpolation
    up = slice(0, first + 1)
    inside = (d[up] >= du[0]) & (d[up] <= du[-1])
    gap = np.abs(F[up][inside] - np.interp(d[up][inside], du, Fu)).max()
    from metamaterial_wb.fe.sleeve3d import all_extrema
    ext = all_extrema(d[up], F[up])
    p1 = next((y for k, _, y in ext if k == "peak"), F[up].max())
    return float(gap / p1)


def cycle_thresholds(run):
    """A ``solid_cycle`` run's first peak and the first valley after it on loading: ``{"P1", "valley"}``."""
    from metamaterial_wb.fe.sleeve3d import all_extrema
    down = np.asarray(run["unloading"], bool)
    ext = all_extrema(np.asarray(run["d"])[~down], np.asarray(run["F"])[~down])
    peak = next(x for x in ext if x[0] == "peak")
    return {"P1": peak[2], "valley": next(y for k, x, y in ext if k == "valley" and x > peak[1])}


def against_mean(run, rows):
    """A ``solid_cycle`` run's first peak and first valley on loading against the mean of its two types' uniform
    rings ``rows`` (``[{"P1", "valley"}, ...]``, as the types stand in it; two cells of each type), as fractions
    (``(P1 / mean - 1, valley / mean - 1)``): 0 for cells that act as springs in parallel under one plate."""
    own = cycle_thresholds(run)
    return tuple(own[q] / np.mean([r[q] for r in rows]) - 1.0 for q in ("P1", "valley"))


def standing_extrapolated(runs, uniform):
    """One combination's static mixed rings over r = 1, 2, 3 (``runs``: ``{mesh: {"cycle", "raised"}}``, as stored
    under ``mixed_cycles``; ``uniform``: ``{mesh: [row, row]}``, as under ``combinations``), extrapolated as
    ``extrapolated`` does: its types as they stand in it (``standing``: each type's P1 and valley, their
    differences, per cent) and, under ``"mixed"``, the ring's own first peak and valley (``cycle_thresholds``),
    each ``(value, error)``; ``None`` until all three meshes have both runs."""
    from metamaterial_wb.core.extrapolation import richardson3
    figs = standing_figures(runs, uniform)
    if figs is None:
        return None
    key = runs["r1"]["cycle"]["combination"]
    out = extrapolated({m: standing(key, runs[m]["raised"], uniform[m]) for m in ("r1", "r2", "r3")})
    _, h, values = figs[-1]
    ext, err, _ = richardson3(h, values)
    out["mixed"] = {"P1": (ext[0], err[0]), "valley": (ext[1], err[1])}
    return out


def standing_figures(runs, uniform):
    """What :func:`standing_extrapolated` extrapolates, as ``extrapolation.order_note`` takes it
    (:func:`extrapolation_figures` of the types as they stand, then the mixed ring's own P1 and valley); ``None``
    until all three meshes have both runs."""
    names = ("r1", "r2", "r3")
    if not all(runs.get(m, {}).get("cycle") and runs[m].get("raised") and all(uniform.get(m) or [None])
               for m in names):
        return None
    key = runs["r1"]["cycle"]["combination"]
    figs = extrapolation_figures({m: standing(key, runs[m]["raised"], uniform[m]) for m in names},
                                 "as they stand, ")
    if figs is None:
        return None
    own = [cycle_thresholds(runs[m]["cycle"]) for m in names]
    return figs + [(["mixed ring's own P1", "mixed ring's own valley"], [1.0 / MESH_R[m] for m in names],
                    [[o["P1"], o["valley"]] for o in own])]


def standing_sentence(key, sx, orders):
    """What the extrapolated standing types (``standing_extrapolated``'s ``sx``) of combination ``key`` say beside
    the mixed ring's own orders on the three meshes (``orders``: ``order_text`` strings), one paragraph."""
    dp, dv = sx["differences"]["P1"], sx["differences"]["valley"]
    beyond = abs(dp[0]) > dp[1] and abs(dv[0]) > dv[1]
    mean = {q: 0.5 * (sx[0][q][0] + sx[1][q][0]) for q in ("P1", "valley")}
    (p, ep), (v, ev) = sx["mixed"]["P1"], sx["mixed"]["valley"]
    own = (f"snaps {orders[0]} on each of them" if len(set(orders)) == 1 else
           "does not snap in the same order on each of them")
    return (f"Over r = 1, 2 and 3 (Richardson in the element size 1 / r) combination {key}'s types as they stand in "
            f"its mixed ring differ by {dp[0]:+.2f} +- {dp[1]:.2f} % on the first peak and {dv[0]:+.2f} +- "
            f"{dv[1]:.2f} % on the valley, so the rule on the extrapolated solid gives "
            f"{order_text(extrapolated_rule(sx))} ("
            + ("both differences beyond their errors" if beyond else "a difference within its error")
            + f"), while the mixed ring itself {own}. Its own first peak and valley extrapolate to "
            f"{1e3 * p:.4f} +- {1e3 * ep:.4f} and {1e3 * v:.4f} +- {1e3 * ev:.4f} x1e-3 (F / (G L^2)), "
            f"{100 * (p / mean['P1'] - 1):+.1f} % and {100 * (v / mean['valley'] - 1):+.1f} % from its types' "
            "extrapolated mean.")


def listed(words):
    """``["1", "2", "3"]`` as "1, 2 and 3" (the meshes a sentence names)."""
    return ", ".join(words[:-1]) + " and " + words[-1] if len(words) > 1 else words[0]


def cycles_markdown(cycles, solid, frame=None):
    """The seed's mixed rings on the solid (``cycles``: ``{combination: {mesh: {"cycle", "raised"}}}``, as stored
    under ``mixed_cycles``): each ring's own sequence and lean (``cycle_sequence``) beside the rule on its types'
    uniform rings as they stand in it (the shorter type's at the flat top, ``raised``; the taller one's from
    ``solid``, the stored ``combinations``), the frame's mixed ring at the same flat top (``frame[key]["flat_top"]``,
    ``fe_frame3d_plate.sequence_study``) and the seed's; "" without a cycle."""
    frame = frame or {}
    L = ["**The seed's mixed rings on the curved solid** (`bench_sleeve_ring3d.py --mixed-cycles`: the ring "
         "[0, 0, 1, 1] of the combination's two types as one CalculiX solid, one brick through the wall, every brick "
         "C3D20, static (\", dynamic\": by implicit dynamics, HHT alpha -0.3 with the small density, the seed's "
         "procedure), raised to d/L 0.7 and lowered back in steps of 0.01 at most under the default bias (\", "
         "unbiased\": static without it); the cells "
         "meet at a flat top at the taller type's height, so the shorter type's edge pillars are longer by the "
         "difference; the order by the frame's reading of the beams' ends, `analysis.snap_order`; lean: the "
         "plate's largest tilt on each path). The rule beside it is the two-hysteron rule on the types' uniform "
         "rings as they stand in the mixed ring (the shorter type's uniform ring at that top):", "",
         "| combination | mesh | mixed ring: loading \\| unloading | lean loading / unloading (deg) | hysteresis "
         "(largest gap / P1) | P1, valley against its types' mean | rule on the "
         "uniform rings at the flat top | frame's mixed ring at the flat top (12 elements) | seed | time |",
         "|---|---|---|---|---|---|---|---|---|---|"]
    rows, gaps, means, unbiased = 0, {m: [] for m in CYCLE_KEYS}, [], []
    static_orders = {}           # (combination, mesh): the static cycle's order, for the extrapolation paragraph
    for key in sorted(cycles):
        for mesh, variant in ((m, x) for m in sorted(cycles[key]) for x in CYCLE_KEYS):
            run = cycles[key][mesh]
            cyc = run.get(CYCLE_KEYS[variant])
            if variant != "static" and not cyc:
                continue
            seq = cycle_sequence(cyc) if cyc else None
            if variant == "static":
                static_orders[key, mesh] = seq
            if cyc and seq is None:
                text, lean = f"stopped at d/L {cyc['d_reached']:.3f}", "-"
            elif seq:
                text = order_text(seq)
                lean = (f"{seq['lean_loading_deg']:.0f} / {seq['lean_unloading_deg']:.0f}"
                        + (" (reverses)" if seq["lean_reverses"] else "")
                        if seq["lean_loading_deg"] is not None and seq["lean_unloading_deg"] is not None else "-")
            else:
                continue
            rule_text, mean_text = "-", "-"
            raised, uni = run.get("raised"), (solid.get(key, {}).get(mesh) or [None, None])
            if raised and all(uni):
                rows_ = standing(key, raised, uni)
                if solid_rule(rows_):
                    rule_text = order_text(rule(rows_)) + " ({:+.1f} %, {:+.1f} %)".format(*differences(rows_))
                    if seq:
                        means.append(against_mean(cyc, rows_))
                        mean_text = "{:+.1f} %, {:+.1f} %".format(*(100 * v for v in means[-1]))
            secs = " + ".join(f"{r['wall_s'] / 60:.0f}" for r in (cyc, raised if variant == "static" else None) if r)
            fl = frame.get(key, {}).get("flat_top")
            fl_text = (order_text(fl) + (", lean reverses" if fl["lean_reverses"] else ", lean the same way")
                       if fl and "loading" in fl else "-")
            gap = hysteresis(cyc) if seq else None
            gaps[variant] += [(key, mesh, gap, seq)] if gap is not None else []
            biased = cycle_sequence(run["cycle"]) if variant == "unbiased" and seq and run.get("cycle") else None
            if biased:
                unbiased.append((key, mesh, seq, biased))
            L.append(f"| {key} | r = {mesh[1:]}{'' if variant == 'static' else ', ' + variant} | {text} | {lean} | "
                     + (f"{100 * gap:.2f} %" if gap is not None else "-") + f" | {mean_text} | {rule_text} | {fl_text} | "
                     f"{order_text(seed_order(key))} | {secs} min |")
            rows += 1
    static = [g for m in ("static", "unbiased") for _, _, g, _ in gaps[m]]
    if static and max(static) < 0.01:
        L += ["", f"Every mixed solid's loading and unloading paths coincide (the largest gap {100 * max(static):.2f} % of "
              "its first peak; the plot below): under displacement control the ring does not snap, its pillars pass "
              "their h back where they passed it, in the reverse order, so its sequence can only be symmetric. The "
              "seed's asymmetric sequence needs a path with hysteresis, which these solids do not have ("
              + ("" if gaps["dynamic"] else "the seed's FE was dynamic implicit; ")
              + "its two-hysteron reading treats each type as a separate bistable element)."]
    groups = {}
    for key, mesh, gap, seq in gaps["dynamic"]:
        groups.setdefault((key, order_text(seq), gap < 0.01), []).append((mesh, gap))
    for (key, order, flat), runs in groups.items():
        L += ["", f"By implicit dynamics (the seed's procedure) combination {key}'s mixed solid on r = "
              f"{listed([m[1:] for m, _ in runs])} "
              + f"snaps {order}, its paths {'coinciding' if flat else 'apart'} (the largest gap "
              + " / ".join(f"{100 * g:.2f}" for _, g in runs) + " % of its first peak"
              + (", by mesh" if len(runs) > 1 else "") + "): "
              + ("inertia does not give the ring hysteresis either." if flat else "inertia gives the ring hysteresis.")]
    for key, mesh, seq, biased in unbiased:
        same = (seq["loading"], seq["unloading"]) == (biased["loading"], biased["unloading"])
        turned = _angle(seq["lean_loading_deg"], biased["lean_loading_deg"])
        L += ["", f"Without the bias moment (the mixed ring's own asymmetry the only one) combination {key}'s mixed "
              f"solid on r = {mesh[1:]} snaps {order_text(seq)}, "
              + ("as" if same else "unlike its order") + " with it, leaning "
              + (f"{turned:.0f} deg from where it leant with it" if turned is not None else "-")
              + (f" ({seq['lean_loading_deg']:.0f} / {seq['lean_unloading_deg']:.0f} deg)"
                 if seq["lean_loading_deg"] is not None and seq["lean_unloading_deg"] is not None else "")
              + _bias_verdict(same, turned, seq, biased)]
    if means:
        worst = max(abs(v) for m in means for v in m)
        L += ["", f"Each mixed solid's first peak and valley lie within {100 * worst:.1f} % of the mean of its two types' "
              "uniform rings as they stand in it: its cells act as springs in parallel under one plate. The seed's "
              "mixed ring took the first type's peak and the other type's valley (its two-hysteron reading)."]
    for key in sorted(cycles):
        sx = standing_extrapolated(cycles[key], solid.get(key, {}))
        orders = [static_orders.get((key, m)) for m in ("r1", "r2", "r3")] if sx else []
        if sx and all(orders):
            note = order_note(standing_figures(cycles[key], solid.get(key, {})))
            L += ["", standing_sentence(key, sx, [order_text(o) for o in orders]) + (" " + note if note else "")]
    L += ["", f"![the seed's mixed rings on the solid: force and each pillar's rise beyond h]({IMG_CYCLES})"]
    return "\n".join(L + [""]) if rows else ""


def _bias_verdict(same, turned, seq, biased):
    """How the unbiased mixed ring's order and lean (``seq``) stand against the biased one's (``biased``; ``same``
    order, the leans ``turned`` degrees apart): the sentence's ending."""
    if not same or turned is None:
        return "."
    if turned < 20:
        return ": the bias does not decide the lean."
    if turned > 150 and not seq["lean_reverses"] and not biased["lean_reverses"]:
        return (f": the small bias ({BIAS:g} G L^2 R) picks which way the mixed ring leans, not its order; either way "
                "the lean stays the same on both paths.")
    return "."


def _angle(a, b):
    """The angle between two leans (deg, 0 to 180), ``None`` where either is missing."""
    if a is None or b is None:
        return None
    return abs((a - b + 180.0) % 360.0 - 180.0)


def solid_markdown(solid, mixed, stacked=False):
    """The solid's thresholds of the seed's combinations (``solid``: ``{combination: {mesh: [row, row]}}``, as
    stored under ``combinations``) and their extrapolation, beside the frame's uniform rings
    (``mixed[key]["uniform"]``, ``fe_frame3d_plate.sequence_study``) and the seed's order, and what they say;
    ``stacked``: a stacked solid is stored (``fe_ring3d_stack``), the text points to it."""
    L = ["**The seed's combinations' thresholds on the curved solid** (`bench/fe_ring3d_combinations.py`, "
         "`bench_sleeve_ring3d.py --combinations`: each type a uniform four-cell ring in CalculiX, one brick "
         "through the wall, every brick C3D20, static to d/L 0.7 in steps of 0.01, the tilting top plate under "
         "the default bias; first peak P1 and first valley, F / (G L^2) x1e-3 at d/L; extrapolated in the element "
         "size 1 / r over r = 1, 2, 3 with its observed order). The stacked frame above puts a stack's thresholds "
         "on its uniform rings', so the rule on a model's uniform rings is that model's order for the stack; "
         + ("the stacked solid below checks that on the solid itself:" if stacked else
            "a stacked solid is not run (its snaps under displacement control are dynamic):"), "",
         "| combination | model, mesh | type 0: P1, valley | type 1: P1, valley | type 1 against type 0: P1, "
         "valley | rule (stacked order) | seed | time |", "|---|---|---|---|---|---|---|---|"]
    verdict, frame_notes, figures = [], [], []
    for key in sorted(solid):
        seed = seed_order(key)
        rows = [("solid, r = " + mesh[1:], solid[key][mesh]) for mesh in sorted(solid[key])]
        ex = extrapolated(solid[key])
        if ex:
            rows.append(("solid, extrapolated", [ex[0], ex[1]]))
            figures += extrapolation_figures(solid[key], f"combination {key}, ")
        u = mixed.get(key, {}).get("uniform")
        if u:
            rows.append(("frame, 12 elements (plane stress, calibrated, free plate)",
                         [{"P1": x["P1"], "valley": x["valley"]} for x in u]))
        orders = {}
        for i, (name, rr) in enumerate(rows):
            if name == "solid, extrapolated":
                dp, dv = ex["differences"]["P1"], ex["differences"]["valley"]
                ru = extrapolated_rule(ex)
                diff = f"{dp[0]:+.2f} +- {dp[1]:.2f} %, {dv[0]:+.2f} +- {dv[1]:.2f} %"
                rule_text = order_text(ru) + (" (both differences beyond their errors)" if abs(dp[0]) > dp[1] and
                                        abs(dv[0]) > dv[1] else " (a difference within its error)")
            else:
                ru = solid_rule(rr)
                diff = "{:+.1f} %, {:+.1f} %".format(*differences(rr)) if ru else "-"
                rule_text = order_text(ru) if ru else "-"
            orders[name] = ru
            secs = " + ".join(f"{r['wall_s'] / 60:.0f}" for r in rr if r and "wall_s" in r)
            L.append(f"| {key if i == 0 else ''} | {name} | {_row(rr[0])} | {_row(rr[1])} | {diff} | {rule_text} | "
                     + (order_text(seed) if i == 0 else "") + f" | {secs + ' min' if secs else ''} |")
        solids = {n: o for n, o in orders.items() if n.startswith("solid, r") and o}
        if solids:
            same = all(o["loading"] == seed["loading"] and o["unloading"] == seed["unloading"] for o in solids.values())
            alike = len({(tuple(o["loading"]), tuple(o["unloading"])) for o in solids.values()}) == 1
            verdict.append(f"combination {key}: the solid's order is "
                           + (order_text(next(iter(solids.values()))) + (" on every mesh" if len(solids) > 1 else "")
                              if alike else "not the same on every mesh")
                           + (", the seed's" if same else ", not the seed's"))
        if ex and u:
            offs = []
            for k in range(2):
                for q in ("P1", "valley"):
                    v, e = ex[k][q]
                    offs.append(f"type {k}'s {q} {100 * (u[k][q] / v - 1):+.1f} % "
                                + ("(inside" if abs(u[k][q] - v) <= e else "(outside")
                                + f" its +- {100 * e / v:.0f} %)")
            fd, sd_ = differences(u), ex["differences"]
            frame_notes.append(f"Combination {key}'s frame against the extrapolated solid: " + ", ".join(offs)
                               + f"; the frame's types differ by {fd[0]:+.1f} % (P1) and {fd[1]:+.1f} % (valley), "
                               f"the solid's by {sd_['P1'][0]:+.2f} +- {sd_['P1'][1]:.2f} % and "
                               f"{sd_['valley'][0]:+.2f} +- {sd_['valley'][1]:.2f} %.")
    note = order_note(figures)
    L += ["", note] if note else []
    L += ["", "; ".join(verdict) + "." if verdict else "", ""]
    if frame_notes:
        L += [" ".join(frame_notes), ""]
    return "\n".join(L)


IMG_CYCLES = "img/sleeve-mixed-solid.png"


def plot_cycles(cycles, path, mesh="r1"):
    """The seed's mixed rings on the solid (``cycles``, as stored under ``mixed_cycles``), one row per combination:
    the force on loading and unloading (static, and the other variants stored on the mesh over it), and each edge
    pillar's rise beyond its cells' mean h (the snap rule: above 0 it has snapped; static), against the plate's
    rise."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from metamaterial_wb.bench.plotting import finish
    keys = [k for k in sorted(cycles) if cycles[k].get(mesh, {}).get("cycle")]
    fig, ax = plt.subplots(len(keys), 2, figsize=(10.5, 3.6 * len(keys)), dpi=100, squeeze=False)
    for row, key in enumerate(keys):
        run = cycles[key][mesh]["cycle"]
        types = combination_cells(key)
        d, F = np.asarray(run["d"]), 1e3 * np.asarray(run["F"])
        h = np.array([types[run["row"][k]].h / types[0].L for k in run["cells"]])
        over, units = np.asarray(run["rises"]) - h, np.asarray(run["units"])
        for (name, sl), style in zip(legs(run).items(), ("-", "--")):
            ax[row, 0].plot(d[sl], F[sl], style, color="k", lw=1.3, label=name)
            for p in range(int(units.max()) + 1):
                kinds = sorted({run["row"][run["cells"][j]] for j in np.flatnonzero(units == p)})
                col = ("C0", "C3", "C2")[kinds[0] if len(kinds) == 1 else 2]
                ax[row, 1].plot(d[sl], over[sl][:, units == p].mean(axis=1), style, color=col, lw=1.1,
                                label=(f"pillar {p} (type {kinds[0]})" if len(kinds) == 1 else f"pillar {p} (mixed)")
                                if name == "loading" else None)
        for variant, col in (("dynamic", "C1"), ("unbiased", "C4")):     # the other variants' forces over it
            other = cycles[key][mesh].get(CYCLE_KEYS[variant])
            if other and np.asarray(other["unloading"], bool).any():
                dv, Fv = np.asarray(other["d"]), 1e3 * np.asarray(other["F"])
                for (name, sl), style in zip(legs(other).items(), ("-", "--")):
                    ax[row, 0].plot(dv[sl], Fv[sl], style, color=col, lw=0.9, label=f"{variant}: {name}")
        seq = cycle_sequence(run)
        ax[row, 0].set_title(f"combination {key}, ring {run['row']} on the solid (r = {run['r']}): "
                             + (order_text(seq).replace("\\|", "|") if seq else "no cycle"), fontsize=9)
        ax[row, 0].set_ylabel("F / (G L^2) x1e-3")
        ax[row, 1].axhline(0.0, color="0.5", lw=0.8)
        ax[row, 1].set_ylabel("pillar's rise beyond h, / L")
        ax[row, 1].set_title("each edge pillar's two beam halves (snapped above 0)", fontsize=9)
    finish(fig, ax.ravel(), "plate's rise d / L", path)
