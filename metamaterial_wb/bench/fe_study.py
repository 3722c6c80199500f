"""The FE rung's studies: the hinge's stiffness under mesh refinement and its large-rotation bending curves,
each against the lattice's hinge law (one and several corotational elements). Returns plain dicts (JSON-able)
and renders the Markdown section of docs/fidelity.md.
"""
import math
import time

import numpy as np

from metamaterial_wb.fe import hinge
from metamaterial_wb.core.extrapolation import P_RANGE, extrapolate
from metamaterial_wb.core.extrapolation import summary as order_summary

DOF_NAMES = ("axial u1", "in-plane shear u2", "out-of-plane shear u3", "torsion T1", "out-of-plane bending T2",
             "in-plane bending T3")
STIFFNESS_SIZES = (0.4, 0.283, 0.2)
BENDING_SIZES = (0.4, 0.283)
CI_SIZE = 0.8


def condensed_bending(K):
    """Pure in-plane bending stiffness M3 / T3 with the end's forces zero (Schur complement of K on T3)."""
    K = np.asarray(K, float)
    keep = [0, 1, 2, 3, 4]
    return float(K[5, 5] - K[5, keep] @ np.linalg.solve(K[np.ix_(keep, keep)], K[keep, 5]))


def run_hinge_study(spec=None, stiffness_sizes=STIFFNESS_SIZES, bending_sizes=BENDING_SIZES, angle_deg=45.0,
                    increments=6, timeout_s=1800.0, progress=None):
    spec = spec or hinge.HingeSpec()
    say = progress or (lambda m: None)
    out = {"spec": spec.__dict__.copy(), "description": spec.describe(), "beam_K": spec.beam_K().tolist(),
           "stiffness": [], "bending": []}
    for h in stiffness_sizes:
        K, info = hinge.stiffness(spec, h, timeout_s)
        out["stiffness"].append({"h_mm": h, "K": K.tolist(), "wall_s": info["wall_s"], "dofs": info["dofs"],
                                 "elements": info["elements"], "bending_condensed": condensed_bending(K),
                                 "h_eff_mm": info["h_eff_mm"], "element_mm": info["element_mm"]})
        say(f"FE hinge stiffness, h = {h:g} mm: {info['dofs']} DOFs, {info['wall_s']:.1f} s")
    if len(out["stiffness"]) >= 2:
        out["stiffness_extrapolated"] = stiffness_extrapolation(out["stiffness"])
    for held in (False, True):
        for h in bending_sizes:
            c, info = hinge.bending_curve(spec, h, angle_deg, increments, held=held, timeout_s=timeout_s)
            row = {"h_mm": h, "held": held, "wall_s": info["wall_s"], "dofs": info["dofs"],
                   "h_eff_mm": info["h_eff_mm"], "element_mm": info["element_mm"],
                   "angle_rad": c["angle_rad"].tolist(), "moment_Nmm": c["moment_Nmm"].tolist(),
                   "end_u_mm": c["end_u_mm"].tolist(), "end_force_N": c["end_force_N"].tolist()}
            out["bending"].append(row)
            say(f"FE hinge bending ({'held' if held else 'free'} end), h = {h:g} mm: {info['dofs']} DOFs, "
                f"{info['wall_s']:.1f} s")
    # the lattice's hinge law on the same loadings (1 and 8 elements), timed
    ang = np.radians(np.linspace(angle_deg / increments, angle_deg, increments))
    out["lattice"] = []
    for held in (False, True):
        for n in (1, 2, 4, 8):
            t0 = time.perf_counter()
            lb = hinge.lattice_bending(spec, ang, held=held, hinge_elements=n)
            out["lattice"].append({"held": held, "n": n, "wall_s": time.perf_counter() - t0,
                                   "angle_rad": ang.tolist(), "moment_Nmm": lb["moment_Nmm"].tolist(),
                                   "end_u_mm": lb["end_u_mm"].tolist(), "end_force_N": lb["end_force_N"].tolist()})
    return out


def mesh_size(row):
    """The element size a mesh row of a study records for extrapolation: ``h_eff_mm``, the representative size of
    its bricks (``hinge.element_sizes``, ``patch.patch_deck``), or its nominal ``h_mm`` when it records no other
    (then :func:`nominal_sizes` says so in the report)."""
    return float(row.get("h_eff_mm", row["h_mm"]))


