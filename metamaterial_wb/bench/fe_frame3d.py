"""The linear 3-D frame of the curved ring (``core/sleeve/frame3d.py``) against the curved CalculiX solid
(issue 18): the curvature's knock-down of the ring's initial stiffness by ring size, from the beam model's own
mesh wrapped on the cylinder, against the solid's and the beam model's curvature springs.

The solid's figures are the stored ``--cells`` runs of ``benchmarks/bench_sleeve_ring3d.py`` (secant to d/L
0.005, mesh r = 1 with two bricks through the wall; flat: the plane-strain 2-D ring); the frame's are linear
(the 2-D beam model's flat ring softens by 3-4 % between its linear stiffness and that secant).
"""
import time

import numpy as np

from metamaterial_wb.fe.sleeve_check import CONVERGED_MESHES

MARK_BEGIN, MARK_END = "<!-- frame3d:begin -->", "<!-- frame3d:end -->"
IMG = "img/sleeve-frame3d.png"
IMG_STIFFNESS = "img/sleeve-frame3d-stiffness.png"
# (key, RingFrame options, label)
VARIANTS = (("strain", {"plane": "strain"}, "E = 4 G in the plane (the beam model's), 3 G through the wall"),
            ("stress", {"plane": "stress"}, "E = 3 G throughout (a 3-D beam's own modulus)"))


# bench_sleeve_ring3d.py --cells-meshes: the converged check's in-plane refinements r = 1, 2, 3, by name
SOLID_MESHES = tuple(f"r{r}" for r, _ in CONVERGED_MESHES)
# bench_sleeve_ring3d.py --cells-flat (r4, r8) and --cells-meshes (r2): the flat 2-D ring's extrapolation meshes,
# nested with ratio 2. Its r = 1 mesh is not yet in the asymptotic range: over r = 1, 2, 3 its observed order was
# 0.56 and its extrapolation 3.5 % under the one over r = 2, 4, 8 (order 1.24, about the re-entrant corners')
FLAT_MESHES = ("r2", "r4", "r8")
# bench_sleeve_ring3d.py --cells-meshes r4: a fourth curved mesh, the reference's check (the curved extrapolation
# over r = 2, 3, 4 against the one over SOLID_MESHES)
CHECK_MESHES = ("r2", "r3", "r4")


def solid_extrapolated(row):
    """The solid's initial stiffness extrapolated over its in-plane meshes (element size 1 / r; ``richardson3``,
    observed order): ``{"curved": (value, error, order), "flat": (...), "flat_coarse": (...), "curved_meshes":
    [...], "flat_meshes": [...], "seconds": [...]}`` from a ``cells`` row (``bench_sleeve_ring3d.py --cells-meshes``
    and ``--cells-flat``): curved every brick C3D20, one brick through the wall, over ``SOLID_MESHES``; flat the
    plane-strain 2-D ring over ``FLAT_MESHES`` (``"flat_coarse"``: over ``SOLID_MESHES``, pre-asymptotic); None
    until every mesh is stored. ``"curved_check"``: the curved over ``CHECK_MESHES`` where stored (else None)."""
    from metamaterial_wb.core.extrapolation import richardson3

    def over(meshes, key):
        """``((value, error, order), values)`` over ``meshes`` of the row's ``key`` fields, None if one is missing."""
        names = [key.format(m) for m in meshes]
        if not all(k in row for k in names):
            return None
        v = [row[k] for k in names]
        ext, err, order = richardson3(_sizes(meshes), v)
        return (ext[0], err[0], order[0]), v
    curved, flat = "c3d20_{}_fe_curved", "{}_fe_flat"
    sides = {"curved": over(SOLID_MESHES, curved), "flat": over(FLAT_MESHES, flat),
             "flat_coarse": over(SOLID_MESHES, flat), "curved_check": over(CHECK_MESHES, curved)}
    if not all(sides[s] for s in ("curved", "flat", "flat_coarse")):
        return None
    out = {"curved_check": None}
    for side, got in sides.items():
        if got:
            out[side], out[f"{side}_meshes"] = got
    out["seconds"] = [row[f"c3d20_{m}_fe_curved_wall_s"] for m in SOLID_MESHES]
    return out


def _sizes(meshes):
    """The element sizes 1 / r of in-plane meshes named ``r<r>``."""
    return [1.0 / int(m[1:]) for m in meshes]


