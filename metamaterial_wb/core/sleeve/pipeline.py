"""Everything the ``sleeve`` command computes for one spec: unit cells, uniform rings, the sleeve's
ring, sequencing, PV curves, design maps and the walker. Returns plain data (and curves for plots)."""
import math
import time

import numpy as np

from metamaterial_wb.core.sleeve.accuracy import (accuracy, frame_nl_note, frame_note, frame_sequence_note,
                                                  frame_walker_note, solid_order_note)
from metamaterial_wb.core.sleeve.frame3d import curvature_check
from metamaterial_wb.core.sleeve.frame3d_nl import first_peak
from metamaterial_wb.core.sleeve.frame3d_sequence import frame_sequence
from metamaterial_wb.core.sleeve.analysis import (extrema, has_force_drop, lean_direction, peaks_valleys,
                                                  pressure_control, pv_curve, sequence_symmetry, snap_order,
                                                  two_hysteron_sequence, zero_crossings)
from metamaterial_wb.core.sleeve.cell import CellGeometry
from metamaterial_wb.core.sleeve.model import SleeveModel, default_stroke
from metamaterial_wb.core.sleeve.spec import MIN_FEATURE_MM
from metamaterial_wb.core.sleeve.walker import walker_cycle


def unit_cell_result(geom, n_el=10, steps=160, plane="strain", d_max=None, root_extension=0.0):
    m = SleeveModel([geom], None, n_el, plane, root_extension=root_extension)
    d_max = default_stroke([geom]) if d_max is None else d_max
    d = np.linspace(0.0, d_max, steps + 1)
    up = m.trace(d)
    down = m.trace(d[::-1], q0=m.last_q)
    # extrema larger than the force resolution only: on a stroke of a few nanometres the curve is round-off
    p, v = extrema(up.F, floor=up.noise)
    F = up.F
    # the stroke's last point is no peak (the force still rises) and no valley (it still falls): null and a note
    peak = p[0] if p else None
    valley = v[0] if v else None
    res_F = force_resolution(up)
    at = lambda i, x: None if i is None else float(x[i])  # noqa: E731
    res = {"t_mm": geom.t, "h_mm": geom.h, "t_over_L": geom.t / geom.L, "h_over_L": geom.h / geom.L,
           "peak_force": at(peak, F), "peak_displacement": at(peak, up.d),
           "valley_force": at(valley, F), "valley_displacement": at(valley, up.d),
           "bistable": bool(peak is not None and np.min(F[peak:]) < -res_F),
           "zero_crossings": zero_crossings(F[1:], res_F),
           "hysteresis": float(np.max(np.abs(up.F - down.F[::-1]))),
           "seconds": up.seconds + down.seconds}
    note = _extrema_note(peak, valley, up.d[-1])
    if note:
        res["note"] = note
    return res, up, down


def _extrema_note(peak, valley, d_end):
    """Why a curve's peak or valley is null: ``""`` when it has both."""
    if peak is None:
        return (f"no peak within the stroke (to d/L {d_end:.4g}: the force never falls by more than 2 % of its "
                "range and the model's force resolution, analysis.extrema)")
    if valley is None:
        return (f"no valley within the stroke (to d/L {d_end:.4g}: after its peak the force never rises by more "
                "than 2 % of its range and the model's force resolution)")
    return ""


def force_resolution(up):
    """How far from zero a force of the model traced along ``up`` (a loading path from d = 0) must be to count as
    positive or negative, F / (G L^2): the path's round-off (``model.Path.noise``) plus the force the model has at
    rest (``up.F[0]``, d = 0: the ring's bias moment, ``model.imperfection``, pushes the plate by a little; a real
    sleeve at rest carries nothing). Both scale with the model's forces: docs/sleeves.md, "Force resolution"."""
    return float(up.noise + abs(up.F[0]))


