"""Files of a sleeve actuator (seed 002): STEP, 3MF and a picture of the parts that
``geometry/sleeve.py`` builds (the B-rep stays in geometry; writing files is this floor's job)."""
import os

import numpy as np

from metamaterial_wb.core.materials import hex_to_rgb
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
    """A flat-shaded picture of the built parts (tessellation + matplotlib, no GUI)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    light = np.array([0.4, -0.6, 0.7])
    light /= np.linalg.norm(light)
    fig = plt.figure(figsize=size_in)
    ax = fig.add_subplot(111, projection="3d")
    tris, cols, pts = [], [], []
    for name, s, colour, _ in parts:
        V, T = tessellate(s, 0.1, name)
        tri = V[T]
        n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
        n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-12)
        shade = 0.3 + 0.7 * np.abs(n @ light)
        base = np.array(hex_to_rgb(colour))
        tris.append(tri)
        cols.append(np.clip(shade[:, None] * base[None, :], 0, 1))
        pts.append(V)
    tri = np.concatenate(tris)
    col = np.concatenate(cols)
    # painter's order along the view direction
    e, a = np.radians(elev), np.radians(azim)
    view = np.array([np.cos(e) * np.cos(a), np.cos(e) * np.sin(a), np.sin(e)])
    order = np.argsort(tri.mean(axis=1) @ view)
    ax.add_collection3d(Poly3DCollection(tri[order], facecolors=col[order], edgecolors="none"))
    P = np.concatenate(pts)
    lo, hi = P.min(axis=0), P.max(axis=0)
    c, r = (lo + hi) / 2, (hi - lo).max() / 2
    ax.set_xlim(c[0] - r, c[0] + r); ax.set_ylim(c[1] - r, c[1] + r); ax.set_zlim(c[2] - r, c[2] + r)
    ax.view_init(elev, azim)
    ax.set_axis_off()
    if title:
        ax.set_title(title, fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=dpi)
    plt.close(fig)
    return path