SIDE_MESHES = {"curved": SOLID_MESHES, "flat": FLAT_MESHES, "flat_coarse": SOLID_MESHES, "curved_check": CHECK_MESHES}
SIDE_NAMES = {"curved": "curved", "flat": "flat", "flat_coarse": "flat over r = 1, 2, 3",
              "curved_check": "curved over r = 2, 3, 4"}


def solid_order_note(exts, sides=("curved", "flat", "flat_coarse", "curved_check")):
    """``extrapolation.order_note`` of the ``sides`` of :func:`solid_extrapolated`'s results ``exts`` (``[(ring
    size, result)]``, from their stored values per mesh): ``""`` when every order was observed inside the range."""
    from metamaterial_wb.core.extrapolation import order_note
    return order_note([(f"{n} cells, {SIDE_NAMES[side]}", _sizes(SIDE_MESHES[side]), x[f"{side}_meshes"])
                       for n, x in exts if x for side in sides if x.get(side)])


def study(fe_cells, root_extensions=(0.0, 0.63), n_el=24):
    """Per ring size stored in ``fe_cells`` (``fe-ring3d.json``'s ``cells``: ``fe_flat``, ``fe_curved`` and the
    beam model's ``model_flat``/``model_curved``, calibrated): the frame's flat and curved axial stiffness for
    every variant and root extension, and the time per frame (build and solve)."""
    from metamaterial_wb.core.sleeve.cell import CellGeometry
    from metamaterial_wb.core.sleeve.frame3d import RingFrame
    g = CellGeometry()
    out = {}
    for n, row in sorted(fe_cells.items(), key=lambda kv: int(kv[0])):
        r = {k: row[k] for k in ("fe_flat", "fe_curved", "model_flat", "model_curved", "model_flat_documented",
                                  "model_curved_documented", "wall_s") if k in row}
        r["solid_ext"] = solid_extrapolated(row)
        times = []
        for e in root_extensions:
            t0 = time.perf_counter()
            r[f"frame_flat_{e:g}"] = RingFrame(g, int(n), curved=False, root_extension=e, n_el=n_el).axial_stiffness()
            times.append(time.perf_counter() - t0)
            for key, kw, _ in VARIANTS:
                t0 = time.perf_counter()
                r[f"frame_{key}_{e:g}"] = RingFrame(g, int(n), root_extension=e, n_el=n_el, **kw).axial_stiffness()
                times.append(time.perf_counter() - t0)
        # the frame before: every pillar clamped at its bar's face (``bar_root=0``)
        r[f"frame_stress_{e:g}_bar0"] = RingFrame(g, int(n), root_extension=e, n_el=n_el, plane="stress",
                                                  bar_root=0.0).axial_stiffness()
        r["frame_s"] = float(np.median(times))
        out[str(n)] = r
    return {"root_extensions": list(root_extensions), "n_el": n_el, "cells": out}


def nonlinear_study(n_els=(12, 24), d_max=0.7, step=0.005, e=0.63, repeat=3):
    """The four-cell ring's curved frame traced nonlinearly (``frame3d_nl.trace_ring``; plane stress, root
    extension ``e``) to ``d_max`` on each beam mesh: ``{str(n_el): {"d", "F", "seconds", "iterations",
    "derivatives_seconds", "reference_derivatives_seconds", "planar_seconds"}}``. Baselines from the same run:
    one evaluation of the gradient and Hessian at the last state (best of ``repeat``) against the plain
    per-element route (``reference_gradient_hessian``), and the whole path against the planar beam model's
    (curvature springs, same mesh and steps)."""
    from metamaterial_wb.core.sleeve.cell import CellGeometry
    from metamaterial_wb.core.sleeve.frame3d import RingFrame
    from metamaterial_wb.core.sleeve.frame3d_nl import reference_gradient_hessian, trace_ring
    from metamaterial_wb.core.sleeve.model import SleeveModel
    d = np.linspace(0.0, d_max, int(round(d_max / step)) + 1)
    out = {}

    def best(f):
        ts = []
        for _ in range(repeat):
            t0 = time.perf_counter()
            f()
            ts.append(time.perf_counter() - t0)
        return min(ts)

    for n_el in n_els:
        t0 = time.perf_counter()
        r = trace_ring(RingFrame(CellGeometry(), 4, plane="stress", root_extension=e, n_el=n_el), d)
        seconds = time.perf_counter() - t0
        fr = r["frame"]
        t0 = time.perf_counter()
        SleeveModel([CellGeometry()], [[0] * 4], n_el, "stress", curvature=True, root_extension=e).trace(d)
        out[str(n_el)] = {"d": d.tolist(), "F": r["F"].tolist(), "seconds": seconds,
                          "iterations": int(sum(r["iterations"])), "root_extension": e,
                          "derivatives_seconds": best(fr.gradient_hessian),
                          "reference_derivatives_seconds": best(lambda: reference_gradient_hessian(fr)),
                          "planar_seconds": time.perf_counter() - t0}
    return out


