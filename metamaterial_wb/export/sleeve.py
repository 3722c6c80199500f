"""Files of a sleeve actuator (seed 002): STEP, 3MF and a picture of the parts that
``geometry/sleeve.py`` builds (the B-rep stays in geometry; writing files is this floor's job).

The STEP file is the assembly (every part where it goes). The 3MF is for printing: every part stands on the bed
as built (the sleeve and the end rings upright, the caps flat), side by side in rows on the bundled printer
profile's bed (``PROFILE``); parts that do not fit one bed go onto the next plate, one 3MF per plate
(:func:`lay_out_plates`, docs/sleeves.md "Geometry and export")."""
import os
import re

import numpy as np

from metamaterial_wb.core.errors import MetamaterialError
from metamaterial_wb.export.mesh import tessellate
from metamaterial_wb.geometry.sleeve import build_all, check_parts

PROFILE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "profiles", "prusaslicer_dual_pla_tpu_0.1mm.ini")
# between two parts on a plate: PrusaSlicer's own arrange distance (duplicate_distance, 6 mm), so that its arrange
# (what a user's slicer runs on opening the file) finds room for what is laid out here
PART_GAP_MM = 6.0
# the 3MF names of an export: one plate, or several (``export_sleeve``); a folder's files of these names are an
# earlier export's (``earlier_plates``)
PLATE_NAME = re.compile(r"sleeve(_plate[1-9][0-9]*)?\.3mf")


def profile_bed(path=PROFILE):
    """``((x0, y0), (x1, y1), height)`` mm of a PrusaSlicer profile: its ``bed_shape``'s bounding box and its
    ``max_print_height`` (the bundled profile: a 330 x 240 mm bed, 300 mm high; core/sleeve/spec.py's size
    limits are these numbers)."""
    text = open(path, encoding="utf-8").read()
    shape = re.search(r"^bed_shape\s*=\s*(.+)$", text, re.M)
    height = re.search(r"^max_print_height\s*=\s*(.+)$", text, re.M)
    if not shape or not height:
        raise MetamaterialError(f"{path}: no bed_shape / max_print_height")
    pts = np.array([[float(c) for c in p.split("x")] for p in shape.group(1).strip().split(",")])
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    return (float(lo[0]), float(lo[1])), (float(hi[0]), float(hi[1])), float(height.group(1))


def lay_out_plates(meshes, bed=None, gap_mm=PART_GAP_MM):
    """Lay separate prints out on beds: ``meshes`` ``[(name, V, T, material, extruder)]`` each keep their
    orientation and stand on ``z = 0``; footprints (bounding boxes) go side by side in rows, ``gap_mm`` apart, the
    largest first (first fit: each part on the first plate with room, a new plate when none has), and each plate's
    parts are centred on the bed. ``bed``: :func:`profile_bed`'s triple (default the bundled profile's). Returns the
    plates, each a list of moved meshes. A part larger than the bed by itself is refused, naming its size and the
    bed."""
    (x0, y0), (x1, y1), height = profile_bed() if bed is None else bed
    W, D = x1 - x0, y1 - y0
    items = []
    for k, (name, V, T, mat, ext) in enumerate(meshes):
        V = np.asarray(V, dtype=float)
        lo, hi = V.min(axis=0), V.max(axis=0)
        w, d, h = hi - lo
        if w > W or d > D or h > height:
            raise MetamaterialError(
                f"{name}: {w:.4g} x {d:.4g} x {h:.4g} mm does not fit the printer's bed, {W:g} x {D:g} mm and "
                f"{height:g} mm high (the bundled profile export/profiles/{os.path.basename(PROFILE)})")
        items.append((k, name, V - lo, T, mat, ext, w, d))
    plates = []          # each: {"rows": [[y, row depth, next x]], "parts": [(item, x, y)]}
    for it in sorted(items, key=lambda i: (-max(i[6], i[7]), i[0])):
        w, d = it[6], it[7]
        for plate in plates:
            if _place(plate, it, w, d, W, D, gap_mm):
                break
        else:
            plates.append({"rows": [], "parts": []})
            _place(plates[-1], it, w, d, W, D, gap_mm)
    out = []
    for plate in plates:
        ext_x = max(x + it[6] for it, x, _ in plate["parts"])
        ext_y = max(y + it[7] for it, _, y in plate["parts"])
        off = np.array([x0 + (W - ext_x) / 2, y0 + (D - ext_y) / 2, 0.0])    # the plate's parts centred on the bed
        out.append([(name, V + np.array([x, y, 0.0]) + off, T, mat, ext)
                    for (_, name, V, T, mat, ext, _, _), x, y in plate["parts"]])
    return out


