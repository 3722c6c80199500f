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

from metamaterial_wb.bench.fe_ring3d import (MARK_BEGIN, MARK_END, MESHES, cell_geometry, curved_summary,  # noqa: E402
                                             markdown, plot)
from metamaterial_wb.core.fileio import write_atomic  # noqa: E402
from metamaterial_wb.fe.sleeve_check import secant  # noqa: E402

RESULTS = os.path.join(ROOT, "benchmarks", "results")
STORE = os.path.join(RESULTS, "fe-ring3d.json")
DOC = os.path.join(ROOT, "docs", "sleeves.md")
IMG = "img/sleeve-fe-ring3d.png"
BIAS = 1e-5                                    # the tilt bias (G L^2) of the static runs (sleeve3d default)


def run_fe(r=1, n_layers=1, d_max=0.7, increments=140, timeout_s=5400.0, radial="free", bias=1e-5, method="dynamic",
           patient=False, imperfection=None, bias_angle=0.5, full_near=0.0, full_low=False, element="C3D20R"):
    from metamaterial_wb.fe import sleeve3d
    g = cell_geometry()
    c, info = sleeve3d.solve_ring3d(g, 4, r, n_layers, d_max=d_max * g.L, increments=increments, bias=bias,
                                    timeout_s=timeout_s, partial=True, radial=radial,
                                    method=method, patient=patient, imperfection=imperfection,
                                    bias_angle=bias_angle, full_near=full_near, full_low=full_low,
                                    element=element)
    info.pop("log_tail", None)
    return {"r": r, "n_layers": n_layers, "radial": radial, "d": c["d"].tolist(), "F": c["F"].tolist(),
            "tilt_rad": c["tilt_rad"].tolist(), "info": info,
            "extrema": sleeve3d.all_extrema(c["d"], c["F"])}


def _probe_run(mesh, d, n_eig=6, timeout_s=5400.0, shapes=False, full_near=0.0, n_cells=4, element="C3D20R"):
    """``sleeve3d.solve_ring3d``'s static path on ``mesh`` to ``d`` (d/L, 0.01 per increment) with ``n_eig``
    eigenvalues of the tangent stiffness there (``full_near``: the beam's corner bricks C3D20; ``n_cells``
    around, every brick ``element``): ``(curve, info)``."""
    from metamaterial_wb.fe import sleeve3d
    g = cell_geometry()
    r, nl = MESHES[mesh]
    return sleeve3d.solve_ring3d(g, n_cells, r, nl, d_max=d * g.L, increments=max(1, int(round(100 * d))),
                                 timeout_s=timeout_s, partial=True, method="static", stability=n_eig, shapes=shapes,
                                 full_near=full_near, element=element)


def probe_key(mesh, d, full_near=0.0, n_cells=4, element="C3D20R"):
    """Where a stability probe is stored under ``"stability"``: ``<mesh>[_full<mm>][_cells<n>][_C3D20]@<d>``."""
    return (mesh + (f"_full{full_near:g}" if full_near else "") + (f"_cells{n_cells}" if n_cells != 4 else "")
            + ("_C3D20" if element == "C3D20" else "") + f"@{d:.3f}")


def stability_probe(mesh, d, n_eig=6, timeout_s=5400.0, full_near=0.0, n_cells=4, element="C3D20R"):
    """The static path on ``mesh`` to ``d`` and the eigenvalues of the tangent stiffness there (``_probe_run``),
    as stored."""
    from metamaterial_wb.fe import sleeve3d
    c, info = _probe_run(mesh, d, n_eig, timeout_s, full_near=full_near, n_cells=n_cells, element=element)
    st = info.get("stability")
    out = {"mesh": mesh, "d": d, "d_reached": info["d_reached"], "F": float(c["F"][-1]), "wall_s": info["wall_s"],
           "density": sleeve3d.DENSITY, "stopped": info.get("stopped"), "full_near": full_near, "n_cells": n_cells,
           "element": element}
    if st:
        out.update(eigenvalues=st["eigenvalues"], plate_rotation=st["plate_rotation"], stable=st["stable"])
    return out