# (key, which elements, which section property, factor): the frame's first peak's sensitivities
SENSITIVITIES = (("EI2_pillars", "pillars", "EI2", 0.8), ("EI2_beams", "beams", "EI2", 0.8),
                 ("GJ_all", "all", "GJ", 0.5), ("EA_all", "all", "EA", 0.5), ("EI3_beams", "beams", "EI3", 0.9))


def p1_sensitivity(n_el=12, e=0.63, d_max=0.25, step=0.005):
    """How the four-cell curved frame's first peak moves when one section property of the beams or the pillars
    (not the rigid links) is scaled (``SENSITIVITIES``): ``{"base": P1, key: P1 / base - 1}``; which part of
    the frame could carry its +17 % over the solid."""
    import copy
    from metamaterial_wb.core.sleeve.cell import CellGeometry
    from metamaterial_wb.core.sleeve.frame3d import RingFrame
    from metamaterial_wb.core.sleeve.frame3d_nl import trace_ring
    g = CellGeometry()
    base = RingFrame(g, 4, plane="stress", root_extension=e, n_el=n_el)
    d = np.linspace(0.0, d_max, int(round(d_max / step)) + 1)
    width = np.sqrt(12.0 * base.EI3 / base.EA)                  # in-plane width: t / L for beams, c / L for pillars
    link = base.GJ >= 0.99 * base.GJ.max()
    masks = {"beams": ~link & (width < 0.5 * (g.t + g.c) / g.L), "pillars": ~link & (width >= 0.5 * (g.t + g.c) / g.L),
             "all": ~link}

    def p1(ring):
        return float(trace_ring(ring, d, stop_after_peak=True)["F"].max())
    out = {"base": p1(base), "bar_root": base.bar_root}
    # the frame before: every pillar clamped at its bar's face
    out["bar_root_0"] = p1(RingFrame(g, 4, plane="stress", root_extension=e, n_el=n_el, bar_root=0.0)) / out["base"] - 1
    for key, which, prop, f in SENSITIVITIES:
        r = copy.deepcopy(base)
        v = getattr(r, prop).copy()
        v[masks[which]] *= f
        setattr(r, prop, v)
        out[key] = p1(r) / out["base"] - 1
    return out


def sensitivity_sentence(sens):
    """One sentence on ``p1_sensitivity``: each change and its ratio to the property's (a log-derivative)."""
    names = {"all": "every element", "beams": "the beams", "pillars": "the pillars"}
    parts = [f"{prop} of {names[which]} x{f:g}: {100 * sens[key]:+.1f} % ({sens[key] / (f - 1):.2f} per unit)"
             for key, which, prop, f in SENSITIVITIES if key in sens]
    return (" How the first peak depends on each section property: it moves by " + "; ".join(parts) + " (EI2: bending "
            "through the wall, GJ: twisting, EA: stretching, EI3: bending in the wall; `fe_frame3d.p1_sensitivity`, "
            "12 elements per beam half). Bending in the wall weighs most but is the flat cell's, which the calibration "
            "matched to the solid; of what curvature adds, the through-wall bending of the short, wide pillars "
            "(their roots in the bars included) weighs most, twisting and stretching little.")


def p1_off(nl, fe, planar):
    """The nonlinear frame's first peak (finest beam mesh of ``nl``) and the planar beam model's (``planar``:
    ``{"d", "F"}``) against the curved solid's extrapolated one (``fe["p1_ext"]``), per cent: ``(frame, planar)``."""
    from metamaterial_wb.fe.sleeve2d import peak_valley
    last = nl[max(nl, key=int)]
    fpe = fe["p1_ext"][1]
    return (100 * (peak_valley(last["d"], last["F"])[1] / fpe - 1),
            100 * (peak_valley(planar["d"], planar["F"])[1] / fpe - 1))