def _place(plate, it, w, d, W, D, gap):
    """Put a ``w`` x ``d`` footprint into the first row of ``plate`` with room, or into a new row below the last;
    False when the plate (``W`` x ``D``) has no room."""
    for row in plate["rows"]:
        if d <= row[1] and row[2] + w <= W:
            plate["parts"].append((it, row[2], row[0]))
            row[2] += w + gap
            return True
    y = plate["rows"][-1][0] + plate["rows"][-1][1] + gap if plate["rows"] else 0.0
    if y + d > D or w > W:
        return False
    plate["rows"].append([y, d, w + gap])
    plate["parts"].append((it, 0.0, y))
    return True


def earlier_plates(folder, names):
    """The 3MF files of an earlier export in ``folder`` (``sleeve.3mf``, ``sleeve_plateN.3mf``: plain files, no
    links) that the new export's ``names`` do not hold: left in place, a one-plate export would sit beside three
    plates of another sleeve. Sorted; empty when ``names`` hold no 3MF (the earlier print is not this one's)."""
    if not any(PLATE_NAME.fullmatch(n) for n in names):
        return []
    try:
        present = os.listdir(folder)
    except OSError:
        return []
    return sorted(n for n in present if PLATE_NAME.fullmatch(n) and n not in names
                  and os.path.isfile(os.path.join(folder, n)) and not os.path.islink(os.path.join(folder, n)))


def export_sleeve(spec, folder, step=True, threemf=True, render=False):
    """Write ``sleeve.step`` / the 3MF (/ ``sleeve.png``) into ``folder``; returns the file names. The 3MF:
    ``sleeve.3mf`` when every part fits one bed of the bundled profile, else ``sleeve_plate1.3mf``,
    ``sleeve_plate2.3mf``, ... (the sleeve on the first): :func:`lay_out_plates`."""
    parts = build_all(spec)
    check_parts(parts)
    files = []
    if render:
        render_png(parts, os.path.join(folder, "sleeve.png"),
                   title=f"sleeve: {spec.M} x {spec.N} cells, pattern {spec.pattern}")
        files.append("sleeve.png")
    if step:
        from metamaterial_wb.export.step import write_step
        write_step(os.path.join(folder, "sleeve.step"), [(n, s, c) for n, s, c, _ in parts],
                   assembly_name=spec.name)
        files.append("sleeve.step")
    if threemf:
        from metamaterial_wb.export.threemf import write_3mf
        mparts = []
        for n, s, _, mat in parts:
            V, T = tessellate(s, 0.05, n)
            mparts.append((n, V, T, mat, 2 if mat == "TPU" else 1))
        plates = lay_out_plates(mparts)
        names = ["sleeve.3mf"] if len(plates) == 1 else [f"sleeve_plate{k + 1}.3mf" for k in range(len(plates))]
        for name, plate in zip(names, plates):
            # separate prints, each its own object on its extruder (as a module's parts: export/package.py)
            write_3mf(os.path.join(folder, name), plate, layout="objects", object_name=os.path.splitext(name)[0])
            files.append(name)
    return files


def render_png(parts, path, elev=22.0, azim=-60.0, size_in=(5.0, 5.0), title=None, dpi=110):
    """A flat-shaded picture of the built parts (tessellation + matplotlib, no GUI): the one mesh renderer
    :func:`metamaterial_wb.export.render.render_meshes_png`, each part in its own colour."""
    from metamaterial_wb.export.render import render_meshes_png

    meshes, colours = [], {}
    for name, shape, colour, _ in parts:
        V, T = tessellate(shape, 0.1, name)
        meshes.append((name, V, T, name, 1))
        colours[name] = colour
    return render_meshes_png(meshes, path, elev=elev, azim=azim, size_in=size_in, title=title, dpi=dpi, zoom=1.0,
                             colours=colours)
