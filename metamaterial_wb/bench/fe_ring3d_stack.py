"""The seed's combinations as two stacked rings on the curved solid (issue 18): each cell type a uniform four-cell
ring, the lower type below, a free plate between them (``fe/sleeve3d_stack.py``), raised to twice a single
ring's d/L 0.7 and lowered back by implicit dynamics.

The two-hysteron rule on the solid's uniform rings (``fe_ring3d_combinations.solid_rule``) is the solid's order
for such a stack only if the rings act in series as the frame's stacked rings do (``fe_frame3d_stack``): here
that is run, not inferred. The order is read as the frame's and the mixed solid's are
(``frame3d_sequence.sequence`` on the beams' rises), each ring a hysteron of its own type.
"""
import concurrent.futures

import numpy as np

from metamaterial_wb.bench.fe_ring3d_combinations import (D_MAX, MESH_R, SEED_COMBINATIONS, combination_cells, legs,
                                                         path_sequence)

STACK_D_MAX = 2 * D_MAX       # d/L of the top: both rings past their first valley (the frame's stack: twice)


def solid_stack(key, r=1, d_max=STACK_D_MAX, increments=70, method="dynamic", timeout_s=10800.0, damping=0.0):
    """Combination ``key``'s two types stacked (type 0 below) on mesh ``r`` (one brick through the wall, C3D20),
    ``increments`` per unit of time at most (``d_max / increments`` d/L each): ``{"combination", "r", "d", "F",
    "ring_rises", "tilt_rad", "middle_tilt_rad", "unloading", "rises", "units", "types", "wall_s", "d_reached",
    "stopped", "method", "d_max", "damping"}`` (``stack_sequence`` reads the order off it); ``damping``: the
    rubber's mass-proportional damping (1/s, ``sleeve3d_stack.stack_deck3d``)."""
    from metamaterial_wb.fe import sleeve3d_stack
    if key not in SEED_COMBINATIONS:
        raise ValueError(f"combination: {key!r}; allowed: {sorted(SEED_COMBINATIONS)}")
    cells = combination_cells(key)
    c, info = sleeve3d_stack.solve_stack3d(cells, 4, r, d_max=d_max * cells[0].L, increments=increments,
                                           method=method, timeout_s=timeout_s, partial=True, damping=damping)
    return _stored(key, r, d_max, method, increments, damping, c, info["wall_s"], info.get("stopped", ""))


def solid_stack_from_dat(key, dat_text, wall_s, stopped, r=1, d_max=STACK_D_MAX, increments=70, method="dynamic",
                         damping=0.0):
    """``solid_stack``'s record of a run read off its ``.dat`` file (``dat_text``, ccx still going or stopped by
    hand: ``stopped`` says why, ``wall_s`` how long it ran), for the same deck ``solid_stack`` writes."""
    from metamaterial_wb.fe import ccx, sleeve3d_stack
    cells = combination_cells(key)
    _, meta = sleeve3d_stack.stack_deck3d(cells, 4, r, d_max * cells[0].L, increments, method=method, watch="ends",
                                          damping=damping)
    c = sleeve3d_stack.read_stack(ccx.parse_dat(dat_text), meta)
    return _stored(key, r, d_max, method, increments, damping, c, wall_s, stopped)


def _stored(key, r, d_max, method, increments, damping, c, wall_s, stopped):
    out = {"combination": key, "r": int(r), "d_max": float(d_max), "method": method, "increments": int(increments),
           "damping": float(damping),
           "wall_s": float(wall_s), "d_reached": float(c["d"][-1]), "stopped": stopped[:300],
           "units": c["units"].tolist(), "types": c["types"].tolist(),
           "unloading": c["unloading"].astype(int).tolist(), "d": np.round(c["d"], 6).tolist(),
           "F": c["F"].tolist()}
    for name in ("ring_rises", "tilt_rad", "middle_tilt_rad", "rises"):
        out[name] = np.round(c[name], 7).tolist()
    return out


def stack_sequence(run):
    """The snapping order of a ``solid_stack`` run's two rings (each of one cell type) on loading and unloading, by
    the frame's own reading (``frame3d_sequence.sequence``), or ``None`` when the run did not come back down."""
    return path_sequence(run, run["types"], rings=2)


def stacked_solid_study(runs=(("2", "r1"),), workers=2, timeout_s=10800.0, done=None, damping=0.0):
    """``solid_stack`` for each (combination, mesh) of ``runs``, ``workers`` ccx runs at a time (one core each), with
    the rubber's ``damping`` (1/s): ``{combination: {mesh: run}}``; ``done(key, mesh, run)`` as each ends (to store
    it at once)."""
    for run in runs:
        if len(run) != 2 or run[0] not in SEED_COMBINATIONS or run[1] not in MESH_R:
            raise ValueError(f"run {tuple(run)!r}; allowed: a combination of {sorted(SEED_COMBINATIONS)} on a mesh "
                             f"of {sorted(MESH_R)}")
    out = {}
    with concurrent.futures.ThreadPoolExecutor(workers) as pool:
        futures = {pool.submit(solid_stack, key, MESH_R[mesh], timeout_s=timeout_s, damping=damping): (key, mesh)
                   for key, mesh in runs}
        for f in concurrent.futures.as_completed(futures):
            key, mesh = futures[f]
            out.setdefault(key, {})[mesh] = f.result()
            if done:
                done(key, mesh, out[key][mesh])
    return out


