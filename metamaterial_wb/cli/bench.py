"""``bench fidelity [--out docs/fidelity.md] [--img docs/img/fidelity-work-precision.png]``.

Runs every model of the fidelity ladder on the standard scenes (chain, 10 x 10 and 30 x 30 grids,
bending strip, mixed hinge sizes; two actuator amplitudes) against the converged nonlinear reference (hinges
of 1, 2, 4, 8 elements, extrapolated) and writes the report and its work-precision plot; ``--fe`` adds the
CalculiX rung (metamaterial_wb/fe). Both files are rendered in memory first and written atomically.
"""
import json
import os
import platform
import sys
import time

NAME = "bench"
STORED_FE = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))), "benchmarks",
                         "results", "fe-study.json")
FE_PARTS = {"hinge": "stiffness", "patch": "patch", "sleeve": "sleeve"}     # --fe-parts: the study's key in the JSON
HELP = "benchmarks: 'bench fidelity' writes docs/fidelity.md and its work-precision plot (error vs run time)"


def add_arguments(p):
    p.add_argument("what", choices=("fidelity",), help="which benchmark")
    p.add_argument("--out", default=os.path.join("docs", "fidelity.md"), help="report (Markdown)")
    p.add_argument("--img", default=os.path.join("docs", "img", "fidelity-work-precision.png"),
                   help="work-precision plot (PNG)")
    p.add_argument("--json", default=None, help="also write the raw figures as JSON")
    p.add_argument("--scenes", default=None,
                   help="comma-separated subset of chain,grid10,grid30,bending,mixed (default: all)")
    p.add_argument("--amplitudes", default=None, help="comma-separated actuator amplitudes (default 0.05,0.5)")
    p.add_argument("--repeats", type=int, default=3, help="timing runs per model (best is reported)")
    p.add_argument("--quiet", action="store_true", help="no progress lines")
    p.add_argument("--fe", action="store_true",
                   help="also run the CalculiX rung (one hinge: stiffness and bending curves; the 3 x 3 patch "
                        "at amplitudes 0.05 and 0.5; mesh studies; 20-60 min on a shared machine); without ccx "
                        "the report says so and the rest still runs; a part whose ccx run fails is left out with "
                        "an 'FE rung failed' note in the report, the other parts kept")
    p.add_argument("--fe-json", default=None,
                   help="with --fe: reuse the FE study stored in this JSON file (written by --fe-json-out) "
                        "instead of running ccx again; without --fe: the FE study rendered into the report "
                        "(default: the stored one, benchmarks/results/fe-study.json, where it exists)")
    p.add_argument("--fe-json-out", default=None, help="with --fe: also write the FE study as JSON")
    p.add_argument("--fe-parts", default="hinge,patch,sleeve",
                   help="with --fe: which FE studies to run (one or more of hinge,patch,sleeve, comma-separated; every "
                        "study run or read from --fe-json is rendered into the report); "
                        "sleeve: the sleeve's unit cell and four-cell ring (2-D plane strain) against the beam model, "
                        "written into --sleeves-out")
    p.add_argument("--sleeves-out", default=os.path.join("docs", "sleeves.md"),
                   help="with --fe and the sleeve part: the document whose marked FE section is rewritten")
    p.add_argument("--sleeves-img", default=os.path.join("docs", "img", "sleeve-fe-check.png"),
                   help="with --fe and the sleeve part: its plot (PNG)")
    p.add_argument("--from-json", default=None,
                   help="render the report and plot from the raw figures of a previous run (its --json file) "
                        "instead of running the models again")


def _read_study(path, hint=""):
    """The FE study stored in the JSON file ``path`` (``--fe-json``), or a SceneError naming it (``hint`` added)."""
    from metamaterial_wb.core.errors import SceneError
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError) as exc:
        raise SceneError("--fe-json", f"{path!r}: cannot read the FE study ({exc}){hint}") from None