def nominal_sizes(rows):
    """The words a table adds when some of its meshes record only their nominal size (``""`` when all record their
    own)."""
    n = sum("h_eff_mm" not in r for r in rows)
    return (f" {n} of these meshes record only the nominal h, extrapolated with it (their bricks' own sizes were not "
            "recorded)." if n else "")


def bricks(row):
    """``"0.25 x 0.267 x 0.538"``: a mesh row's brick edges (along, across, through) in mm, or ``""``."""
    e = row.get("element_mm")
    return " x ".join(f"{x:.3g}" for x in e) if e else ""


def _json_num(x):
    return float(x) if np.isfinite(x) else None


def stiffness_extrapolation(rows):
    """The hinge stiffness study's extrapolation (``"stiffness_extrapolated"``): the six diagonal terms and the
    pure bending stiffness of the mesh rows ``rows`` (coarse to fine) extrapolated over the meshes' own sizes
    (:func:`mesh_size`; ``richardson.extrapolate``), with every order used, observed (None where none was) and
    whether it was clipped to ``P_RANGE`` or assumed."""
    vals = [np.concatenate([np.diag(r["K"]), [r["bending_condensed"]]]) for r in rows]
    res = extrapolate([mesh_size(r) for r in rows], vals)
    return {"diag": res["value"][:6].tolist(), "diag_err": res["error"][:6].tolist(),
            "order": res["order"][:6].tolist(), "order_observed": [_json_num(x) for x in res["order_observed"][:6]],
            "order_clipped": res["clipped"][:6].tolist(), "order_assumed": res["assumed"][:6].tolist(),
            "bending_condensed": float(res["value"][6]), "bending_condensed_err": float(res["error"][6]),
            "bending_condensed_order": float(res["order"][6]),
            "bending_condensed_clipped": bool(res["clipped"][6]), "bending_condensed_assumed": bool(res["assumed"][6]),
            "h_eff_mm": [mesh_size(r) for r in rows], "summary": order_summary(res)}


def _order_text(order, clipped, assumed, observed=None):
    """``"order 2.7"``, ``"order 4, clipped from 5.3"``, ``"order 2 assumed"``."""
    if assumed:
        return f"order {order:.2g} assumed"
    if clipped:
        return f"order {order:.2g}, clipped" + (f" from {observed:.2g}" if observed is not None else "")
    return f"order {order:.2g}"


def _f(x):
    return f"{x:.3g}" if abs(x) >= 1e-3 else f"{x:.1e}"


def _ff(x):
    """Forces: rounding noise (an end left free carries none) printed as 0."""
    return "0" if abs(x) < 1e-6 else _f(x)


def bending_orders(study=None):
    """``{False: p_free, True: p_held}``: the order the bending curves' two-mesh error assumes for each end
    condition, the cautious (lowest) of 2 and the hinge stiffness study's observed orders (``study``; 2 without one)
    of the stiffness terms the loading engages: pure in-plane bending for the free end; axial, in-plane shear and
    in-plane bending for the held end, whose chord is held."""
    ext = (study or {}).get("stiffness_extrapolated") or {}
    if "bending_condensed_order" not in ext:
        return {False: 2.0, True: 2.0}
    return {False: min(2.0, ext["bending_condensed_order"]), True: min([2.0] + [ext["order"][k] for k in (0, 1, 5)])}


