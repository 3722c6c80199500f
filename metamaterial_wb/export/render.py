"""Quick pictures of built parts (FreeCAD tessellation + matplotlib, no GUI): docs and previews."""
import numpy as np

from metamaterial_wb.core.materials import MATERIALS, hex_to_rgb


def render_png(result, path, parts=None, elev=35.0, azim=-60.0, size_in=(8.0, 5.0), title=None,
               tolerance_mm=0.2, dpi=110, zoom=None):
    """Render ``parts`` (default: all) of a BuildResult to ``path`` with flat Lambert shading."""
    from metamaterial_wb.export.mesh import part_meshes

    parts = result.parts if parts is None else parts
    meshes = part_meshes(result, parts, tolerance_mm)
    return render_meshes_png(meshes, path, elev=elev, azim=azim, size_in=size_in, title=title, dpi=dpi, zoom=zoom)


def render_meshes_png(meshes, path, elev=35.0, azim=-60.0, size_in=(8.0, 5.0), title=None, dpi=110, zoom=None,
                      colours=None):
    """Render ``[(name, V, T, material, extruder)]`` meshes (``colours``: material -> "#RRGGBB" overrides)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    table = dict(MATERIALS, **(colours or {}))
    light = np.array([0.4, -0.5, 0.8])
    light /= np.linalg.norm(light)
    fig = plt.figure(figsize=size_in)
    ax = fig.add_subplot(111, projection="3d")
    lo = np.full(3, np.inf)
    hi = np.full(3, -np.inf)
    all_tri, all_col = [], []
    for name, V, T, material, _ in meshes:
        tri = V[T]
        n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
        n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-12)
        shade = 0.35 + 0.65 * np.abs(n @ light)          # two-sided: tessellations may wind either way
        base = np.array(hex_to_rgb(table.get(material, "#888888")))
        cols = np.clip(base[None, :] * shade[:, None], 0, 1)
        all_tri.append(tri)
        all_col.append(cols)
        lo = np.minimum(lo, V.min(axis=0))
        hi = np.maximum(hi, V.max(axis=0))
    # one collection: matplotlib depth-sorts within a collection, not across collections
    cols = np.concatenate(all_col)
    pc = Poly3DCollection(np.concatenate(all_tri), facecolors=cols, edgecolors=cols, linewidths=0.25)
    ax.add_collection3d(pc)
    centre = 0.5 * (lo + hi)
    half = 0.5 * float(np.max(hi - lo)) * (zoom or 0.62)
    ax.set_xlim(centre[0] - half, centre[0] + half)
    ax.set_ylim(centre[1] - half, centre[1] + half)
    ax.set_zlim(centre[2] - half, centre[2] + half)
    try:
        ax.set_box_aspect((1, 1, 1))
    except Exception:
        pass
    ax.view_init(elev=elev, azim=azim)
    ax.set_axis_off()
    if title:
        ax.set_title(title)
    fig.tight_layout()
    fig.savefig(path, dpi=dpi)
    plt.close(fig)
    return path
