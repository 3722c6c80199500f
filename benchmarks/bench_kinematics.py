#!/usr/bin/env python3
"""Pose computation benchmark (issue 3): D field -> 3D node poses.

Grids of 10x10 and 100x100 CELLS, planar (no axes) and folded (two vertical rotary axes). For each:
*factor* = building the reusable :class:`Kinematics` object (tilts, limits, sparse LU of the node
Laplacian); *frame (reused)* = one pose update with that object (what an animation frame costs);
*frame (fresh)* = ``node_poses(scene, D)`` without reuse, i.e. factor + frame every time (the
baseline); the ratio shows what reuse buys. D is a non-uniform field from the quadratic solver
(one actuator), so the least-squares path is measured, not a shortcut. Also checks the residual
of the exact mechanism (uniform D) at each size.

Usage: /usr/bin/python3 benchmarks/bench_kinematics.py [--no-write] [--repeat 5]
"""
import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from benchmarks._report import best_of, machine_line, update_section  # noqa: E402
from metamaterial_wb.core import design, kinematics  # noqa: E402
from metamaterial_wb.core.scene import Scene  # noqa: E402
from metamaterial_wb.core.solver import solve_scene  # noqa: E402


def make(n, folded):
    axes = ([{"direction": "vertical", "line": n // 3, "fold_deg": 40},
             {"direction": "vertical", "line": (2 * n) // 3, "fold_deg": -30}] if folded else [])
    s = Scene.from_dict({"layout": {"grid": [n, n]}, "hinge": {"length_mm": 5.0, "width_mm": 0.8},
                         "axes": axes, "actuators": [{"name": "m", "joint": f"V{n // 2},{n // 2}", "value": 0.9}]})
    if folded:
        design.configure(s)
    return s


def bench(n, folded, repeat):
    s = make(n, folded)
    D, *_ = solve_scene(s)
    t_factor, kin = best_of(lambda: kinematics.Kinematics(s), repeat)
    kin.poses(D)
    t_frame, _ = best_of(lambda: kin.poses(D), repeat)
    t_fresh, _ = best_of(lambda: kinematics.node_poses(s, D), max(2, repeat // 2))
    Du = np.ones(s.topology.n_nodes)
    pos, R, phi = kin.poses(Du)
    res = kin.closure_residual(phi, pos)
    return {"grid": f"{n}x{n} cells ({s.topology.n_nodes} nodes)", "kind": "folded (2 axes)" if folded else "planar",
            "factor": t_factor, "frame": t_frame, "fresh": t_fresh, "ratio": t_fresh / t_frame, "residual": res}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--no-write", action="store_true")
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args()
    rows = []
    for n in (10, 100):
        for folded in (False, True):
            r = bench(n, folded, args.repeat)
            rows.append(r)
            print(f"{r['grid']:<28} {r['kind']:<16} factor {r['factor'] * 1e3:8.2f} ms  frame {r['frame'] * 1e3:8.2f} ms"
                  f"  fresh {r['fresh'] * 1e3:8.2f} ms  fresh/reused x{r['ratio']:.1f}  exact residual "
                  f"{r['residual']:.1e} mm", flush=True)
    if args.no_write:
        return
    lines = ["## Kinematics: poses from D (issue 3)", "",
             "`/usr/bin/python3 benchmarks/bench_kinematics.py`. *factor* builds the reusable `Kinematics` object "
             "(tilts, rotation limits, sparse LU of the node Laplacian); *frame* is one pose update with it (fold "
             "frames + hinge-closure least squares, a multi-right-hand-side back-substitution); *fresh* is "
             "`node_poses(scene, D)` without reuse (factor + frame, the baseline). D is a non-uniform solver "
             "field. *residual* is the hinge-closure residual of the exact mechanism (uniform D = 1). Best of "
             "several runs on a shared machine.", "", machine_line(), "",
             "| grid | sheet | factor | frame (reused) | frame (fresh) | fresh / reused | exact residual |",
             "|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['grid']} | {r['kind']} | {r['factor'] * 1e3:.2f} ms | {r['frame'] * 1e3:.2f} ms | "
                     f"{r['fresh'] * 1e3:.2f} ms | x{r['ratio']:.1f} | {r['residual']:.1e} mm |")
    update_section("kinematics", "\n".join(lines))
    print("docs/benchmarks.md updated (section kinematics)")


if __name__ == "__main__":
    main()