def run(args):
    from metamaterial_wb.bench import fidelity
    from metamaterial_wb.core.errors import MetamaterialError, SceneError
    from metamaterial_wb.core.fileio import write_atomic, write_json

    from metamaterial_wb.core.fileio import check_output
    check_output(args.out, "file", "--out")
    check_output(args.img, "file", "--img")
    if args.json is not None:
        check_output(args.json, "file", "--json")
    amps = fidelity.AMPLITUDES
    if args.amplitudes:
        try:
            amps = tuple(float(x) for x in args.amplitudes.split(","))
        except ValueError:
            raise SceneError("--amplitudes", f"{args.amplitudes!r}: expected numbers like 0.05,0.5") from None
        for a in amps:
            if not (0 < a <= 1):
                raise SceneError("--amplitudes", f"{a!r} is outside the allowed range (0, 1]")
    if args.repeats < 1 or args.repeats > 20:
        raise SceneError("--repeats", f"{args.repeats} is outside the allowed range [1, 20]")
    keys = None
    if args.scenes:
        keys = [k.strip() for k in args.scenes.split(",") if k.strip()]
        known = [k for k, _, _ in fidelity.standard_scenes()]
        for k in keys:
            if k not in known:
                raise SceneError("--scenes", f"{k!r} is not a standard scene; known: {', '.join(known)}")

    t0 = time.perf_counter()

    def progress(msg):
        if not args.quiet:
            print(f"[{time.perf_counter() - t0:6.1f} s] {msg}", file=sys.stderr, flush=True)

    fe_study, fe_note = None, None
    parts = [x.strip() for x in args.fe_parts.split(",") if x.strip()]
    if not parts:
        raise SceneError("--fe-parts", f"{args.fe_parts!r} names no FE study; allowed: one or more of hinge, patch, "
                                       "sleeve, comma-separated")
    for x in parts:
        if x not in FE_PARTS:
            raise SceneError("--fe-parts", f"{x!r} is not an FE study; allowed: one or more of hinge, patch, sleeve, "
                                           "comma-separated")
    if args.fe and "sleeve" in parts:
        check_output(args.sleeves_out, "file", "--sleeves-out")
        check_output(args.sleeves_img, "file", "--sleeves-img")
    if args.fe:
        from metamaterial_wb.bench import fe_study as study
        from metamaterial_wb.fe import ccx
        fe_study = {}
        if args.fe_json:
            fe_study = _read_study(args.fe_json)
            fe_note = f"FE figures read from `{os.path.basename(args.fe_json)}` (a previous `--fe` run)."
        # run every requested part the JSON (if any) does not hold
        todo = [x for x in parts if FE_PARTS[x] not in fe_study]
        ok, why = ccx.available()
        if todo and not ok:
            fe_note = f"FE rung not run: {why}."
            progress(fe_note)
        failed = []
        for part in (todo if ok else []):     # each part on its own: one that fails keeps the others
            try:
                if part == "hinge":
                    fe_study.update(study.run_hinge_study(progress=progress))
                    fe_study["aspect"] = study.run_aspect_study(progress=progress)
                elif part == "patch":
                    fe_study["patch"] = study.run_patch_study(progress=progress)
                else:
                    from metamaterial_wb.bench import fe_sleeve
                    fe_study["sleeve"] = fe_sleeve.run_sleeve_study(progress=progress)
            except MetamaterialError as exc:          # ccx failed, stopped or wrote no tables (ccx.FEError)
                failed.append(f"FE rung failed: {part} study: {' '.join(str(exc).split())}")
                progress(failed[-1])
        if failed:
            fe_note = " ".join(filter(None, [fe_note] + [f + ("" if f.endswith(".") else ".") for f in failed]))
        if not fe_study:
            fe_study = None
        if fe_study is not None and args.fe_json_out:
            write_json(args.fe_json_out, fe_study)
    else:
        # the stored CalculiX study goes into the report as it is, so regenerating it keeps its FE rung
        path = args.fe_json or (STORED_FE if os.path.exists(STORED_FE) else None)
        if path:
            fe_study = _read_study(path, "; without --fe-json the stored one is read, with --fe CalculiX runs again")
            fe_note = (f"FE figures read from `{os.path.basename(path)}` (a stored `--fe` run; `--fe` runs "
                       "CalculiX again).")
    results = []
    if args.from_json:
        try:
            with open(args.from_json) as f:
                results = json.load(f)["results"]
        except (OSError, ValueError, KeyError) as exc:
            raise SceneError("--from-json", f"{args.from_json!r}: cannot read the raw figures ({exc})") from None
        results = [r for r in results if (keys is None or r["key"] in keys) and r["amplitude"] in amps]
    for a in ([] if args.from_json else amps):
        scenes = [s for s in fidelity.standard_scenes(a) if keys is None or s[0] in keys]
        results += fidelity.run_ladder(scenes, progress=progress, repeats=args.repeats, amplitudes=(a,))
    machine = (f"Measured {time.strftime('%Y-%m-%d', time.gmtime())} on {os.cpu_count()} cores, "
               f"Python {platform.python_version()} ({platform.machine()}); shared machine, treat times as upper "
               f"bounds" + ("" if args.from_json else f" (load average {os.getloadavg()[0]:.1f} at the end of the run)")
               + "." + ("" if args.from_json or os.getloadavg()[0] <= (os.cpu_count() or 1) else
                        " The machine was oversubscribed (more runnable jobs than cores): absolute times are inflated "
                        f"up to about {os.getloadavg()[0] / (os.cpu_count() or 1):.0f}x against an idle machine; ratios "
                        "within the run and every error are unaffected."))
    img_rel = os.path.relpath(os.path.abspath(args.img), os.path.dirname(os.path.abspath(args.out)))
    command = "python3 -m metamaterial_wb bench fidelity" + (f" --repeats {args.repeats}" if args.repeats != 3 else "")
    if args.fe:
        command += " --fe"
    fe_md = None
    if args.fe or fe_study:
        from metamaterial_wb.bench import fe_study as study
        fe_md = study.markdown(fe_study) + (f"\n{fe_note}\n" if fe_note else "")
    text = fidelity.report_markdown(results, img_rel.replace(os.sep, "/"), machine, command=command,
                                    repeats=args.repeats, fe_markdown=fe_md)
    import tempfile
    with tempfile.TemporaryDirectory() as tmp:
        tmp_png = os.path.join(tmp, "plot.png")
        fidelity.plot_work_precision(results, tmp_png, fe_study)
        with open(tmp_png, "rb") as f:
            png = f.read()
    write_atomic(args.img, png, mode="wb")
    write_atomic(args.out, text)
    if args.fe and fe_study and fe_study.get("sleeve"):
        from metamaterial_wb.bench import fe_sleeve
        sl = fe_sleeve.summarise(fe_study["sleeve"])
        sl_img = os.path.relpath(os.path.abspath(args.sleeves_img), os.path.dirname(os.path.abspath(args.sleeves_out)))
        with tempfile.TemporaryDirectory() as tmp:
            tmp_png = os.path.join(tmp, "sleeve.png")
            fe_sleeve.plot(sl, tmp_png)
            with open(tmp_png, "rb") as f:
                png = f.read()
        section = fe_sleeve.markdown(sl, sl_img.replace(os.sep, "/"))
        write_atomic(args.sleeves_img, png, mode="wb")
        write_atomic(args.sleeves_out, fe_sleeve.write_section(args.sleeves_out, section))
    if args.json:
        write_json(args.json, {"format": "metamaterial-fidelity", "version": 1, "results": results})
    for s in fidelity.summary(results):
        print(f"{s['key']:8s} amp {s['amplitude']:<5g} quadratic {s['quadratic_ms']:7.2f} ms  linear "
              f"{s['linear_ms']:7.2f} ms  nonlinear {s['nonlinear_ms']:8.1f} ms  RMS dD quadratic "
              f"{s['quadratic_rms_D']:.3g} linear {s['linear_rms_D']:.3g} (ratio {s['ratio']:.2f})"
              f"{'' if s['nonlinear_converged'] else '  NONLINEAR NOT CONVERGED'}")
    print(f"wrote {args.out} and {args.img} ({time.perf_counter() - t0:.1f} s)")
    return 0 if all(r["reference_converged"] for r in results) else 1
