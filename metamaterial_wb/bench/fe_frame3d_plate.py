"""The nonlinear 3-D frame with the curved solid's top plate (issue 18): the ring's tilt, its stability, and why
the eight-cell solid stalls.

The curved CalculiX solid's plate (``fe/sleeve3d.py``) rises as prescribed, tilts and twists freely and carries a
small bias moment. ``frame3d_nl.trace_ring(..., plate="free")`` gives the frame the same plate
(``frame3d_nl.RigidPlate``); with ``modes`` it also follows the lowest eigenvalues of the reduced Hessian along
the path, the plate's tilt pair among them (the two modes the plate takes most part in). This module runs the
four- and eight-cell rings that way (``plate_study``) and sets them beside the solid's stored runs and stability
probes (``benchmarks/results/fe-ring3d-comparison.json``): where the tilt pair reaches zero, how far the plate
leans under the default and a hundred-fold bias, and the force on the way.
"""
import time

import numpy as np

from metamaterial_wb.bench.fe_ring3d_combinations import SEED_COMBINATIONS, combination_cells, order_text, seed_order

IMG = "img/sleeve-frame3d-plate.png"
# key: (cells, d_max, bias, modes followed, the rise over which the bias is ramped: the solid run's step end)
RUNS = {"4": (4, 0.40, 0.0, 4, None), "8": (8, 0.14, 0.0, 4, None), "4_bias1e-05": (4, 0.40, 1e-5, 0, 0.7),
        "8_bias1e-05": (8, 0.40, 1e-5, 0, 0.17), "8_bias0.001": (8, 0.40, 1e-3, 0, 0.30)}


def plate_study(n_el=12, e=0.63, step=0.005, runs=RUNS):
    """Every run of ``runs`` on the frame with the free plate (plane stress, root extension ``e``, ``n_el``
    elements per beam half): ``{key: {"cells", "bias", "d", "F", "tilt_deg", "twist_deg", "seconds"[, "tilt_pair"]}}``,
    the tilt pair as the two lowest eigenvalues of the modes the plate takes most part in."""
    from metamaterial_wb.core.sleeve.cell import CellGeometry
    from metamaterial_wb.core.sleeve.frame3d import RingFrame
    from metamaterial_wb.core.sleeve.frame3d_nl import trace_ring
    out = {}
    for key, (n, d_max, bias, modes, ramp) in runs.items():
        d = np.linspace(0.0, d_max, int(round(d_max / step)) + 1)
        t0 = time.perf_counter()
        r = trace_ring(RingFrame(CellGeometry(), n, plane="stress", root_extension=e, n_el=n_el), d, plate="free",
                       bias=bias, modes=modes, bias_ramp=ramp, stable=bias > 0)   # unbiased: the untilted path
        th = r["tilt"]
        row = {"cells": n, "bias": bias, "bias_ramp": ramp, "d": d.tolist(), "F": r["F"].tolist(),
               "tilt_deg": np.degrees(np.hypot(th[:, 0], th[:, 1])).tolist(),
               "twist_deg": np.degrees(th[:, 2]).tolist(), "seconds": time.perf_counter() - t0, "elements": n_el,
               "snapped": r["snapped"].astype(int).tolist()}
        if modes:
            pair = np.argsort(-r["plate_share"], axis=1)[:, :2]
            row["tilt_pair"] = np.take_along_axis(r["modes"], pair, axis=1).min(axis=1).tolist()
        out[key] = row
    return out


MESH_RUNS = ("8_bias1e-05", "8_bias0.001")   # the eight-cell leaning runs whose snapping count is meshed


def count_meshes(meshes=(6, 24), e=0.63, step=0.005):
    """The eight-cell leaning runs (``MESH_RUNS``) on beam meshes other than the plate study's: ``{str(n_el): {key:
    {"snapping", "seconds"}}}`` (``snapping``), the count at the first valley on every mesh."""
    out = {}
    for n_el in meshes:
        runs = plate_study(n_el, e, step, {k: RUNS[k] for k in MESH_RUNS})
        out[str(n_el)] = {k: {"snapping": snapping(r), "seconds": r["seconds"]} for k, r in runs.items()}
    return out


