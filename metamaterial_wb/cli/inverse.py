"""``inverse SCENE --target TARGET --servos N --out DIR [--values-only] [--forbid JOINT ...] [--model M]
[--workers N | --scheduler ADDR] [--screen K] [--no-picture]``: inverse design, from a target shape to servo
placement and values.

Writes ``DIR/scene.json`` (the scene with the servos placed, values and keyframe profiles filled),
``DIR/report.json`` (errors under every model, per node, chosen joints and values, run time,
candidates evaluated, the files written; docs/inverse.md) and ``DIR/result.png`` (answer over the target,
coloured by distance), all together or none (``fileio.OutputSet``). Progress on stderr. The flags and
``DIR`` are checked before any work; a bad flag, target or output folder is an error (exit 2) and nothing
is written. With ``--no-picture`` a ``DIR/result.png`` that the previous inverse report in ``DIR`` lists
as its own is removed (it shows another answer); any other is left, with a note.
"""
import os
import sys
import time

from metamaterial_wb.cli import integer
from metamaterial_wb.core.inverse import WORKERS_RANGE   # one bound, also Fit to target's Workers box

NAME = "inverse"
HELP = "inverse design: place N servos and find their values that best reach a target shape"


def add_arguments(p):
    p.add_argument("scene", help="scene file (JSON); its angular constraints stay, its actuators are "
                                 "replaced (kept and only revalued with --values-only)")
    p.add_argument("--target", required=True,
                   help="target: target JSON (docs/inverse.md), a solve result JSON, or a surface "
                        "(.stl, .obj; .step/.stp with FreeCAD)")
    p.add_argument("--servos", type=integer, default=None,
                   help="servo budget N (required, except with --values-only; not with --values-only)")
    p.add_argument("--out", required=True, help="output folder")
    p.add_argument("--values-only", action="store_true", help="keep the scene's actuators; fit their values only")
    p.add_argument("--forbid", action="extend", nargs="+", default=[], metavar="JOINT",
                   help="joints that may not get a servo, H<i>,<j> / V<i>,<j> (the comma belongs to the name): "
                        "several after one flag (--forbid V0,1 H2,3), the flag repeated, or one value separated "
                        "by spaces or semicolons (\"V0,1; H2,3\"); not with --values-only")
    p.add_argument("--hinges", action="store_true",
                   help="also fit the hinge sizes per region (length, and thickness / width when the calibration "
                        "table has them; within its range)")
    p.add_argument("--hinge-regions", default=None, metavar="ROWSxCOLS",
                   help="regions of --hinges (only with --hinges): blocks of the sheet, 1..20 each (default 2x2)")
    p.add_argument("--model", default="quadratic", choices=("quadratic", "linear", "nonlinear"),
                   help="model whose error the values minimise (placement always searched with the quadratic "
                        "model; linear / nonlinear polish the values afterwards, report.json 'polish'); always "
                        "evaluated")
    p.add_argument("--evaluate", default="quadratic,linear,nonlinear",
                   help="models the answer is evaluated with (comma-separated, at least one; default all three; "
                        "the --model model is added when left out)")
    p.add_argument("--screen", type=integer, default=None,
                   help="placements fully fitted per search round, 0..1000 (0: every candidate; default 12; "
                        "not with --values-only)")
    g = p.add_mutually_exclusive_group()
    g.add_argument("--workers", type=integer, default=None,
                   help=f"local worker processes of the placement search, {WORKERS_RANGE[0]}..{WORKERS_RANGE[1]} (default 1; "
                        f"not with --values-only)")
    g.add_argument("--scheduler", default=None, metavar="tcp://HOST:PORT",
                   help="a Dask scheduler to run the placement search on: tcp://HOST:PORT or tls://HOST:PORT "
                        "(not with --values-only)")
    p.add_argument("--no-picture", action="store_true",
                   help="skip result.png (an earlier inverse run's result.png in DIR is removed; docs/inverse.md)")
    p.add_argument("--fab-checks", default="all", choices=("all", "parameters", "off"),
                   help="fabrication checks of the answer, the ones build runs (report.json 'fabrication', "
                        "'printable'): all (parameters, then the geometry checks in a subprocess when FreeCAD "
                        "is there; default), parameters (printable tilt, walls, fits only), off")