def paths(run):
    """A ``solid_stack`` run split at its turn as the frame's stack stores its paths (``fe_frame3d_stack``):
    ``{"loading", "unloading"}``, each ``{"d", "F", "ring_rises"}`` (the unloading path from the turn down)."""
    return {name: {k: run[k][s] for k in ("d", "F", "ring_rises")} for name, s in legs(run).items()}


def series_check(run, uniform):
    """How far a ``solid_stack`` run's loading extrema lie from two rings in series made of its types' uniform
    rings ``uniform`` (``[{"P1", "valley"}, ...]``, the same mesh): its two peaks against the two first peaks, its
    two valleys against the first-snapping ring's and the higher of the two (a snapped ring carries no less than
    its valley): ``(largest peak gap, largest valley gap)`` as fractions, or ``None`` if the run does not show two
    of each on loading."""
    from metamaterial_wb.bench.fe_ring3d_combinations import rule
    from metamaterial_wb.fe.sleeve3d import all_extrema
    p = paths(run)["loading"]
    ext = all_extrema(p["d"], p["F"])
    peaks = [y for k, _, y in ext if k == "peak"]
    valleys = [y for k, _, y in ext if k == "valley"]
    if len(peaks) < 2 or len(valleys) < 2:
        return None
    first = rule(uniform)["loading"][0]
    expect = [uniform[first]["valley"], max(u["valley"] for u in uniform)]
    dp = max(abs(a / b - 1) for a, b in zip(sorted(peaks[:2]), sorted(u["P1"] for u in uniform)))
    dv = max(abs(a / b - 1) for a, b in zip(valleys[:2], expect))
    return float(dp), float(dv)


def ring_states(run):
    """How many of each ring's edge pillars have snapped (``analysis.units_snapped``: the mean rise of a pillar's two
    beam halves beyond their cell's h) at every point of a ``solid_stack`` run: ``(k, 2)``."""
    from metamaterial_wb.core.sleeve.analysis import units_snapped
    cells = combination_cells(run["combination"])
    types, units = np.asarray(run["types"]), np.asarray(run["units"])
    h = np.array([cells[t].h / cells[t].L for t in types])
    snapped = units_snapped(np.asarray(run["rises"]), h, units)          # (k, pillars): ring 0's, then ring 1's
    ring_of = np.array([types[np.flatnonzero(units == u)[0]] for u in range(snapped.shape[1])])
    return np.stack([snapped[:, ring_of == j].sum(axis=1) for j in range(2)], axis=1)


def ring_events(run):
    """A ``solid_stack`` run's ring-level events, in order: ``(point, d, ring, "snaps" | "snaps back")`` whenever a
    ring's pillars become all snapped from not all, or none from some (``ring_states``)."""
    st = ring_states(run)
    types, units = np.asarray(run["types"]), np.asarray(run["units"])
    full = [len(set(units[types == j])) for j in range(2)]                  # each ring's pillars
    out = []
    for i in range(1, len(st)):
        for j in range(2):
            if st[i, j] == full[j] and st[i - 1, j] < full[j]:
                out.append((i, float(run["d"][i]), j, "snaps"))
            elif st[i, j] == 0 and st[i - 1, j] > 0:
                out.append((i, float(run["d"][i]), j, "snaps back"))
    return out


def events_text(events):
    """``ring_events`` in words, a ring that snaps back and forth more than twice in a row as one entry:
    ``ring 0 snaps at d/L 0.380, ring 1 snaps at 0.872, ring 0 back and forth 6 times from 0.847 to 0.889``."""
    groups = []
    for e in events:
        if groups and groups[-1][0][2] == e[2]:
            groups[-1].append(e)
        else:
            groups.append([e])
    words = []
    for g in groups:
        if len(g) > 2:
            words.append(f"ring {g[0][2]} back and forth {len(g)} times from {g[0][1]:.3f} to {g[-1][1]:.3f}")
        else:
            words += [f"ring {j} {what} at {d:.3f}" for _, d, j, what in g]
    return ", ".join(words).replace(" at ", " at d/L ", 1)


IMG = "img/sleeve-stacked-solid.png"