def bending_uncertainty(rows, study=None):
    """The FE bending curves' own error (issue 18: every reference figure with its error): from the two finest
    meshes of each end condition, Richardson with the cautious order :func:`bending_orders` (``study``: the hinge
    study whose observed orders it takes): the finest mesh's moment at 45 degrees is uncertain by
    ``|M2 - M1| / (r^p - 1)``, ``r`` the ratio of the two meshes' own sizes (:func:`mesh_size`)."""
    parts, ratios = [], []
    orders = bending_orders(study)
    for held in (False, True):
        rs = sorted((r for r in rows if r["held"] == held), key=lambda r: -r["h_mm"])
        if len(rs) < 2:
            continue
        a, b = rs[-2], rs[-1]
        ratio = mesh_size(a) / mesh_size(b)
        ratios.append(ratio)
        div = ratio ** orders[held] - 1.0
        i = int(np.argmin(np.abs(np.asarray(b["angle_rad"]) - math.radians(45.0))))
        j = int(np.argmin(np.abs(np.asarray(a["angle_rad"]) - math.radians(45.0))))
        dm = abs(b["moment_Nmm"][i] - a["moment_Nmm"][j]) / div
        df = np.abs(np.asarray(b["end_force_N"][i]) - np.asarray(a["end_force_N"][j])).max() / div
        parts.append(f"{'held' if held else 'free'} end (order {orders[held]:.2g}): M at 45 deg "
                     f"{_f(b['moment_Nmm'][i])} +- {_f(dm)} N mm ({100 * dm / abs(b['moment_Nmm'][i]):.1f} %), end "
                     f"force +- {_f(df)} N")
    if not parts:
        return ""
    ext = (study or {}).get("stiffness_extrapolated") or {}
    why = "order 2"
    if "bending_condensed_order" in ext:
        o = ext["order"]
        why = (f"the cautious order: the lowest of 2 and the stiffness study's observed orders of the terms the "
               f"loading engages, pure bending {ext['bending_condensed_order']:.2g} for the free end, axial "
               f"{o[0]:.2g}, in-plane shear {o[1]:.2g} and in-plane bending {o[5]:.2g} for the held one")
    return (f"Error of the FE curves themselves (finest mesh, Richardson from the two meshes, their own size ratio "
            f"{', '.join(sorted({f'{r:.3g}' for r in ratios}))}, with {why}): "
            + "; ".join(parts) + ". Every lattice-against-FE difference in this table is uncertain by that much."
            + nominal_sizes(rows) + "\n")


def markdown(study):
    """The FE section of docs/fidelity.md: every study ``study`` holds, each rendered when there (the hinge's,
    :func:`run_hinge_study`; ``"aspect"``, :func:`run_aspect_study`; ``"patch"``, :func:`run_patch_study`;
    ``"sleeve"``, ``fe_sleeve.run_sleeve_study``), so that a run of some of them (``--fe-parts``) shows them all;
    with none, the heading alone."""
    study = study or {}
    L = _hinge_markdown(study) if "stiffness" in study or study.get("bending") else ["## FE top rung: CalculiX\n"]
    if study.get("aspect"):
        L.append(aspect_markdown(study["aspect"]))
    if study.get("patch"):
        L.append(patch_markdown(study["patch"]))
    if study.get("sleeve"):
        from metamaterial_wb.bench.fe_sleeve_calibration import fidelity_markdown
        L.append(fidelity_markdown(study["sleeve"], study.get("sleeve_calibration"), study.get("sleeve_curved")))
    return "\n".join(L) + "\n"