def nonlinear_markdown(nl, fe, planar, sens=None):
    """The nonlinear frame's paragraph: P1 and the valley on each beam mesh against the curved solid's
    (``fe``: ``fe_ring3d_corner.family_convergence`` of the all-C3D20 paths) and the planar beam model's
    calibrated ring's (``planar``)."""
    from metamaterial_wb.fe.sleeve2d import peak_valley
    from metamaterial_wb.bench.fe_ring3d_paths import _kinds
    from metamaterial_wb.fe.sleeve3d import all_extrema
    parts = []
    for n_el, r in nl.items():
        dp, fp, dv, fv = peak_valley(r["d"], r["F"])
        ex = all_extrema(r["d"], r["F"])
        kinds = _kinds(ex)
        parts.append(f"{n_el} elements per beam half: {kinds}, P1 {1e3 * fp:.3f} at d/L {dp:.3f}, valley "
                     f"{1e3 * fv:.3f} at d/L {dv:.3f}, force at d/L 0.7 {1e3 * r['F'][-1]:.3f} "
                     f"({r['seconds']:.0f} s, {r['iterations']} Newton and chord iterations{timing_note(r)})")
    _, fpe, efp, _ = fe["p1_ext"]
    dve, fve, efv, _ = fe["valley_ext"]
    off, off_planar = p1_off(nl, fe, planar)
    last = nl[max(nl, key=int)]
    _, _, dvf, fvf = peak_valley(last["d"], last["F"])
    if abs(fvf - fve) <= efv:
        valley = (f"its valley within the solid's error bar ({1e3 * fvf:.3f}e-3 at d/L {dvf:.3f}, "
                  f"{100 * (fvf / fve - 1):+.0f} %)")
    else:
        valley = (f"its valley {'deeper' if fvf < fve else 'shallower'} and {'later' if dvf > dve else 'earlier'} "
                  f"than the solid's ({1e3 * fvf:.3f}e-3 at d/L {dvf:.3f})")
    return ("**The frame made nonlinear** (`core/sleeve/frame3d_nl.py`: corotational 3-D beams, the same sections; "
            "the top raised without tilt, as the solid's four-cell ring hardly tilts; plane stress, calibrated; "
            "flat it retraces the 2-D beam model's nonlinear ring to 1e-7, tested): " + "; ".join(parts) + ". The curved "
            f"solid (every brick C3D20, four meshes, extrapolated): P1 {1e3 * fpe:.3f} +- {1e3 * efp:.3f}, valley "
            f"{1e3 * fve:.3f} +- {1e3 * efv:.3f} at d/L {dve:.3f}. So the frame has the solid's shape - one peak at "
            f"the solid's place, a stable descent, a positive valley, the last stiffening; no second peak - and its "
            f"P1 is {off:+.0f} % off the solid's, where the planar beam model's calibrated ring is "
            f"{off_planar:+.0f} % off and pulls back (a negative valley); {valley}. The "
            "default `sleeve` model is unchanged; the frame's first peak is an option of the `sleeve` command "
            "(`frame_nonlinear`, docs/scene-format.md)." + (sensitivity_sentence(sens) if sens else ""))


def bar_root_markdown(sens, held, fe):
    """The paragraph on the pillars' roots in the bars: the solid's first peak with one part held at its radius
    (``held``: P1 per part and ``"free"``, ``bench_sleeve_ring3d.py --held-p1``) and the frame's with its pillars
    clamped at the bars' faces or bending on through them (``sens``: ``p1_sensitivity``), against the solid's
    extrapolated P1 (``fe["p1_ext"]``)."""
    if not sens or "bar_root_0" not in sens or not held.get("free") or "bars" not in held:
        return ""
    _, fpe, efp, _ = fe["p1_ext"]
    p1, p0 = sens["base"], sens["base"] * (1 + sens["bar_root_0"])
    names = {"bars": "the bars", "pillars": "the pillars", "fixed": "the whole wall"}
    others = "; ".join(f"{names.get(k, k)} held {1e3 * v:.3f}e-3 ({100 * (v / held['free'] - 1):+.0f} %)"
                       for k, v in held.items() if k not in ("free", "bars"))
    return ("**Where the frame's excess was.** The frame used to clamp each pillar at its bar's face, as the planar "
            "model does (its bars are rigid). In the printed sleeve and the solid the pillar's own material runs on "
            "through its bar, c / 2 high, to the clamped face or the plate's, and bends through the wall there too. "
            "The solid says this is the freedom that mattered: with its bars held at their radius (`bench_sleeve_ring3d.py "
            f"--held-p1`; four cells, mesh r = 1, two bricks through the wall) its first peak rises from "
            f"{1e3 * held['free']:.3f}e-3 to {1e3 * held['bars']:.3f}e-3 ({100 * (held['bars'] / held['free'] - 1):+.1f} %)"
            + (f" ({others}, towards the flat ring's)" if others else "") +
            f". The frame with its pillars clamped at the bars' faces peaks at {1e3 * p0:.3f}e-3, "
            f"{100 * (p0 / fpe - 1):+.0f} % over the solid's extrapolated {1e3 * fpe:.3f} +- {1e3 * efp:.3f}e-3 and "
            f"{100 * (p0 / held['bars'] - 1):+.0f} % off the solid with its bars held; with each pillar bending on "
            f"through its bar (`RingFrame(bar_root=1)`, the default now: the bar's height is the geometry's, nothing "
            f"fitted) at {1e3 * p1:.3f}e-3, {100 * (p1 / fpe - 1):+.1f} % off the solid's "
            f"({100 * efp / fpe:.1f} % its error bar; 12 elements per beam half, `p1_sensitivity`). Every frame "
            "figure in this section is of the frame with the roots.")