def ring_trace(cells, pattern, n_el=8, steps=160, plane="strain", d_max=None, unload=True,
               imperfection=1e-4, progress=None, curvature=True, pillar_tip="guided", root_extension=0.0):
    """Load (and unload) a sleeve. ``imperfection``: a tiny bias moment on the top plate, relative
    to the beams' axial stiffness times the radius, in a direction on no mirror axis of the ring
    (``model.BIAS_ANGLE``), that fixes the tilt direction like the seed's mesh imperfections. It
    is applied to mixed sleeves too: a pattern such as [0, 0, 1, 1] keeps one mirror axis, and
    which of two mirror-image pillars joins the first-snapping group would otherwise be decided
    by round-off, i.e. by the mesh."""
    m = SleeveModel(cells, pattern, n_el, plane, imperfection=imperfection,
                    curvature=curvature, pillar_tip=pillar_tip, root_extension=root_extension)
    used = [cells[t] for row in pattern for t in row]
    d_max = default_stroke(used) * len(pattern) if d_max is None else d_max
    d = np.linspace(0.0, d_max, steps + 1)
    up = m.trace(d, progress=progress)
    down = m.trace(d[::-1], q0=m.last_q, progress=progress) if unload else None
    return m, up, down


def ring_thresholds(up):
    """First peak P1 and second valley V2 (last valley when there is only one) of a loading curve; None for one
    the stroke does not reach (the end of the stroke is neither)."""
    p, v = extrema(up.F, floor=up.noise)
    P1 = float(up.F[p[0]]) if p else None
    V2 = float(up.F[v[1]]) if len(v) >= 2 else (float(up.F[v[0]]) if v else None)
    return P1, V2, len(p), len(v)


def design_axis(model):
    """Unit vector from the lowest cell type's cells to the highest type's (None for a uniform ring
    or a pattern without a direction)."""
    typs = [t for (_, _, t) in model.cell_index]
    lo_t, hi_t = min(typs), max(typs)
    axis = np.zeros(2)
    for (_, k, t) in model.cell_index:
        sgn = 1.0 if t == hi_t else (-1.0 if t == lo_t else 0.0)
        phi = 2 * math.pi * k / model.N
        axis += sgn * np.array([math.cos(phi), math.sin(phi)])
    if hi_t == lo_t or np.linalg.norm(axis) <= 1e-9:
        return None
    return axis / np.linalg.norm(axis)


def simulated_sequence(model, up, down):
    """Snapping order of the cell types along the traced loading and unloading paths, and tilts. ``symmetric`` is
    null, with a ``note`` saying why (``analysis.sequence_symmetry``), when nothing snapped or when a type could not
    be ordered on a path (no pillar of its own type, no snap of it on that path); ``note`` is "" otherwise."""
    types, geoms, units = model.state_types, model.state_geoms, model.state_units
    # a snap needs a force drop: on a path without one (a monostable sleeve) the cells pass their chord as springs
    drop_up, drop_dn = has_force_drop(up), has_force_drop(down)
    lo, ev_up = snap_order(up, types, geoms, units) if drop_up else ([], [])
    un, ev_dn = snap_order(down, types, geoms, units) if drop_dn else ([], [])
    # symmetric or not from complete orders only: nothing snapped, or a type not ordered on a path, is neither
    sym, note = sequence_symmetry(types, units, [("loading", lo, ev_up, drop_up, float(up.d[-1])),
                                                 ("unloading", un, ev_dn, drop_dn, float(down.d[-1]))])
    ti_up = up.tilt[np.argmax(np.linalg.norm(up.tilt, axis=1))]
    ti_dn = down.tilt[np.argmax(np.linalg.norm(down.tilt, axis=1))]
    lu, ld = lean_direction(ti_up), lean_direction(ti_dn)
    # the design's axis: from the lowest type's cells to the highest type's; a lean "reverses"
    # when its component along that axis changes sign (the component across it is set by the
    # imperfection: which of two mirror-image pillars joins the first-snapping group)
    axis = design_axis(model)
    if axis is not None:
        reverses = bool(np.dot(lu, axis) * np.dot(ld, axis) < 0)
    else:
        reverses = bool(np.dot(lu, ld) < 0)
    return {"loading": lo, "unloading": un, "symmetric": sym, "note": note,
            "max_tilt_loading_deg": float(math.degrees(np.linalg.norm(ti_up))),
            "max_tilt_unloading_deg": float(math.degrees(np.linalg.norm(ti_dn))),
            "lean_loading_deg": float(math.degrees(math.atan2(lu[1], lu[0]))) if np.any(lu) else None,
            "lean_unloading_deg": float(math.degrees(math.atan2(ld[1], ld[0]))) if np.any(ld) else None,
            "lean_reverses": reverses,
            "events_loading": [{"d": e[1], "cells": e[2], "snapped": e[3]} for e in ev_up],
            "events_unloading": [{"d": e[1], "cells": e[2], "snapped": e[3]} for e in ev_dn]}