def mode_pattern(mesh, u):
    """A mode's share per cell (RMS displacement over each cell's nodes, relative to the largest): tells a mode
    alike in every cell from one that moves some cells only."""
    X = mesh.nodes
    phi = np.mod(np.arctan2(X[:, 1], X[:, 0]) + np.pi / mesh.cells, 2 * np.pi)
    cell = np.minimum((phi / (2 * np.pi / mesh.cells)).astype(int), mesh.cells - 1)
    rms = np.array([np.sqrt(np.mean(np.sum(u[cell == k] ** 2, axis=1))) for k in range(mesh.cells)])
    return (rms / rms.max()).tolist()


def branch(mesh, d_at, amp=0.01, d_max=0.7, timeout_s=5400.0):
    """Branch switching: the static path's lowest mode at ``d_at`` (``stability_probe`` with shapes), scaled to
    ``amp`` t at its largest, as a geometric imperfection; the imperfect ring's static path to ``d_max``."""
    from metamaterial_wb.fe import sleeve3d
    g = cell_geometry()
    r, nl = MESHES[mesh]
    c, info = _probe_run(mesh, d_at, 6, timeout_s, shapes=True)
    st = info["stability"]
    k = int(np.argmin(st["eigenvalues"]))
    u = c["modes"][k]
    ring = sleeve3d.ring_mesh(g, 4, r, nl)
    imp = amp * g.t * u / np.abs(u).max()
    tr = run_fe(r, nl, d_max=d_max, increments=int(round(100 * d_max)), timeout_s=timeout_s, method="static",
                imperfection=imp)
    tr["imperfection"] = {"mesh": mesh, "d_at": d_at, "amp_t": amp, "eigenvalue_rho": st["eigenvalues"][k] * sleeve3d.DENSITY,
                          "plate_rotation_size": st["plate_rotation_size"][k], "cells": mode_pattern(ring, u),
                          "probe_wall_s": info["wall_s"]}
    return tr


def stiffness_check(kinds=("flat", "fixed", "free", "free_layers2")):
    """Secant stiffness to d/L 0.005 of the flat ring and of the curved one (two increments to d/L 0.01)."""
    from metamaterial_wb.fe import sleeve2d, sleeve3d
    g = cell_geometry()
    out = {}
    for k in kinds:
        if k == "flat":
            c, info = sleeve2d.solve_ring(g, 4, 1, d_max=0.01 * g.L, increments=2, timeout_s=600)
        else:
            nl = 2 if "layers2" in k else 1
            r = 2 if "r2" in k else 1
            radial = "fixed" if k == "fixed" else k[len("fixed_"):] if k.startswith("fixed_") else "free"
            c, info = sleeve3d.solve_ring3d(g, 4, r, nl, d_max=0.01 * g.L, increments=2, timeout_s=900,
                                            radial=radial,
                                            element="C3D20" if "full" in k else "C3D20R")
        out[k] = {"k": secant(c["d"], c["F"]), "wall_s": info["wall_s"],
                  "dofs": info["dofs"], "d": c["d"].tolist(), "F": c["F"].tolist()}
        print(k, out[k]["k"], info["wall_s"], flush=True)
    return out


def cells_check(ns=(4, 6, 8, 12)):
    """How the curvature's softening falls with the ring's size: the secant stiffness to d/L 0.005 of the flat
    2-D ring and the curved 3-D one (r = 1, two bricks through the wall: the same two increments without cut-backs)
    of ``n`` cells. Stored per ``n``; the beam model's rings are added by ``cells_model`` (no ccx)."""
    from metamaterial_wb.fe import sleeve2d, sleeve3d
    g = cell_geometry()
    out = {}
    for n in ns:
        flat, fi = sleeve2d.solve_ring(g, n, 1, d_max=0.01 * g.L, increments=2, timeout_s=900)
        curved, ci = sleeve3d.solve_ring3d(g, n, 1, 2, d_max=0.01 * g.L, increments=2, timeout_s=1800)
        out[str(n)] = {"radius_mm": ci["radius_mm"], "fe_flat": secant(flat["d"], flat["F"]),
                       "fe_curved": secant(curved["d"], curved["F"]), "wall_s": fi["wall_s"] + ci["wall_s"]}
        print(n, out[str(n)], flush=True)
    return out