def timing_note(r):
    """``; the derivatives x times faster than the plain route, the path y times the planar model's`` when the
    run stored its baselines (``nonlinear_study``), else nothing."""
    if "reference_derivatives_seconds" not in r:
        return ""
    return (f"; one gradient and Hessian in {1e3 * r['derivatives_seconds']:.0f} ms, "
            f"{r['reference_derivatives_seconds'] / r['derivatives_seconds']:.1f} times faster than differencing each "
            f"element's whole energy, the path {r['seconds'] / r['planar_seconds']:.1f} times the planar model's "
            f"{r['planar_seconds']:.1f} s")


def summary(s, e=0.63):
    """How far the curved-to-flat ratios are from the solid's over the ring sizes, in per cent, as ``(lo, hi)``:
    ``"frame"`` plane stress with root extension ``e``, ``"all"`` every variant and root extension of the frame,
    ``"model"`` the beam model's curvature springs (calibrated; None when not stored); and how far the frame's
    curved stiffness itself is from the solid's: ``"absolute"`` (plane stress, ``e``), ``"absolute_bar0"`` (the
    same with the pillars clamped at the bars' faces; None when not stored)."""
    v = {k: [] for k in ("frame", "all", "model", "absolute", "absolute_bar0", "ext", "ext_error", "ext_ratio",
                         "ext_coarse")}
    E = f"{e:g}"
    for r in s["cells"].values():
        fe = r["fe_curved"] / r["fe_flat"]
        stress, flat = r[f"frame_stress_{E}"], r[f"frame_flat_{E}"]
        v["frame"].append(100 * (stress / flat / fe - 1))
        v["absolute"].append(100 * (stress / r["fe_curved"] - 1))
        x = r.get("solid_ext")
        if x:
            curved = x["curved"][0]
            v["ext"].append(100 * (stress / curved - 1))
            v["ext_error"].append(100 * x["curved"][1] / curved)
            v["ext_ratio"].append(100 * (stress / flat / (curved / x["flat"][0]) - 1))
            v["ext_coarse"].append(100 * (r["fe_curved"] / curved - 1))
        if f"frame_stress_{E}_bar0" in r:
            v["absolute_bar0"].append(100 * (r[f"frame_stress_{E}_bar0"] / r["fe_curved"] - 1))
        v["all"] += [100 * (r[f"frame_{k}_{x:g}"] / r[f"frame_flat_{x:g}"] / fe - 1) for x in s["root_extensions"]
                     for k, _, _ in VARIANTS]
        if "model_curved" in r:
            v["model"].append(100 * (r["model_curved"] / r["model_flat"] / fe - 1))
    out = {k: _span(v[k]) for k in ("frame", "all", "model", "absolute", "absolute_bar0")}
    out["extrapolated"] = ({"absolute": _span(v["ext"]), "error": _span(v["ext_error"]),
                            "ratio": _span(v["ext_ratio"]), "coarse": _span(v["ext_coarse"]), "sizes": len(v["ext"])}
                           if v["ext"] else None)
    return out


def _span(values):
    """``(min, max)`` of a list, ``None`` for an empty one."""
    return (min(values), max(values)) if values else None


