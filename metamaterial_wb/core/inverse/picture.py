"""Picture of an inverse-design answer: the sheet's plates at the answer's poses (aligned into the
target's frame), coloured by each node's distance to the target, over the target (points, or the
target surface as a light mesh). One panel per keyframe (at most 4). matplotlib, Agg backend."""
import io

import numpy as np

from metamaterial_wb.core.render import plate_corners


def answer_png(problem, scene, evaluation, title="", size=None, max_frames=4, title_tail="", notes=None):
    """PNG bytes. The title is ``title + title_tail``; ``title`` (the scene name) is shortened to fit the picture
    if need be, drawn literally, and anything that could not be drawn as given is said in ``notes`` (one-line
    warnings; see :func:`metamaterial_wb.core.render.fit_title`)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    frames = evaluation["per_frame"]
    nf = min(len(frames), max_frames)
    size = size or ((1400, 700) if nf <= 2 else (1200, 1000))
    fig = plt.figure(figsize=(size[0] / 100, size[1] / 100), dpi=100)
    per_node = evaluation["per_node"]
    vmax = max([r.get("error_mm", 0.0) for r in per_node] + [1e-9])
    cmap = plt.get_cmap("viridis")
    from metamaterial_wb.core import kinematics as _k
    nrow, ncol = (1, nf) if nf <= 2 else (2, 2)
    for fi in range(nf):
        ax = fig.add_subplot(nrow, ncol, fi + 1, projection="3d")
        e = frames[fi]
        al = e["alignment"]
        Rm, t, sc = np.array(al["rotation"]), np.array(al["translation_mm"]), al["scale"]
        pos = sc * e["positions_mm"] @ Rm.T + t
        fr = problem.target.frames[fi]
        # plate orientation: the kinematic model's rotations at this keyframe, aligned
        s = scene.copy()
        vals = [a.value for a in s.actuators]
        from metamaterial_wb.core.motion import scene_values_at
        if len(problem.target.frames) > 1:
            vals = list(scene_values_at(s, fr.time_s).values())
        for a, v in zip(s.actuators, vals):
            s.set_value(a.name, v)
        from metamaterial_wb.core.solver import solve_scene
        D = solve_scene(s)[0]
        R = Rm @ _k.node_poses(s, D)[1]
        corners = plate_corners(s, pos, R)
        err = np.zeros(len(pos))
        for r in per_node:
            if r["frame"] == fi and "error_mm" in r:
                i, j = (int(x) for x in r["node"][1:].split(","))
                err[problem.topo.node_id(i, j)] = r["error_mm"]
        pc = Poly3DCollection(corners, facecolors=cmap(err / vmax), edgecolors="k", linewidths=0.3, alpha=0.9)
        ax.add_collection3d(pc)
        pts = [corners.reshape(-1, 3)]
        if fr.nodes is not None:
            ax.scatter(*fr.nodes.pos.T, c="r", s=8, depthshade=False, label="target nodes")
            pts.append(fr.nodes.pos)
        if fr.surface is not None:
            tri = fr.surface.surface.tri
            lo = corners.reshape(-1, 3).min(0) - scene.cell_size_mm
            hi = corners.reshape(-1, 3).max(0) + scene.cell_size_mm
            cen = tri.mean(axis=1)
            near = tri[np.all((cen >= lo) & (cen <= hi), axis=1)]      # the part of the surface at the sheet
            step = max(1, len(near) // 3000)
            if len(near):
                ax.add_collection3d(Poly3DCollection(near[::step], facecolors=(1, 0.5, 0.2, 0.2),
                                                     edgecolors=(1, 0.5, 0.2, 0.35), linewidths=0.2))
        P = np.vstack(pts)
        ext = P.max(0) - P.min(0)
        if ext[2] < 0.02 * max(ext[0], ext[1]):     # a planar answer: look from above
            ax.view_init(elev=90, azim=-90)
            ax.set_zticks([])
        c, r = 0.5 * (P.min(0) + P.max(0)), 0.5 * float((P.max(0) - P.min(0)).max()) + 1e-9
        ax.set_xlim(c[0] - r, c[0] + r)
        ax.set_ylim(c[1] - r, c[1] + r)
        ax.set_zlim(c[2] - r, c[2] + r)
        ax.set_box_aspect((1, 1, 1))
        ax.set_xlabel("x (mm)")
        ax.set_ylabel("y (mm)")
        lab = f"t = {e['time_s']:g} s\n" if nf > 1 else ""
        txt = []
        if e.get("rms_mm") is not None:
            txt.append(f"rms {e['rms_mm']:.3g} mm, max {e['max_mm']:.3g} mm")
        if e.get("rms_deg") is not None:
            txt.append(f"folds rms {e['rms_deg']:.3g} deg")
        ax.set_title(lab + "; ".join(txt), fontsize=8)
    sm = plt.cm.ScalarMappable(cmap=cmap, norm=matplotlib.colors.Normalize(0, vmax))
    fig.colorbar(sm, ax=fig.axes, shrink=0.6, label="distance to target (mm)")
    import warnings

    from metamaterial_wb.core.render import drawing_notes, fit_title
    notes = [] if notes is None else notes
    text = ""
    with warnings.catch_warnings(record=True) as caught:     # said as one-line notes, not raw library warnings
        warnings.simplefilter("always")
        try:
            from matplotlib.font_manager import FontProperties
            pt = FontProperties(size=plt.rcParams["figure.titlesize"]).get_size_in_points()
            text = fit_title(fig, title, title_tail, notes=notes, fontsize=pt,
                             advice="only the picture's title is shortened, the scene keeps its name") if title else ""
            if text:
                fig.suptitle(text, fontsize=pt, parse_math=False)
            buf = io.BytesIO()
            fig.savefig(buf, format="png")
        finally:
            plt.close(fig)
    notes.extend(drawing_notes(caught, size, text, field_size="the picture size"))
    return buf.getvalue()
