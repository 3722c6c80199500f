"""``inverse SCENE --target TARGET --servos N --out DIR [--values-only] [--forbid J ...] [--model M]
[--workers N | --scheduler ADDR]``: inverse design, from a target shape to servo placement and values.

Writes ``DIR/scene.json`` (the scene with the servos placed, values and keyframe profiles filled),
``DIR/report.json`` (errors under every model, per node, chosen joints and values, run time,
candidates evaluated; docs/inverse.md) and ``DIR/result.png`` (answer over the target, coloured by
distance). Progress on stderr. A bad target is an error (exit 2) and nothing is written.
"""
import os
import sys
import time

NAME = "inverse"
HELP = "inverse design: place N servos and find their values that best reach a target shape"


def add_arguments(p):
    p.add_argument("scene", help="scene file (JSON); its angular constraints stay, its actuators are "
                                 "replaced (kept and only revalued with --values-only)")
    p.add_argument("--target", required=True,
                   help="target: target JSON (docs/inverse.md), a solve result JSON, or a surface "
                        "(.stl, .obj; .step/.stp with FreeCAD)")
    p.add_argument("--servos", type=int, default=None, help="servo budget N (not with --values-only)")
    p.add_argument("--out", required=True, help="output folder")
    p.add_argument("--values-only", action="store_true", help="keep the scene's actuators; fit their values only")
    p.add_argument("--forbid", action="append", default=[], metavar="JOINT",
                   help="a joint that may not get a servo (repeatable, or comma-separated)")
    p.add_argument("--hinges", action="store_true",
                   help="also fit the hinge sizes per region (length, and thickness / width when the calibration "
                        "table has them; within its range)")
    p.add_argument("--hinge-regions", default="2x2", metavar="ROWSxCOLS",
                   help="regions of --hinges: blocks of the sheet (default 2x2)")
    p.add_argument("--model", default="quadratic", choices=("quadratic", "linear", "nonlinear"),
                   help="model whose error the values minimise (placement always searched with the quadratic "
                        "model; linear / nonlinear polish the values afterwards)")
    p.add_argument("--evaluate", default="quadratic,linear,nonlinear",
                   help="models the answer is evaluated with (comma-separated; default all three)")
    p.add_argument("--screen", type=int, default=12, help="placements fully fitted per search round (default 12)")
    g = p.add_mutually_exclusive_group()
    g.add_argument("--workers", type=int, default=1, help="local worker processes (default 1)")
    g.add_argument("--scheduler", default=None, metavar="tcp://HOST:PORT", help="a Dask scheduler to run on")
    p.add_argument("--no-picture", action="store_true", help="skip result.png")
    p.add_argument("--fab-checks", default="all", choices=("all", "parameters", "off"),
                   help="fabrication checks of the answer, the ones build runs (report.json 'fabrication', "
                        "'printable'): all (parameters, then the geometry checks in a subprocess when FreeCAD "
                        "is there; default), parameters (printable tilt, walls, fits only), off")


def _mesh_loader(path):
    from metamaterial_wb.geometry.surface import load_surface_mesh
    return load_surface_mesh(path)


def _progress(msg):
    print(f"inverse: {msg}", file=sys.stderr, flush=True)


def run(args):
    from metamaterial_wb.core.errors import SceneError
    from metamaterial_wb.core.fileio import write_atomic, write_json
    from metamaterial_wb.core.inverse import pipeline
    from metamaterial_wb.core.inverse.targets import load_target
    from metamaterial_wb.core.scene import Scene

    t0 = time.perf_counter()
    regions = None
    if args.hinges:
        from metamaterial_wb.core.inverse.hinges import parse_regions
        regions = parse_regions(args.hinge_regions)
    models = [m.strip() for m in args.evaluate.split(",") if m.strip()]
    if args.workers < 1:
        raise SceneError("--workers", f"{args.workers} is outside the allowed range [1, 256]")
    scene = Scene.load(args.scene)
    target = load_target(scene, args.target, mesh_loader=_mesh_loader)
    _progress(f"target {args.target}: {len(target.frames)} keyframe(s)")
    forbidden = [f.strip() for item in args.forbid for f in item.split(",") if f.strip()]
    fab_check = None
    if args.fab_checks != "off":
        from metamaterial_wb.export.printability import check_printable

        def fab_check(s):
            return check_printable(s, geometry="subprocess" if args.fab_checks == "all" else "off")
    mapper, nworkers = None, 1
    if not args.values_only and args.servos is not None:
        from metamaterial_wb.parallel import make_mapper
        mapper, nworkers = make_mapper(args.workers, args.scheduler)
    try:
        run_ = pipeline.solve(scene, target, servos=args.servos, values_only=args.values_only, forbidden=forbidden,
                              hinge_regions=regions, model=args.model, evaluate=models, screen=args.screen,
                              mapper=mapper, workers=nworkers, progress=_progress, fab_check=fab_check)
    finally:
        if mapper is not None:
            mapper.close()
    picture = None
    first = next((m for m in (args.model, "quadratic") if m in run_.errors and "per_frame" in run_.errors[m]), None)
    if not args.no_picture and first:
        from metamaterial_wb.core.inverse.picture import answer_png
        picture = answer_png(run_.problem, run_.scene, run_.errors[first],
                             title=f"{scene.name or 'scene'}: answer ({first} model) vs target")
    report = pipeline.report_dict(
        run_, scene=os.path.abspath(args.scene), target=os.path.abspath(args.target),
        values_only=bool(args.values_only), fit_model=args.model, forbidden=forbidden, workers=nworkers,
        scheduler=args.scheduler)
    report["run_time_s"] = time.perf_counter() - t0
    os.makedirs(args.out, exist_ok=True)
    write_atomic(os.path.join(args.out, "scene.json"), run_.scene.to_json())
    if picture is not None:
        write_atomic(os.path.join(args.out, "result.png"), picture, mode="wb")
    write_json(os.path.join(args.out, "report.json"), report)
    for line in pipeline.summary_lines(run_):
        _progress(line)
    _progress(f"{', '.join(f'{a.name} on {a.joint}' for a in run_.scene.actuators)}; "
              f"{time.perf_counter() - t0:.2f} s; wrote {args.out}")
    return 0