def design_map(L, c, delta, T, t_range, h_range, ring=False, n_el=8, steps=120, plane="strain",
               n_cells=4, progress=None, layout="single", curvature=True, pillar_tip="guided", root_extension=0.0):
    """Peak/valley over a grid of t/L and h/L (seed figure 2C; with ``ring`` also P1/V2, fig. 2F)."""
    from metamaterial_wb.core.errors import SceneError
    ts = np.linspace(*t_range[:2], t_range[2])
    hs = np.linspace(*h_range[:2], h_range[2])
    out = {"t_over_L": ts.tolist(), "h_over_L": hs.tolist(), "peak": [], "valley": [], "notes": []}
    if ring:
        out.update({"P1": [], "V2": [], "peaks_count": []})
    k = 0
    for h in hs:
        rowp, rowv, rp1, rv2, rn = [], [], [], [], []
        for t in ts:
            try:       # a grid point the spec validator refuses (e.g. c >= L - 2t: no free beam) is not built
                g = CellGeometry.checked("design_map", L=L, t=t * L, h=h * L, c=c, delta=delta, T=T, layout=layout)
                if t * L < MIN_FEATURE_MM:
                    raise SceneError("design_map.t_over_L", f"t = {t * L:.4g} mm is below the printable "
                                                            f"{MIN_FEATURE_MM:g} mm (cell_types' t_mm)")
            except SceneError as exc:
                out["notes"].append(f"t/L {t:.4g}, h/L {h:.4g}: skipped, not a valid cell ({exc}); its entries "
                                    "are null")
                rowp.append(None); rowv.append(None)
                if ring:
                    rp1.append(None); rv2.append(None); rn.append(None)
                k += 1
                if progress:
                    progress(k, len(ts) * len(hs))
                continue
            res, _, _ = unit_cell_result(g, n_el, steps, plane, root_extension=root_extension)
            rowp.append(res["peak_force"]); rowv.append(res["valley_force"])
            if ring:
                _, up, _ = ring_trace([g], [[0] * n_cells], n_el, steps, plane, unload=False,
                                      curvature=curvature, pillar_tip=pillar_tip, root_extension=root_extension)
                P1, V2, n_p, _ = ring_thresholds(up)
                rp1.append(P1); rv2.append(V2); rn.append(n_p)
            k += 1
            if progress:
                progress(k, len(ts) * len(hs))
        out["peak"].append(rowp); out["valley"].append(rowv)
        if ring:
            out["P1"].append(rp1); out["V2"].append(rv2); out["peaks_count"].append(rn)
    return out


