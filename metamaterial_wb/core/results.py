"""Result documents the CLI writes and the document objects read back: the dynamics trajectory
(``simulate --out DIR`` -> ``DIR/trajectory.json``, format in docs/dynamics.md). Pure data, no FreeCAD."""


def trajectory_dict(model, traj):
    """The trajectory document of a simulated ``model`` (floor-frame poses in mm and degrees).

    Parameters
    ----------
    model : DynamicsModel
        The model that was simulated.
    traj : Trajectory
        Its result.

    Returns
    -------
    dict
        JSON-ready trajectory document.
    """
    import numpy as np

    t, q = traj.arrays()
    out = {"format": "metamaterial-trajectory", "version": 1, "model": model.kind,
           "frame": "floor frame: x along the floor towards increasing column index, y up from the floor, "
                    "angles counter-clockwise; the floor is y = 0, tilted by incline_deg",
           "incline_deg": model.cfg["incline_deg"],
           "times_s": [round(float(x), 6) for x in t],
           "bodies": int(q.shape[1]) if q.size else 0,
           "poses": np.round(np.concatenate([q[:, :, :2] * 1e3, np.degrees(q[:, :, 2:])], axis=2), 4).tolist()}
    if model.kind == "sheet":
        out["body_of_node"] = {f"N{i},{j}": int(b) for (i, j), b in
                               zip(model.scene_nodes, model.node_body)} if hasattr(model, "scene_nodes") else {}
        out["body_columns"] = model.info["columns"]
    else:
        out["cell_of_body"] = [int(c) for c in model.seg_cell]
        if traj.extra:
            out["cell_pressure_kpa"] = np.round(np.array(traj.extra), 3).tolist()
    return out