def _hinge_markdown(study):
    """The hinge study's part of :func:`markdown` (lines)."""
    L = []
    L.append("## FE top rung: one hinge in CalculiX\n")
    L.append(f"Hinge: {study['description']}; plate blocks {study['spec']['plate_len']:g} mm long, "
             f"{study['spec']['plate_margin']:g} mm wider than the hinge on each side; plate A's far face clamped, "
             "plate B's far face a rigid body whose reference node is the hinge end (where the lattice measures "
             "its hinge strains). 20-node bricks (C3D20R) on a graded structured grid, `h` the nominal element size "
             "in the hinge (the grid rounds each count up: the bricks' own edges along x across x through the hinge, "
             "in mm, are given with it, and the mesh studies extrapolate over their representative size "
             "(edge product)^(1/3), generalised Richardson for unequal size ratios, orders outside "
             f"[{P_RANGE[0]:g}, {P_RANGE[1]:g}] clipped and said so); linear steps for the stiffness, `NLGEOM` with "
             "Neo-Hooke TPU for the bending curves. Run "
             "`python3 -m metamaterial_wb bench fidelity --fe` (code: `metamaterial_wb/fe/`).\n")
    st = study.get("stiffness") or []
    beam = np.asarray(study["beam_K"])
    if st:
        L.append("### Hinge stiffness (the lattice's hinge law) against beam theory\n")
        head = "| DOF | beam theory (lattice) | " + " | ".join(
            f"FE h = {r['h_mm']:g} mm" + (f" ({bricks(r)})" if bricks(r) else "") for r in st)
        ext = study.get("stiffness_extrapolated")
        head += " | FE extrapolated (Richardson) | FE / beam |" if ext else " | FE / beam |"
        L.append(head)
        L.append("|" + "---|" * (head.count("|") - 1))
        units = ["N/mm"] * 3 + ["N mm/rad"] * 3
        for k in range(6):
            vals = [np.asarray(r["K"])[k, k] for r in st]
            best = ext["diag"][k] if ext else vals[-1]
            row = f"| {DOF_NAMES[k]} ({units[k]}) | {_f(beam[k, k])} | " + " | ".join(_f(v) for v in vals)
            if ext:
                obs = (ext.get("order_observed") or [None] * 6)[k]
                how = _order_text(ext["order"][k], (ext.get("order_clipped") or [False] * 6)[k],
                                  (ext.get("order_assumed") or [False] * 6)[k], obs)
                row += f" | {_f(ext['diag'][k])} +- {_f(ext['diag_err'][k])} ({how})"
            row += (f" | {best / beam[k, k]:.2f} +- {ext['diag_err'][k] / beam[k, k]:.2g} |" if ext
                    else f" | {best / beam[k, k]:.2f} |")
            L.append(row)
        bb = condensed_bending(beam)
        vals = [r["bending_condensed"] for r in st]
        best = ext["bending_condensed"] if ext else vals[-1]
        row = f"| pure in-plane bending M3/T3, end free (N mm/rad) | {_f(bb)} | " + " | ".join(_f(v) for v in vals)
        if ext:
            how = ""
            if "bending_condensed_order" in ext:
                how = " (" + _order_text(ext["bending_condensed_order"], ext.get("bending_condensed_clipped"),
                                         ext.get("bending_condensed_assumed")) + ")"
            row += f" | {_f(ext['bending_condensed'])} +- {_f(ext['bending_condensed_err'])}{how} |"
            L.append(row + f" {best / bb:.2f} +- {ext['bending_condensed_err'] / bb:.2g} |")
        else:
            L.append(row + f" {best / bb:.2f} |")
        L.append("")
        if ext:
            hs = [mesh_size(r) for r in st]
            L.append("Extrapolated over the meshes' representative sizes " + ", ".join(f"{h:.3g}" for h in hs)
                     + " mm (size ratios " + ", ".join(f"{a / b:.3g}" for a, b in zip(hs, hs[1:])) + "): "
                     + (ext.get("summary") or "every order observed inside "
                        f"[{P_RANGE[0]:g}, {P_RANGE[1]:g}]") + "." + nominal_sizes(st) + "\n")
        L.append("Run time per mesh (six linear load cases in one ccx run): " + ", ".join(
            f"h = {r['h_mm']:g} mm: {r['dofs']} DOFs, {r['wall_s']:.1f} s" for r in st) + ".\n")
    if study.get("bending"):
        L.append("### Large rotation: moment and end force against the lattice's hinge law\n")
        L.append("The end turned about the sheet normal to 45 degrees; *free*: its translations free (pure "
                 "bending); *held*: held at the rest position (the hardest case for a hinge inside the sheet, "
                 "where neighbouring plates keep the chord). Forces and displacements of the end in the sheet's "
                 "axes (x along the unloaded hinge). Lattice: `core.lattice.refine.hinge_end_response` with n "
                 "corotational Timoshenko elements (linear elastic TPU; the FE uses Neo-Hooke with the same small-"
                 "strain moduli).\n")
        L.append("| end | model | M at 15 deg (N mm) | M at 45 deg (N mm) | end force (x, y) at 45 deg (N) | "
                 "end displacement (x, y) at 45 deg (mm) | run time (s) |")
        L.append("|---|---|---|---|---|---|---|")

        def pick(a, deg):
            a = np.asarray(a["angle_rad"])
            return int(np.argmin(np.abs(a - math.radians(deg))))

        for held in (False, True):
            sources = [(r, f"FE h = {r['h_mm']:g} mm" + (f" ({bricks(r)})" if bricks(r) else ""), f"{r['wall_s']:.0f}")
                       for r in study["bending"] if r["held"] == held]
            sources += [(r, f"lattice, n = {r['n']}", f"{r['wall_s']:.3f}")
                        for r in study["lattice"] if r["held"] == held]
            for r, label, wall in sources:
                i15, i45 = pick(r, 15), pick(r, 45)
                u = np.asarray(r["end_u_mm"])[i45]
                F = r["end_force_N"][i45]
                L.append(f"| {'held' if held else 'free'} | {label} | {_f(r['moment_Nmm'][i15])} | "
                         f"{_f(r['moment_Nmm'][i45])} | ({_ff(F[0])}, {_ff(F[1])}) | "
                         f"({_f(u[0])}, {_f(u[1])}) | {wall} |")
        L.append("")
        L.append(bending_uncertainty(study["bending"], study))
    return L


