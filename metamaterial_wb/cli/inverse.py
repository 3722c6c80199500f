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
                   help="also fit one hinge length per region (within the calibration table's range)")
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


def _mesh_loader(path):
    from metamaterial_wb.geometry.surface import load_surface_mesh
    return load_surface_mesh(path)


def _progress(msg):
    print(f"inverse: {msg}", file=sys.stderr, flush=True)


def run(args):
    import numpy as np

    from metamaterial_wb.core.errors import SceneError
    from metamaterial_wb.core.fileio import write_atomic, write_json
    from metamaterial_wb.core.inverse import evaluate as ev
    from metamaterial_wb.core.inverse.fit import Problem
    from metamaterial_wb.core.inverse.search import search_placement
    from metamaterial_wb.core.inverse.targets import load_target
    from metamaterial_wb.core.scene import Scene

    t0 = time.perf_counter()
    if args.hinges:
        from metamaterial_wb.core.inverse.hinges import parse_regions
        regions = parse_regions(args.hinge_regions)
    models = [m.strip() for m in args.evaluate.split(",") if m.strip()]
    for m in models:
        if m not in ev.MODELS:
            raise SceneError("--evaluate", f"{m!r}; allowed: {', '.join(ev.MODELS)}")
    if args.screen < 0:
        raise SceneError("--screen", f"{args.screen} is outside the allowed range [0, 1000] (0: fit every candidate)")
    if args.values_only and args.forbid:
        raise SceneError("--forbid", "has no effect with --values-only (the placement is the scene's)")
    if args.workers < 1:
        raise SceneError("--workers", f"{args.workers} is outside the allowed range [1, 256]")
    scene = Scene.load(args.scene)
    target = load_target(scene, args.target, mesh_loader=_mesh_loader)
    _progress(f"target {args.target}: {len(target.frames)} keyframe(s)")
    pb = Problem(scene, target, keep_actuators=args.values_only)
    forbidden = [f.strip() for item in args.forbid for f in item.split(",") if f.strip()]
    info = {"fits": 0, "screened": 0, "linearised": 0}
    lower = None
    mapper, nworkers = None, 1
    if args.values_only:
        if args.servos is not None and args.servos != len(scene.actuators):
            raise SceneError("--servos", f"{args.servos} with --values-only: the scene has {len(scene.actuators)} "
                                         f"actuators (leave --servos out)")
        if not scene.actuators:
            raise SceneError("actuators", "--values-only needs a scene with actuators")
        joints = tuple(a.joint for a in scene.actuators)
        names = [a.name for a in scene.actuators]
        fit = pb.fit(joints, starts=(0.5, -0.5))
        info["fits"] = 1
    else:
        if args.servos is None:
            raise SceneError("--servos", "give the servo budget N (or --values-only)")
        from metamaterial_wb.parallel import make_mapper
        mapper, nworkers = make_mapper(args.workers, args.scheduler)
        try:
            res = search_placement(pb, args.servos, forbidden=forbidden, mapper=mapper, workers=nworkers,
                                   progress=_progress, screen=args.screen)
        finally:
            if mapper is not None:
                mapper.close()
        joints, fit, names = res.joints, res.fit, None
        info.update(fits=res.fits, screened=res.screened, linearised=res.info.get("linearised", 0))
        lower = res.info.get("lower_bound")
    values = fit.values
    hinge_report, overrides = None, None
    if args.hinges:
        from metamaterial_wb.core.inverse.hinges import HingeRegions
        hr = HingeRegions(pb, *regions)
        _progress(f"fitting {len(hr.regions)} hinge length(s) with the values")
        hfit, lengths = hr.fit(joints, v0=values)
        if hfit.cost < fit.cost:
            fit, values = hfit, hfit.values
            overrides = hr.overrides(lengths)
        else:
            lengths = np.array(hr.start)
        hinge_report = hr.report(lengths)
        info["fits"] += 1
    out_scene = ev.answer_scene(pb, joints, values, names, hinge_overrides=overrides)
    if args.model != "quadratic":
        values = ev.polish_values(pb, out_scene, values, args.model, progress=_progress)
        out_scene = ev.answer_scene(pb, joints, values, names, hinge_overrides=overrides)
    errors = ev.evaluate_all(pb, out_scene, values, models, progress=_progress)
    picture = None
    first = next((m for m in (args.model, "quadratic") if m in errors and "per_frame" in errors[m]), None)
    if not args.no_picture and first:
        from metamaterial_wb.core.inverse.picture import answer_png
        picture = answer_png(pb, out_scene, errors[first],
                             title=f"{scene.name or 'scene'}: answer ({first} model) vs target")
    report = {
        "format": "metamaterial-inverse-report", "version": 1,
        "scene": os.path.abspath(args.scene), "target": os.path.abspath(args.target),
        "values_only": bool(args.values_only), "fit_model": args.model, "servos": len(joints),
        "forbidden": forbidden,
        "placement": [{"name": a.name, "joint": a.joint, "values": [float(v) for v in values[:, k]]}
                      for k, a in enumerate(out_scene.actuators)],
        "keyframes": [{"time_s": f.time_s} for f in target.frames],
        "hinges": hinge_report,
        "errors": {m: _json_errors(e) for m, e in errors.items()},
        "fit_cost_mm2": float(fit.cost), "free_field_bound_mm2": lower,
        "candidates_evaluated": info, "workers": nworkers, "scheduler": args.scheduler,
        "run_time_s": time.perf_counter() - t0,
    }
    os.makedirs(args.out, exist_ok=True)
    write_atomic(os.path.join(args.out, "scene.json"), out_scene.to_json())
    if picture is not None:
        write_atomic(os.path.join(args.out, "result.png"), picture, mode="wb")
    write_json(os.path.join(args.out, "report.json"), report)
    for m, e in errors.items():
        if e.get("rms_mm") is not None:
            _progress(f"{m}: rms {e['rms_mm']:.4g} mm, max {e['max_mm']:.4g} mm")
        if e.get("rms_deg") is not None:
            _progress(f"{m}: folds rms {e['rms_deg']:.4g} deg, max {e['max_deg']:.4g} deg")
        if "error" in e:
            _progress(f"{m}: {e['error']}")
    _progress(f"{', '.join(f'{a.name} on {a.joint}' for a in out_scene.actuators)}; "
              f"{time.perf_counter() - t0:.2f} s; wrote {args.out}")
    return 0


def _json_errors(e):
    if "per_frame" not in e:
        return dict(e)
    out = {k: v for k, v in e.items() if k not in ("per_frame",)}
    out["per_frame"] = [{k: v for k, v in f.items() if k != "positions_mm"} for f in e["per_frame"]]
    return out
