#!/usr/bin/env python3
"""The sleeve beam model calibrated on CalculiX, and the FE ring over the working range (issue 18).

    /usr/bin/python3 benchmarks/bench_sleeve_calibration.py [--trace [--trace-r 1 --trace-increments 140]] [--no-write]

``--trace`` first runs CalculiX's four-cell ring (mesh ``--trace-r``) to d/L 0.7 in fixed displacement increments
(ccx cuts them back itself where Newton struggles) and keeps every converged increment even when the run stops
early (``solve_ring(partial=True)``: where and why it stopped is reported); it writes
``benchmarks/results/fe-ring-trace.json`` (tens of minutes; needs ``ccx``). Then, from that file and the FE study
``benchmarks/results/fe-study.json``, it fits the beam model's root extension on the FE cell's peak and checks
it on the valley and the ring (``metamaterial_wb/bench/fe_sleeve_calibration.py``), writing the section between
the ``<!-- fe-calibration -->`` markers of docs/sleeves.md, ``docs/img/sleeve-fe-calibration.png`` and
``benchmarks/results/fe-calibration.json``; the calibration is stored in the FE study too (``sleeve_calibration``),
and docs/fidelity.md's FE section is regenerated from that study (``fe_study.markdown``, as ``bench fidelity
--fe --fe-json benchmarks/results/fe-study.json`` would write it), which now ends with the sleeve's trust statement.
"""
import argparse
import json
import os
import sys

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)
from metamaterial_wb.bench import fe_sleeve_calibration as cal, fe_study  # noqa: E402
from metamaterial_wb.core.fileio import write_atomic  # noqa: E402

RESULTS = os.path.join(ROOT, "benchmarks", "results")
DOC = os.path.join(ROOT, "docs", "sleeves.md")
IMG = "img/sleeve-fe-calibration.png"


def run_trace(r, increments, d_max=0.7, timeout_s=6000.0):
    from metamaterial_wb.core.sleeve.cell import CellGeometry
    from metamaterial_wb.fe import sleeve2d
    g = CellGeometry()
    c, info = sleeve2d.solve_ring(g, 4, r, d_max=d_max * g.L, increments=increments, timeout_s=timeout_s,
                                  partial=True)
    info.pop("log_tail", None)
    return {"r": r, "d": c["d"].tolist(), "F": c["F"].tolist(), "tilt_rad": c["tilt_rad"].tolist(), "info": info}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--trace", action="store_true", help="run the CalculiX ring trace first (needs ccx)")
    ap.add_argument("--trace-r", type=int, default=1)
    ap.add_argument("--trace-increments", type=int, default=140)
    ap.add_argument("--no-write", action="store_true")
    ap.add_argument("--reuse-fit", action="store_true",
                    help="take the root extension (and its range) from benchmarks/results/fe-calibration.json")
    a = ap.parse_args(argv)
    tpath = os.path.join(RESULTS, "fe-ring-trace.json")
    if a.trace:
        tr = run_trace(a.trace_r, a.trace_increments)
        with open(tpath, "w") as f:
            json.dump(tr, f, indent=1)
    trace = json.load(open(tpath)) if os.path.exists(tpath) else None
    spath = os.path.join(RESULTS, "fe-study.json")
    full = json.load(open(spath))
    study = full["sleeve"]
    from metamaterial_wb.bench.fe_sleeve import summarise
    summarise(study)
    fit = None
    if a.reuse_fit:
        old = json.load(open(os.path.join(RESULTS, "fe-calibration.json")))
        fit = (old["root_extension"], *old["root_extension_range"])
    bpath = os.path.join(RESULTS, "fe-ring-trace-bias.json")
    btrace = json.load(open(bpath)) if os.path.exists(bpath) and trace is not None else None
    out = cal.run(study, trace, fit=fit, bias_trace=btrace)
    section = cal.markdown(out, IMG)
    print(section)
    if not a.no_write:
        with open(os.path.join(RESULTS, "fe-calibration.json"), "w") as f:
            json.dump(out, f, indent=1)
        cal.plot(out, os.path.join(ROOT, "docs", IMG))
        text = cal.write_section(DOC, section)
        write_atomic(DOC, text)
        print("wrote docs/sleeves.md")
        import copy
        keep = copy.deepcopy({k: v for k, v in out.items() if k not in ("trace", "trace_bias")})
        for m in keep["models"].values():            # the curves stay in fe-calibration.json; the extrema here
            if "ring_curve" in m:
                m["ring_curve"] = {"n_el": m["ring_curve"]["n_el"], "extrema": m["ring_curve"]["extrema"],
                                   "d_end": m["ring_curve"]["d"][-1]}
        full["sleeve_calibration"] = keep
        if "trace" in out:
            full["sleeve_calibration"]["trace"] = {"r": out["trace"]["r"], "info": out["trace"]["info"],
                                                   "extrema": out["trace"]["extrema"]}
        write_atomic(spath, json.dumps(full, indent=1))              # the study holds NaN (write_json refuses it)
        fe_study.write_fidelity_section(full, os.path.join(ROOT, "docs", "fidelity.md"))
        print("wrote docs/fidelity.md (FE section)")


if __name__ == "__main__":
    main()
