"""The export package of a built sheet: checks first, then STEP / 3MF / module files and the manifest, all
written to a temporary folder and moved into place as one set (what ``build`` and the GUI's Export both
call). Files and layouts: the ``build`` command's doc (cli/build.py) and docs/fabrication.md."""
import os
import shutil
import sys
import time

BED_MARGIN_MM = 10.0


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
    """Check (:func:`run_checks`, ``checks=()`` to skip) and write the files of a BuildResult into
    ``out_dir`` (atomically as a set). Returns the file list."""
    from metamaterial_wb.export.manifest import FORMAT, build_manifest, write_manifest
    from metamaterial_wb.export.mesh import part_meshes
    from metamaterial_wb.export.printpose import forced_poses, lay_out_best_poses
    from metamaterial_wb.export.step import result_instances, write_step_instanced
    from metamaterial_wb.export.threemf import write_3mf
    from metamaterial_wb.core.materials import MATERIALS
    from metamaterial_wb.geometry.progress import note

    stream = stream if stream is not None else sys.stderr
    result.checks_ran = run_checks(result, checks, progress, stream)
    os.makedirs(out_dir, exist_ok=True)
    from metamaterial_wb.core.fileio import commit_set, earlier_outputs, make_temp_dir, remove_outputs
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
                shapes, inst, cols = result_instances(result, parts)     # each unique shape once
                write_step_instanced(os.path.join(tmp, base + ".step"), shapes, inst, base, cols)
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
                    meshes, reps = lay_out_best_poses(meshes, forced=forced_poses(parts))
                    meshes, _ = onto_bed(meshes)        # the bed margin, as the sheet's: no arrange needed
                    poses.update(reps)
                    write_3mf(os.path.join(tmp, base + ".3mf"), meshes, layout="objects", materials=colours,
                              object_name=base)
                    written.append(base + ".3mf")
            files_by_group[group] = written[n_before:]
            note(f"{group}: {len(parts)} part(s) exported in {time.perf_counter() - t0:.2f} s", progress, stream)
        if step and len(groups) > 1:
            base = f"{stem}_assembly"
            shapes, inst, cols = result_instances(result, result.parts)
            write_step_instanced(os.path.join(tmp, base + ".step"), shapes, inst, base, cols)
            written.append(base + ".step")
            files_by_group["assembly"] = [base + ".step"]
        write_manifest(os.path.join(tmp, "manifest.json"),
                       build_manifest(result, files_by_group, stem, result.checks_ran, poses))
        written.append("manifest.json")
        umask = os.umask(0)
        os.umask(umask)
        for name in written:
            os.chmod(os.path.join(tmp, name), 0o666 & ~umask)    # mkstemp files are 0600
        stale = earlier_outputs(out_dir, "manifest.json", FORMAT, written)
        commit_set(tmp, out_dir, written)
        gone = remove_outputs(out_dir, stale)
        if gone:
            note(f"removed {len(gone)} file(s) of the earlier build that this one does not write: {', '.join(gone)}",
                 progress, stream)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return [os.path.join(out_dir, n) for n in written]