PATCH_MESHES = ((0.5, 2), (0.35, 3), (0.25, 4))      # (element size in the hinge, elements through t)
PATCH_AMPLITUDES = (0.05, 0.5)
PATCH_MODELS = (("quadratic", "quadratic (R0)", {}),
                ("linear", "linear lattice (R1), no contact", {"contact": False}),
                ("nonlinear", "nonlinear (R2), 1 element/hinge, no contact", {"contact": False}),
                ("nonlinear", "nonlinear (R2), 2 elements/hinge, no contact", {"contact": False, "hinge_elements": 2}),
                ("nonlinear", "nonlinear (R2), 4 elements/hinge, no contact", {"contact": False, "hinge_elements": 4}),
                ("nonlinear", "nonlinear (R2), 8 elements/hinge, no contact", {"contact": False, "hinge_elements": 8}),
                ("nonlinear", "nonlinear (R2), default (1 element, plate contact)", {}))


def run_patch_study(amplitudes=PATCH_AMPLITUDES, meshes=PATCH_MESHES, timeout_s=3600.0, progress=None,
                    on_row=None):
    """The 3 x 3 patch with two actuated joints in CalculiX at every mesh, extrapolated in the mesh
    (:func:`patch_reference`: Richardson on the plate rotations and positions over the meshes' own sizes), and
    every model's error against it. ``meshes``: one tuple of (h, nz) for all amplitudes, or a dict amplitude ->
    tuple. ``on_row(rows)`` after each amplitude. Every FE row keeps its plate rotations and positions, so the
    reference can be recomputed from the stored study."""
    from metamaterial_wb.core.models import run_model
    from metamaterial_wb.fe import patch

    say = progress or (lambda m: None)
    out = []
    for amp in amplitudes:
        scene = patch.patch_scene(amp)
        fes = []
        for h, nz in (meshes.get(amp, PATCH_MESHES) if isinstance(meshes, dict) else meshes):
            r = patch.solve_patch(scene, h, nz, increments=4 if amp <= 0.1 else 10, timeout_s=timeout_s)
            fes.append(r)
            say(f"FE patch, amplitude {amp}, h = {h:g} mm: {r.info['dofs']} DOFs, {r.info['wall_s']:.1f} s")
        row, ref = patch_fe_row(amp, scene, fes)
        for name, label, opts in PATCH_MODELS:
            best, res = None, None
            for _ in range(3):
                t0 = time.perf_counter()
                res = run_model(name, scene, **opts)
                dt = time.perf_counter() - t0
                best = dt if best is None else min(best, dt)
            row["models"].append({"label": label, "time_s": best, "converged": bool(res.converged),
                                  **patch_errors(scene, res, ref)})
        out.append(row)
        if on_row:
            on_row(out)
    return out


def patch_errors(scene, result, ref):
    """``{"rms_D", "max_D", "max_pos"}`` of a model's or an FE run's ``result`` against the FE reference ``ref``."""
    from metamaterial_wb.bench.measures import compare
    e = compare(scene, result, ref)
    return {k: float(e[k]) for k in ("rms_D", "max_D", "max_pos")}


def patch_reference(fes):
    """``(reference, orders)``: the FE patch runs ``fes`` (``patch.FEPatchResult``, coarse to fine) extrapolated in
    the mesh over their own sizes (``info["h_eff_mm"]``, :func:`mesh_size`; ``richardson.extrapolate``) as an
    ``ExtrapolatedReference`` (the rotations aligned on the finest run's mean first), and how the plate rotations'
    orders came about: ``{"h_eff_mm", "order_median"`` (over the rotations that change with the mesh),
    ``"orders_clipped", "orders_assumed", "rotations", "summary"}``."""
    from metamaterial_wb.bench.reference import ExtrapolatedReference
    hs = [mesh_size(f.info) for f in fes]
    phi0 = fes[-1].phi
    phis = [f.phi - np.mean(f.phi - phi0) for f in fes]
    rp = extrapolate(hs, phis)
    rx = extrapolate(hs, [f.positions_mm for f in fes])
    moving = np.ptp(np.array(phis), axis=0) > 0
    orders = {"h_eff_mm": hs, "order_median": float(np.median(rp["order"][moving])) if moving.any() else None,
              "orders_clipped": int(rp["clipped"].sum()), "orders_assumed": int(rp["assumed"].sum()),
              "rotations": int(moving.sum()), "summary": order_summary(rp)}
    return ExtrapolatedReference(rp["value"], rx["value"]), orders


