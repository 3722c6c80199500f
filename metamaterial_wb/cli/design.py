"""``design SCENE.json --out CONFIGURED.json [--fold AXIS=DEG ...] [--report REPORT.json]``.

The seed's design stage (section 4.1): validate the rotary axes, report the maximum achievable
fold of every axis, compute the hinge tilt of every crossed joint and write the configured scene.
"""
import sys

NAME = "design"
HELP = "configure the joints of a scene from its rotary axes and fold angles (writes a configured scene)"


def add_arguments(p):
    p.add_argument("scene", help="scene file with \"axes\" (JSON, docs/design.md)")
    p.add_argument("--out", required=True, help="configured scene (JSON) with joint_config")
    p.add_argument("--fold", action="append", default=[], metavar="AXIS=DEG",
                   help="set the fold (deg, at D = +1) of an axis by name or index (repeatable)")
    p.add_argument("--report", default=None, metavar="REPORT.json",
                   help="also write the design report (maximum folds, what binds, limits) as JSON")
    p.add_argument("--quiet", action="store_true", help="do not print the report")


def _apply_folds(scene, items):
    from metamaterial_wb.core.design import plan_axes
    from metamaterial_wb.core.errors import SceneError, check_number

    for s in items:
        if "=" not in s:
            raise SceneError(f"--fold {s}", "expected AXIS=DEG, e.g. --fold spine=30 or --fold 0=30")
        key, _, val = s.partition("=")
        key = key.strip()
        try:
            v = float(val)
        except ValueError:
            raise SceneError(f"--fold {key}", f"{val!r} is not a number") from None
        plans = plan_axes(scene)
        idx = None
        for p in plans:
            if key in (p.label_name, str(p.index), scene.axes[p.index].name):
                idx = p.index
        if idx is None:
            names = [p.label_name for p in plans]
            raise SceneError(f"--fold {key}", f"no axis is called {key!r}; the scene has {names or 'no axes'} "
                                              f"(or give the index 0..{len(plans) - 1})")
        scene.axes[idx].fold_deg = check_number(f"--fold {key}", v, -180.0, 180.0, "deg")


def run(args):
    from metamaterial_wb.core.design import configure, format_report
    from metamaterial_wb.core.errors import SceneError
    from metamaterial_wb.core.fileio import check_output, write_atomic, write_json
    from metamaterial_wb.core.scene import Scene

    check_output(args.out, "file", "--out")     # the configured scene may replace its input (configure in place)
    if args.report is not None:
        check_output(args.report, "file", "--report", inputs=[("scene", args.scene)])
    scene = Scene.load(args.scene)
    if not scene.axes:
        raise SceneError("axes", f"{args.scene} has no rotary axes; add \"axes\": [{{\"direction\": \"vertical\", "
                                 f"\"line\": 1, \"fold_deg\": 30}}] (docs/design.md)")
    _apply_folds(scene, args.fold)
    report = configure(scene)
    text = scene.to_json()
    if args.report:
        write_json(args.report, report)
    write_atomic(args.out, text)
    if not args.quiet:
        for line in format_report(report):
            print(line, file=sys.stdout if not line.startswith("warning") else sys.stderr)
    return 0
