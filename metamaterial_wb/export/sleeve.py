"""Files of a sleeve actuator (seed 002): STEP, 3MF and a picture of the parts that
``geometry/sleeve.py`` builds (the B-rep stays in geometry; writing files is this floor's job)."""
import os

from metamaterial_wb.export.mesh import tessellate
from metamaterial_wb.geometry.sleeve import build_all, check_parts


def export_sleeve(spec, folder, step=True, threemf=True, render=False):
    """Write ``sleeve.step`` / ``sleeve.3mf`` (/ ``sleeve.png``) into ``folder``; returns the file names."""
    parts = build_all(spec)
    check_parts(parts)
    files = []
    if render:
        render_png(parts, os.path.join(folder, "sleeve.png"), title=f"sleeve: {spec.M} x {spec.N} cells, pattern {spec.pattern}")
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
        write_3mf(os.path.join(folder, "sleeve.3mf"), mparts, layout="components")
        files.append("sleeve.3mf")
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