def patch_fe_row(amp, scene, fes):
    """``(row, reference)``: a patch study row (``"models"`` empty) of the FE runs ``fes`` at amplitude ``amp``:
    every run (sizes, rotations, positions) with its error against :func:`patch_reference`, whose own
    uncertainty (the finest run's error) and orders are ``row["fe_uncertainty"]``."""
    ref, orders = patch_reference(fes)
    row = {"amplitude": amp, "fe": [], "models": [],
           "fe_uncertainty": {**patch_errors(scene, fes[-1], ref), **orders}}
    for f in fes:
        row["fe"].append({"h_mm": f.info["h_mm"], "nz": f.info["nz"], "dofs": f.info["dofs"],
                          "wall_s": f.info["wall_s"], "increments": f.info["increments"],
                          **{k: f.info[k] for k in ("h_eff_mm", "element_mm") if k in f.info},
                          "phi": f.phi.tolist(), "positions_mm": f.positions_mm.tolist(),
                          **patch_errors(scene, f, ref)})
    return row, ref


def patch_markdown(rows):
    L = ["### 3 x 3 patch, two actuated joints: every model against CalculiX\n",
         "Rigid plates joined by solid TPU hinges (C3D20R, Neo-Hooke, `NLGEOM`; `metamaterial_wb/fe/patch.py`), "
         "the actuators' relative plate rotations prescribed to the lattice's own targets, the centre plate held; "
         "no plate contact in the FE, so the lattice models run with `contact=False` (the default nonlinear model "
         "with contact is listed last). The FE reference is extrapolated in the mesh (Richardson over the meshes' "
         "own sizes: `h` is the nominal element size, the hinges' bricks measure the given edges along x across x "
         "through, and their representative size (edge product)^(1/3) is what the extrapolation uses); its "
         "uncertainty is the correction to the finest mesh, and every error below carries it.\n"]
    for r in rows:
        u = r["fe_uncertainty"]
        how = ""
        if "h_eff_mm" in u:
            hs = u["h_eff_mm"]
            how = (" (Richardson over the representative sizes " + ", ".join(f"{h:.3g}" for h in hs) + " mm, ratios "
                   + ", ".join(f"{a / b:.3g}" for a, b in zip(hs, hs[1:]))
                   + (f"; the plate rotations' orders: median {u['order_median']:.2g}" if u.get("order_median")
                      and len(hs) >= 3 else "") + (f"; {u['summary']}" if u.get("summary") else "") + ")")
        L.append(f"Amplitude {r['amplitude']}: FE uncertainty RMS dD {_f(u['rms_D'])}, max dD {_f(u['max_D'])}, "
                 f"max position {_f(u['max_pos'])} cells{how}.{nominal_sizes(r['fe'])}\n")
        L.append("| model | time (ms) | RMS dD vs FE | max dD | RMS dD / amplitude | max pos. err / cell |")
        L.append("|---|---|---|---|---|---|")
        for f in r["fe"]:
            size = f" ({bricks(f)})" if bricks(f) else ""
            L.append(f"| CalculiX, h = {f['h_mm']:g} mm{size}, {f['nz']} through t ({f['dofs']} DOFs) | "
                     f"{1e3 * f['wall_s']:.0f} | {_f(f['rms_D'])} | {_f(f['max_D'])} | "
                     f"{_f(f['rms_D'] / r['amplitude'])} | {_f(f['max_pos'])} |")
        for m in r["models"]:
            L.append(f"| {m['label']} | {1e3 * m['time_s']:.2f} | {_f(m['rms_D'])} +- {_f(u['rms_D'])} | "
                     f"{_f(m['max_D'])} | {_f(m['rms_D'] / r['amplitude'])} | {_f(m['max_pos'])} +- {_f(u['max_pos'])} |")
        L.append("")
        dflt = next((m for m in r["models"] if m["label"].startswith("nonlinear (R2), default")), None)
        nl8 = next((m for m in r["models"] if "8 elements" in m["label"]), None)
        if dflt and nl8 and dflt["rms_D"] > 10 * max(nl8["rms_D"], 1e-12):
            L.append(f"At amplitude {r['amplitude']} plates of this patch touch: the default nonlinear model (with "
                     f"plate contact) is {_f(dflt['rms_D'])} RMS dD from the contact-free FE, so here the FE checks "
                     "the hinge mechanics (contact-free models against contact-free FE), not the sheet.\n")
    return "\n".join(L) + "\n"