def count_words(pl, meshes):
    """The sentence on the eight-cell leaning runs' snapping count on every beam mesh (``count_meshes`` and the
    plate study's own), or nothing when a run has no valley."""
    runs = dict(meshes)
    runs[str(pl["8"]["elements"])] = {k: {"snapping": snapping(pl[k]), "seconds": pl[k]["seconds"]} for k in MESH_RUNS}
    order = sorted(runs, key=int)
    sn = {k: [runs[n][k]["snapping"] for n in order] for k in MESH_RUNS}
    if not all(x["valley"] for k in MESH_RUNS for x in sn[k]):
        return ""
    counts = {x["valley"][1] for k in MESH_RUNS for x in sn[k]}

    def listed(values, fmt):
        return ", ".join(format(v, fmt) for v in values)

    parts = []
    for k, what in zip(MESH_RUNS, ("the default bias", "the hundred-fold bias")):
        x = sn[k]
        half = [v["half"] for v in x]
        parts.append(f"with {what} {listed([v['valley'][1] for v in x], 'd')} of {x[0]['units']} at the first valley "
                     f"(d/L {listed([v['valley'][0] for v in x], '.3f')})"
                     + (f", half the ring by d/L {listed(half, '.3f')}" if all(h is not None for h in half) else ""))
    near = all(v["contiguous"] for k in MESH_RUNS for v in sn[k])
    secs = sum(runs[n][k]["seconds"] for n in order for k in MESH_RUNS)
    return (f"On {listed([int(n) for n in order], 'd')} elements per beam half the count is "
            + ("the same" if len(counts) == 1 else "not the same") + ": " + "; ".join(parts)
            + ("; neighbours on every mesh" if near else "; not neighbours on every mesh")
            + f" (`fe_frame3d_plate.count_meshes`, {secs:.0f} s for the {len(order) * len(MESH_RUNS)} runs). ")


def zero_crossings(d, lam):
    """Where ``lam(d)`` changes sign, by linear interpolation: a list of ``(d, "down" | "up")``."""
    out = []
    for k in range(1, len(d)):
        if (lam[k - 1] > 0) != (lam[k] > 0):
            x = d[k - 1] + lam[k - 1] * (d[k] - d[k - 1]) / (lam[k - 1] - lam[k])
            out.append((float(x), "down" if lam[k] <= 0 else "up"))
    return out


def contiguous(mask):
    """Whether the snapped hysterons (``mask`` around the ring) form one group of neighbours."""
    m = np.asarray(mask, bool)
    if m.all() or not m.any():
        return True
    return int(np.sum(m & ~np.roll(m, 1))) == 1


def snapping(run):
    """The leaning branch's snapping: ``{"valley": (d, snapped count) or None (no valley before the run's end),
    "half": d where half the hysterons have snapped or None, "contiguous": whether they are neighbours there (at
    the end without half), "units": their number, "end": (d, snapped count) at the run's end}``."""
    from metamaterial_wb.fe.sleeve2d import peak_valley
    S = np.asarray(run["snapped"], bool)
    d = np.asarray(run["d"])
    _, _, dv, _ = peak_valley(d, run["F"])
    count = S.sum(axis=1)
    valley = (float(dv), int(count[int(np.argmin(np.abs(d - dv)))])) if np.isfinite(dv) else None
    half = np.nonzero(count >= S.shape[1] / 2)[0]
    k = int(half[0]) if len(half) else len(d) - 1
    return {"valley": valley, "half": float(d[k]) if len(half) else None,
            "contiguous": contiguous(S[k]), "units": int(S.shape[1]), "end": (float(d[-1]), int(count[-1]))}


def stage_timing(sn):
    """When half the ring has snapped against the first valley, as the end of a sentence."""
    if not (sn["valley"] and sn["half"] is not None):
        return ". "
    if sn["half"] > sn["valley"][0]:
        return ", here complete only after the first valley. "
    return (", reached before the first valley; a pillar snaps back on the way (the count is not monotonic "
            "along the path). " if sn["valley"][1] < sn["units"] / 2 else ", reached by the first valley. ")


def snapping_words(sn):
    """``snapping``'s result in words: how many at the first valley, where half the ring has snapped, neighbours."""
    out = (f"{sn['valley'][1]} of {sn['units']} at the first valley (d/L {sn['valley'][0]:.3f})" if sn["valley"] else
           f"{sn['end'][1]} of {sn['units']} at d/L {sn['end'][0]:.3f}, the run's end, before any valley")
    if sn["half"] is not None:
        out += f", half the ring by d/L {sn['half']:.3f}"
    return out + (", neighbours of each other" if sn["contiguous"] else ", not all neighbours")


def solid_snapped(row, pre="c3d20_bias0.001_"):
    """The solid run's hysterons by the beam model's rule, from its beam ends' rises (``cells_p1``'s
    ``p1_rises``, ``p1_units``, ``p1_snap_height``): ``{"d", "F", "snapped" (k, units)}`` as ``snapping`` reads
    it, or None when the run kept no rises."""
    from metamaterial_wb.core.sleeve.analysis import units_snapped
    if pre + "p1_rises" not in row:
        return None
    snapped = units_snapped(row[pre + "p1_rises"], row[pre + "p1_snap_height"], row[pre + "p1_units"])
    cv = row[pre + "p1_curve"]
    return {"d": cv["d"], "F": cv["F"], "snapped": snapped.astype(int).tolist()}