def fe_secants(comp):
    """The four-cell solid's secant stiffness to d/L 0.01 on each in-plane mesh of the all-C3D20 family (one brick
    through the wall), ``[(mesh, k)]``, from the stored paths of ``fe-ring3d-comparison.json``."""
    out = []
    for r in (1, 2, 3, 4):
        run = comp.get(f"p1_r{r}_C3D20")
        if run:
            out.append((f"r = {r}", float(np.interp(0.01, run["d"], run["F"]) / 0.01)))
    return out


def coarse_note(secants, cells):
    """How stiff the table's coarse solid is against the finest stored mesh (four cells), one clause."""
    if not secants or "4" not in cells:
        return ""
    coarse = cells["4"]["fe_curved"]
    return (f"the solid's coarse mesh is itself {100 * (coarse / secants[-1][1] - 1):.0f} % stiffer than its finest "
            f"here (on four cells its secant to d/L 0.01 falls from {1e3 * secants[0][1]:.1f} to "
            f"{1e3 * secants[-1][1]:.1f} over the all-C3D20 family's {len(secants)} in-plane meshes, against "
            f"{1e3 * coarse:.1f} on this mesh), ")


def extrapolated_note(x, cells):
    """The frame against the solid extrapolated over its meshes (``summary``'s ``"extrapolated"``), one clause."""
    secs = [t for r in cells.values() for t in r["solid_ext"]["seconds"]]
    return (f"against the solid extrapolated over three in-plane meshes (r = 1, 2, 3, every brick C3D20, one brick "
            f"through the wall, flat on the same r; `bench_sleeve_ring3d.py --cells-meshes`, {min(secs):.0f}-"
            f"{max(secs):.0f} s per curved run) the frame's curved stiffness is {x['absolute'][0]:+.0f} to "
            f"{x['absolute'][1]:+.0f} % off at the {x['sizes']} ring sizes (the extrapolation's own error "
            f"{x['error'][0]:.1f}-{x['error'][1]:.1f} %) and its knock-down {x['ratio'][0]:+.0f} to "
            f"{x['ratio'][1]:+.0f} % off the extrapolated curved / flat; the table's coarse solid is "
            f"{x['coarse'][0]:+.0f} to {x['coarse'][1]:+.0f} % off the extrapolated one, ")


