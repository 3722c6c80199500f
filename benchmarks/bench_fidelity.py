"""Fidelity-ladder targets (issue 6): run time and error of the linear and nonlinear lattice models
against the quadratic model measured in the same run (the baseline), on the standard 10 x 10 and
30 x 30 grids at two actuator amplitudes.

    /usr/bin/python3 benchmarks/bench_fidelity.py [--no-write]

Prints a table and writes it into docs/benchmarks.md between ``<!-- begin:fidelity -->`` and
``<!-- end:fidelity -->`` (only that section is touched). The full report with every scene and the
work-precision plot comes from ``python3 -m metamaterial_wb bench fidelity`` (docs/fidelity.md).

Targets: linear model on 10 x 10 <= 5 ms with at most a third of the quadratic model's error;
nonlinear model on 10 x 10 <= 200 ms and on 30 x 30 <= 1 s. "linear" is the linear model as it runs by
default (``about=quadratic``); its option ``about=flat`` (the flat-sheet linearisation) is measured alongside.
"""
import argparse
import os
import platform
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
sys.path.insert(0, REPO)

from metamaterial_wb.bench import fidelity  # noqa: E402
from metamaterial_wb.bench.reference import converged_reference  # noqa: E402
from metamaterial_wb.core.models import run_model  # noqa: E402

BEGIN, END = "<!-- begin:fidelity -->", "<!-- end:fidelity -->"


def cold_times(scene, repeats=20, **options):
    """Linear model, cold builds exactly as ``fidelity.timed`` measures them: (best, median) of ``repeats``."""
    import statistics

    import metamaterial_wb.core.lattice as lattice
    ts = []
    for _ in range(repeats):
        lattice.clear_cache()
        t = time.perf_counter()
        run_model("linear", scene, **options)
        ts.append(time.perf_counter() - t)
    return min(ts), statistics.median(ts)


def resolve_time(scene, repeats=20):
    """Linear model at the flat sheet, values only changed (cached factorisation): best of ``repeats``."""
    import metamaterial_wb.core.lattice as lattice
    lattice.clear_cache()
    run_model("linear", scene, about="flat")
    best = None
    for _ in range(repeats):
        t = time.perf_counter()
        run_model("linear", scene, about="flat")
        dt = time.perf_counter() - t
        best = dt if best is None else min(best, dt)
    return best


LOAD = os.getloadavg()


def _oversubscribed(load):
    """A sentence when the machine ran more jobs than it has cores: absolute times are then inflated, the
    targets' verdicts describe the loaded machine, and only ratios within the run compare."""
    cores = os.cpu_count() or 1
    if load <= cores:
        return ""
    return (f" **The machine was oversubscribed** ({load:.0f} runnable jobs on {cores} cores, other engineers' test "
            f"runs): every absolute time here is inflated, by up to about {load / cores:.0f}x against an idle machine, "
            "and the time targets' verdicts describe this loaded machine; the ratios against the quadratic baseline "
            "measured in the same run, and every error, are unaffected.")


