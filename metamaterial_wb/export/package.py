"""The export package of a built sheet: checks first, then STEP / 3MF / module files and the manifest, all
written to a temporary folder and moved into place as one set (what ``build`` and the GUI's Export both
call). Files and layouts: the ``build`` command's doc (cli/build.py) and docs/fabrication.md."""
import os
import shutil
import sys
import time

from metamaterial_wb.core.outdir import missing_dirs
from metamaterial_wb.geometry.parts import safe_stem  # noqa: F401  (re-exported: cli/build.py, the GUI)

BED_MARGIN_MM = 10.0
MAX_NAME_BYTES = 255            # a file name on Linux, macOS and Windows file systems
MANIFEST = "manifest.json"


def file_name(stem, group, kind):
    """The name of one output: ``kind`` "step", "prusa" / "components" (the sheet's 3MF layouts) or "3mf" (a
    module's 3MF); ``group`` "sheet", "assembly" or a module's name."""
    base = f"{stem}_{group}"
    return base + {"step": ".step", "prusa": ".3mf", "components": "_components.3mf", "3mf": ".3mf"}[kind]


def output_names(stem, modules, step=True, threemf=True, layouts=("prusa", "components")):
    """Every file a build writes, in writing order, before anything is built: ``[(file, field, what)]`` with the
    scene field that names it (``name`` for the sheet's, ``modules[k].name`` for a module's) and what it holds.
    ``modules``: module names or ``(index, name)`` pairs, in the scene's order."""
    mods = [m if isinstance(m, tuple) else (k, m) for k, m in enumerate(modules)]
    out = []
    groups = [("sheet", "name", "the sheet")] + [(n, f"modules[{k}].name", f"module {n!r}") for k, n in mods]
    for group, field, what in groups:
        if step:
            out.append((file_name(stem, group, "step"), field, what + "'s STEP"))
        if threemf and group == "sheet":
            out += [(file_name(stem, group, lay), field, f"the sheet's {lay} layout") for lay in layouts]
        elif threemf:
            out.append((file_name(stem, group, "3mf"), field, what + "'s 3MF"))
    if step and mods:
        out.append((file_name(stem, "assembly", "step"), "name", "the assembly"))
    out.append((MANIFEST, None, "the manifest"))
    return out


def _nbytes(text):
    return len(os.fsencode(text))


def check_output_names(stem, modules, step=True, threemf=True, layouts=("prusa", "components"), stem_field="name"):
    """Refuse, before any work, an output name longer than 255 bytes or one that two outputs share (also in another
    letter case: one file on Windows and macOS). The error names the scene field that makes the name (the scene's
    ``name``, given as ``stem_field``, or ``modules[k].name``). Returns :func:`output_names`."""
    from metamaterial_wb.core.errors import SceneError

    names = output_names(stem, modules, step, threemf, layouts)
    fixed = [(n, what) for n, field, what in names if field == "name"]        # the scene name's own files first
    tail = max(_nbytes(n) - _nbytes(stem) for n, _ in fixed)
    for n, what in fixed:
        if _nbytes(n) > MAX_NAME_BYTES:
            raise SceneError(stem_field, f"{stem[:24]!r}... has {_nbytes(stem)} bytes and makes {what}'s file name "
                                         f"{_nbytes(n)} bytes long ({n[:12]}...{n[-24:]}), over the {MAX_NAME_BYTES} "
                                         f"bytes a file name may have; allowed: a name of at most "
                                         f"{MAX_NAME_BYTES - tail} bytes")
    by_field = {f"modules[{k}].name": m for k, m in (m if isinstance(m, tuple) else (i, m)
                                                     for i, m in enumerate(modules))}
    for n, field, what in names:
        if field in by_field and _nbytes(n) > MAX_NAME_BYTES:
            module = by_field[field]
            room = MAX_NAME_BYTES - (_nbytes(n) - _nbytes(module))
            raise SceneError(field, f"{module!r} makes {what}'s file name {_nbytes(n)} bytes long ({n[:12]}..."
                                    f"{n[-24:]}), over the {MAX_NAME_BYTES} bytes a file name may have; allowed: a "
                                    f"module name of at most {room} bytes with this scene's name ({_nbytes(stem)} "
                                    f"bytes)")
    seen = {}
    for n, field, what in names:
        key = n.casefold()
        if key in seen:
            other, owhat = seen[key]
            same = "" if other == n else f" ({other}: names that differ only in case are one file on Windows and macOS)"
            raise SceneError(field or "name", f"{what} would be written as {n}, the file of {owhat} too{same}; "
                                              f"allowed: a name whose files no other output has (not sheet, "
                                              f"sheet_components, assembly nor another module's name)")
        seen[key] = (n, what)
    return names


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




def onto_bed(meshes, margin_mm=BED_MARGIN_MM):
    """Move meshes (the sheet in sheet coordinates, rows growing towards -y; a module's parts laid out in
    their print poses) so that their bounding box starts at ``(margin, margin, 0)``: slicers that keep
    positions (PrusaSlicer ``--dont-arrange``, components layouts) then find them on the bed. Returns
    ``(meshes, offset)``."""
    import numpy as np
    lo = np.min([V.min(axis=0) for _, V, _, _, _ in meshes], axis=0)
    off = np.array([margin_mm - lo[0], margin_mm - lo[1], -lo[2]])
    return [(n, V + off, T, m, e) for n, V, T, m, e in meshes], [round(float(c), 6) for c in off]