def cells_meshes(ns=(4, 6, 8, 12), meshes=("r1", "r2", "r3")):
    """The ``cells_check`` stiffness on finer meshes: the secant to d/L 0.005 of the curved ring (every brick
    C3D20, one brick through the wall, in-plane refinement r; the four-cell path family's meshes) and of the flat
    2-D ring on the same r, per ring size and mesh: ``c3d20_<mesh>_fe_curved``, ``<mesh>_fe_flat`` and their
    seconds (``..._wall_s``), extrapolated by ``fe_frame3d.solid_extrapolated``."""
    from metamaterial_wb.fe.sleeve_check import ring_stiffness
    g = cell_geometry()
    out = {}
    for n in ns:
        row = out.setdefault(str(n), {})
        for m in meshes:
            r, layers = MESHES[m]
            row.update(_flat_row(g, n, m))
            k, wall_s = ring_stiffness(g, n, r, layers, "C3D20")
            row.update({f"c3d20_{m}_fe_curved": k, f"c3d20_{m}_fe_curved_wall_s": wall_s})
            print(n, m, {k: v for k, v in row.items() if k.startswith((m, f"c3d20_{m}"))}, flush=True)
    return out


def _flat_row(g, n, mesh):
    """The flat 2-D ring's secant stiffness on in-plane mesh ``mesh`` ("r<k>"): ``{"<mesh>_fe_flat",
    "<mesh>_fe_flat_wall_s"}`` (two increments to d/L 0.01, the whole run required)."""
    from metamaterial_wb.fe import sleeve2d
    flat, fi = sleeve2d.solve_ring(g, n, int(mesh[1:]), d_max=0.01 * g.L, increments=2, timeout_s=1800)
    return {f"{mesh}_fe_flat": secant(flat["d"], flat["F"]), f"{mesh}_fe_flat_wall_s": fi["wall_s"]}


def cells_flat(ns=(4, 6, 8, 12), meshes=("r4", "r8")):
    """The flat 2-D ring's stiffness alone on finer in-plane meshes (``fe_frame3d.FLAT_MESHES``: its r = 1 mesh is
    not yet in the asymptotic range, so the flat extrapolation uses r = 2, 4, 8), per ring size and mesh."""
    g = cell_geometry()
    out = {}
    for n in ns:
        for m in meshes:
            out.setdefault(str(n), {}).update(_flat_row(g, n, m))
            print(n, m, out[str(n)], flush=True)
    return out


CELLS_P1_MESH = "layers2"                       # the cells_p1 runs' default mesh (fe_ring3d_paths.MESHES)


def cells_p1_prefix(element="C3D20R", bias=BIAS, mesh=CELLS_P1_MESH):
    """The prefix of a ``cells_p1`` run's fields: ``c3d20_`` for every brick fully integrated, ``bias<b>_`` for a
    tilt bias other than the default (a larger one follows a tilted branch past a bifurcation smoothly),
    ``<mesh>_`` for a mesh other than the default (r = 1, two bricks through the wall)."""
    return (("c3d20_" if element == "C3D20" else "") + (f"bias{bias:g}_" if bias != BIAS else "")
            + (f"{mesh}_" if mesh != CELLS_P1_MESH else ""))


