#!/usr/bin/env python3
"""Quadratic-model solver benchmark (issue 2 targets).

Grids of 10x10 ... 1000x1000 NODES ((n-1) x (n-1) cells), three actuators, k1 from the default
hinge. For each size: scene set-up, factorisation (including the response matrix), re-solve (new
actuator values: one product with the response matrix) and a plain back-substitution; backends
SuperLU (default, always available) and CHOLMOD (optional); a dense Cholesky solve as the baseline
where it fits in memory. Prints a table and updates the solver section of docs/benchmarks.md.

Usage: /usr/bin/python3 benchmarks/bench_solver.py [--max-nodes 1000] [--no-write]
Targets: 100x100 factor <= 20 ms, re-solve <= 1 ms; 1000x1000 factor <= 5 s, re-solve <= 0.3 s.
"""
import argparse
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from benchmarks._report import best_of, machine_line, update_section  # noqa: E402
from metamaterial_wb.core import solver  # noqa: E402
from metamaterial_wb.core.scene import Scene  # noqa: E402


def bench(n, backend, repeat):
    cells = n - 1
    t = time.perf_counter()
    s = Scene.grid(cells, cells, actuators=[
        {"name": "a", "joint": "V0,0", "value": 0.5},
        {"name": "b", "joint": f"H{cells // 2},{cells // 2}", "value": -0.8},
        {"name": "c", "joint": f"V{cells - 1},{cells}", "value": 1.0}])
    setup = time.perf_counter() - t
    prep, m = best_of(lambda: solver.model_for_scene(s, backend=backend), 1 if n >= 1000 else repeat)
    rng = np.random.default_rng(0)
    vals = rng.uniform(-1, 1, (repeat * 5, 3))
    it = iter(vals)
    resolve, D = best_of(lambda: m.solve(next(it)), repeat * 5)
    it = iter(vals)
    backsub, D2 = best_of(lambda: m.solve(next(it), use_response=False), min(repeat, 3))
    return {"n": n, "setup": setup, "factor": m.timings["factor_s"], "prepare": m.timings["total_prepare_s"],
            "resolve": resolve, "backsub": backsub, "model": m, "scene": s}


def dense_baseline(res):
    m = res["model"]
    import scipy.linalg as sla
    A = m.H_FF.toarray()
    t = time.perf_counter()
    c = sla.cho_factor(A)
    tf = time.perf_counter() - t
    b = -(m.H_FA @ np.array([0.5, 0.5, -0.8, -0.8, 1.0, 1.0])[:m.H_FA.shape[1]])
    t = time.perf_counter()
    x = sla.cho_solve(c, b)
    ts = time.perf_counter() - t
    return tf, ts, x


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--max-nodes", type=int, default=1000)
    ap.add_argument("--no-write", action="store_true")
    args = ap.parse_args()
    sizes = [n for n in (10, 30, 100, 300, 1000) if n <= args.max_nodes]
    backends = ["superlu"] + (["cholmod"] if solver.cholmod_available() else [])
    rows = []
    for n in sizes:
        for be in backends:
            r = bench(n, be, 5 if n <= 100 else 2)
            dense = ""
            if be == "superlu" and n * n <= 10000:
                tf, ts, _ = dense_baseline(r)
                dense = f"{tf * 1e3:.1f} ms / {ts * 1e3:.2f} ms (x{tf / r['factor']:.0f} slower factor)"
            elif be == "superlu":
                dense = f"not run ({(n * n) ** 2 * 8 / 1e9:.0f} GB matrix)"
            line = (f"| {n}x{n} ({n * n} nodes) | {be} | {r['setup'] * 1e3:.1f} ms | {r['factor'] * 1e3:.1f} ms | "
                    f"{r['prepare'] * 1e3:.1f} ms | {r['resolve'] * 1e3:.3f} ms | {r['backsub'] * 1e3:.2f} ms | "
                    f"{dense} |")
            print(line, flush=True)
            rows.append(line)
            del r
    body = "\n".join([
        "## Quadratic solver (issue 2)",
        "",
        "`/usr/bin/python3 benchmarks/bench_solver.py` (grids of n x n nodes, three actuators). "
        "*factor* is the sparse factorisation of the free-node Hessian; *prepare* adds assembly, island "
        "detection and the response matrix (one back-substitution per actuator); *re-solve* is what a slider "
        "move costs (new actuator values -> every D, a product with the response matrix); *back-sub* is the "
        "plain triangular solve for comparison. Dense Cholesky is the baseline where it fits in memory. "
        "Best of several runs; the machine is shared, so treat figures as upper bounds.",
        "",
        machine_line(),
        "",
        "| grid | backend | scene set-up | factor | prepare (total) | re-solve | back-sub | dense factor / solve |",
        "|---|---|---|---|---|---|---|---|",
        *rows,
        "",
        "Targets: 100x100 factor <= 20 ms and re-solve <= 1 ms; 1000x1000 factor <= 5 s and re-solve <= 0.3 s. "
        "SuperLU (MMD on A^T+A) is the default that is always there; CHOLMOD (scikit-sparse, optional, "
        "installed by `tools/install-deps.sh` when it builds) is chosen automatically when present.",
    ])
    if not args.no_write:
        update_section("solver", body)
        print("updated docs/benchmarks.md")


if __name__ == "__main__":
    main()