def analyse(spec, progress=None, log=None):
    """Run everything for a :class:`SleeveSpec`. Returns (summary dict, curves dict)."""
    t0 = time.perf_counter()
    say = log or (lambda s: None)
    L, G = spec.L, spec.G
    Fscale = G * L * L                  # N per normalised force unit (MPa * mm^2)
    curves = {"cells": [], "uniform": [], "ring": None}
    unit_cells = []
    dmax = None if spec.d_max_mm is None else spec.d_max_mm / L
    for i, g in enumerate(spec.cells):
        say(f"unit cell {i}: t = {g.t:g} mm, h = {g.h:g} mm")
        res, up, down = unit_cell_result(g, spec.n_el_cell, spec.steps, spec.plane, dmax, spec.root_extension)
        res["type"] = i
        res["peak_force_N"] = None if res["peak_force"] is None else res["peak_force"] * Fscale
        res["valley_force_N"] = None if res["valley_force"] is None else res["valley_force"] * Fscale
        unit_cells.append(res)
        curves["cells"].append((up, down))
    used = sorted({t for row in spec.pattern for t in row})
    n = spec.N
    thresholds = []
    uniform = []
    for i in used:
        say(f"uniform ring of type {i} ({n} cells)")
        _, up, _ = ring_trace([spec.cells[i]], [[0] * n], spec.n_el_ring, spec.steps, spec.plane,
                              dmax, unload=False, imperfection=spec.imperfection,
                              curvature=spec.ring_curvature, pillar_tip=spec.pillar_tip,
                              root_extension=spec.root_extension)
        P1, V2, n_p, n_v = ring_thresholds(up)
        pv = peaks_valleys(up.d, up.F, floor=up.noise)
        uniform.append({"type": i, "P1": P1, "V2": V2, "two_peaks": n_p >= 2 and n_v >= 2,
                        "peaks": [f for _, f in pv["peaks"]], "valleys": [f for _, f in pv["valleys"]],
                        "seconds": up.seconds})
        note = _extrema_note(None if P1 is None else 0, None if V2 is None else 0, up.d[-1])
        if note:
            uniform[-1]["note"] = note
        if spec.ring_curvature and spec.layout == "single":
            uniform[-1]["frame3d"] = curvature_check(spec.cells[i], n, spec.plane, spec.root_extension,
                                                     spec.pillar_tip, spec.n_el_ring)
        if spec.frame_nonlinear:
            say(f"uniform ring of type {i}: first peak of the nonlinear 3-D frame")
            uniform[-1]["frame3d_nl"] = first_peak(spec.cells[i], n, spec.root_extension, spec.frame_elements,
                                                   up.d, P1, spec.plane)
        thresholds.append((P1, V2))
        curves["uniform"].append((i, up))
    say(f"sleeve: {spec.M} ring(s) x {n} cells, pattern {spec.pattern}")
    model, up, down = ring_trace(spec.cells, spec.pattern, spec.n_el_ring, spec.steps, spec.plane,
                                 dmax * spec.M if dmax else None, imperfection=spec.imperfection,
                                 progress=progress, curvature=spec.ring_curvature, pillar_tip=spec.pillar_tip,
                                 root_extension=spec.root_extension)
    curves["ring"] = (model, up, down)
    pv = peaks_valleys(up.d, up.F, floor=up.noise)
    pvd = peaks_valleys(down.d[::-1], down.F[::-1], floor=down.noise)
    ring = {"cells": n, "rings": spec.M, "pattern": spec.pattern,
            "peaks": [f for _, f in pv["peaks"]], "valleys": [f for _, f in pv["valleys"]],
            "peak_displacements": [d for d, _ in pv["peaks"]],
            "valley_displacements": [d for d, _ in pv["valleys"]],
            "unloading_peaks": [f for _, f in pvd["peaks"]], "unloading_valleys": [f for _, f in pvd["valleys"]],
            "max_tilt_deg": float(math.degrees(np.max(np.linalg.norm(up.tilt, axis=1)))),
            "radius_mm": spec.radius_mm, "seconds_loading": up.seconds, "seconds_unloading": down.seconds,
            "degrees_of_freedom": int(model.nred)}
    missing = [i for k, i in enumerate(used) if None in thresholds[k]]
    if missing:                # the rule ranks P1 and V2: a uniform ring without them within the stroke has no rank
        rule = {"loading": None, "unloading": None, "symmetric": None, "combination": None,
                "note": f"no two-hysteron prediction: the uniform ring of type(s) {missing} has no first peak or "
                        "no valley within the stroke"}
    else:
        rule = two_hysteron_sequence([thresholds[used.index(i)] for i in used])
        rule["loading"] = [used[k] for k in rule["loading"]]
        rule["unloading"] = [used[k] for k in rule["unloading"]]
    rule["thresholds"] = {str(i): {"P1": thresholds[k][0], "V2": thresholds[k][1]} for k, i in enumerate(used)}
    sim = simulated_sequence(model, up, down)
    seq = {"loading": sim["loading"], "unloading": sim["unloading"], "symmetric": sim["symmetric"],
           "method": "direct simulation of the sleeve (snapping order of the cell types along the "
                     "displacement-controlled loading and unloading paths)",
           "lean_reverses": sim["lean_reverses"],
           "lean_loading_deg": sim["lean_loading_deg"], "lean_unloading_deg": sim["lean_unloading_deg"],
           "max_tilt_loading_deg": sim["max_tilt_loading_deg"],
           "max_tilt_unloading_deg": sim["max_tilt_unloading_deg"],
           "events_loading": sim["events_loading"], "events_unloading": sim["events_unloading"],
           "two_hysteron": rule,
           "agrees_with_two_hysteron": (None if rule["loading"] is None or sim["symmetric"] is None else
                                        bool(sim["loading"] == rule["loading"]
                                             and sim["unloading"] == rule["unloading"]))}
    if sim["note"]:                   # nothing snapped, or an incomplete order: neither symmetric nor asymmetric
        seq["note"] = sim["note"]
    frame_paths = None
    if spec.frame_nonlinear:
        say("sleeve: loading and unloading cycle on the nonlinear 3-D frame")
        seq["frame3d_nl"], fu, fd = frame_sequence(
            spec.cells, spec.pattern, float(up.d[-1]), spec.steps, spec.frame_elements, spec.root_extension,
            lambda path, k, dk: k % 20 or say(f"frame cycle: {path}, d/L {dk:.2f}"))
        frame_paths = (fu, fd) if fu is not None else None
        seq["frame3d_nl"]["agrees_with_model"] = (seq["frame3d_nl"].get("loading") == seq["loading"] and
                                                  seq["frame3d_nl"].get("unloading") == seq["unloading"])
    # PV curve
    A = math.pi * (spec.core_diameter / 2) ** 2
    Vl, pl = pv_curve(up.d * L, up.F * Fscale, A, spec.membrane)
    Vu, pu = pv_curve(down.d * L, down.F * Fscale, A, spec.membrane)
    Vpc, ppc, jl = pressure_control(Vl, pl, True)
    Vpu, ppu, ju = pressure_control(Vu, pu, False)
    kPa = Fscale / A * 1000.0          # kPa per normalised force unit
    ppv = peaks_valleys(Vl, pl, floor=up.noise * kPa)
    # below zero: below it by more than the force resolution (round-off at d = 0 is no valley)
    reset_tol = force_resolution(up) * kPa
    pvres = {"cap_diameter_mm": spec.core_diameter, "cap_area_mm2": A, "membrane_kPa_per_mL": spec.membrane,
             "peaks_kPa": [p for _, p in ppv["peaks"]], "valleys_kPa": [p for _, p in ppv["valleys"]],
             "peak_volumes_mL": [v for v, _ in ppv["peaks"]],
             "pressure_control_loading_jumps": [{"p_kPa": a, "V_from_mL": b, "V_to_mL": c} for a, b, c in jl],
             "pressure_control_unloading_jumps": [{"p_kPa": a, "V_from_mL": b, "V_to_mL": c} for a, b, c in ju],
             "needs_vacuum_to_reset": bool(np.min(pu) < -reset_tol),
             "notes": [spec.core_diameter_note] if spec.core_diameter_note else []}
    curves["pv"] = {"load": (Vl, pl), "unload": (Vu, pu), "pc_load": (Vpc, ppc), "pc_unload": (Vpu, ppu)}
    summary = {"format": "metamaterial-sleeve-summary", "version": 1, "name": spec.name,
               "normalisation": {"force": "F / (G L^2)", "displacement": "d / L", "G_MPa": G, "L_mm": L,
                                 "force_unit_N": Fscale},
               "cell": {"width_mm": spec.cells[0].width, "height_mm": max(g.height for g in spec.cells),
                        "c_mm": spec.c, "delta_mm": spec.delta, "T_mm": spec.T},
               "unit_cells": unit_cells, "uniform_rings": uniform, "ring": ring, "sequence": seq,
               "pv": pvres, "accuracy": accuracy(spec.cells, n, spec.root_extension, spec.ring_curvature, spec.plane,
                                                     spec.pillar_tip, spec.n_el_cell, spec.n_el_ring)}
    summary["accuracy"]["notes"] += [frame_note(u["type"], n, u["frame3d"]) for u in uniform if "frame3d" in u]
    summary["accuracy"]["notes"] += [frame_nl_note(u["type"], n, u["frame3d_nl"], Fscale, L)
                                     for u in uniform if "frame3d_nl" in u]
    order = solid_order_note(spec.cells, n, seq)
    if order:
        summary["accuracy"]["notes"].append(order)
    if spec.frame_nonlinear:
        summary["accuracy"]["notes"].append(frame_sequence_note(seq))
    if spec.walker:
        wk = spec.walker
        H = spec.M * max(g.height for g in spec.cells)
        cyc = walker_cycle(up.d * L, up.tilt, down.d * L, down.tilt, H, wk["foot_length_mm"],
                           wk["contact_band_mm"], design_axis(model))
        curves["walker"] = cyc
        summary["walker"] = {k: cyc[k] for k in ("area_mm2", "orientation", "lateral_stroke_mm", "lift_mm",
                                                   "step_per_cycle_mm", "direction")}
        summary["walker"].update({"legs": 4, "pairs_in_antiphase": [[1, 3], [2, 4]],
                                  "sleeve_height_mm": H, "foot_length_mm": wk["foot_length_mm"], "notes": []})
        if "body_length_mm" in wk:
            summary["walker"]["notes"].append(
                f"walker.body_length_mm ({wk['body_length_mm']:g} mm) is not used: the walker model (one leg's tip "
                "loop and the diagonal gait) does not depend on the body's length")
        if frame_paths:                        # the same leg on the frame's cycle (model.frame_nonlinear)
            fu, fd = frame_paths
            fc = walker_cycle(fu["d"] * L, fu["tilt"][:, :2], fd["d"] * L, fd["tilt"][:, :2], H,
                              wk["foot_length_mm"], wk["contact_band_mm"], design_axis(model))
            summary["walker"]["frame3d_nl"] = {k: fc[k] for k in ("area_mm2", "lateral_stroke_mm", "lift_mm",
                                                                  "step_per_cycle_mm")}
            summary["accuracy"]["notes"].append(frame_walker_note(fc, cyc))
    if spec.design_map:
        dm = spec.design_map
        say("design map")
        summary["design_map"] = design_map(L, spec.c, spec.delta, spec.T, dm["t_over_L"], dm["h_over_L"],
                                           dm["ring"], dm["elements"], max(60, spec.steps // 2), spec.plane,
                                           n, layout=spec.layout, curvature=spec.ring_curvature,
                                           pillar_tip=spec.pillar_tip, root_extension=spec.root_extension)
    summary["timings"] = {"total_s": time.perf_counter() - t0,
                          "unit_cell_s": [u["seconds"] for u in unit_cells],
                          "ring_s": up.seconds + down.seconds}
    return summary, curves
