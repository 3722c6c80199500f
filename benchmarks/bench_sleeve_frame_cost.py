#!/usr/bin/env python3
"""What the nonlinear 3-D frame costs in the ``sleeve`` command (issue 18: "sleeves predicted in seconds").

The code path users run: ``pipeline.analyse`` (what ``metamaterial_wb sleeve SPEC`` runs, single-threaded BLAS) on
the bundled examples, as they are (the planar beam model: the baseline of the same run) and with
``model.frame_nonlinear`` (the frame's first peaks, its loading and unloading cycle and, for the walker, the leg's
loop on it). Prints the seconds and the frame's cost as a multiple of the baseline, and writes the table to
docs/benchmarks.md (section ``sleeve-frame-cost``).

Usage: /usr/bin/python3 benchmarks/bench_sleeve_frame_cost.py [--no-write] [--repeat 1] [--examples walker,...]
"""
import argparse
import json
import os
import sys

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)
from benchmarks._report import best_of, machine_line, update_section  # noqa: E402

EXAMPLES = ("walker", "sleeve_two_rings")


def run(name, frame):
    """``pipeline.analyse`` of ``examples/<name>.json``, with ``model.frame_nonlinear`` if ``frame``: the summary."""
    from metamaterial_wb.core.sleeve.pipeline import analyse
    from metamaterial_wb.core.sleeve.spec import SleeveSpec
    from metamaterial_wb.core.threads import blas_threads
    data = json.load(open(os.path.join(ROOT, "examples", name + ".json")))
    if frame:
        data["model"] = dict(data.get("model", {}), frame_nonlinear=True)
    with blas_threads(1):
        return analyse(SleeveSpec(data, source=name))[0]


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("--no-write", action="store_true")
    ap.add_argument("--repeat", type=int, default=1)
    ap.add_argument("--examples", default=",".join(EXAMPLES))
    a = ap.parse_args(argv)
    rows = []
    for name in a.examples.split(","):
        t0, _ = best_of(lambda: run(name, False), a.repeat)
        t1, s = best_of(lambda: run(name, True), a.repeat)
        fr = s["sequence"].get("frame3d_nl", {})
        order = f"{fr.get('loading')} \\| {fr.get('unloading')}" if fr.get("loading") is not None else "-"
        rows.append((name, t0, t1, order))
        print(f"{name}: planar {t0:.1f} s, with the frame {t1:.1f} s (x{t1 / t0:.1f}); frame's order {order}",
              flush=True)
    lines = ["## The nonlinear 3-D frame in the `sleeve` command (issue 18)", "",
             "`/usr/bin/python3 benchmarks/bench_sleeve_frame_cost.py`: `pipeline.analyse` (the `sleeve` command's "
             "run, single-threaded BLAS) on the bundled examples as they are (the planar beam model, the baseline "
             "of the same run) and with `model.frame_nonlinear` (the frame's first peaks, its loading and unloading "
             f"cycle, the walker's loop on it; 12 elements per beam half). Best of {a.repeat}; shared machine.", "",
             machine_line(), "", "| example | planar model (s) | with the frame (s) | frame / planar | frame's order |",
             "|---|---|---|---|---|"]
    lines += [f"| `examples/{n}.json` | {t0:.1f} | {t1:.1f} | x{t1 / t0:.1f} | {o} |" for n, t0, t1, o in rows]
    if not a.no_write:
        update_section("sleeve-frame-cost", "\n".join(lines))
    return rows


if __name__ == "__main__":
    main()