def at(d, y, x):
    return float(np.interp(x, d, y))


def solid_tilt_pair(c, n):
    """The solid's tilt pair along its path (omega^2 rho, the lower of the two) from the stored stability probes
    of the ``n``-cell ring: sorted ``[(d, lambda)]``."""
    from metamaterial_wb.bench.fe_ring3d import classify_modes
    out = []
    for key, pr in c.get("stability", {}).items():
        if pr.get("n_cells", 4) != n or not pr.get("eigenvalues") or not key.startswith(("r2@", "layers2_cells")):
            continue
        lam, kind = classify_modes(pr)
        if np.any(kind == "tilt"):
            out.append((pr["d"], float(lam[kind == "tilt"].min())))
    return sorted(out)


def facts(pl, c):
    """The figures the paragraph quotes (frame and solid), as a dict."""
    from metamaterial_wb.fe.sleeve2d import peak_valley
    f = {}
    for n in (4, 8):
        r = pl[str(n)]
        d, lam = np.array(r["d"]), np.array(r["tilt_pair"])
        f[f"frame{n}_zero"] = zero_crossings(d, lam)
        f[f"frame{n}_min"] = (float(d[np.argmin(lam)]), float(lam.min() / lam[0]))
        f[f"frame{n}_untilted_p1"] = (float(d[np.argmax(r["F"])]), float(max(r["F"])))
        sp = solid_tilt_pair(c, n)
        f[f"solid{n}_pair"] = sp
        if sp:
            d0 = sp[0][0]
            f[f"frame{n}_rel"] = [(x, at(d, lam, x) / at(d, lam, d0)) for x, _ in sp]
            f[f"solid{n}_rel"] = [(x, v / sp[0][1]) for x, v in sp]
        for bias in ("1e-05", "0.001"):
            b = pl.get(f"{n}_bias{bias}")
            if b:
                dp, fp, _, _ = peak_valley(b["d"], b["F"])
                f[f"frame{n}_bias{bias}"] = {"P1": (dp, fp), "tilt_max": (float(b["d"][int(np.argmax(b["tilt_deg"]))]),
                                                                       float(max(b["tilt_deg"]))),
                                             "tilt_025": at(b["d"], b["tilt_deg"], 0.25)}
                if "snapped" in b:
                    f[f"frame{n}_bias{bias}"]["snapping"] = snapping(b)
    row = c.get("cells", {}).get("8", {})
    if "c3d20_p1_curve" in row:
        f["solid8_stop"] = (row["c3d20_p1_d_reached"], row["c3d20_p1_curve"]["F"][-1])
    if "c3d20_bias0.001_fe_curved_p1" in row:
        cv = row["c3d20_bias0.001_p1_curve"]
        f["solid8_bias0.001"] = {"P1": (row["c3d20_bias0.001_fe_curved_p1_d"], row["c3d20_bias0.001_fe_curved_p1"]),
                                 "tilt_025": at(cv["d"], row["c3d20_bias0.001_p1_tilt_deg"], 0.25),
                                 "d_reached": row["c3d20_bias0.001_p1_d_reached"],
                                 "seconds": row["c3d20_bias0.001_p1_wall_s"]}
        ss = solid_snapped(row)
        if ss:
            f["solid8_bias0.001"]["snapping"] = snapping(ss)
    four = c.get("cells", {}).get("4", {})
    if four.get("c3d20_fe_curved_p1") and "p1_r3_C3D20" in c:
        from metamaterial_wb.bench.fe_ring3d_corner import family_convergence
        ext = family_convergence(c, "_C3D20")["p1_ext"]
        if ext:                                   # the eight-cell runs' mesh on four cells against the extrapolation
            f["mesh_factor_c3d20_r1"] = four["c3d20_fe_curved_p1"] / ext[1]
    m8 = eight_cell_meshes(c)
    if m8:
        f["solid8_meshes"] = m8
    return f