def stacked_solid_markdown(stacked, solid, frame_stack=None, attempts=None):
    """The seed's combinations as two stacked rings on the solid (``stacked``: ``{combination: {mesh: run}}``, as
    stored under ``stacked_solid``): each stack's order and lean (``stack_sequence``) beside the rule on the
    solid's uniform rings of the same mesh (``solid``, as stored under ``combinations``), the frame's stack
    (``frame_stack``, ``fe_frame3d_stack.stacked_study``) and the seed's, and how far the stack's extrema lie from
    its rings' own (``series_check``); ``attempts`` (``{combination: {mesh: [run, ...]}}``, as stored under
    ``stacked_solid_attempts``): earlier runs of the same stack that stopped, each a row after it with its
    ``"note"``; "" without a run."""
    from metamaterial_wb.bench.fe_ring3d_combinations import order_text, seed_order, solid_rule
    frame_stack = frame_stack or {}
    L = ["**The seed's combinations as two stacked rings on the curved solid** (`bench/fe_ring3d_stack.py`, "
         "`bench_sleeve_ring3d.py --stacked-solid`: each type a uniform four-cell ring, one brick through the wall, "
         "every brick C3D20, type 0 below, the plate between them free to rise, tilt and twist, the top plate "
         "under the default bias; raised to d/L 1.4 and lowered back by implicit dynamics, the seed's procedure, "
         "d/L 0.02 per increment at most; undamped as the single rings, or with the rubber's mass-proportional "
         "Rayleigh damping, `--stacked-damping`, 1/s). The stack's snaps are dynamic under displacement control, "
         "so it could not be run statically; this is the frame's stacked study above as a solid:", "",
         "| combination | mesh | solid, stacked: sequence | events (d/L of the top) | lean (loading / unloading) | "
         "rule on the solid's uniform rings | frame, stacked (12) | seed | in series: peaks, valleys off | time |",
         "|---|---|---|---|---|---|---|---|---|---|"]
    verdict = []
    for key in sorted(stacked):
        seed = seed_order(key)
        runs = [(mesh, run) for mesh in sorted(stacked[key])
                for run in [stacked[key][mesh]] + (attempts or {}).get(key, {}).get(mesh, [])]
        for mesh, run in runs:
            name = f"r = {mesh[1:]}" + (f", damping {run['damping']:g}/s" if run.get("damping") else ", undamped")
            s = stack_sequence(run)
            rows = solid.get(key, {}).get(mesh)
            ru = solid_rule(rows)
            fr = frame_stack.get(key, {}).get("frame", {}).get("12")
            off = series_check(run, rows) if ru else None
            events = ring_events(run)
            if s is None:
                first = []
                for _, _, j, what in events:
                    if what == "snaps" and j not in first:
                        first.append(j)
                seq = f"loading {first}, then stopped at d/L {run['d_reached']:.3f} before unloading"
                lean = "-"
                verdict.append(f"combination {key} ({name}): the stacked solid snaps loading {first}"
                               + (", the rule's and the seed's" if ru and first == ru["loading"] == seed["loading"]
                                  else "") + f", and was stopped at d/L {run['d_reached']:.3f}: {run.get('note', '')}")
            else:
                seq = order_text(s) + (f" (stopped on unloading at d/L {run['d_reached']:.3f}, every ring back)"
                                       if run["stopped"] else "")
                lean = (f"{s['max_tilt_loading_deg']:.1f} / {s['max_tilt_unloading_deg']:.1f} deg, "
                        + ("reverses" if s["lean_reverses"] else "the same way"))
                same = s["loading"] == seed["loading"] and s["unloading"] == seed["unloading"]
                agree = ru is not None and s["loading"] == ru["loading"] and s["unloading"] == ru["unloading"]
                verdict.append(f"combination {key} ({name}): the stacked solid snaps {order_text(s)}, "
                               + ("the seed's order" if same else "not the seed's order")
                               + (", as the rule on its uniform rings says" if agree else
                                  ", not what the rule on its uniform rings says" if ru else "")
                               + (f" ({run['note']})" if run.get("note") else ""))
            L.append(f"| {key} | {name} | {seq} | {events_text(events) or '-'} | {lean} | "
                     f"{order_text(ru) if ru else '-'} | {order_text(fr) if fr else '-'} | {order_text(seed)} | "
                     + (f"{100 * off[0]:.1f} %, {100 * off[1]:.1f} %" if off else "-")
                     + f" | {run['wall_s'] / 60:.0f} min |")
    if len(L) == 5:
        return ""
    L += ["", "; ".join(verdict) + "." if verdict else "",
          "", "The peaks and valleys columns: the stack's two peaks on loading against its rings' first peaks, its "
          "two valleys against the first-snapping ring's valley and the higher of the two (a snapped ring carries "
          "no less than its valley), each ring run alone on the same mesh; the largest gap of each.", ""]
    two = stacked.get("2", {})
    if two:
        L += [f"![combination 2 as two stacked rings on the solid]({IMG})", ""]
    return "\n".join(L)


def plot(stacked, path, mesh="r1"):
    """Combination 2's stacked solid on ``mesh``: force and each ring's rise (``fe_frame3d_stack.plot_paths``)."""
    from metamaterial_wb.bench.fe_frame3d_stack import plot_paths
    plot_paths(paths(stacked["2"][mesh]), path,
               f"combination 2 as two stacked rings, curved solid (r = {mesh[1:]})")
