"""``render SCENE.json --out PICTURE.png [--global G | --set NAME=V ...] [--view ELEV,AZIM]``.

Draws the sheet in 3D in one state (matplotlib, no GUI): plates coloured by D, tilted hinges
green, actuators red. A scene with axes and no joint configuration is configured first.
"""
import sys

NAME = "render"
HELP = "draw the sheet in 3D in a given state to a PNG (no GUI needed)"


def add_arguments(p):
    from metamaterial_wb.cli import number

    p.add_argument("scene", help="scene file (JSON)")
    p.add_argument("--out", required=True, help="picture (PNG)")
    p.add_argument("--global", dest="global_g", type=number, default=None, metavar="G",
                   help="global deformation: every D = G in [-1, 1] (flat 0, folded target +1)")
    p.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                   help="change one actuator's or constraint's value before solving (repeatable)")
    p.add_argument("--view", default="28,-62", metavar="ELEV,AZIM",
                   help="camera angles in degrees, elevation in [-90, 90], azimuth in [-360, 360] (default 28,-62; "
                        "a negative elevation needs the = form: --view=-10,30)")
    p.add_argument("--size", default="1200x800", metavar="WxH", help="picture size in pixels")
    p.add_argument("--title", default=None,
                   help="title, drawn as typed (a newline starts a line); one that does not fit the picture is "
                        "refused (default: the scene name, shortened with a warning if too long, and the state)")


def _size(text):
    from metamaterial_wb.core.errors import SceneError
    from metamaterial_wb.core.numbers import parse_int
    try:                    # strictly: no 1_200, no non-ASCII digits
        w, h = (parse_int("--size", x) for x in text.lower().split("x"))
    except (ValueError, SceneError):
        raise SceneError("--size", f"{text!r}: expected WxH in pixels (ASCII digits), e.g. 1200x800") from None
    if not (100 <= w <= 8000 and 100 <= h <= 8000):
        raise SceneError("--size", f"{text!r}: width and height must be in [100, 8000] px")
    return w, h


def run(args):
    from metamaterial_wb.cli.solve import chosen_global, parse_sets
    from metamaterial_wb.core import kinematics
    from metamaterial_wb.core.design import ensure_configured, global_D, kinematics_for
    from metamaterial_wb.core.render import check_title, render_png, state_title_parts, view_angles
    from metamaterial_wb.core.scene import Scene
    from metamaterial_wb.core.solver import solve_scene

    from metamaterial_wb.core.fileio import check_output
    check_output(args.out, "file", "--out", inputs=[("scene", args.scene)])
    if not args.out.lower().endswith(".png"):
        from metamaterial_wb.core.errors import SceneError
        raise SceneError("--out", f"{args.out}: render writes a PNG picture; give a name ending in .png")
    size = _size(args.size)         # before any work
    check_title(args.title, size)   # a --title that does not fit: refused now, not after solving
    scene = Scene.load(args.scene)
    sets = parse_sets(args.set)
    for name, v in sets:
        scene.set_value(name, v)
    g = chosen_global(args.global_g, sets, scene)
    elev, azim = view_angles(args.view)
    for w in (ensure_configured(scene) or {}).get("warnings", []):
        print(f"warning: {w}", file=sys.stderr)
    if g is not None:
        D = global_D(scene, g)
        warnings = []
    else:
        D, _m, warnings, _t = solve_scene(scene)
    pos, R, _phi = kinematics.node_poses(scene, D, kin=kinematics_for(scene))
    if args.title is not None:      # as typed: refused above if it does not fit
        head, tail, field = args.title, "", "--title"
    else:                           # the scene name (up to 100 000 characters) is shortened to fit, and said
        (head, tail), field = state_title_parts(
            scene, g, None if g is not None else {it.name: it.value for _, it in scene.fixed_items()}), None
    notes = []
    render_png(scene, pos, R, D, args.out, title=head, title_tail=tail, title_field=field, elev=elev, azim=azim,
               size_px=size, notes=notes)
    for w in notes:
        print(f"warning: {w}", file=sys.stderr)
    for w in warnings:
        print(f"warning: {w}", file=sys.stderr)
    return 0
