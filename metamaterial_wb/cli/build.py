"""``build SCENE.json --out DIR [--step] [--3mf] [--modules]``: fabrication files of a scene.

Writes (``NAME`` = the scene's name, else the file's stem):

* ``DIR/NAME_sheet.step``: the sheet, one named body per node and hinge, PLA/TPU colours;
* ``DIR/NAME_sheet.3mf``: PrusaSlicer layout (one object, a volume per part, per-part extruder);
* ``DIR/NAME_sheet_components.3mf``: components layout with Bambu Studio / OrcaSlicer and Cura hints;
* checks before anything is written (geometry/validity.py): by default the solids and the modules
  (module/module and module/sheet collisions, the servo's horn adapter over its whole rotation);
  ``--check`` adds the rigid/flexible overlap check of every hinge; ``--no-check`` skips them all
  (experts). Parameter checks (walls of at least two nozzle widths, fits) always run;
* with ``--modules``: ``DIR/NAME_<module>.step`` and ``.3mf`` per module (separate prints) and
  ``DIR/NAME_assembly.step`` (sheet and modules in place).

Every build also writes ``DIR/manifest.json`` (docs/fabrication.md, "The build manifest"): parts,
placements, files, servo shafts and joint pivots, snap-fit strains, print-pose checks, checks run.
Module 3MF files hold each part in the axis-aligned pose that needs the least support (checked on
the mesh: export/printpose.py). Without ``--step`` and ``--3mf`` both are written. Progress goes to stderr. Every file is written
to a temporary directory first and moved into DIR only when all succeeded (DIR, if this run created it, is
removed again when it fails). Every output name is known before any geometry: a module whose files would be
another output's (``sheet_components``), a name that makes a file name longer than 255 bytes, or an output that is
the scene file itself (``DIR/manifest.json`` read as the scene), is refused then. Files of an earlier build that
this one does not write are removed and named on stderr, also with ``--quiet``.
"""
import os
import sys
import time

NAME = "build"
HELP = "fabrication: build the sheet (and modules) and export STEP / 3MF for dual-extruder printers"

from metamaterial_wb.core.fileio import check_scene_not_output  # noqa: E402
from metamaterial_wb.export.package import check_output_names, export_result, safe_stem  # noqa: E402


def add_arguments(p):
    from metamaterial_wb.cli import number

    p.add_argument("scene", help="scene file (JSON, docs/scene-format.md)")
    p.add_argument("--out", required=True, help="output directory (created if missing)")
    p.add_argument("--step", action="store_true", help="write STEP files")
    p.add_argument("--3mf", dest="threemf", action="store_true", help="write 3MF files")
    p.add_argument("--modules", action="store_true", help="also build the scene's modules (own files)")
    p.add_argument("--layout", choices=("prusa", "components", "both"), default=None,
                   help="3MF layout(s) of the sheet (default both; not with --step alone)")
    p.add_argument("--tolerance", type=number, default=None, metavar="MM",
                   help="3MF tessellation tolerance in mm (default: fabrication.tolerance_mm, 0.05; not with --step "
                        "alone)")
    p.add_argument("--no-sockets", action="store_true", help="plain nodes without snap-fit sockets")
    p.add_argument("--clearance", type=number, default=None, metavar="MM",
                   help="socket / plug clearance in mm (default: fabrication.clearance_mm, 0.2)")
    p.add_argument("--check", action="store_true",
                   help="also check rigid/flexible overlap only at the anchors of every hinge (slow on large "
                        "sheets); the solids and the modules are always checked unless --no-check")
    p.add_argument("--no-check", action="store_true",
                   help="experts: skip the geometry checks (collisions, solids) before writing")
    p.add_argument("--quiet", action="store_true", help="no progress lines")


def run(args):
    from metamaterial_wb.core.errors import SceneError
    from metamaterial_wb.core.scene import Scene
    from metamaterial_wb.geometry.build import build_scene
    from metamaterial_wb.core.design import effective_tilts_deg
    from metamaterial_wb.core.fabrication import fabrication_params

    from metamaterial_wb.core.fileio import check_output
    check_output(args.out, "dir", "--out")
    if args.check and args.no_check:
        raise SceneError("--no-check", "contradicts --check (one adds the hinge-anchor check, the other skips all "
                                       "checks): give one of them")
    if args.layout is not None and args.step and not args.threemf:
        raise SceneError("--layout", f"{args.layout!r} chooses a 3MF layout, but only --step is written: add --3mf "
                                     f"or drop --layout")
    if args.tolerance is not None and args.step and not args.threemf:
        raise SceneError("--tolerance", f"{args.tolerance:g} mm sets the 3MF tessellation, but only --step is written "
                                        f"(STEP keeps the exact solids): add --3mf or drop --tolerance")
    t0 = time.perf_counter()
    scene = Scene.load(args.scene)
    step = args.step or not args.threemf
    threemf = args.threemf or not args.step
    layouts = ("prusa", "components") if args.layout in (None, "both") else (args.layout,)
    stem = safe_stem(scene.name or os.path.splitext(os.path.basename(args.scene))[0])
    names = dict(stem=stem, step=step, threemf=threemf, layouts=layouts,
                 stem_field="name" if scene.name else "scene (its file name)")
    check_scene_not_output(args.out, check_output_names(modules=[], **names), args.scene, writer="the build")  # first
    overrides = {}
    if args.no_sockets:
        overrides["sockets"] = False
    if args.clearance is not None:
        overrides["clearance_mm"] = args.clearance
    if args.tolerance is not None:
        overrides["tolerance_mm"] = args.tolerance
    try:
        params = fabrication_params(scene, effective_tilts_deg(scene), **overrides)   # all checks before any geometry
    except SceneError as exc:      # a value from a flag: name the flag the user typed
        flag = {"fabrication.clearance_mm": "--clearance", "fabrication.tolerance_mm": "--tolerance"}.get(exc.field)
        if flag is None or getattr(args, flag[2:]) is None:
            raise
        raise SceneError(f"{flag} ({exc.field})", exc.message) from None
    if args.modules:
        from metamaterial_wb.geometry.modules import parse_modules
        check_scene_not_output(args.out, check_output_names(
            modules=[(m.index, m.name) for m in parse_modules(scene, params)], **names), args.scene, writer="the build")
    elif scene.modules and not args.quiet:
        print(f"build: the scene has {len(scene.modules)} module(s); add --modules to build them", file=sys.stderr)
    if os.path.exists(args.out) and not os.path.isdir(args.out):
        raise SceneError("--out", f"{args.out!r} exists and is not a directory")
    result = build_scene(scene, modules=args.modules, progress=not args.quiet, params=params)
    from metamaterial_wb.geometry.validity import ALL_CHECKS, DEFAULT_CHECKS
    checks = () if args.no_check else (ALL_CHECKS if args.check else DEFAULT_CHECKS)
    files = export_result(result, args.out, step=step, threemf=threemf, layouts=layouts,
                          progress=not args.quiet, stem=stem, checks=checks)
    if not args.quiet:
        print(f"build: wrote {len(files)} file(s) to {args.out} in {time.perf_counter() - t0:.2f} s", file=sys.stderr)
    for f in files:
        print(f)
    return 0