def export_result(result, out_dir, step=True, threemf=True, layouts=("prusa", "components"), progress=True,
                  stem="scene", stream=None, tolerance_mm=None, checks=None):
    """Check the output names (:func:`check_output_names`) and the geometry (:func:`run_checks`, ``checks=()`` to
    skip), then write the files of a BuildResult into ``out_dir`` (atomically as a set; folders this call creates
    are removed again if it fails). Returns the file list."""
    from metamaterial_wb.core.fileio import commit_set, earlier_outputs, make_temp_dir, remove_outputs
    from metamaterial_wb.export.manifest import FORMAT
    from metamaterial_wb.geometry.progress import note

    stream = stream if stream is not None else sys.stderr
    index = {spec.name: spec.index for spec in result.modules}
    groups = result.groups()
    check_output_names(stem, [(index.get(g, "?"), g) for g in groups if g != "sheet"], step, threemf, layouts)
    result.checks_ran = run_checks(result, checks, progress, stream)
    created = missing_dirs(out_dir)
    tmp = None
    try:
        os.makedirs(out_dir, exist_ok=True)
        tmp = make_temp_dir(out_dir, "build")
        written = _write_files(result, groups, tmp, step, threemf, layouts, progress, stem, stream, tolerance_mm)
        stale = earlier_outputs(out_dir, MANIFEST, FORMAT, written)
        commit_set(tmp, out_dir, written)     # refuses a set naming one file twice before any move
    except BaseException:
        if tmp is not None:                     # first: the folders below can only go once empty
            shutil.rmtree(tmp, ignore_errors=True)
        for d in created:                       # innermost first: the folders this call made, if still empty
            try:
                os.rmdir(d)
            except OSError:
                break
        raise
    finally:
        if tmp is not None:
            shutil.rmtree(tmp, ignore_errors=True)
    gone = remove_outputs(out_dir, stale)
    if gone:        # not progress: said also with --quiet (docs/fabrication.md)
        note(f"removed {len(gone)} file(s) of the earlier build that this one does not write: {', '.join(gone)}",
             True, stream)
    return [os.path.join(out_dir, n) for n in written]


def _write_files(result, groups, tmp, step, threemf, layouts, progress, stem, stream, tolerance_mm):
    """Write every file of the set into the temporary folder ``tmp`` (names: :func:`file_name`); returns them."""
    from metamaterial_wb.export.manifest import build_manifest, write_manifest
    from metamaterial_wb.export.mesh import part_meshes
    from metamaterial_wb.export.printpose import forced_poses, lay_out_best_poses
    from metamaterial_wb.export.step import result_instances, write_step_instanced
    from metamaterial_wb.export.threemf import write_3mf
    from metamaterial_wb.core.materials import MATERIALS
    from metamaterial_wb.geometry.progress import note

    written = []
    files_by_group = {}
    poses = {}
    colours = dict(MATERIALS)
    for group, parts in groups.items():
        t0 = time.perf_counter()
        base = f"{stem}_{group}"
        if group == "sheet":
            parts = sorted(parts, key=lambda q: (q.role != "node", 0))   # nodes first: hinges win overlaps
        n_before = len(written)
        if step:
            shapes, inst, cols = result_instances(result, parts)     # each unique shape once
            write_step_instanced(os.path.join(tmp, file_name(stem, group, "step")), shapes, inst, base, cols)
            written.append(file_name(stem, group, "step"))
        if threemf:
            meshes = part_meshes(result, parts, tolerance_mm)
            if group == "sheet":
                meshes, result.bed_offset_mm = onto_bed(meshes)
                for layout in layouts:
                    name = file_name(stem, group, layout)
                    write_3mf(os.path.join(tmp, name), meshes, layout=layout, materials=colours, object_name=base)
                    written.append(name)
            else:
                # print poses: each part in the axis-aligned pose that needs the least support, side by side
                meshes, reps = lay_out_best_poses(meshes, forced=forced_poses(parts))
                meshes, _ = onto_bed(meshes)        # the bed margin, as the sheet's: no arrange needed
                poses.update(reps)
                write_3mf(os.path.join(tmp, file_name(stem, group, "3mf")), meshes, layout="objects",
                          materials=colours, object_name=base)
                written.append(file_name(stem, group, "3mf"))
        files_by_group[group] = written[n_before:]
        note(f"{group}: {len(parts)} part(s) exported in {time.perf_counter() - t0:.2f} s", progress, stream)
    if step and len(groups) > 1:
        name = file_name(stem, "assembly", "step")
        shapes, inst, cols = result_instances(result, result.parts)
        write_step_instanced(os.path.join(tmp, name), shapes, inst, f"{stem}_assembly", cols)
        written.append(name)
        files_by_group["assembly"] = [name]
    write_manifest(os.path.join(tmp, MANIFEST), build_manifest(result, files_by_group, stem, result.checks_ran, poses))
    written.append(MANIFEST)
    umask = os.umask(0)
    os.umask(umask)
    for name in written:
        os.chmod(os.path.join(tmp, name), 0o666 & ~umask)    # mkstemp files are 0600
    return written