def main(argv=None):
    ap = argparse.ArgumentParser(description="Fidelity-ladder targets: run time and error of the linear and "
                                             "nonlinear lattice models against the quadratic model, written into "
                                             "docs/benchmarks.md (the fidelity section only)")
    ap.add_argument("--no-write", action="store_true", help="print the table only; leave docs/benchmarks.md as it is")
    write = not ap.parse_args(argv).no_write
    rows = []
    for amp in fidelity.AMPLITUDES:
        for key, title, scene in fidelity.standard_scenes(amp):
            if key not in ("grid10", "grid30"):
                continue
            ref, study = converged_reference(scene)
            out = {"key": key, "amp": amp, "unc": study["uncertainty"]["rms_D"]}
            for model in ("quadratic", "linear", "nonlinear"):
                res, dt = fidelity.timed(model, scene, repeats=5)
                err = fidelity.compare(scene, res, ref)
                out[model] = (dt, err["rms_D"], err["max_pos"], res.converged)
            res, dt = fidelity.timed("linear", scene, repeats=5, about="flat")
            out["flat"] = (dt, fidelity.compare(scene, res, ref)["rms_D"])
            out["resolve"] = resolve_time(scene)
            if key == "grid10":
                out["cold20"] = cold_times(scene)
            # the linear model's former pose rule (flat positions + solved displacements), same run
            out["old_pos"] = fidelity.compare(scene, run_model("linear", scene, poses="linear"), ref)["max_pos"]
            rows.append(out)
            q, li, nl = out["quadratic"], out["linear"], out["nonlinear"]
            c20 = (f" (20 cold runs: best {out['cold20'][0] * 1e3:.2f}, median {out['cold20'][1] * 1e3:.2f} ms)"
                   if "cold20" in out else "")
            print(f"{key} amp {amp}: quadratic {q[0] * 1e3:.2f} ms (baseline), linear {li[0] * 1e3:.2f} ms{c20} "
                  f"(x{li[0] / q[0]:.1f}), nonlinear {nl[0] * 1e3:.1f} ms "
                  f"(x{nl[0] / q[0]:.0f}); RMS dD quadratic {q[1]:.3g}, linear {li[1]:.3g} "
                  f"(x{li[1] / q[1]:.2f}), nonlinear {nl[1]:.1e}; about=flat {out['flat'][0] * 1e3:.2f} ms "
                  f"(re-solve {out['resolve'] * 1e3:.2f} ms), RMS dD {out['flat'][1]:.3g} "
                  f"(x{out['flat'][1] / q[1]:.2f})", flush=True)
    lines = [BEGIN, "## Fidelity ladder (issue 6)", "",
             "`/usr/bin/python3 benchmarks/bench_fidelity.py` (standard scenes of `metamaterial_wb/bench/fidelity.py`, "
             "four actuators; reference = nonlinear model at tolerance 1e-11 with 1, 2, 4, 8 elements per hinge, "
             "extrapolated to infinitely many (`bench/reference.py`); every error is uncertain by the reference's "
             "uncertainty, given per row). Times are cold runs (geometry, assembly, "
             "factorisation, solve, poses), best of 5 (10 x 10: also best and median of 20); *linear* is the linear "
             "model as it runs by default (`about=quadratic`, linearised about the quadratic model's predicted state); "
             "*about=flat* is its flat-sheet linearisation, whose *re-solve* is the model called again with new actuator "
             "values (cached factorisation; the default has no such cache: its linearisation point moves with the "
             "values). Errors: RMS node angle in D units after removing the rigid rotation. "
             "Ratios are against the quadratic model measured in the same run. Full report and work-precision "
             "plot: [fidelity.md](fidelity.md).", "",
             f"Measured {time.strftime('%Y-%m-%d', time.gmtime())} on {os.cpu_count()} cores, Python "
             f"{platform.python_version()}; the machine is shared (load from other jobs), treat times as upper "
             f"bounds (load average {LOAD[0]:.1f} at the start, {os.getloadavg()[0]:.1f} at the end of this run)."
             + _oversubscribed(max(LOAD[0], os.getloadavg()[0])), "",
             "| scene | amplitude | reference uncertainty (RMS dD) | quadratic (baseline) | linear | nonlinear | RMS dD quadratic | "
             "RMS dD linear (ratio) | RMS dD nonlinear (default: 1 element per hinge) | max pos. err / cell quadratic | "
             "max pos. err / cell linear (ratio) | about=flat: time, re-solve, RMS dD (ratio) |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        q, li, nl = r["quadratic"], r["linear"], r["nonlinear"]
        c20 = (f"; 20 runs: best {r['cold20'][0] * 1e3:.2f}, median {r['cold20'][1] * 1e3:.2f} ms"
               if "cold20" in r else "")
        lines.append(f"| {r['key']} | {r['amp']} | {r['unc']:.1e} | {q[0] * 1e3:.2f} ms | {li[0] * 1e3:.2f} ms (x{li[0] / q[0]:.1f}{c20}) | "
                     f"{nl[0] * 1e3:.1f} ms (x{nl[0] / q[0]:.0f}) | {q[1]:.3g} | "
                     f"{li[1]:.3g} ({li[1] / q[1]:.2f}) | {nl[1]:.1e} | {q[2]:.3g} | {li[2]:.3g} ({li[2] / q[2]:.2f}) | "
                     f"{r['flat'][0] * 1e3:.2f} ms, {r['resolve'] * 1e3:.2f} ms, {r['flat'][1]:.3g} "
                     f"({r['flat'][1] / q[1]:.2f}) |")
    g10 = [r for r in rows if r["key"] == "grid10"]
    g30 = [r for r in rows if r["key"] == "grid30"]
    nl10 = max(r["nonlinear"][0] for r in g10)
    nl30 = max(r["nonlinear"][0] for r in g30)
    t10 = "; ".join("%.2f ms at amplitude %g (%s)" % (r["linear"][0] * 1e3, r["amp"],
                                                        "met" if r["linear"][0] <= 5e-3 else "not met") for r in g10)
    ratios = "; ".join("%.2f at amplitude %g (%s)" % (r["linear"][1] / r["quadratic"][1], r["amp"],
                                                      "met" if r["linear"][1] <= r["quadratic"][1] / 3 else "not met")
                       for r in g10)
    flat = "; ".join("ratio %.2f in %.2f ms at amplitude %g (%s)" % (
        r["flat"][1] / r["quadratic"][1], r["flat"][0] * 1e3, r["amp"],
        "both met" if r["flat"][1] <= r["quadratic"][1] / 3 and r["flat"][0] <= 5e-3 else "not both met")
        for r in g10)
    old_pos = "; ".join(f"{r['old_pos']:.3g} ({r['key']}, amplitude {r['amp']})" for r in rows)
    lines += ["", f"Targets: linear 10 x 10 <= 5 ms: {t10}. Linear error <= 1/3 of the quadratic model's on "
              f"10 x 10: {ratios}. Nonlinear 10 x 10 <= 200 ms: {'met' if nl10 <= 0.2 else 'not met'} "
              f"(worst {nl10 * 1e3:.0f} ms); nonlinear 30 x 30 <= 1 s: {'met' if nl30 <= 1.0 else 'not met'} "
              f"(worst {nl30 * 1e3:.0f} ms). The linear model's default linearises about the quadratic model's "
              f"predicted state (one quadratic solve, then one lattice solve there with plate contact by low-rank "
              f"re-solves and a step length from the energy; [model guide](fidelity-models.md#linearised-about-the-"
              f"quadratic-models-state-aboutquadratic), `benchmarks/bench_fidelity_r0_linearised.py`). Its flat-sheet "
              f"linearisation (`--option about=flat`, the default before) on 10 x 10: {flat}; it stays the choice for "
              f"animation (cached re-solve) (valid up to amplitude about 0.4 on 10 x 10: beyond it hinges pass their opening/closing limits, which `solve` now warns; at 0.7 its error is worse than the quadratic model's, [model guide](fidelity-models.md)). The linear model's positions come from "
              f"its rotations through the hinge chain; adding the solved displacements instead (`--option "
              f"poses=linear`) gives a largest position error of {old_pos} cells.", END]
    block = "\n".join(lines)
    print(block)
    if write:
        path = os.path.join(REPO, "docs", "benchmarks.md")
        from metamaterial_wb.core.fileio import write_atomic
        text = open(path, encoding="utf-8").read() if os.path.exists(path) else "# Benchmarks\n"
        if BEGIN in text and END in text:
            a = text.index(BEGIN)
            b = text.index(END) + len(END)
            text = text[:a] + block + text[b:]
        else:
            text = text.rstrip("\n") + "\n\n" + block + "\n"
        write_atomic(path, text)
        print(f"updated {path}")


if __name__ == "__main__":
    main()
