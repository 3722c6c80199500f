#!/usr/bin/env python3
"""The sleeve cell's FE reference against its own element formulation (issue 18).

    OMP_NUM_THREADS=1 /usr/bin/python3 benchmarks/bench_sleeve_cell_elements.py [--refinements 1,2,3,4] [--no-run]
        [--no-write]

Runs the periodic unit cell in CalculiX on four nested meshes with reduced CPE8R elements, with the beam's
corners fully integrated and with the whole beam fully integrated (``metamaterial_wb/bench/fe_cell_elements.py``,
about ten minutes; needs ``ccx``), stores the runs in ``benchmarks/results/fe-study.json`` (``sleeve.cell.elements``)
and rewrites the FE section of docs/sleeves.md (``fe_sleeve.markdown``, as ``bench fidelity --fe --fe-json
benchmarks/results/fe-study.json`` would). ``--no-run`` re-renders from the stored runs.
"""
import argparse
import json
import os
import sys

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ["OMP_NUM_THREADS"] = "1"
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)
from metamaterial_wb.bench import fe_cell_elements, fe_sleeve  # noqa: E402
from metamaterial_wb.core.fileio import write_atomic  # noqa: E402

STUDY = os.path.join(ROOT, "benchmarks", "results", "fe-study.json")
DOC = os.path.join(ROOT, "docs", "sleeves.md")
IMG = "img/sleeve-fe-check.png"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--refinements", default=",".join(map(str, fe_cell_elements.REFINEMENTS)))
    ap.add_argument("--no-run", action="store_true", help="render from the stored runs")
    ap.add_argument("--no-write", action="store_true")
    a = ap.parse_args(argv)
    try:
        refinements = tuple(int(v) for v in a.refinements.split(","))
    except ValueError:
        ap.error(f"--refinements: {a.refinements!r}; expected integers like 1,2,3,4")
    if len(refinements) < 3 or any(not 1 <= r <= 6 for r in refinements):
        ap.error(f"--refinements: {a.refinements!r}; allowed: three or more meshes r in [1, 6]")
    with open(STUDY) as f:
        full = json.load(f)
    cell = full["sleeve"]["cell"]
    if not a.no_run:
        cell["elements"] = fe_cell_elements.run(refinements, fe_sleeve.CELL_INCREMENTS, progress=lambda m: print(m, flush=True))
        with open(STUDY) as f:                                      # the runs go into the study as it is now
            full = json.load(f)
        full["sleeve"]["cell"]["elements"] = cell["elements"]
    elif "elements" not in cell:
        ap.error(f"--no-run: {STUDY} holds no sleeve.cell.elements yet; run without --no-run first")
    sl = fe_sleeve.summarise(full["sleeve"])
    lines = fe_cell_elements.markdown_lines(sl["cell"])
    print("\n".join(lines))
    if not a.no_write:
        write_atomic(STUDY, json.dumps(full, indent=1))              # the study holds NaN (write_json refuses it)
        write_atomic(DOC, fe_sleeve.write_section(DOC, fe_sleeve.markdown(sl, IMG)))
        print(f"wrote {os.path.relpath(STUDY, ROOT)} and docs/sleeves.md")


if __name__ == "__main__":
    main()
