#!/usr/bin/env python3
"""Regenerate the inverse-design examples (docs/inverse.md): target files, solved scenes, pictures.

* fish tail curl: the fish's tail swing (its own sine gait sampled at 4 keyframes) as node targets;
  the search places 2 servos and fills their keyframe profiles;
* gripper closing on a cylinder: a cylinder (STL) fitted through the gripper's cross bar when its
  servos close it; the search places 2 servos whose values wrap the bar onto the cylinder;
* worm gait: the worm's crawl (rear / front sines) at 4 keyframes as node targets; 2 servos.

Usage: /usr/bin/python3 tools/make_inverse_examples.py [--workers 2] [--only fish|gripper|worm ...]
(``--only``: regenerate those examples alone, repeatable; default all three).
"""
import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile

import numpy as np

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, REPO)
from metamaterial_wb.cli.solve import result_dict  # noqa: E402
from metamaterial_wb.core import design  # noqa: E402
from metamaterial_wb.core.models import run_model  # noqa: E402
from metamaterial_wb.core.motion import scene_values_at  # noqa: E402
from metamaterial_wb.core.scene import Scene  # noqa: E402

EX = os.path.join(REPO, "examples")
IMG = os.path.join(REPO, "docs", "img")


def nodes_at(scene, t):
    s = scene.copy()
    for name, v in scene_values_at(s, t).items():
        s.set_value(name, v)
    return [{"name": n["name"], "position_mm": [round(x, 6) for x in n["position_mm"]]}
            for n in result_dict(s, run_model("quadratic", s))["nodes"]]


def bare(scene, name, description):
    d = scene.to_dict()
    d["actuators"] = []
    d["modules"] = [m for m in d.get("modules", []) if m.get("type") != "servo_housing"]
    d["name"], d["description"] = name, description
    return d


def cylinder_stl(path, centre_xz, radius, y0, y1, n=96):
    ang = np.linspace(0, 2 * np.pi, n + 1)
    tri = []
    for a, b in zip(ang[:-1], ang[1:]):
        pa = [centre_xz[0] + radius * np.cos(a), centre_xz[1] + radius * np.sin(a)]
        pb = [centre_xz[0] + radius * np.cos(b), centre_xz[1] + radius * np.sin(b)]
        q = [[pa[0], y0, pa[1]], [pb[0], y0, pb[1]], [pb[0], y1, pb[1]], [pa[0], y1, pa[1]]]
        tri += [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]
    with open(path, "w") as f:
        f.write("solid cylinder\n")
        for t in tri:
            f.write(" facet normal 0 0 0\n  outer loop\n")
            for v in t:
                f.write(f"   vertex {v[0]:.6f} {v[1]:.6f} {v[2]:.6f}\n")
            f.write("  endloop\n endfacet\n")
        f.write("endsolid cylinder\n")


def run(scene_path, target_path, servos, out, workers, extra=()):
    cmd = [sys.executable, "-m", "metamaterial_wb", "inverse", scene_path, "--target", target_path,
           "--servos", str(servos), "--out", out, "--workers", str(workers), *extra]
    print(" ".join(os.path.relpath(c, REPO) if c.startswith(REPO) else c for c in cmd[1:]), flush=True)
    subprocess.run(cmd, check=True, env=dict(os.environ, PYTHONPATH=REPO))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--workers", type=int, default=1)
    ap.add_argument("--only", action="append", choices=("fish", "gripper", "worm"),
                    help="regenerate this example only (repeatable; default: all)")
    args = ap.parse_args()
    only = set(args.only or ("fish", "gripper", "worm"))
    tmp = tempfile.mkdtemp()
    jobs = []
    if "fish" in only:
        make_fish(tmp, jobs)
    if "gripper" in only:
        make_gripper(tmp, jobs)
    if "worm" in only:
        make_worm(tmp, jobs)
    for name, scene_path, target, servos in jobs:
        out = os.path.join(tmp, name + "_out")
        run(scene_path, target, servos, out, args.workers)
        shutil.copy(os.path.join(out, "scene.json"), os.path.join(EX, f"{name}_inverse_solved.json"))
        with open(os.path.join(out, "report.json")) as f:
            rep = json.load(f)
        rep["scene"] = f"examples/{name}.json without its actuators"
        rep["target"] = os.path.relpath(target, REPO)
        with open(os.path.join(EX, f"{name}_inverse_report.json"), "w") as f:
            json.dump(rep, f, indent=1)
        shutil.copy(os.path.join(out, "result.png"), os.path.join(IMG, f"inverse_{name}.png"))
    shutil.rmtree(tmp)


