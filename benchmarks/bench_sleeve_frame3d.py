#!/usr/bin/env python3
"""The curved sleeve ring as a linear 3-D frame against the curved CalculiX solid (issue 18).

    /usr/bin/python3 benchmarks/bench_sleeve_frame3d.py [--nonlinear] [--plate] [--sequence] [--walker] [--stacked]
        [--no-write]

Builds the frame (``metamaterial_wb/core/sleeve/frame3d.py``) of every ring size the solid was run for
(``benchmarks/results/fe-ring3d.json``, ``cells``; ``bench_sleeve_ring3d.py --cells``), flat and curved, in two
moduli and two root extensions (a few seconds in all, no ccx), stores them in
``benchmarks/results/frame3d.json`` and rewrites its section of docs/sleeves.md. ``--nonlinear`` traces the
four-cell ring nonlinearly (about 15 s), ``--plate`` the four- and eight-cell rings with the solid's free plate
and the eight-cell leaning runs on two more beam meshes (``bench/fe_frame3d_plate.py``, about 2 min),
``--sequence`` the seed's two mixed rings' cycles on it (about 2 min), ``--walker`` the walker on the frame's
cycle on three beam meshes (about 1 min), ``--stacked`` the seed's combinations as two
stacked rings (``bench/fe_frame3d_stack.py``, about 3 min);
otherwise their stored runs are reused. The solid's thresholds of the seed's combinations
(``bench_sleeve_ring3d.py --combinations``, stored in fe-ring3d.json) are tabulated beside the frame's.
"""
import argparse
import json
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)
from metamaterial_wb.bench import fe_frame3d  # noqa: E402
from metamaterial_wb.core.fileio import write_atomic  # noqa: E402