def _mesh_loader(path):
    from metamaterial_wb.geometry.surface import load_surface_mesh
    return load_surface_mesh(path)


def _progress(msg):
    print(f"inverse: {msg}", file=sys.stderr, flush=True)


def _check_flags(args):
    """The flags alone, before any file is read or written: ``(hinge regions or None, models, forbidden)``."""
    from metamaterial_wb.core.errors import SceneError, range_message
    from metamaterial_wb.core.inverse import pipeline

    if args.values_only and args.servos is not None:
        raise SceneError("--servos", f"{args.servos} with --values-only; allowed: one of the two (--values-only "
                                     f"keeps the scene's actuators and fits their values: leave --servos out)")
    if not args.values_only and args.servos is None:
        raise SceneError("--servos", "missing; give the servo budget N (or --values-only)")
    if args.hinge_regions is not None and not args.hinges:
        raise SceneError("--hinge-regions", f"{args.hinge_regions!r} without --hinges; allowed: only with --hinges "
                                            f"(the regions whose hinge sizes are fitted)")
    regions = None
    if args.hinges:
        from metamaterial_wb.core.inverse.hinges import parse_regions
        regions = parse_regions(args.hinge_regions if args.hinge_regions is not None else "2x2")
    models = pipeline.parse_models(args.evaluate, "--evaluate")
    if args.workers is not None:
        lo, hi = WORKERS_RANGE
        if not lo <= args.workers <= hi:
            raise SceneError("--workers", range_message(args.workers, lo, hi))
    lo, hi = pipeline.SCREEN_RANGE
    if args.screen is not None and not lo <= args.screen <= hi:
        raise SceneError("--screen", range_message(args.screen, lo, hi) + " (0: fit every candidate)")
    for flag, value in (("--workers", args.workers), ("--scheduler", args.scheduler)):
        if value is not None and args.values_only:
            raise SceneError(flag, f"{value} with --values-only; allowed: only without --values-only (a values-only "
                                   f"fit runs in this process; the placement search is what runs in parallel)")
    if args.screen is not None and args.values_only:
        raise SceneError("--screen", f"{args.screen} with --values-only; allowed: only without --values-only (it sets "
                                     f"how many placements the search fits fully; a values-only fit searches none)")
    forbidden = pipeline.parse_joint_list(args.forbid, "--forbid", unique=True) if args.forbid else []
    if forbidden and args.values_only:
        raise SceneError("--forbid", f"{', '.join(forbidden)} with --values-only; allowed: only without "
                                     f"--values-only (the placement is the scene's)")
    if args.scheduler is not None:
        from metamaterial_wb.parallel import check_scheduler_address
        check_scheduler_address(args.scheduler, "--scheduler")
    return regions, models, forbidden


def _check_out(args):
    """``--out`` before any work: a folder that can be written, no entry of another kind where an output file goes,
    no output file that is one of the inputs (``fileio.check_output`` on each). Returns the absolute folder."""
    from metamaterial_wb.core.fileio import check_output

    out = check_output(args.out, kind="dir", option="--out")
    for n in ("scene.json", "report.json") + (() if args.no_picture else ("result.png",)):
        check_output(os.path.join(out, n), "file", "--out", inputs=[("scene", args.scene), ("target", args.target)])
    return out


def _old_picture(out):
    """``(path, ours)`` of a ``result.png`` already in ``out`` (``(None, False)`` if there is none); ``ours``:
    the inverse report beside it lists it among the files its run wrote (so it shows that run's answer)."""
    from metamaterial_wb.core.errors import MetamaterialError
    from metamaterial_wb.core.inputfile import read_json

    png = os.path.join(out, "result.png")
    if not os.path.lexists(png):
        return None, False
    try:
        old = read_json(os.path.join(out, "report.json"), "report.json")
    except (MetamaterialError, OSError):
        old = None
    ours = (isinstance(old, dict) and old.get("format") == "metamaterial-inverse-report"
            and isinstance(old.get("files"), list) and "result.png" in old["files"]
            and os.path.isfile(png) and not os.path.islink(png))
    return png, ours