ASPECT_LENGTHS = (1.0, 2.0, 4.0, 6.0)
ASPECT_SIZE = 0.283
ASPECT_SIZES = (0.4, 0.283, 0.2)


def aspect_mesh_row(spec, h, timeout_s=1800.0):
    """One FE stiffness run of the aspect study: the diagonal and the condensed bending stiffness at mesh ``h``."""
    K, info = hinge.stiffness(spec, h, timeout_s)
    return {"h_mm": h, "wall_s": info["wall_s"], "dofs": info["dofs"], "fe_diag": np.diag(K).tolist(),
            "fe_bending": condensed_bending(K), "h_eff_mm": info["h_eff_mm"], "element_mm": info["element_mm"]}


def run_aspect_study(lengths=ASPECT_LENGTHS, sizes=ASPECT_SIZES, timeout_s=1800.0, progress=None):
    """FE stiffness against beam theory for hinges of several lengths (width 0.8, thickness 7 mm): where the
    lattice's beam law can be trusted in hinge aspect ratio (length / in-plane width). Every length runs on
    each mesh of ``sizes`` (coarse to fine) so that each ratio carries the FE's own mesh error
    (:func:`aspect_uncertainty`); the finest mesh's figures are also the row's top-level ones."""
    say = progress or (lambda m: None)
    rows = []
    for L in lengths:
        spec = hinge.HingeSpec(length=L)
        beam = spec.beam_K()
        meshes = []
        for h in sizes:
            meshes.append(aspect_mesh_row(spec, h, timeout_s))
            say(f"FE hinge stiffness, L = {L:g} mm (aspect {L / spec.w:.2g}), h = {h:g} mm: "
                f"{meshes[-1]['wall_s']:.1f} s")
        fine = meshes[-1]
        rows.append({"length_mm": L, "aspect": L / spec.w, "h_mm": fine["h_mm"], "wall_s": fine["wall_s"],
                     "fe_diag": fine["fe_diag"], "beam_diag": np.diag(beam).tolist(),
                     "fe_bending": fine["fe_bending"], "beam_bending": condensed_bending(beam), "meshes": meshes})
    return rows


def aspect_uncertainty(row, full=False):
    """``(ratios, errors)`` of one aspect-study row: FE / beam stiffness (six diagonal terms and the pure
    bending stiffness) on the finest mesh, and each ratio's mesh error, the correction Richardson
    extrapolation (``richardson.extrapolate`` over the meshes' own sizes, :func:`mesh_size`: observed order from
    three meshes, order 2 from two) makes to the finest mesh. Errors are NaN when the row holds one mesh only.
    ``full=True``: the extrapolation's whole result (orders, clipped, assumed) too, or None for one mesh."""
    beam = np.concatenate([np.asarray(row["beam_diag"], float), [float(row["beam_bending"])]])
    meshes = sorted(row.get("meshes") or [{"h_mm": row["h_mm"], "fe_diag": row["fe_diag"],
                                           "fe_bending": row["fe_bending"]}], key=lambda m: -m["h_mm"])
    vals = [np.concatenate([np.asarray(m["fe_diag"], float), [float(m["fe_bending"])]]) / beam for m in meshes]
    if len(vals) < 2:
        out = vals[-1], np.full_like(vals[-1], np.nan)
        return out + (None,) if full else out
    res = extrapolate([mesh_size(m) for m in meshes], vals)
    return (vals[-1], res["error"], res) if full else (vals[-1], res["error"])