TIMES = [0.0, 0.5, 1.0, 1.5]


def make_fish(tmp, jobs):
    times = TIMES
    fish = Scene.load(os.path.join(EX, "fish.json"))
    with open(os.path.join(EX, "fish_tail_target.json"), "w") as f:
        json.dump({"format": "metamaterial-target", "version": 1,
                   "description": "the fish's tail curling left and right (its sine gait at 4 keyframes)",
                   "period_s": 2.0, "keyframes": [{"time_s": t, "nodes": nodes_at(fish, t)} for t in times]}, f, indent=1)
    with open(os.path.join(tmp, "fish.json"), "w") as f:
        json.dump(bare(fish, "fish_tail_inverse", "the fish sheet without servos (placed by inverse design)"), f)
    jobs.append(("fish", os.path.join(tmp, "fish.json"), os.path.join(EX, "fish_tail_target.json"), 2))


def make_gripper(tmp, jobs):
    grip = Scene.load(os.path.join(EX, "gripper.json"))
    design.ensure_configured(grip)
    closed = grip.copy()
    for a in closed.actuators:
        closed.set_value(a.name, 0.9)
    topo = closed.topology
    # a cylinder along y above the bar (the arms rise when the gripper closes): with its axes folding
    # 10 degrees each, the bar closes onto a cylinder of about 250 mm radius; the rigid alignment
    # places the sheet on it
    radius = 250.0
    flat = np.array([[j * closed.cell_size_mm, -i * closed.cell_size_mm] for i in (3, 4) for j in range(8)
                     if topo.node_id(i, j) >= 0])
    fx, fy = flat.mean(axis=0)
    cylinder_stl(os.path.join(EX, "gripper_cylinder.stl"), (fx, radius), radius, fy - 60, fy + 60, n=720)
    names = [f"N{i},{j}" for i in (3, 4) for j in range(8) if topo.node_id(i, j) >= 0]
    with open(os.path.join(EX, "gripper_cylinder_target.json"), "w") as f:
        json.dump({"format": "metamaterial-target", "version": 1,
                   "description": f"the gripper's cross bar wrapped on a cylinder of radius {radius:.1f} mm",
                   "surface": {"file": "gripper_cylinder.stl", "nodes": names}}, f, indent=1)
    with open(os.path.join(tmp, "gripper.json"), "w") as f:
        json.dump(bare(grip, "gripper_cylinder_inverse", "the gripper without servos (placed by inverse design)"), f)
    jobs.append(("gripper", os.path.join(tmp, "gripper.json"), os.path.join(EX, "gripper_cylinder_target.json"), 2))


def make_worm(tmp, jobs):
    times = TIMES
    worm = Scene.load(os.path.join(EX, "worm.json"))
    with open(os.path.join(EX, "worm_gait_target.json"), "w") as f:
        json.dump({"format": "metamaterial-target", "version": 1,
                   "description": "the worm's crawl: 4 keyframes of its gait (rear and front waves a quarter apart)",
                   "period_s": 2.0, "keyframes": [{"time_s": t, "nodes": nodes_at(worm, t)} for t in times]}, f,
                  indent=1)
    with open(os.path.join(tmp, "worm.json"), "w") as f:
        json.dump(bare(worm, "worm_gait_inverse", "the worm chain without servos (placed by inverse design)"), f)
    jobs.append(("worm", os.path.join(tmp, "worm.json"), os.path.join(EX, "worm_gait_target.json"), 2))


if __name__ == "__main__":
    main()