def markdown(s, extra=()):
    """The docs/sleeves.md section (between ``MARK_BEGIN`` and ``MARK_END``), ending with the ``extra``
    paragraphs (the frame with the solid's plate, ``fe_frame3d_plate.markdown``)."""
    cells = s["cells"]
    e0, e1 = s["root_extensions"][0], s["root_extensions"][-1]
    ext = all(r.get("solid_ext") for r in cells.values())
    L = [MARK_BEGIN, "", "### A linear 3-D frame of the curved ring (issue 18)", "",
         "Regenerated by `benchmarks/bench_sleeve_frame3d.py` (model: `metamaterial_wb/core/sleeve/frame3d.py`, "
         "report: `metamaterial_wb/bench/fe_frame3d.py`). The beam model's own mesh of a uniform ring "
         f"({s['n_el']} elements per beam half, pillars of {3} elements, rigid links and bars), wrapped onto the "
         "cylinder R = N W / 2 pi and solved as a linear 3-D frame: every element a straight beam between its "
         "wrapped nodes that bends in the wall (the model's EI), bends through the wall (b T^3 / 12, b the "
         "element's width in the plane) and twists (G J of the b x T rectangle); each pillar goes on bending "
         "through the wall inside its bar, down to the clamped face or up to the plate's (rigid in the plane, as "
         "the bars: `bar_root`, \"Where the frame's excess was\" below); bottom bar clamped, top bar raised without "
         "tilt. Flat, the same frame is the beam model's linear flat ring (to 1e-10 with the pillars clamped at the "
         "bars' faces, as the model's; 1e-3 with the roots). Initial "
         "axial stiffness, F / (G L^2) per d/L x1e-3, and the curvature's knock-down curved / flat:", "",
         "| N | solid: flat | solid: curved | solid: curved / flat | frame: curved / flat, " +
         " | frame: curved / flat, ".join(f"{k} ({'documented' if e == e0 else 'calibrated'})"
                                          for e in (e0, e1) for k, _, _ in VARIANTS) +
         " | beam model (springs, calibrated): curved / flat | frame (stress, calibrated) / solid, curved | "
         "the same, pillars clamped at the bars' faces / solid, curved | "
         "beam model (calibrated) / solid, curved | frame / solid run time |" +
         (" solid: curved, extrapolated (r = 1, 2, 3, all C3D20) | frame (stress, calibrated) / extrapolated solid |"
          if ext else ""),
         "|---|---|---|---|" + "---|" * (2 * len(VARIANTS)) + "---|---|---|---|---|" + ("---|---|" if ext else "")]
    for n, r in cells.items():
        fe = r["fe_curved"] / r["fe_flat"]
        ratios = " | ".join(f"{r[f'frame_{k}_{e:g}'] / r[f'frame_flat_{e:g}']:.2f}" for e in (e0, e1)
                            for k, _, _ in VARIANTS)
        mo = r["model_curved"] / r["model_flat"] if "model_curved" in r else np.nan
        L.append(f"| {n} | {1e3 * r['fe_flat']:.1f} | {1e3 * r['fe_curved']:.1f} | {fe:.2f} | {ratios} | {mo:.2f} | "
                 f"{r[f'frame_stress_{e1:g}'] / r['fe_curved']:.2f} | "
                 f"{r.get(f'frame_stress_{e1:g}_bar0', np.nan) / r['fe_curved']:.2f} | "
                 f"{r['model_curved'] / r['fe_curved'] if 'model_curved' in r else np.nan:.2f} | "
                 f"{r['frame_s']:.2f} s / {r.get('wall_s', np.nan):.0f} s |" +
                 (f" {1e3 * r['solid_ext']['curved'][0]:.1f} +- {1e3 * r['solid_ext']['curved'][1]:.1f} | "
                  f"{r[f'frame_stress_{e1:g}'] / r['solid_ext']['curved'][0]:.2f} |" if ext else ""))
    note = solid_order_note([(n, r["solid_ext"]) for n, r in cells.items()], ("curved",)) if ext else ""
    L += ["", note] if note else []
    sm = summary(s, e1)
    L += ["", "Variants: " + "; ".join(f"{k}: {label}" for k, _, label in VARIANTS) + ".", "",
          f"**Reading.** The frame gives the solid's curvature knock-down where the beam model's springs do not: "
          f"plane stress and calibrated, its curved / flat ratio is {sm['frame'][0]:+.0f} to {sm['frame'][1]:+.0f} % "
          f"off the solid's over {len(cells)} ring sizes, every variant {sm['all'][0]:+.0f} to {sm['all'][1]:+.0f} %"
          + (f", the beam model's springs {sm['model'][0]:+.0f} to {sm['model'][1]:+.0f} %" if sm["model"] else "") +
          " (the flat denominators are plane strain on both sides, so plane stress carries the solid's loss of "
          "the plane-strain restraint too; the solid is the coarse mesh r = 1 on both sides). So the missing mechanism is the one the frame adds - the wall's bending through its thickness and "
          "twisting, the pillars swinging out of the cylinder - and a thin-beam model holds it; the solid is not "
          "needed to see it. The frame's curved stiffness itself is "
          f"{sm['absolute'][0]:+.0f} to {sm['absolute'][1]:+.0f} % off the solid's" +
          (f" (with the pillars clamped at the bars' faces {sm['absolute_bar0'][0]:+.0f} to "
           f"{sm['absolute_bar0'][1]:+.0f} %)" if sm["absolute_bar0"] else "") +
          "; " + (extrapolated_note(sm["extrapolated"], cells) if ext and sm["extrapolated"] else
                  coarse_note(s.get("fe_secants"), cells)) + "and the frame carries the flat calibration's own offset (the calibration fitted the cell's peak, not its "
          "stiffness) and the linear-to-secant gap. Linear here; the nonlinear frame follows. The "
          "beam model's ring forces are still quoted with their measured error (`accuracy`).", ""]
    if ext:
        L += [f"![initial stiffness by ring size: the solid on three meshes and extrapolated, the frame and the planar "
              f"model]({IMG_STIFFNESS})", ""]
    if s.get("nonlinear") and s.get("fe_family") and s.get("planar_calibrated"):
        L += [nonlinear_markdown(s["nonlinear"], s["fe_family"], s["planar_calibrated"], s.get("p1_sensitivity")), "",
              f"![the nonlinear frame against the curved solid and the planar beam model]({IMG})", ""]
        br = bar_root_markdown(s.get("p1_sensitivity"), s.get("held", {}), s["fe_family"])
        L += [br, ""] if br else []
    L += list(extra) + [MARK_END, ""]
    return "\n".join(L)