def aspect_markdown(rows):
    sizes = sorted({m["h_mm"] for r in rows for m in (r.get("meshes") or [])}, reverse=True)
    with_err = all(len(r.get("meshes") or []) >= 2 for r in rows)
    if with_err:
        how = ("the observed order from the three finest meshes" if min(len(r["meshes"]) for r in rows) >= 3 else
               "order 2 from two meshes")
        mesh_txt = (f"meshes h = {', '.join(f'{h:g}' for h in sizes)} mm (nominal; each length's bricks differ, the "
                    "extrapolation uses every mesh's own representative size, as the stiffness study above); each "
                    f"ratio is the finest mesh's, +- its mesh error (the correction Richardson extrapolation makes to "
                    f"the finest mesh: {how}; for the default 2 mm hinge it matches the stiffness study above), "
                    "regenerated by `benchmarks/bench_fidelity_aspect_error.py` (FE run times per mesh, coarse to "
                    "fine)")
    else:
        mesh_txt = (f"mesh h = {rows[0]['h_mm']:g} mm (one mesh: no error of its own; the mesh study above gives "
                    "the error for the default hinge)")
    L = ["### Beam law against FE by hinge aspect ratio\n",
         f"FE stiffness / beam-theory stiffness (the lattice's hinge law) for hinges 0.8 mm wide and 7 mm thick "
         f"of several lengths, {mesh_txt}.\n",
         "| length (mm) | length / width | " + " | ".join(DOF_NAMES) + " | pure bending | FE run time (s) |",
         "|---|---|" + "---|" * (len(DOF_NAMES) + 2)]
    notes = []
    for r in rows:
        ratios, err, res = aspect_uncertainty(r, full=True)
        cells = [f"{x:.2f}" + (f" +- {_f(e)}" if np.isfinite(e) else "") for x, e in zip(ratios, err)]
        wall = " + ".join(f"{m['wall_s']:.0f}" for m in sorted(r.get("meshes") or [r], key=lambda m: -m["h_mm"]))
        L.append(f"| {r['length_mm']:g} | {r['aspect']:.2g} | " + " | ".join(cells) + f" | {wall} |")
        if res is not None:
            hs = sorted((mesh_size(m) for m in r["meshes"]), reverse=True)
            flags = order_summary(res)
            notes.append(f"{r['length_mm']:g} mm: sizes {', '.join(f'{h:.3g}' for h in hs)} mm, orders "
                         + ", ".join(_order_text(p, c, a)[6:] for p, c, a in zip(res["order"], res["clipped"],
                                                                                 res["assumed"]))
                         + (f" ({flags})" if flags else "") + nominal_sizes(r["meshes"]))
    L.append("")
    if notes:
        L.append("Representative element sizes (coarse to fine) and the orders used, in the table's column order: "
                 + "; ".join(notes) + ".\n")
    law = [(r, m) for r in rows for m in (r.get("meshes") or []) if abs(m["h_mm"] - ASPECT_SIZE) < 1e-9]
    if with_err and len(law) == len(rows) and min(m["h_mm"] for r in rows for m in r["meshes"]) < ASPECT_SIZE:
        fin = {id(r): min(r["meshes"], key=lambda x: x["h_mm"]) for r in rows}
        dev = max(float(np.max(np.abs(np.asarray(m["fe_diag"]) / np.asarray(fin[id(r)]["fe_diag"]) - 1.0)))
                  for r, m in law)
        L.append(f"The lattice's `hinge_law=\"fe\"` factors (`core/data/fe_hinge_law.json`) were taken on the "
                 f"h = {ASPECT_SIZE:g} mm mesh: they differ from the finest mesh's by at most {100 * dev:.1f} % "
                 "(all DOFs, all lengths).\n")
    return "\n".join(L) + "\n"


def ci_case(spec=None, timeout_s=120.0):
    """The smallest FE case (CI): stiffness and a short pure-bending run on the coarsest mesh."""
    spec = spec or hinge.HingeSpec()
    K, kinfo = hinge.stiffness(spec, CI_SIZE, timeout_s)
    c, binfo = hinge.bending_curve(spec, CI_SIZE, 20.0, 2, held=False, timeout_s=timeout_s)
    return K, kinfo, c, binfo


def write_fidelity_section(full, doc):
    """``doc`` (docs/fidelity.md) with its FE section (from "## FE top rung" to the FE note or the next top-level
    heading) regenerated from the FE study ``full`` (:func:`markdown`)."""
    from metamaterial_wb.core.fileio import write_atomic
    with open(doc) as f:
        text = f.read()
    i = text.index("## FE top rung")
    j = text.find("FE figures read from", i)
    if j < 0:
        j = text.find("\n## ", i + 3) + 1
    write_atomic(doc, text[:i] + markdown(full) + "\n" + text[j:])


__all__ = ["run_hinge_study", "run_aspect_study", "aspect_uncertainty", "run_patch_study", "markdown", "ci_case",
           "condensed_bending", "write_fidelity_section", "stiffness_extrapolation", "patch_reference", "patch_fe_row",
           "patch_errors", "mesh_size"]