def eight_cell_meshes(c, pre="c3d20_bias0.001_"):
    """The eight-cell ring's own mesh error on its leaning branch: its biased first peak on meshes r = 1 and 2 (one
    brick through the wall, every brick C3D20; ``--cells-p1-mesh r1|r2``), the fall from one to the other beside
    the four-cell ring's on the same meshes (the all-C3D20 family), and the eight-cell peak extrapolated with the
    four-cell family's observed order (``richardson3`` over its r = 1, 2, 3): ``None`` until both runs are stored
    with a peak."""
    from metamaterial_wb.core.extrapolation import order_note, richardson3
    from metamaterial_wb.bench.fe_ring3d_corner import family_convergence
    row = c.get("cells", {}).get("8", {})
    p8 = [row.get(f"{pre}{m}_fe_curved_p1") for m in ("r1", "r2")]
    if not all(p8) or not all(f"p1_{m}_C3D20" in c for m in ("r1", "r2", "r3")):
        return None
    pc = family_convergence(c, "_C3D20")
    p4 = [F for m, (_, F) in zip(pc["meshes"], pc["p1"]) if m in ("r1", "r2", "r3")]
    h = [1.0, 0.5, 1.0 / 3.0]                 # element sizes of r = 1, 2, 3
    _, _, order = richardson3(h, p4)
    figures = [("the four-cell family's order", h, p4)]
    p = order[0]
    ext = p8[1] + (p8[1] - p8[0]) * 0.5 ** p / (1.0 - 0.5 ** p)
    out = {"r1": p8[0], "r2": p8[1], "d": [row.get(f"{pre}{m}_fe_curved_p1_d") for m in ("r1", "r2")],
           "seconds": [row.get(f"{pre}{m}_p1_wall_s") for m in ("r1", "r2")],
           "fall": p8[1] / p8[0] - 1.0, "four_fall": p4[1] / p4[0] - 1.0, "order": p, "ext": (ext, abs(ext - p8[1])),
           "layers2": row.get(f"{pre}fe_curved_p1")}
    r3 = row.get(f"{pre}r3_fe_curved_p1")
    if r3:                    # a third mesh: the eight-cell ring's own observed order (--cells-p1-mesh r3)
        e3, err3, p3 = richardson3(h, p8 + [r3])
        figures.append(("the eight-cell ring's own order", h, p8 + [r3]))
        out.update({"r3": r3, "r3_d": row.get(f"{pre}r3_fe_curved_p1_d"), "r3_seconds": row.get(f"{pre}r3_p1_wall_s"),
                    "fall3": r3 / p8[1] - 1.0, "four_fall3": p4[2] / p4[1] - 1.0, "own_order": p3[0],
                    "own_ext": (e3[0], err3[0])})
    out["note"] = order_note(figures)
    return out


def eight_cell_words(m, frame_p1):
    """The sentence on the eight-cell ring's own mesh error (``eight_cell_meshes``) and the frame's leaning peak
    (``frame_p1``) against its extrapolation."""
    e, err = m["ext"]
    return (f"The eight-cell ring's own mesh error, measured on the same leaning branch (the same bias at every "
            f"rise, to d/L 0.12, one brick through the wall, every brick C3D20; `--cells-p1-mesh r1` and `r2`, "
            f"{m['seconds'][0] / 60:.0f} and {m['seconds'][1] / 60:.0f} min): its first peak falls from "
            f"{1e3 * m['r1']:.3f}e-3 on r = 1 to {1e3 * m['r2']:.3f}e-3 on r = 2 ({100 * m['fall']:+.1f} %), where "
            f"the four-cell ring's falls by {100 * m['four_fall']:+.1f} % on the same meshes (two bricks through the "
            f"wall on r = 1: {1e3 * m['layers2']:.3f}e-3); with the four-cell family's observed order "
            f"({m['order']:.2f}) it extrapolates to {1e3 * e:.2f} +- {1e3 * err:.2f}e-3, and the frame's leaning "
            f"peak is {100 * (frame_p1 / e - 1):+.0f} % off it ({100 * err / e:.0f} % its error). " +
            (f"A third mesh, r = 3 (`--cells-p1-mesh r3`, {m['r3_seconds'] / 60:.0f} min), gives {1e3 * m['r3']:.3f}e-3 "
             f"({100 * m['fall3']:+.1f} % from r = 2, where the four-cell ring's falls by {100 * m['four_fall3']:+.1f} "
             f"%): the eight-cell ring's own observed order is {m['own_order']:.2f}, its peak extrapolates to "
             f"{1e3 * m['own_ext'][0]:.2f} +- {1e3 * m['own_ext'][1]:.2f}e-3, and the frame's leaning peak is "
             f"{100 * (frame_p1 / m['own_ext'][0] - 1):+.0f} % off it ({100 * m['own_ext'][1] / m['own_ext'][0]:.0f} "
             "% its error). " if "r3" in m else "") + (m["note"] + " " if m.get("note") else ""))