def cells_p1(ns=(4, 8), d_max=0.17, element="C3D20R", bias=BIAS, timeout_s=5400.0, mesh=CELLS_P1_MESH,
             bias_ramp=None):
    """The curved ring's first peak by ring size: static, mesh r = 1 with two bricks through the wall (0.01 d/L per
    increment, where the four-cell ring's P1 is within a few per cent of its three-mesh extrapolation; ``mesh``:
    another of ``MESHES``). With ``element="C3D20"`` every brick is fully integrated; the fields' prefix:
    ``cells_p1_prefix``. The bias moment grows with the rise, to ``bias`` at ``d_max``, or at ``bias_ramp`` (d/L)
    if given: a run stopped short of a longer one then sees the same bias at every rise (``bias * d_max /
    bias_ramp`` applied at ``d_max``). The beams' ends are printed at every increment: ``p1_rises`` (per point,
    per beam half: ``sleeve3d.hysterons``) with the halves' edge pillars ``p1_units`` and their snap height
    ``p1_snap_height`` (h / L) give the snapped hysterons."""
    from metamaterial_wb.fe import sleeve3d
    from metamaterial_wb.fe.sleeve_check import first_peak
    g = cell_geometry()
    r, n_layers = MESHES[mesh]
    applied = bias if bias_ramp is None else bias * d_max / bias_ramp
    out = {}
    for n in ns:
        ring = sleeve3d.ring_mesh(g, n, r, n_layers)
        ends = ring.beam_ends()
        watch = np.concatenate([ends["outer"].ravel(), ends["inner"].ravel()])
        c, info = sleeve3d.solve_ring3d(g, n, r, n_layers, d_max=d_max * g.L, increments=int(round(100 * d_max)),
                                        timeout_s=timeout_s, partial=True, element=element, bias=applied,
                                        watch=watch)
        rises, _snapped = sleeve3d.hysterons(ring, ends, c["u_watch"], watch)
        at, P1 = first_peak(c["d"], c["F"])
        ok = bool(np.isfinite(P1))                     # None: no peak before the run ended (see p1_stopped)
        pre = cells_p1_prefix(element, bias, mesh)
        row = {"fe_curved_p1": float(P1) if ok else None, "fe_curved_p1_d": float(at) if ok else None,
               "p1_wall_s": info["wall_s"], "p1_d_reached": info["d_reached"],
               "p1_stopped": info.get("stopped", "")[:200], "p1_curve": {"d": c["d"].tolist(), "F": c["F"].tolist()},
               "p1_tilt_deg_max": float(np.degrees(np.hypot(*np.asarray(c["tilt_rad"]).T)).max()),
               "p1_tilt_deg": np.degrees(np.hypot(*np.asarray(c["tilt_rad"]).T)).tolist(), "p1_bias": bias,
               "p1_bias_ramp": bias_ramp if bias_ramp is not None else d_max, "p1_mesh": mesh,
               "p1_extrema": sleeve3d.all_extrema(c["d"], c["F"]),
               "p1_rises": np.round(rises, 6).tolist(), "p1_units": ends["units"].tolist(), "p1_snap_height": g.h / g.L}
        out[str(n)] = {pre + k: v for k, v in row.items()}
        print(n, out[str(n)], flush=True)
    return out


def held_p1(parts=("bars", "fixed", "pillars"), timeout_s=3600.0):
    """The four-cell curved ring's first peak with one part of the wall held at its radius (``radial=<part>``;
    ``"fixed"``: all of it), on the ``cells_p1`` mesh and steps (r = 1, two bricks through the wall, 0.01 d/L per
    increment, C3D20R): which freedom the frame's pillars clamped at their bars' faces were missing
    (docs/sleeves.md). Beside ``cells["4"]["fe_curved_p1"]``, the same ring free."""
    from metamaterial_wb.fe import sleeve3d
    from metamaterial_wb.fe.sleeve_check import first_peak
    g = cell_geometry()
    out = {}
    for part in parts:
        c, info = sleeve3d.solve_ring3d(g, 4, 1, 2, d_max=0.17 * g.L, increments=17, timeout_s=timeout_s,
                                        partial=True, radial=part)
        at, P1 = first_peak(c["d"], c["F"])
        out[part] = {"p1": float(P1), "p1_d": float(at), "wall_s": info["wall_s"], "d_reached": info["d_reached"],
                     "stopped": info.get("stopped", "")[:300], "d": c["d"].tolist(), "F": c["F"].tolist()}
        print(part, out[part]["p1"], out[part]["p1_d"], f"{info['wall_s']:.0f} s", flush=True)
    return out


def cells_model(cells, e, n_el=24):
    """The beam model's flat and curved rings of every stored size, as documented (root extension 0) and
    calibrated (``e``): the same secant as ``cells_check``."""
    from metamaterial_wb.fe.sleeve2d import peak_valley
    out = {}
    for n, row in cells.items():
        row = dict(row)
        for key, ext, curv in (("model_flat", e, False), ("model_curved", e, True),
                               ("model_flat_documented", 0.0, False), ("model_curved_documented", 0.0, True)):
            p = _model_ring(int(n), n_el, 0.01, 2, root_extension=ext, curvature=curv)
            row[key] = secant(p.d, p.F)
        if row.get("fe_curved_p1") is not None:        # its first peak too, where the FE's was found
            for key, ext in (("model_curved_p1", e), ("model_curved_documented_p1", 0.0)):
                p = _model_ring(int(n), n_el, 0.3, 60, root_extension=ext)
                row[key + "_d"], row[key] = (float(v) for v in peak_valley(p.d, p.F)[:2])
        out[n] = row
    return out