def write(doc_path, section):
    """``doc_path``'s text with the section replaced, or inserted after the curved FE ring's section."""
    with open(doc_path) as f:
        text = f.read()
    if MARK_BEGIN in text and MARK_END in text:
        a, b = text.index(MARK_BEGIN), text.index(MARK_END) + len(MARK_END) + 1
        return text[:a] + section + text[b:]
    anchor = "<!-- fe-ring3d:end -->\n"
    i = text.index(anchor) + len(anchor) if anchor in text else len(text)
    return text[:i] + "\n" + section + text[i:]


def plot_nonlinear(nl, solid, model, path):
    """The nonlinear frame's paths, the curved solid's finest path (``solid``: ``{"d", "F", "label"}``) and the
    planar beam model's calibrated curved ring (``model``: ``{"d", "F"}``)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(7.0, 4.2), dpi=110)
    ax.plot(solid["d"], 1e3 * np.asarray(solid["F"]), "k-", lw=1.6, label=solid["label"])
    for (n_el, r), col in zip(sorted(nl.items(), key=lambda kv: int(kv[0])), ("C1", "C0")):
        ax.plot(r["d"], 1e3 * np.asarray(r["F"]), "--", color=col, lw=1.3,
                label=f"nonlinear 3-D frame, {n_el} elements per beam half")
    ax.plot(model["d"], 1e3 * np.asarray(model["F"]), ":", color="C3", lw=1.3,
            label="planar beam model, curved, calibrated")
    ax.axhline(0, color="k", lw=0.5)
    ax.set_xlabel("d / L")
    ax.set_ylabel("F / (G L^2) x1e-3")
    ax.set_title("four-cell curved ring: the 3-D frame against the solid", fontsize=9)
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def plot_stiffness(s, path, e=0.63):
    """The rings' initial stiffness by ring size (left) and against the extrapolated solid (right): the solid on each
    of its meshes and extrapolated (with its error bar), the table's coarse solid, the linear frame (plane stress,
    calibrated) and the planar beam model (calibrated), F / (G L^2) per d/L."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    rows = sorted(((int(n), r) for n, r in s["cells"].items() if r.get("solid_ext") and "model_curved" in r),
                  key=lambda nr: nr[0])
    if not rows:
        return False
    N = np.array([n for n, _ in rows])
    ext = np.array([r["solid_ext"]["curved"][:2] for _, r in rows])
    series = [(f"curved solid, mesh r = {k + 1} (all C3D20)", mk, "0.55", "none",
               [r["solid_ext"]["curved_meshes"][k] for _, r in rows]) for k, mk in enumerate(("v", "<", ">"))]
    series += [("curved solid, the table's coarse mesh", "x", "0.3", "none", [r["fe_curved"] for _, r in rows]),
               ("linear 3-D frame (plane stress, calibrated)", "s", "C0", "-", [r[f"frame_stress_{e:g}"] for _, r in rows]),
               ("planar beam model, curved, calibrated", "^", "C3", ":", [r["model_curved"] for _, r in rows])]
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(10.5, 4.2), dpi=100)
    for label, mk, col, ls, v in series:
        v = np.asarray(v)
        ax.plot(N, 1e3 * v, marker=mk, color=col, ls=ls, ms=5, label=label)
        bx.plot(N, v / ext[:, 0], marker=mk, color=col, ls=ls, ms=5)
    ax.errorbar(N, 1e3 * ext[:, 0], yerr=1e3 * ext[:, 1], fmt="ko", capsize=3, ms=5,
                label="curved solid, extrapolated (+- its error)")
    bx.errorbar(N, np.ones(len(N)), yerr=ext[:, 1] / ext[:, 0], fmt="ko", capsize=3, ms=5)
    ax.set_ylabel("initial stiffness, F / (G L^2) per d/L x1e-3")
    bx.set_ylabel("against the extrapolated solid")
    bx.set_yscale("log")
    bx.set_yticks([0.8, 1.0, 1.25, 1.5, 2, 2.5, 3, 3.5])
    bx.get_yaxis().set_major_formatter(matplotlib.ticker.ScalarFormatter())
    for a_ in (ax, bx):
        a_.set_xlabel("cells around the ring, N")
        a_.set_xticks(N)
        a_.grid(alpha=0.3)
    ax.set_title("curved ring's initial stiffness by ring size", fontsize=9)
    bx.set_title("each over the solid extrapolated in its mesh", fontsize=9)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
    return True