def markdown(pl, c, p1_off=None, meshes=None):
    """The paragraph for docs/sleeves.md's frame section; ``p1_off``: the four-cell frame's untilted first peak
    against the solid's extrapolated one, per cent (``fe_frame3d.p1_off``); ``meshes``: the eight-cell leaning runs
    on other beam meshes (``count_meshes``)."""
    f = facts(pl, c)
    z8 = [x for x, k in f["frame8_zero"] if k == "down"]
    z4 = f["frame4_zero"]
    s8, s4 = f["solid8_pair"], f["solid4_pair"]
    (d1, l1), (d2, l2) = s8[-2:]
    ext = d2 + l2 * (d2 - d1) / (l1 - l2)
    r8 = dict(f["frame8_rel"])
    b5, b3 = f["frame8_bias1e-05"], f["frame8_bias0.001"]
    sb = f.get("solid8_bias0.001")
    secs = sum(r["seconds"] for r in pl.values())
    t = ("**The frame with the solid's plate** (`trace_ring(..., plate=\"free\")`: the top plate rigid, rising as "
         "prescribed, tilting and twisting freely under the solid's bias moment, ramped with the rise as in its "
         "runs; the lowest eigenvalues of the "
         "reduced Hessian followed along the untilted path, the tilt pair the two modes the plate takes most part "
         f"in; {pl['8']['elements']} elements per beam half, plane stress, calibrated; `bench_sleeve_frame3d.py "
         f"--plate`, {secs:.0f} s for the {len(pl)} runs). Eight cells: the tilt pair falls from the start and "
         + (f"reaches zero at d/L {z8[0]:.3f}, before the untilted path's peak ({1e3 * f['frame8_untilted_p1'][1]:.2f}e-3 "
            f"at d/L {f['frame8_untilted_p1'][0]:.3f}): the untilted ring bifurcates into tilt. " if z8 else
            "stays positive. ") +
         f"At the solid's probes it is at {100 * r8[0.07]:.0f} % (d/L 0.07) and {100 * r8[0.077]:.0f} % (0.077) of "
         f"its value at 0.05; the solid's at {100 * l1 / s8[0][1]:.0f} % and {100 * l2 / s8[0][1]:.0f} %, falling "
         f"{'faster' if l2 / s8[0][1] < r8[0.077] else 'slower'}, its last two probes' line reaching zero at d/L "
         f"{ext:.3f} (the solid's are mass-weighted "
         "frequencies, the frame's stiffness eigenvalues: only where they reach zero compares). So the static solid's stall at d/L "
         f"{f['solid8_stop'][0]:.3f} ({1e3 * f['solid8_stop'][1]:.2f}e-3, the force flattening) lies just before the "
         "tilt bifurcation that both models put near: the eight-cell ring leaves the untilted path there (the solid's "
         "probes at the stop are still stable, so ccx's stall is the approach, not the crossing). With the default "
         f"bias the frame peaks at {1e3 * b5['P1'][1]:.2f}e-3 at d/L {b5['P1'][0]:.3f} and leans, "
         f"{b5['tilt_025']:.1f} deg at d/L 0.25; with the hundred-fold bias at {1e3 * b3['P1'][1]:.2f}e-3 at "
         f"{b3['P1'][0]:.3f}, {b3['tilt_025']:.1f} deg at 0.25" +
         (f" (the solid: {1e3 * sb['P1'][1]:.2f}e-3 at {sb['P1'][0]:.3f}, {sb['tilt_025']:.1f} deg at 0.25): on the "
          f"leaning branch the frame's peak is {100 * (b3['P1'][1] / sb['P1'][1] - 1):+.0f} % off the solid's and its "
          f"lean {b3['tilt_025'] - sb['tilt_025']:+.1f} deg" if sb else "") +
         (f"; that solid is mesh r = 1 with every brick C3D20, whose four-cell first peak is "
          f"{100 * (f['mesh_factor_c3d20_r1'] - 1):+.0f} % over the four-cell ring's extrapolated one: scaled by it, "
          f"the eight-cell leaning peak would be {1e3 * sb['P1'][1] / f['mesh_factor_c3d20_r1']:.2f}e-3 and the frame's "
          f"{100 * (b3['P1'][1] * f['mesh_factor_c3d20_r1'] / sb['P1'][1] - 1):+.0f} % off it"
          + (" (an estimate: the eight-cell ring's own mesh error is not measured). " if not f.get("solid8_meshes")
             else ". " + eight_cell_words(f["solid8_meshes"], b3["P1"][1]))
          if sb and f.get("mesh_factor_c3d20_r1") else ". "))
    sn = b5.get("snapping")
    if sn:
        t += ("On the leaning branch the hysterons (the edge pillars with their two beam halves, snapped by the beam "
              "model's rule) go one after another: " + snapping_words(sn) +
              (": the seed's first stage (half the cells, on one side)" + stage_timing(sn) if sn["contiguous"]
               else ". "))
    s3, ss = b3.get("snapping"), (sb or {}).get("snapping")
    if s3 and ss:
        t += ("Under the hundred-fold bias the frame's go " + snapping_words(s3) + "; the solid's, read off its beams' "
              "ends by the same rule (`sleeve3d.hysterons`; the run's beam ends printed at every increment, "
              f"{sb['seconds'] / 60:.0f} min to d/L {sb['d_reached']:.2f}), " + snapping_words(ss) + ". ")
    if meshes:
        t += count_words(pl, meshes)
    dm, rel = f["frame4_min"]
    lo4 = min(s4, key=lambda p: p[1])
    b4 = f["frame4_bias1e-05"]
    t += (f"Four cells: the frame's tilt pair is lowest at d/L {dm:.2f} "
          + (f"and just below zero from {z4[0][0]:.3f} to {z4[1][0]:.3f} ({100 * rel:+.1f} % of its initial value), "
             if len(z4) >= 2 else f"({100 * rel:.0f} % of its initial value), ")
          + f"where the solid's is lowest too (d/L {lo4[0]:.2f}, {100 * lo4[1] / s4[0][1]:.0f} % of its value at "
          f"{s4[0][0]:.2f}, positive); with the default bias the frame leans up to {b4['tilt_max'][1]:.1f} deg at d/L "
          f"{b4['tilt_max'][0]:.2f} and comes back, where the solid's four-cell ring tilts by under 0.2 deg. So the frame "
          "gets whether and roughly where and how far each ring leans - four cells hardly" +
          (" (its tilt a little too soft there)" if b4["tilt_max"][1] > 1.0 else "") +
          ", eight cells past a tilt bifurcation near d/L 0.1" +
          (" (the solid's a little earlier)" if z8 and z8[0] > ext else " (the frame's a little earlier)" if z8 else "")
          + (f" - and its axial first peak is {p1_off:+.0f} % off the solid's on four cells" if p1_off is not None
             else "") + "; the eight-cell ring is imperfection-sensitive in both.")
    return t + f"\n\n![the frame with the solid's plate: force, lean and the tilt pair against the solid]({IMG})\n"


