#!/usr/bin/env python3
"""Result output of ``solve`` (issue 18, item 6): JSON against ``--fields`` and ``--npz``.

A 200 x 200-node sheet (three actuators, quadratic model) is solved once; then the result is
written the way ``solve`` writes it: the former per-node JSON code (kept here as the baseline,
``legacy_result_dict``), the current JSON (same document), JSON with ``--fields D`` and the binary
``--npz`` form (all fields). Times include building the document and writing the file; ratios are
against the baseline of the same run. Updates the "result-io" section of docs/benchmarks.md.

Usage: /usr/bin/python3 benchmarks/bench_result_io.py [--nodes 200] [--repeat 3] [--no-write]
"""
import argparse
import math
import os
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from benchmarks._report import best_of, machine_line, update_section  # noqa: E402
from metamaterial_wb.cli.solve import joint_results, result_dict  # noqa: E402
from metamaterial_wb.core import resultfile  # noqa: E402
from metamaterial_wb.core.fileio import write_json  # noqa: E402
from metamaterial_wb.core.models import run_model  # noqa: E402
from metamaterial_wb.core.scene import Scene  # noqa: E402


def legacy_result_dict(scene, res, global_g=None, model="quadratic"):
    """The result document as ``solve`` built it before issue 18 (one Python dict per node)."""
    topo = scene.topology
    nodes = []
    for k, (i, j) in enumerate(topo.nodes):
        R = res.rotations[k]
        nodes.append({"i": i, "j": j, "name": f"N{i},{j}", "D": float(res.D[k]),
                      "rotation_deg": math.degrees(math.atan2(R[1, 0], R[0, 0])),
                      "position_mm": [float(x) for x in res.positions_mm[k]],
                      "rotation": [[float(x) for x in row] for row in R]})
    out = {"format": "metamaterial-result", "version": 1, "scene": scene.name, "model": model,
           "converged": bool(res.converged), "global_deformation": global_g,
           "actuators": {a.name: a.value for a in scene.actuators},
           "constraints": {c.name: c.value for c in scene.constraints},
           "nodes": nodes, "warnings": list(res.warnings), "timings": dict(res.timings)}
    out["joints"] = joint_results(scene, res.rotations)
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--nodes", type=int, default=200)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--no-write", action="store_true")
    a = ap.parse_args()
    n = a.nodes
    cells = n - 1
    scene = Scene.grid(cells, cells, actuators=[
        {"name": "a", "joint": "V0,0", "value": 0.5},
        {"name": "b", "joint": f"H{cells // 2},{cells // 2}", "value": -0.8},
        {"name": "c", "joint": f"V{cells - 1},{cells}", "value": 1.0}])
    t = time.perf_counter()
    res = run_model("quadratic", scene)
    t_solve = time.perf_counter() - t
    tmp = tempfile.mkdtemp(prefix="bench-result-io-")
    rows = []

    def case(label, fn, files):
        sec, _ = best_of(fn, a.repeat)
        size = sum(os.path.getsize(os.path.join(tmp, f)) for f in files)
        rows.append((label, sec, size))
        print(f"{label:48s} {sec:8.3f} s {size / 1e6:9.1f} MB", flush=True)

    case("JSON, former code (baseline)",
         lambda: write_json(os.path.join(tmp, "a.json"), legacy_result_dict(scene, res)), ["a.json"])
    case("JSON, all fields (same document)",
         lambda: write_json(os.path.join(tmp, "b.json"), result_dict(scene, res)), ["b.json"])
    case("JSON, --fields D",
         lambda: write_json(os.path.join(tmp, "c.json"), result_dict(scene, res, fields=("D",))), ["c.json"])

    def npz(fields=resultfile.FIELDS, name="d"):
        arrays = resultfile.result_arrays(scene, res, fields)
        meta = result_dict(scene, res, fields=fields, arrays=arrays)
        resultfile.write_npz(os.path.join(tmp, name + ".npz"), arrays, meta)
        write_json(os.path.join(tmp, name + ".json"), meta)
    case("--npz, all fields (.npz + small .json)", npz, ["d.npz", "d.json"])
    case("--npz --fields D", lambda: npz(("D",), "e"), ["e.npz", "e.json"])
    base = rows[0][1]
    lines = [f"`/usr/bin/python3 benchmarks/bench_result_io.py` ({n} x {n} nodes, {len(scene.topology.joint_names)} "
             f"joints; solve itself {t_solve:.2f} s; times: building the document and writing the file, best of "
             f"{a.repeat}). {machine_line()}", "",
             "| output | write (s) | size (MB) | speed-up over the former JSON code |", "|---|---|---|---|"]
    for label, sec, size in rows:
        lines.append(f"| {label} | {sec:.3f} | {size / 1e6:.1f} | {base / sec:.1f}x |")
    body = "## Result output: JSON, --fields, --npz (issue 18)\n\n" + "\n".join(lines)
    print(body)
    if not a.no_write:
        update_section("result-io", body)
    import shutil
    shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    main()