RESULTS = os.path.join(ROOT, "benchmarks", "results")
DOC = os.path.join(ROOT, "docs", "sleeves.md")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--no-write", action="store_true")
    ap.add_argument("--nonlinear", action="store_true", help="trace the four-cell curved frame nonlinearly to d/L "
                    "0.7 on 12 and 24 elements per beam half (about 15 s); else the stored traces are reused")
    ap.add_argument("--plate", action="store_true", help="trace the four- and eight-cell rings with the solid's "
                    "free, biased top plate and follow their tilt pair, the eight-cell leaning runs on 6 and 24 "
                    "elements too (about 2 min); else the stored runs are reused")
    ap.add_argument("--sequence", action="store_true", help="the seed's combinations 1 and 2 loaded and unloaded on "
                    "the frame with the free plate (about 2 min); else the stored runs are reused")
    ap.add_argument("--walker", action="store_true", help="the walker of examples/walker.json on the frame's cycle, "
                    "on 6, 12 and 24 elements (about 1 min); else the stored runs are reused")
    ap.add_argument("--stacked", action="store_true", help="the seed's combinations as two stacked rings on the "
                    "frame, on 6, 12 and 24 elements, and on the beam model (about 3 min); else the stored runs are reused")
    a = ap.parse_args(argv)
    comp = json.load(open(os.path.join(RESULTS, "fe-ring3d-comparison.json")))
    s = fe_frame3d.study(comp["cells"])
    from metamaterial_wb.bench.fe_ring3d_corner import family_convergence
    fam = family_convergence(comp, "_C3D20")
    s["fe_family"] = {"p1_ext": fam["p1_ext"], "valley_ext": fam["valley_ext"]}
    s["planar_calibrated"] = {k: comp["curved_calibrated"][k] for k in ("d", "F", "n_el", "root_extension")}
    s["fe_secants"] = fe_frame3d.fe_secants(comp)
    raw = json.load(open(os.path.join(RESULTS, "fe-ring3d.json")))
    s["held"] = {part: run["p1"] for part, run in raw.get("p1_held", {}).items()}
    s["held"]["free"] = raw.get("cells", {}).get("4", {}).get("fe_curved_p1")
    old = os.path.join(RESULTS, "frame3d.json")
    stored = json.load(open(old)) if os.path.exists(old) else None      # read once: the runs not redone are kept

    def keep(*keys):
        if stored is not None:
            s.update({k: stored.get(k) for k in keys})
    if a.nonlinear:
        s["nonlinear"] = fe_frame3d.nonlinear_study()
        s["p1_sensitivity"] = fe_frame3d.p1_sensitivity()
    else:
        keep("nonlinear", "p1_sensitivity")
    from metamaterial_wb.bench import fe_frame3d_plate
    if a.plate:
        s["plate"] = fe_frame3d_plate.plate_study()
        s["plate_meshes"] = fe_frame3d_plate.count_meshes()
    else:
        keep("plate", "plate_meshes")
    if a.sequence:
        s["sequence"] = fe_frame3d_plate.sequence_study()
    else:
        keep("sequence")
    if a.walker:
        s["walker"] = fe_frame3d_plate.walker_study()
    else:
        keep("walker")
    from metamaterial_wb.bench import fe_frame3d_stack, fe_ring3d_combinations, fe_ring3d_stack
    if a.stacked:
        s["stacked"] = fe_frame3d_stack.stacked_study()
    else:
        keep("stacked")
    off = (fe_frame3d.p1_off(s["nonlinear"], s["fe_family"], s["planar_calibrated"])[0]
           if s.get("nonlinear") else None)
    plate = [fe_frame3d_plate.markdown(s["plate"], comp, off, s.get("plate_meshes"))] if s.get("plate") else []
    section = fe_frame3d.markdown(s, plate +
                                  ([fe_frame3d_plate.sequence_markdown(s["sequence"])] if s.get("sequence") else []) +
                                  ([fe_frame3d_plate.walker_markdown(s["walker"])] if s.get("walker") else []) +
                                  ([fe_frame3d_stack.stacked_markdown(s["stacked"], s.get("sequence") or {})]
                                   if s.get("stacked") else []) +
                                  ([fe_ring3d_combinations.solid_markdown(raw["combinations"], s.get("sequence") or {},
                                                                          stacked=bool(raw.get("stacked_solid")))]
                                   if raw.get("combinations") else []) +
                                  ([fe_ring3d_combinations.cycles_markdown(raw["mixed_cycles"],
                                                                           raw.get("combinations", {}),
                                                                           s.get("sequence") or {})]
                                   if raw.get("mixed_cycles") else []) +
                                  ([fe_ring3d_stack.stacked_solid_markdown(raw["stacked_solid"],
                                                                           raw.get("combinations", {}),
                                                                           s.get("stacked") or {},
                                                                           raw.get("stacked_solid_attempts"))]
                                   if raw.get("stacked_solid") else []))
    print(section)
    if not a.no_write:
        write_atomic(os.path.join(RESULTS, "frame3d.json"), json.dumps(s, indent=1))
        write_atomic(DOC, fe_frame3d.write(DOC, section))
        fe_frame3d.plot_stiffness(s, os.path.join(ROOT, "docs", fe_frame3d.IMG_STIFFNESS))
        if s.get("nonlinear") and "p1_r4_C3D20" in comp:
            fine = comp["p1_r4_C3D20"]
            if s.get("plate"):
                fe_frame3d_plate.plot(s["plate"], comp, os.path.join(ROOT, "docs", fe_frame3d_plate.IMG))
            if s.get("stacked"):
                fe_frame3d_stack.plot(s["stacked"], os.path.join(ROOT, "docs", fe_frame3d_stack.IMG))
            fe_frame3d.plot_nonlinear(s["nonlinear"], {"d": fine["d"], "F": fine["F"],
                                                       "label": "CalculiX curved solid, r = 4, all C3D20"},
                                      comp["curved_calibrated"], os.path.join(ROOT, "docs", fe_frame3d.IMG))
        if raw.get("mixed_cycles"):
            fe_ring3d_combinations.plot_cycles(raw["mixed_cycles"],
                                               os.path.join(ROOT, "docs", fe_ring3d_combinations.IMG_CYCLES))
        if raw.get("stacked_solid", {}).get("2", {}).get("r1", {}).get("unloading"):
            fe_ring3d_stack.plot(raw["stacked_solid"], os.path.join(ROOT, "docs", fe_ring3d_stack.IMG))
        print("wrote benchmarks/results/frame3d.json and docs/sleeves.md")


if __name__ == "__main__":
    main()
