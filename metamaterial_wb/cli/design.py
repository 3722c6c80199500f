"""``design SCENE.json --out CONFIGURED.json [--fold AXIS=DEG ...] [--report REPORT.json]``.

The seed's design stage (section 4.1): validate the rotary axes, report the maximum achievable
fold of every axis, compute the hinge tilt of every crossed joint and write the configured scene.
``--out`` and ``--report`` are checked before any work and written together: both or neither (a failed
write leaves both files as they were).
"""
import json
import os
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
    p.add_argument("--quiet", action="store_true", help="do not print the report (warnings are still printed)")


def _apply_folds(scene, items):
    """Set the folds given by ``--fold``; returns ``{axis index: (the flag's key, its text)}`` (for errors)."""
    from metamaterial_wb.core.design import plan_axes
    from metamaterial_wb.core.errors import SceneError, check_number
    from metamaterial_wb.core.numbers import parse_float

    given = {}
    for s in items:
        if "=" not in s:
            raise SceneError(f"--fold {s}", "expected AXIS=DEG, e.g. --fold spine=30 or --fold 0=30")
        key, _, val = s.partition("=")
        key = key.strip()
        v = parse_float(f"--fold {key}", val)     # strictly: no 1_0, non-ASCII digits, inf/nan, subnormals
        plans = plan_axes(scene)
        hits = sorted({p.index for p in plans if key in (p.label_name, str(p.index), scene.axes[p.index].name)})
        if len(hits) > 1:
            raise SceneError(f"--fold {key}", f"names axes {hits} (one by name, another by index); give the "
                                              f"other axis's name or index")
        idx = hits[0] if hits else None
        if idx is None:
            names = [p.label_name for p in plans]
            raise SceneError(f"--fold {key}", f"no axis is called {key!r}; the scene has {names or 'no axes'} "
                                              f"(or give the index 0..{len(plans) - 1})")
        if idx in given:
            raise SceneError(f"--fold {key}", f"axis {idx} given twice ({given[idx][1]} and {s.strip()}); give "
                                              f"each axis once")
        scene.axes[idx].fold_deg = check_number(f"--fold {key}", v, -180.0, 180.0, "deg")
        given[idx] = (key, s.strip())
    return given


def run(args):
    from metamaterial_wb.core.design import configure, format_report
    from metamaterial_wb.core.errors import SceneError
    from metamaterial_wb.core.fileio import check_output, write_together
    from metamaterial_wb.core.scene import Scene

    check_output(args.out, "file", "--out")     # the configured scene may replace its input (configure in place)
    if args.report is not None:
        check_output(args.report, "file", "--report", inputs=[("scene", args.scene)])
        if os.path.realpath(args.report) == os.path.realpath(args.out):
            raise SceneError("--report", f"{args.report} is also --out; the configured scene would overwrite the "
                                         f"report: give two files")
        for a, b in ((args.report, args.out), (args.out, args.report)):     # one would need the other as a folder
            if os.path.realpath(b).startswith(os.path.realpath(a).rstrip(os.sep) + os.sep):
                raise SceneError("--report", f"{args.report} with --out {args.out}: {b} would be inside {a}, which "
                                             f"is written as a file; give two files, neither inside the other")
    scene = Scene.load(args.scene)
    if not scene.axes:
        from metamaterial_wb.core.design import suggest_axis
        axis = suggest_axis(scene)      # one this scene accepts (a 1x1 grid has no column 1)
        raise SceneError("axes", f"{args.scene} has no rotary axes; "
                                 + (f"add \"axes\": [{json.dumps(axis)}] (docs/design.md)" if axis else
                                    "no line of its layout takes one (docs/design.md)"))
    given = _apply_folds(scene, args.fold)
    try:
        report = configure(scene)
    except SceneError as exc:       # a fold from the command line: name the flag the user typed
        idx = next((i for i in given if exc.field == f"axes[{i}].fold_deg"), None)
        if idx is None:
            raise
        raise SceneError(f"--fold {given[idx][0]} ({exc.field})", exc.message) from None
    outputs = [(args.out, scene.to_json())]          # both serialised before anything is written
    if args.report:
        marked = {"format": "metamaterial-design-report", "version": 1, **report}   # named if read as a scene
        outputs.append((args.report, json.dumps(marked, indent=1, allow_nan=False) + "\n"))
    write_together(outputs)
    for line in format_report(report):      # --quiet hides the report, never a warning
        if line.startswith("warning"):
            print(line, file=sys.stderr)
        elif not args.quiet:
            print(line)
    return 0