def plot(pl, c, path):
    """Three panels: the eight-cell force and lean (frame untilted, default and hundred-fold bias; the solid's
    untilted stall and biased run) and the tilt pair relative to its value at the solid's first probe."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from metamaterial_wb.bench.plotting import finish
    row = c.get("cells", {}).get("8", {})
    fig, ax = plt.subplots(1, 3, figsize=(12.5, 3.9), dpi=100)
    for key, col, lab in (("8", "C0", "frame, untilted path"), ("8_bias1e-05", "C1", "frame, bias 1e-5"),
                          ("8_bias0.001", "C3", "frame, bias 1e-3")):
        r = pl[key]
        ax[0].plot(r["d"], 1e3 * np.asarray(r["F"]), "--", color=col, lw=1.3, label=lab)
        if key != "8":
            ax[1].plot(r["d"], r["tilt_deg"], "--", color=col, lw=1.3, label=lab)
    if "c3d20_p1_curve" in row:
        cv = row["c3d20_p1_curve"]
        ax[0].plot(cv["d"], 1e3 * np.asarray(cv["F"]), "k-", lw=1.5, label="solid, bias 1e-5 (stalls)")
    if "c3d20_bias0.001_p1_curve" in row:
        cv = row["c3d20_bias0.001_p1_curve"]
        ax[0].plot(cv["d"], 1e3 * np.asarray(cv["F"]), "-", color="C3", lw=1.5, label="solid, bias 1e-3")
        ax[1].plot(cv["d"], row["c3d20_bias0.001_p1_tilt_deg"], "-", color="C3", lw=1.5, label="solid, bias 1e-3")
    ax[0].set_title("eight cells: force", fontsize=9)
    ax[0].set_ylabel("F / (G L^2) x1e-3")
    ax[1].set_title("eight cells: the plate's lean", fontsize=9)
    ax[1].set_ylabel("tilt (deg)")
    for n, col in ((4, "C2"), (8, "C0")):
        r = pl[str(n)]
        sp = solid_tilt_pair(c, n)
        d0 = sp[0][0] if sp else 0.0
        lam = np.asarray(r["tilt_pair"])
        ax[2].plot(r["d"], lam / at(r["d"], lam, d0), "--", color=col, lw=1.3, label=f"frame, {n} cells")
        if sp:
            ax[2].plot([p[0] for p in sp], [p[1] / sp[0][1] for p in sp], "o", color=col, ms=4,
                       label=f"solid probes, {n} cells")
    ax[2].axhline(0, color="k", lw=0.5)
    ax[2].set_title("tilt pair / its value at the solid's first probe", fontsize=9)
    finish(fig, ax, "d / L", path)


def sequence_study(meshes={"1": (6, 12, 24), "2": (6, 12, 24)}, root_extension=0.63, steps=160):
    """The seed's combinations on the frame (``frame3d_sequence``, ring [0, 0, 1, 1], the free plate) on each
    beam mesh of ``meshes``, and on the beam model as the ``sleeve`` command runs it (``pipeline.analyse`` on
    examples/sleeve.json with the combination's cells): ``{combination: {"frame": {n_el: sequence},
    "model": {...}, "flat_top": sequence}}``, the last on 12 elements with every pillar hanging from the taller
    type's top (``RingFrame(flat_top=True)``, as the curved solid's mixed ring stands)."""
    import json
    import os
    from metamaterial_wb.core.sleeve.analysis import peaks_valleys
    from metamaterial_wb.core.sleeve.frame3d import RingFrame
    from metamaterial_wb.core.sleeve.frame3d_nl import trace_ring
    from metamaterial_wb.core.sleeve.frame3d_sequence import frame_sequence
    from metamaterial_wb.core.sleeve.model import default_stroke
    from metamaterial_wb.core.sleeve.pipeline import analyse
    from metamaterial_wb.core.sleeve.spec import SleeveSpec
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    base = json.load(open(os.path.join(root, "examples", "sleeve.json")))
    out = {}
    for key, comb in SEED_COMBINATIONS.items():
        L = base["L_mm"]
        cells = combination_cells(key)
        frames = {}
        for n_el in meshes.get(key, ()):
            fs, _, _ = frame_sequence(cells, [0, 0, 1, 1], default_stroke(cells), steps, n_el, root_extension)
            frames[str(n_el)] = {k: v for k, v in fs.items() if not k.startswith("events")}
        flat, _, _ = frame_sequence(cells, [0, 0, 1, 1], default_stroke(cells), steps, 12, root_extension,
                                    flat_top=True)
        uniform = []
        for g in cells:                                # the two-hysteron thresholds on the frame: uniform rings
            dm = default_stroke([g])
            r = trace_ring(RingFrame(g, 4, plane="stress", root_extension=root_extension, n_el=12),
                           np.linspace(0, dm, steps + 1), plate="free", bias_ramp=dm)
            pv = peaks_valleys(r["d"], r["F"])
            uniform.append({"P1": pv["peaks"][0][1] if pv["peaks"] else None,
                            "valley": pv["valleys"][0][1] if pv["valleys"] else None})
        spec = dict(base, cell_types=[{"t_mm": t * L, "h_mm": h * L} for h, t in comb["cells"]], walker=False)
        summ, _ = analyse(SleeveSpec(spec, "sequence study"))
        q = summ["sequence"]
        out[key] = {"frame": frames, "uniform": uniform, "flat_top": flat, "model": {k: q[k] for k in ("loading", "unloading", "symmetric", "lean_reverses",
                                                                  "max_tilt_loading_deg", "max_tilt_unloading_deg")}}
    return out


WALKER_KEYS = ("area_mm2", "lateral_stroke_mm", "lift_mm", "step_per_cycle_mm")


def walker_study(meshes=(6, 12, 24)):
    """The leg of examples/walker.json on the frame's cycle as the ``sleeve`` command runs it with
    ``model.frame_nonlinear`` (``pipeline.analyse``), on each beam mesh: ``{str(n_el): {WALKER_KEYS..., "seconds"},
    "model": the beam model's own figures}``."""
    import json
    import os
    from metamaterial_wb.core.sleeve.pipeline import analyse
    from metamaterial_wb.core.sleeve.spec import SleeveSpec
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    base = json.load(open(os.path.join(root, "examples", "walker.json")))
    out = {}
    for n_el in meshes:
        spec = dict(base, model=dict(base.get("model", {}), frame_nonlinear=True, frame_elements=n_el))
        t0 = time.perf_counter()
        summ, _ = analyse(SleeveSpec(spec, "walker study"))
        out[str(n_el)] = dict({k: summ["walker"]["frame3d_nl"][k] for k in WALKER_KEYS},
                              seconds=time.perf_counter() - t0)
    out["model"] = {k: summ["walker"][k] for k in WALKER_KEYS}     # the beam model's: the same on every frame mesh
    return out


def walker_markdown(w):
    """The walker on the frame per beam mesh (``walker_study``): a table and the largest change between the two
    finest meshes."""
    meshes = sorted((k for k in w if k != "model"), key=int)
    L = ["**The walker on the frame** (`examples/walker.json` with `model.frame_nonlinear`, as the `sleeve` command "
         "runs it: the leg's tip loop on the frame's cycle of combination 2's mixed ring, root extension 0; "
         "`bench_sleeve_frame3d.py --walker`):", "",
         "| model | loop area (mm^2) | lateral stroke (mm) | lift (mm) | step per cycle (mm) | time (whole run) |",
         "|---|---|---|---|---|---|"]
    for n in meshes:
        r = w[n]
        L.append(f"| frame, {n} elements per beam half | {r['area_mm2']:.3f} | {r['lateral_stroke_mm']:.3f} | "
                 f"{r['lift_mm']:.2f} | {r['step_per_cycle_mm']:.3f} | {r['seconds']:.0f} s |")
    m = w["model"]
    L.append(f"| beam model (`sleeve` command) | {m['area_mm2']:.1f} | {m['lateral_stroke_mm']:.2f} | "
             f"{m['lift_mm']:.2f} | {m['step_per_cycle_mm']:.3f} | |")
    a, b = w[meshes[-2]], w[meshes[-1]]
    change = max(abs(b[k] / a[k] - 1) for k in WALKER_KEYS)
    L += ["", f"From {meshes[-2]} to {meshes[-1]} elements per beam half the frame's figures change by at most "
          f"{100 * change:.1f} %: its loop is mesh-converged, and about {m['area_mm2'] / b['area_mm2']:.0f} times "
          "smaller than the beam model's (the frame's combination 2 snaps symmetrically and leans one way by about a "
          "degree).", ""]
    return "\n".join(L)


def sequence_markdown(st, root_extension=0.63):
    """The table of the seed's combinations: the seed's sequence, the beam model's and the frame's per mesh."""
    seq = order_text

    def lean(s):
        return (f"{s['max_tilt_loading_deg']:.1f} / {s['max_tilt_unloading_deg']:.1f} deg, "
                + ("reverses" if s["lean_reverses"] else "the same way"))
    L = ["**Sequencing on the frame** (`core/sleeve/frame3d_sequence.py`: the mixed ring [0, 0, 1, 1] raised to the "
         "beam model's stroke and lowered back in 160 steps on the frame with the solid's free plate, bias 1e-5 "
         f"ramped over the loading, plane stress, root extension {root_extension:g} t; the snapping order by the beam "
         "model's rule on the frame's beam halves; `bench_sleeve_frame3d.py --sequence`; the `sleeve` command runs "
         "the same with `model.frame_nonlinear`). Sequences as loading \\| unloading, cell types in the seed's "
         "order; lean: the plate's largest tilt on loading / unloading:", "",
         "| combination | seed | beam model (`sleeve` command) | beam model: lean | frame, elements per beam half: "
         "sequence | frame: lean | frame: time |", "|---|---|---|---|---|---|---|"]
    for key, r in st.items():
        sd = SEED_COMBINATIONS[key]
        seed = seed_order(key)
        for i, (n_el, f) in enumerate(r["frame"].items()):
            head = (f"| {key} (h/L, t/L: {sd['cells'][0]}, {sd['cells'][1]}) | {seq(seed)}, leaning {sd['lean']} | "
                    f"{seq(r['model'])} | {lean(r['model'])} | " if i == 0 else "| | | | | ")
            L.append(head + f"{n_el}: {seq(f)} | {lean(f)} | {f['seconds']:.0f} s |")
    two = st.get("2", {}).get("frame", {})
    same_seq = len({(tuple(f["loading"]), tuple(f["unloading"])) for f in two.values()}) == 1
    same_lean = len({f["lean_reverses"] for f in two.values()}) == 1
    tilt = max((max(f["max_tilt_loading_deg"], f["max_tilt_unloading_deg"]) for f in two.values()), default=0.0)
    u = st.get("2", {}).get("uniform")
    text = ("On the frame the sequence and the lean are the same on every beam mesh" if same_seq and same_lean else
            f"On the frame the sequence is the same on every beam mesh, the lean's turn (at most {tilt:.1f} deg) not"
            if same_seq else "On the frame the sequence changes with the beam mesh") + \
        " (the beam model's lean turned with its mesh)."
    if u and all(x["P1"] and x["valley"] for x in u):
        rule_load = [0, 1] if u[0]["P1"] < u[1]["P1"] else [1, 0]
        rule_unload = [0, 1] if u[0]["valley"] > u[1]["valley"] else [1, 0]
        text += (f" Combination 2's uniform rings on the frame (free plate, 12 elements): P1 {1e3 * u[0]['P1']:.4f} and "
                 f"{1e3 * u[1]['P1']:.4f}e-3, valleys {1e3 * u[0]['valley']:.4f} and {1e3 * u[1]['valley']:.4f}e-3 "
                 f"({100 * abs(u[0]['P1'] / u[1]['P1'] - 1):.1f} % and {100 * abs(u[0]['valley'] / u[1]['valley'] - 1):.0f} "
                 f"% apart), so the seed's two-hysteron rule on the frame's thresholds gives loading {rule_load}, "
                 f"unloading {rule_unload}")
        f12 = two.get("12")
        if f12:
            text += (", " + ("which the mixed ring on the frame follows" if (f12["loading"] == rule_load and
                                                                             f12["unloading"] == rule_unload)
                             else f"which the mixed ring on the frame does not follow ({seq(f12)}): the frame does not "
                                  "reproduce the seed's asymmetric sequence. The same two types as two stacked rings "
                                  "do follow it (below): the cells of a mixed ring share one plate and do not snap as "
                                  "independent hysterons when their thresholds lie this close (the beam model's own "
                                  "mixed ring does not follow the rule either)"))
        text += "."
    L += ["", text, ""]
    return "\n".join(L)
