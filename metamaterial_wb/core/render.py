"""Pictures without a GUI: the sheet in 3D as a PNG (matplotlib, Agg backend).

Plates are drawn as squares (side ``cell_size - hinge length``) at their 3D poses, coloured by D
(blue = -1, white = 0, red = +1); hinges as line segments between the plate corners they join
(green where tilted, i.e. bending cells, grey elsewhere); actuators as red dots on their joints,
angular constraints as black crosses. Equal scale on all three axes.
"""
import io

import numpy as np

from metamaterial_wb.core import kinematics as kin


def plate_corners(scene, pos, R):
    """(n, 4, 3) corners of every plate (mm)."""
    a = 0.5 * kin.plate_side_mm(scene)
    local = np.array([[-a, -a, 0.0], [a, -a, 0.0], [a, a, 0.0], [-a, a, 0.0]])
    return pos[:, None, :] + np.einsum("nij,cj->nci", R, local)


def hinge_segments(scene, pos, R):
    """(m, 2, 3) end points of every hinge (mm)."""
    a, b, ra, rb, _d0 = kin._hinge_geometry(scene)
    pa = pos[a] + np.einsum("mij,mj->mi", R[a], ra)
    pb = pos[b] + np.einsum("mij,mj->mi", R[b], rb)
    return np.stack([pa, pb], axis=1)


def render_png(scene, pos, R, D, path=None, title=None, elev=28.0, azim=-62.0, size_px=(1200, 800), dpi=150,
               tilts_deg=None):
    """Draw the sheet; write a PNG to ``path`` atomically (or return the PNG bytes when path is None)."""
    import matplotlib
    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt
    from mpl_toolkits.mplot3d.art3d import Line3DCollection, Poly3DCollection

    from metamaterial_wb.core.fileio import write_atomic
    from metamaterial_wb.core.scene import parse_joint

    pos = np.asarray(pos, dtype=float)
    R = np.asarray(R, dtype=float)
    D = np.asarray(D, dtype=float)
    topo = scene.topology
    fig = plt.figure(figsize=(size_px[0] / dpi, size_px[1] / dpi), dpi=dpi)
    try:
        ax = fig.add_subplot(111, projection="3d")
        corners = plate_corners(scene, pos, R)
        cmap = plt.get_cmap("coolwarm")
        colours = cmap(0.5 + 0.4 * np.clip(D, -1, 1))
        lw = 0.6 if topo.n_nodes <= 400 else 0.15
        poly = Poly3DCollection(corners, facecolors=colours, edgecolors=(0.2, 0.2, 0.25, 1.0), linewidths=lw,
                                alpha=0.95)
        ax.add_collection3d(poly)
        seg = hinge_segments(scene, pos, R)
        tilts = np.asarray(tilts_deg) if tilts_deg is not None else None
        if tilts is None:
            from metamaterial_wb.core.design import effective_tilts_deg
            tilts = effective_tilts_deg(scene)
        tilted = np.abs(tilts) > 1e-9
        hw = 1.6 if topo.n_joints <= 800 else 0.4
        if np.any(~tilted):
            ax.add_collection3d(Line3DCollection(seg[~tilted], colors=(0.35, 0.35, 0.35, 1), linewidths=hw))
        if np.any(tilted):
            ax.add_collection3d(Line3DCollection(seg[tilted], colors=(0.1, 0.65, 0.2, 1), linewidths=hw * 1.6))
        # actuators and constraints at the middle of their hinge
        for kind, item in scene.fixed_items():
            k = topo.joint_id(*parse_joint(item.joint))
            mid = seg[k].mean(axis=0)
            if kind == "actuator":
                ax.scatter([mid[0]], [mid[1]], [mid[2]], s=70, c="red", edgecolors="darkred", depthshade=False,
                           zorder=10)
            else:
                ax.scatter([mid[0]], [mid[1]], [mid[2]], s=50, c="black", marker="x", depthshade=False, zorder=10)
        pts = corners.reshape(-1, 3)
        lo, hi = pts.min(axis=0), pts.max(axis=0)
        span = hi - lo
        big = float(span.max()) or 1.0
        span = np.maximum(span, 0.12 * big)
        mid = 0.5 * (lo + hi)
        for setter, c, s in zip((ax.set_xlim, ax.set_ylim, ax.set_zlim), mid, span):
            setter(c - 0.5 * s, c + 0.5 * s)
        ax.set_box_aspect(tuple(span))
        ax.view_init(elev=elev, azim=azim)
        ax.set_xlabel("x (mm)")
        ax.set_ylabel("y (mm)")
        ax.set_zlabel("z (mm)")
        ax.tick_params(labelsize=6)
        if title:
            ax.set_title(title, fontsize=9)
        fig.tight_layout()
        buf = io.BytesIO()
        fig.savefig(buf, format="png", dpi=dpi)
    finally:
        plt.close(fig)
    data = buf.getvalue()
    if path is None:
        return data
    write_atomic(path, data, mode="wb")
    return path


def state_title(scene, g=None, values=None, extra=""):
    name = scene.name or "scene"
    if g is not None:
        s = f"{name}: global deformation g = {g:g}"
    elif values:
        s = f"{name}: " + ", ".join(f"{k} = {v:g}" for k, v in values.items())
    else:
        s = name
    return s + (f" {extra}" if extra else "")


def view_angles(text):
    """``"ELEV,AZIM"`` -> (elev, azim) degrees, with a clear error."""
    from metamaterial_wb.core.errors import SceneError
    from metamaterial_wb.core.numbers import parse_float

    items = text.split(",") if isinstance(text, str) else []
    if len(items) != 2:
        raise SceneError("--view", f"{text!r}: expected ELEV,AZIM in degrees, e.g. 28,-62")
    # strict: no '1_0', no non-ASCII digits, no inf/nan (float() would take them all)
    e, a = (parse_float(f"--view {what}", x) for what, x in zip(("elevation", "azimuth"), items))
    for what, v, lim in (("elevation", e, 90), ("azimuth", a, 360)):
        if not -lim <= v <= lim:
            raise SceneError("--view", f"{text!r}: {what} {v:g} is outside the allowed range [-{lim}, {lim}] deg")
    return e, a