def _model_ring(n, n_el, d_max, steps, **kw):
    """The beam model's uniform ring of ``n`` seed cells (imperfection 1e-4, as the calibration's), traced to
    ``d_max`` in ``steps``; ``kw``: ``SleeveModel`` options."""
    from metamaterial_wb.bench.fe_sleeve_calibration import _geom
    from metamaterial_wb.core.sleeve.model import SleeveModel
    return SleeveModel([_geom()], [[0] * n], n_el, imperfection=1e-4, **kw).trace(np.linspace(0, d_max, steps + 1))


def _load():
    return json.load(open(STORE)) if os.path.exists(STORE) else {}


def _store_rows(key, rows):
    """Each row of ``rows`` (a dict of dicts) merged field by field into the row stored under ``key``: a rerun of
    one study keeps that row's other studies' fields."""
    data = _load().get(key, {})
    _store(key, {n: dict(data.get(n, {}), **v) for n, v in rows.items()}, merge=True)


def _store(key, value, merge=False):
    """``value`` under ``key`` in the store, read just before it is written (runs in parallel store too); with
    ``merge`` the entries of the dict ``value`` are added to those stored under ``key``."""
    data = _load()
    data[key] = dict(data.get(key, {}), **value) if merge else value
    write_atomic(STORE, json.dumps(data, indent=1))


def model_curve(e, curvature, n_el=24, d_max=0.7, steps=140):
    """The beam model's four-cell ring (as in fe_sleeve_calibration: imperfection 1e-4), root extension ``e``."""
    from metamaterial_wb.bench.fe_sleeve_calibration import model_ring
    from metamaterial_wb.fe.sleeve3d import all_extrema
    t0 = time.perf_counter()
    p = model_ring(e, n_el, d_max=d_max, steps=steps, curvature=curvature)
    return {"n_el": n_el, "root_extension": e, "curvature": curvature, "d": p.d.tolist(), "F": p.F.tolist(),
            "tilt_deg": np.degrees(np.hypot(*np.asarray(p.tilt).T)).tolist(), "extrema": all_extrema(p.d, p.F),
            "wall_s": time.perf_counter() - t0}


def model_relief(e, n_el=24):
    """The beam model's (root extension ``e``) answer to the same initial-stiffness question: its secant stiffness
    to d/L 0.005 and its first peak, flat and curved with the pillar tips guided (default) or free, plane strain
    (as calibrated) and plane stress (the curved solid's narrow beams are free through the wall)."""
    from metamaterial_wb.fe.sleeve2d import peak_valley
    out = {}
    for key, kw in (("flat", {"curvature": False}), ("guided", {"pillar_tip": "guided"}),
                    ("free", {"pillar_tip": "free"}), ("guided_stress", {"pillar_tip": "guided", "plane": "stress"}),
                    ("free_stress", {"pillar_tip": "free", "plane": "stress"})):
        p = _model_ring(4, n_el, 0.3, 60, root_extension=e, **kw)
        at, P1 = peak_valley(p.d, p.F)[:2]
        out[key] = {"k": secant(p.d, p.F), "P1": float(P1), "P1_at": float(at)}
    return out


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
                "flat_calibrated": model_curve(e, False), "model_relief": model_relief(e)})
    for k in ("stiffness", "stability", "combinations"):
        if k in data:
            out[k] = data[k]
    if "cells" in data:
        out["cells"] = cells_model({n: {k: v for k, v in row.items() if not k.startswith("model_")}
                                    for n, row in data["cells"].items()}, e)
    for k in (["trace", "p1_r2", "p1_r3", "p1_layers2", "p1_r2layers2", "radial_fixed", "branch_r2"]
              + [k for k in data if k.startswith(("attempt_", "p1_r1_full", "p1_r2_full", "p1_r3_full")) or k.endswith("_C3D20")]):
        if k in data:
            out[k] = dict(data[k], tilt_deg=np.degrees(np.hypot(*np.asarray(data[k]["tilt_rad"]).T)).tolist())
    return out


