"""Animation frame rate of the workbench for a 10 x 10 sheet, excluding rendering.

    /usr/bin/python3 benchmarks/bench_gui.py [--rows 10 --cols 10 --frames 300]

Measures, on the document objects the workbench creates (App level, no 3D view):

* live: what the Animate panel does per frame: motion profiles -> values, re-solve with the stored
  factorisation, node / hinge / marker poses, writing the PlacementLists and marker placements
  (no recompute);
* solve only: the numpy part of a frame (values -> D -> poses -> hinge frames);
* baseline: the naive way, writing the motor values into the properties and recomputing the
  document every frame (as recompute-driven animators do).

Prints frames per second and the ratio live / baseline. Target: live >= 30 frames/s.
"""
import argparse
import math
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.append("/usr/lib/freecad-python3/lib")

import FreeCAD  # noqa: E402

if sys.path[0] != os.path.dirname(os.path.dirname(os.path.abspath(__file__))):
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

from metamaterial_wb.core.scene import Scene  # noqa: E402
from metamaterial_wb.objects import structure  # noqa: E402


def sheet(rows, cols):
    acts = [
        {"name": "m1", "joint": "V0,0", "value": 0.0,
         "profile": {"shape": "sine", "amplitude": 0.8, "frequency_hz": 0.5, "phase_deg": 0}},
        {"name": "m2", "joint": f"V0,{cols}", "value": 0.0,
         "profile": {"shape": "sine", "amplitude": 0.8, "frequency_hz": 0.5, "phase_deg": 90}},
        {"name": "m3", "joint": f"H{rows},0", "value": 0.0,
         "profile": {"shape": "sine", "amplitude": 0.6, "frequency_hz": 1.0, "phase_deg": 180}},
        {"name": "m4", "joint": f"H{rows},{cols - 1}", "value": 0.0,
         "profile": {"shape": "sine", "amplitude": 0.6, "frequency_hz": 1.0, "phase_deg": 270}},
    ]
    return Scene.from_dict({"format": "metamaterial-scene", "version": 1, "name": f"sheet{rows}x{cols}",
                            "layout": {"grid": [rows, cols]}, "actuators": acts})


def measure(rows, cols, frames, baseline_frames):
    doc = FreeCAD.newDocument("BenchGui")
    scene = sheet(rows, cols)
    t0 = time.perf_counter()
    sc = structure.make_structure(doc, scene)
    t_make = time.perf_counter() - t0
    solver = structure.solver_for(sc)
    dt = 1.0 / 30.0

    # solve only
    t0 = time.perf_counter()
    for k in range(frames):
        solver.frame(values=solver.values_at(k * dt))
    t_solve = (time.perf_counter() - t0) / frames

    # live frame (what the panel does), placements written, no recompute
    builds = doc.getObject("NodeShape").BuildCount
    t0 = time.perf_counter()
    for k in range(frames):
        f = solver.frame(values=solver.values_at(k * dt))
        structure.apply_frame(sc, solver, f, purge=True)
    t_live = (time.perf_counter() - t0) / frames
    assert doc.getObject("NodeShape").BuildCount == builds

    # baseline: values into properties + recompute per frame
    items = {o.ItemName: o for o in sc.Items}
    t0 = time.perf_counter()
    for k in range(baseline_frames):
        for name, v in solver.values_at(k * dt).items():
            items[name].Value = v
        doc.recompute()
    t_base = (time.perf_counter() - t0) / baseline_frames
    assert sc.isValid()
    FreeCAD.closeDocument(doc.Name)
    return {"rows": rows, "cols": cols, "nodes": scene.topology.n_nodes, "hinges": scene.topology.n_joints,
            "motors": len(scene.actuators), "make_s": t_make, "solve_ms": 1000 * t_solve,
            "live_ms": 1000 * t_live, "base_ms": 1000 * t_base}


def report(r):
    fl, fs, fb = 1000 / r["live_ms"], 1000 / r["solve_ms"], 1000 / r["base_ms"]
    print(f"sheet {r['rows']} x {r['cols']}: {r['nodes']} nodes, {r['hinges']} hinges, {r['motors']} motors; "
          f"document made in {r['make_s']:.2f} s")
    print(f"solve only (values -> D -> poses -> hinge frames): {r['solve_ms']:7.2f} ms/frame  {fs:8.1f} fps")
    print(f"live frame (solve + write placements, no recompute): {r['live_ms']:7.2f} ms/frame  {fl:8.1f} fps"
          f"   target >= 30 fps: {'met' if fl >= 30 else 'NOT met'}")
    print(f"baseline (set motor values + recompute per frame):   {r['base_ms']:7.2f} ms/frame  {fb:8.1f} fps")
    print(f"ratio live / baseline: {fl / fb:.1f} x")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rows", type=int, default=10)
    ap.add_argument("--cols", type=int, default=10)
    ap.add_argument("--frames", type=int, default=300)
    ap.add_argument("--baseline-frames", type=int, default=20)
    ap.add_argument("--write-doc", action="store_true",
                    help="measure 10x10 and 20x20 and update the workbench section of docs/benchmarks.md")
    args = ap.parse_args(argv)
    if not args.write_doc:
        report(measure(args.rows, args.cols, args.frames, args.baseline_frames))
        return 0
    rows = []
    for n, fr, bf in ((10, args.frames, args.baseline_frames), (20, max(50, args.frames // 3), 10)):
        r = measure(n, n, fr, bf)
        report(r)
        rows.append(r)
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from _report import machine_line, update_section
    lines = ["## Workbench animation frame rate (issue 5)", "",
             "`/usr/bin/python3 benchmarks/bench_gui.py --write-doc`: one animation frame of the Animate panel on",
             "the document objects (motion profiles -> values, re-solve with the stored factorisation, node and",
             "hinge poses, PlacementLists of the two link arrays and the marker placements written; no recompute;",
             "rendering excluded). Baseline in the same run: motor values written into the properties and the",
             "document recomputed every frame (recompute-driven animation of the same objects; the node and hinge",
             "shapes are cached, so this baseline is already kind). Four sine motors.", "",
             "| sheet | nodes | hinges | solve only (ms) | live frame (ms) | live fps | recompute frame (ms) | "
             "live / recompute |",
             "| --- | --- | --- | --- | --- | --- | --- | --- |"]
    for r in rows:
        lines.append(f"| {r['rows']} x {r['cols']} | {r['nodes']} | {r['hinges']} | {r['solve_ms']:.2f} | "
                     f"{r['live_ms']:.2f} | {1000 / r['live_ms']:.0f} | {r['base_ms']:.2f} | "
                     f"{r['base_ms'] / r['live_ms']:.1f} x |")
    ok = 1000 / rows[0]["live_ms"] >= 30
    lines += ["", f"Target (10 x 10 >= 30 frames/s excluding rendering): {'met' if ok else 'NOT met'}. "
              "Most of a live frame is building the FreeCAD Placement objects (about 9 us each); the numpy "
              "solve is under 1 ms. Under Xvfb with software OpenGL the render itself costs 30-110 ms per frame "
              "(research note), so on screen the frame rate is bound by the renderer, not by the workbench.",
              "", machine_line()]
    update_section("gui", "\n".join(lines))
    return 0


if __name__ == "__main__":
    sys.exit(main())