def run(args):
    from metamaterial_wb.core.fileio import OutputSet, write_atomic, write_json
    from metamaterial_wb.core.inverse import pipeline
    from metamaterial_wb.core.inverse.surface import TargetError
    from metamaterial_wb.core.inverse.targets import load_target
    from metamaterial_wb.core.errors import SceneError
    from metamaterial_wb.core.scene import Scene

    t0 = time.perf_counter()
    regions, models, forbidden = _check_flags(args)
    out = _check_out(args)
    scene = Scene.load(args.scene)
    try:
        target = load_target(scene, args.target, mesh_loader=_mesh_loader)
    except TargetError as exc:
        if os.path.splitext(args.target)[1].lower() == ".json":
            raise
        raise SceneError("--target", exc.message) from None     # a bare surface file: the flag is the field
    _progress(f"target {args.target}: {len(target.frames)} keyframe(s)")
    for w in target.info.get("warnings", []):      # at once, not after the search (also in report.json)
        _progress(f"warning: {w}")
    fab_check = None
    if args.fab_checks != "off":
        from metamaterial_wb.export.printability import check_printable

        def fab_check(s):
            return check_printable(s, geometry="subprocess" if args.fab_checks == "all" else "off")
    mapper, nworkers = None, 1
    if not args.values_only:
        from metamaterial_wb.parallel import make_mapper
        mapper, nworkers = make_mapper(args.workers or 1, args.scheduler)
    from metamaterial_wb.export.printability import first_module_problem
    try:
        run_ = pipeline.solve(scene, target, servos=args.servos, values_only=args.values_only, forbidden=forbidden,
                              hinge_regions=regions, model=args.model, evaluate=models,
                              screen=pipeline.SCREEN_DEFAULT if args.screen is None else args.screen,
                              mapper=mapper, workers=nworkers, progress=_progress, fab_check=fab_check,
                              module_check=first_module_problem)
    finally:
        if mapper is not None:
            mapper.close()
    picture = None
    first = next((m for m in (args.model, "quadratic") if m in run_.errors and "per_frame" in run_.errors[m]), None)
    if not args.no_picture and first:
        from metamaterial_wb.core.inverse.picture import answer_png
        notes = []
        picture = answer_png(run_.problem, run_.scene, run_.errors[first], title=scene.name or "scene",
                             title_tail=f": answer ({first} model) vs target", notes=notes)
        for w in notes:             # e.g. a long scene name shortened in the picture's title: said once
            _progress(f"warning: result.png: {w}")
    report = pipeline.report_dict(
        run_, scene=os.path.abspath(args.scene), target=os.path.abspath(args.target),
        values_only=bool(args.values_only), fit_model=args.model, forbidden=forbidden, workers=nworkers,
        scheduler=args.scheduler)
    report["files"] = sorted(["report.json", "scene.json"] + (["result.png"] if picture is not None else []))
    old_png, ours = _old_picture(out) if picture is None else (None, False)
    report["run_time_s"] = time.perf_counter() - t0
    created = not os.path.isdir(out)
    try:
        with OutputSet(out) as tmp:           # all three files land together, or none
            write_atomic(os.path.join(tmp, "scene.json"), run_.scene.to_json())
            if picture is not None:
                write_atomic(os.path.join(tmp, "result.png"), picture, mode="wb")
            write_json(os.path.join(tmp, "report.json"), report)
    except BaseException:
        if created:
            try:
                os.rmdir(out)                 # only if empty: the folder this run made, nothing else
            except OSError:
                pass
        raise
    if old_png and ours:
        try:
            os.unlink(old_png)
        except OSError as exc:
            _progress(f"note: could not remove the earlier run's {old_png} ({exc.strerror or exc}); this run "
                      f"wrote {', '.join(report['files'])}")
    elif old_png:
        _progress(f"note: {old_png} was not written by this run (--no-picture) and is left as it is; this run "
                  f"wrote {', '.join(report['files'])}")
    for line in pipeline.summary_lines(run_):
        _progress(line)
    _progress(f"{', '.join(f'{a.name} on {a.joint}' for a in run_.scene.actuators)}; "
              f"{time.perf_counter() - t0:.2f} s; wrote {args.out}")
    return 0