def write(c):
    from metamaterial_wb.bench.fe_sleeve import write_section
    section = markdown(c, IMG)
    plot(c, os.path.join(ROOT, "docs", IMG))
    from metamaterial_wb.bench.fe_ring3d_corner import IMG as CORNER_IMG, plot_family
    plot_family(c, os.path.join(ROOT, "docs", CORNER_IMG))
    write_atomic(DOC, write_section(DOC, section, MARK_BEGIN, MARK_END))
    summ = curved_summary(c)
    spath = os.path.join(RESULTS, "fe-study.json")
    if summ and os.path.exists(spath):
        from metamaterial_wb.bench import fe_study
        full = json.load(open(spath))
        full["sleeve_curved"] = summ
        write_atomic(spath, json.dumps(full, indent=1))              # the study holds NaN (write_json refuses it)
        fe_study.write_fidelity_section(full, os.path.join(ROOT, "docs", "fidelity.md"))
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
    ap.add_argument("--p1-mesh", default=None, help="a finer mesh, static past the first peak: 'r2', 'r3', 'layers2' or 'r2layers2'")
    ap.add_argument("--stiffness", default=None, help="comma list of initial-stiffness runs: flat,fixed,free,"
                    "free_layers2,free_r2, or fixed_<part> with a part of sleeve3d.PARTS held at its radius (stored under "
                    "'stiffness', merged)")
    ap.add_argument("--p1-dmax", type=float, default=0.17, help="d/L of the P1 mesh run (static, 0.01 per increment)")
    ap.add_argument("--p1-increments", type=int, default=None, help="increments of the P1 mesh run (default 100 "
                    "per d/L; another count is stored apart, as p1_<mesh>_inc<N>)")
    ap.add_argument("--p1-full-near", type=float, default=0.0, help="mm: the beam's bricks within it of its "
                    "re-entrant corners fully integrated (C3D20) in the P1 mesh run (stored as p1_<mesh>..._full<mm>)")
    ap.add_argument("--p1-full-low", action="store_true", help="with --p1-full-near: the bricks of the beam's "
                    "continuation into the edge pillar (edge_pillar_low) near its side too (stored as ..._full<mm>low)")
    ap.add_argument("--p1-element", default="C3D20R", choices=("C3D20R", "C3D20"), help="the P1 mesh run's "
                    "bricks: C3D20 integrates every brick fully (no spurious modes anywhere; stored as ..._C3D20)")
    ap.add_argument("--stability-at", default=None, help="comma list of d/L: the static path's stability there "
                    "(eigenvalues of the tangent stiffness; stored under 'stability', merged)")
    ap.add_argument("--stability-mesh", default="r2", choices=sorted(MESHES))
    ap.add_argument("--stability-full-near", type=float, default=0.0, help="mm: the probes' path with the beam's "
                    "corner bricks fully integrated (stored as <mesh>_full<mm>@<d>)")
    ap.add_argument("--stability-cells", type=int, default=4, help="the probes' ring size (cells around)")
    ap.add_argument("--stability-element", default="C3D20R", choices=("C3D20R", "C3D20"), help="the probes' bricks")
    ap.add_argument("--branch-at", type=float, default=None, help="d/L: the lowest mode of the static path "
                    "(--stability-mesh) there, as an imperfection of --branch-amp t; the imperfect ring's path")
    ap.add_argument("--branch-amp", type=float, default=0.01)
    ap.add_argument("--radial-fixed", action="store_true", help="the check with the wall held at its radius")
    ap.add_argument("--cells", default=None, help="comma list of ring sizes (cells around): the flat and the curved "
                    "ring's initial stiffness, FE and beam model (stored under 'cells', merged)")
    ap.add_argument("--cells-meshes", default=None, help="comma list of meshes (r1,r2,r3): the --cells stiffness "
                    "of 4, 6, 8, 12 cells on each, every brick C3D20, one brick through the wall, "
                    "and the flat ring on the same r (stored under 'cells', merged; extrapolated in the frame's table)")
    ap.add_argument("--cells-flat", default=None, help="comma list of in-plane meshes r<k> (e.g. r4,r8): the flat "
                    "2-D ring alone on each, for the 4, 6, 8, 12 cells (ccx, 10 s to 3 min each; stored under 'cells', "
                    "merged; the flat extrapolation uses fe_frame3d.FLAT_MESHES)")
    ap.add_argument("--cells-p1", default=None, help="comma list of ring sizes: the curved ring's first peak (ccx, "
                    "static, r = 1 with two bricks through the wall; stored under 'cells', merged)")
    ap.add_argument("--cells-p1-bias", type=float, default=BIAS, help="the --cells-p1 runs' tilt bias (G L^2); "
                    "another than the default is stored with the prefix bias<b>_")
    ap.add_argument("--cells-p1-dmax", type=float, default=0.17, help="d/L of the --cells-p1 runs")
    ap.add_argument("--cells-p1-mesh", default=CELLS_P1_MESH, choices=sorted(MESHES), help="the --cells-p1 runs' "
                    "mesh (another than the default is stored with the prefix <mesh>_)")
    ap.add_argument("--cells-p1-bias-ramp", type=float, default=None, help="d/L at which the --cells-p1 bias "
                    "reaches --cells-p1-bias (default: at --cells-p1-dmax); a shorter run then sees a longer one's bias")
    ap.add_argument("--cells-p1-element", default="C3D20R", choices=("C3D20R", "C3D20"), help="the --cells-p1 "
                    "runs' bricks (C3D20: every brick fully integrated, stored with the prefix c3d20_)")
    ap.add_argument("--held-p1", default=None, help="comma list of parts (sleeve3d.PARTS or 'fixed'): the four-cell "
                    "ring's first peak with that part held at its radius (ccx, 2-5 min each)")
    ap.add_argument("--combinations", default=None, help="comma list of <combination>:<mesh> (mesh r1, r2 or r3): "
                    "each cell type of the seed's combination as a uniform four-cell ring (ccx, every brick C3D20, "
                    "static to d/L 0.7), two runs at a time; stored under 'combinations' as each ends")
    ap.add_argument("--mixed-cycles", default=None, help="comma list of <combination>:<mesh>[:dynamic|:unbiased] "
                    "(mesh r1, r2 or r3): the seed's mixed ring [0, 0, 1, 1] on the solid (ccx, every brick C3D20) "
                    "raised to d/L 0.7 and lowered back, static (and the shorter type's uniform ring at its flat top), "
                    "by implicit dynamics, or static without the plate's bias moment; stored under 'mixed_cycles' as "
                    "each ends")
    ap.add_argument("--stacked-solid", default=None, help="comma list of <combination>:<mesh> (mesh r1, r2 or r3): "
                    "the seed's two types as two stacked uniform rings on the solid (ccx, every brick C3D20, a free "
                    "plate between them), raised to d/L 1.4 and lowered back by implicit dynamics; stored under "
                    "'stacked_solid' as each ends")
    ap.add_argument("--stacked-damping", type=float, default=0.0, help="1/s: the --stacked-solid runs' rubber damping "
                    "(mass-proportional Rayleigh ALPHA; 200 damps the swing that follows combination 2's second "
                    "snap)")
    ap.add_argument("--no-write", action="store_true")
    a = ap.parse_args(argv)
    if a.p1_element == "C3D20" and a.p1_full_near:
        ap.error("--p1-element C3D20 integrates every brick fully; --p1-full-near (mm) picks some of them, so it "
                 f"must be 0 with it, not {a.p1_full_near:g}")
    if a.p1_full_low and not a.p1_full_near:
        ap.error("--p1-full-low: the edge pillar's strip joins the corner bricks of --p1-full-near (mm, > 0), "
                 "which is 0")
    if a.trace:
        t0 = time.time()
        tr = run_fe(increments=a.increments, timeout_s=a.timeout, bias=a.bias, method=a.method,
                    patient=a.patient)
        tr["info"]["increments_asked"] = a.increments
        print(f"trace: {tr['info']['increments']} increments to d/L {tr['info']['d_reached']:.3f} in "
              f"{time.time() - t0:.0f} s; extrema {tr['extrema']}", flush=True)
        _store(a.key, tr)
    if a.p1_mesh:
        r, nl = MESHES[a.p1_mesh]
        inc = a.p1_increments or int(round(100 * a.p1_dmax))
        tr = run_fe(r, nl, d_max=a.p1_dmax, increments=inc, timeout_s=a.timeout, method="static",
                    full_near=a.p1_full_near, full_low=a.p1_full_low, element=a.p1_element)
        print(f"P1 mesh {a.p1_mesh}: {tr['extrema']} to d/L {tr['info']['d_reached']:.3f} "
              f"({tr['info']['wall_s']:.0f} s)", flush=True)
        _store("p1_" + a.p1_mesh + (f"_inc{a.p1_increments}" if a.p1_increments else "")
               + (f"_full{a.p1_full_near:g}" + ("low" if a.p1_full_low else "") if a.p1_full_near else "")
               + ("_C3D20" if a.p1_element == "C3D20" else ""), tr)
    if a.stability_at:
        for d in (float(v) for v in a.stability_at.split(",")):
            kw = dict(full_near=a.stability_full_near, n_cells=a.stability_cells, element=a.stability_element)
            pr = stability_probe(a.stability_mesh, d, timeout_s=a.timeout, **kw)
            print(f"stability {a.stability_mesh} d/L {d}: {pr.get('eigenvalues')} ({pr['wall_s']:.0f} s)", flush=True)
            _store("stability", {probe_key(a.stability_mesh, d, **kw): pr}, merge=True)
    if a.branch_at:
        tr = branch(a.stability_mesh, a.branch_at, a.branch_amp, timeout_s=a.timeout)
        print(f"branch {a.stability_mesh} from d/L {a.branch_at}: {tr['imperfection']}; {tr['extrema']} "
              f"({tr['info']['wall_s']:.0f} s)", flush=True)
        _store("branch_" + a.stability_mesh, tr)
    if a.cells:
        _store_rows("cells", cells_check([int(v) for v in a.cells.split(",")]))
    for m in a.cells_meshes.split(",") if a.cells_meshes else ():     # stored mesh by mesh
        _store_rows("cells", cells_meshes(meshes=(m,)))
    for m in a.cells_flat.split(",") if a.cells_flat else ():
        _store_rows("cells", cells_flat(meshes=(m,)))
    if a.cells_p1:
        _store_rows("cells", cells_p1([int(v) for v in a.cells_p1.split(",")], d_max=a.cells_p1_dmax,
                                      element=a.cells_p1_element, bias=a.cells_p1_bias, timeout_s=a.timeout,
                                      mesh=a.cells_p1_mesh, bias_ramp=a.cells_p1_bias_ramp))
    if a.stiffness:
        _store("stiffness", stiffness_check(a.stiffness.split(",")), merge=True)
    if a.held_p1:
        _store("p1_held", held_p1(a.held_p1.split(","), timeout_s=a.timeout), merge=True)
    if a.combinations:
        from metamaterial_wb.bench.fe_ring3d_combinations import solid_thresholds

        def done(key, mesh, k, row):
            data = _load().get("combinations", {})
            rows = data.setdefault(key, {}).setdefault(mesh, [None, None])
            rows[k] = row
            print(f"combination {key} {mesh} type {k}: P1 {row['P1']} at {row['P1_d']}, valley {row['valley']} at "
                  f"{row['valley_d']} ({row['wall_s']:.0f} s, to d/L {row['d_reached']:.3f})", flush=True)
            _store("combinations", data)
        solid_thresholds([tuple(v.split(":")) for v in a.combinations.split(",")], timeout_s=a.timeout, done=done)
    if a.mixed_cycles:
        from metamaterial_wb.bench.fe_ring3d_combinations import mixed_study

        def done_cycle(key, mesh, what, row):
            data = _load().get("mixed_cycles", {})
            data.setdefault(key, {}).setdefault(mesh, {})[what] = row
            print(f"mixed combination {key} {mesh} {what}: {row['wall_s']:.0f} s, d/L {row['d_reached']:.3f} "
                  f"{row['stopped']}", flush=True)
            _store("mixed_cycles", data)
        mixed_study([tuple(v.split(":")) for v in a.mixed_cycles.split(",")], timeout_s=a.timeout, done=done_cycle)
    if a.stacked_solid:
        from metamaterial_wb.bench.fe_ring3d_stack import stacked_solid_study

        def done_stack(key, mesh, run):
            data = _load().get("stacked_solid", {})
            data.setdefault(key, {})[mesh] = run
            print(f"stacked combination {key} {mesh}: {run['wall_s']:.0f} s, d/L {run['d_reached']:.3f} "
                  f"{run['stopped']}", flush=True)
            _store("stacked_solid", data)
        stacked_solid_study([tuple(v.split(":")) for v in a.stacked_solid.split(",")], timeout_s=a.timeout,
                            done=done_stack, damping=a.stacked_damping)
    if a.radial_fixed:
        tr = run_fe(d_max=0.7, increments=a.increments, timeout_s=a.timeout, radial="fixed")
        print(f"radial fixed: {tr['extrema']} ({tr['info']['wall_s']:.0f} s)", flush=True)
        _store("radial_fixed", tr)
    data = _load()
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
