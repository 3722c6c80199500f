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
to a temporary directory first and moved into DIR only when all succeeded.
"""
import os
import shutil
import sys
import time

NAME = "build"
HELP = "fabrication: build the sheet (and modules) and export STEP / 3MF for dual-extruder printers"


def add_arguments(p):
    p.add_argument("scene", help="scene file (JSON, docs/scene-format.md)")
    p.add_argument("--out", required=True, help="output directory (created if missing)")
    p.add_argument("--step", action="store_true", help="write STEP files")
    p.add_argument("--3mf", dest="threemf", action="store_true", help="write 3MF files")
    p.add_argument("--modules", action="store_true", help="also build the scene's modules (own files)")
    p.add_argument("--layout", choices=("prusa", "components", "both"), default="both",
                   help="3MF layout(s) of the sheet (default both)")
    p.add_argument("--tolerance", type=float, default=None, metavar="MM",
                   help="3MF tessellation tolerance in mm (default: fabrication.tolerance_mm, 0.05)")
    p.add_argument("--no-sockets", action="store_true", help="plain nodes without snap-fit sockets")
    p.add_argument("--clearance", type=float, default=None, metavar="MM",
                   help="socket / plug clearance in mm (default: fabrication.clearance_mm, 0.2)")
    p.add_argument("--check", action="store_true",
                   help="also check rigid/flexible overlap only at the anchors of every hinge (slow on large "
                        "sheets); the solids and the modules are always checked unless --no-check")
    p.add_argument("--no-check", action="store_true",
                   help="experts: skip the geometry checks (collisions, solids) before writing")
    p.add_argument("--quiet", action="store_true", help="no progress lines")


def safe_stem(text):
    keep = "".join(ch if ch.isalnum() or ch in "-_." else "_" for ch in text)
    return keep.strip("._") or "scene"


def run_checks(result, checks=None, progress=True, stream=None):
    """The geometry checks every export runs (``checks``: names for geometry.validity.check_build;
    ``None``: its defaults; ``()``: none). Raises MetamaterialError listing the problems, nothing written.
    Returns the names of the checks that ran."""
    from metamaterial_wb.core.errors import MetamaterialError
    from metamaterial_wb.geometry.progress import note
    from metamaterial_wb.geometry.validity import DEFAULT_CHECKS, check_build

    t0 = time.perf_counter()
    problems, ran = check_build(result, DEFAULT_CHECKS if checks is None else checks)
    if problems:
        more = f" (+{len(problems) - 5} more)" if len(problems) > 5 else ""
        raise MetamaterialError(f"{len(problems)} geometry problem(s), nothing written: " + "; ".join(problems[:5]) +
                                more)
    if ran:
        note(f"checks passed ({', '.join(ran)}) in {time.perf_counter() - t0:.2f} s", progress, stream)
    return ran


BED_MARGIN_MM = 10.0


def onto_bed(meshes, margin_mm=BED_MARGIN_MM):
    """Move sheet meshes (sheet coordinates: rows grow towards -y) so that their bounding box starts at
    ``(margin, margin, 0)``: slicers that keep positions (PrusaSlicer ``--dont-arrange``, components
    layouts) then find the sheet on the bed. Returns ``(meshes, offset)``."""
    import numpy as np
    lo = np.min([V.min(axis=0) for _, V, _, _, _ in meshes], axis=0)
    off = np.array([margin_mm - lo[0], margin_mm - lo[1], -lo[2]])
    return [(n, V + off, T, m, e) for n, V, T, m, e in meshes], [round(float(c), 6) for c in off]


def export_result(result, out_dir, step=True, threemf=True, layouts=("prusa", "components"), progress=True,
                  stem="scene", stream=None, tolerance_mm=None, checks=None):
    """Check (:func:`run_checks`, ``checks=()`` to skip) and write the files of a BuildResult into
    ``out_dir`` (atomically as a set). Returns the file list."""
    from metamaterial_wb.export.manifest import build_manifest, write_manifest
    from metamaterial_wb.export.mesh import part_meshes
    from metamaterial_wb.export.printpose import lay_out_best_poses
    from metamaterial_wb.export.step import result_bodies, write_step
    from metamaterial_wb.export.threemf import write_3mf
    from metamaterial_wb.geometry.params import MATERIALS
    from metamaterial_wb.geometry.progress import note

    stream = stream if stream is not None else sys.stderr
    result.checks_ran = run_checks(result, checks, progress, stream)
    os.makedirs(out_dir, exist_ok=True)
    from metamaterial_wb.core.fileio import commit_set, make_temp_dir
    tmp = make_temp_dir(out_dir, "build")
    written = []
    files_by_group = {}
    poses = {}
    colours = dict(MATERIALS)
    try:
        groups = result.groups()
        for group, parts in groups.items():
            t0 = time.perf_counter()
            base = f"{stem}_{group}"
            if group == "sheet":
                parts = sorted(parts, key=lambda q: (q.role != "node", 0))   # nodes first: hinges win overlaps
            n_before = len(written)
            if step:
                write_step(os.path.join(tmp, base + ".step"), result_bodies(result, parts), base)
                written.append(base + ".step")
            if threemf:
                meshes = part_meshes(result, parts, tolerance_mm)
                if group == "sheet":
                    meshes, result.bed_offset_mm = onto_bed(meshes)
                    for layout in layouts:
                        name = base + (".3mf" if layout == "prusa" else "_components.3mf")
                        write_3mf(os.path.join(tmp, name), meshes, layout=layout, materials=colours, object_name=base)
                        written.append(name)
                else:
                    # print poses: each part in the axis-aligned pose that needs the least support, side by side
                    meshes, reps = lay_out_best_poses(meshes)
                    poses.update(reps)
                    write_3mf(os.path.join(tmp, base + ".3mf"), meshes, layout="objects", materials=colours,
                              object_name=base)
                    written.append(base + ".3mf")
            files_by_group[group] = written[n_before:]
            note(f"{group}: {len(parts)} part(s) exported in {time.perf_counter() - t0:.2f} s", progress, stream)
        if step and len(groups) > 1:
            base = f"{stem}_assembly"
            write_step(os.path.join(tmp, base + ".step"), result_bodies(result, result.parts), base)
            written.append(base + ".step")
            files_by_group["assembly"] = [base + ".step"]
        write_manifest(os.path.join(tmp, "manifest.json"),
                       build_manifest(result, files_by_group, stem, result.checks_ran, poses))
        written.append("manifest.json")
        umask = os.umask(0)
        os.umask(umask)
        for name in written:
            os.chmod(os.path.join(tmp, name), 0o666 & ~umask)    # mkstemp files are 0600
        commit_set(tmp, out_dir, written)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return [os.path.join(out_dir, n) for n in written]


def run(args):
    from metamaterial_wb.core.errors import SceneError
    from metamaterial_wb.core.scene import Scene
    from metamaterial_wb.geometry.build import build_scene
    from metamaterial_wb.geometry.params import fabrication_params

    from metamaterial_wb.core.fileio import check_output
    check_output(args.out, "dir", "--out")
    t0 = time.perf_counter()
    scene = Scene.load(args.scene)
    overrides = {}
    if args.no_sockets:
        overrides["sockets"] = False
    if args.clearance is not None:
        overrides["clearance_mm"] = args.clearance
    if args.tolerance is not None:
        overrides["tolerance_mm"] = args.tolerance
    params = fabrication_params(scene, **overrides)       # all checks before any geometry
    if args.modules:
        from metamaterial_wb.geometry.modules import parse_modules
        parse_modules(scene, params)
    elif scene.modules and not args.quiet:
        print(f"build: the scene has {len(scene.modules)} module(s); add --modules to build them", file=sys.stderr)
    if os.path.exists(args.out) and not os.path.isdir(args.out):
        raise SceneError("--out", f"{args.out!r} exists and is not a directory")
    step = args.step or not args.threemf
    threemf = args.threemf or not args.step
    layouts = ("prusa", "components") if args.layout == "both" else (args.layout,)
    result = build_scene(scene, modules=args.modules, progress=not args.quiet, params=params)
    from metamaterial_wb.geometry.validity import ALL_CHECKS, DEFAULT_CHECKS
    checks = () if args.no_check else (ALL_CHECKS if args.check else DEFAULT_CHECKS)
    stem = safe_stem(scene.name or os.path.splitext(os.path.basename(args.scene))[0])
    files = export_result(result, args.out, step=step, threemf=threemf, layouts=layouts,
                          progress=not args.quiet, stem=stem, checks=checks)
    if not args.quiet:
        print(f"build: wrote {len(files)} file(s) to {args.out} in {time.perf_counter() - t0:.2f} s", file=sys.stderr)
    for f in files:
        print(f)
    return 0
