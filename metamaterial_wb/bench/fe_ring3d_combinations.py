"""The seed's combinations' thresholds on the curved solid (issue 18): each cell type of a combination as a
uniform four-cell ring in CalculiX (``fe/sleeve3d.py``, every brick C3D20, static to d/L 0.7 in steps of 0.01,
the tilting top plate under the default bias), its first peak and first valley, and the two-hysteron rule on
them (``fe_frame3d_stack.rule``) beside the frame's.

Rings stacked in series share only their force: the frame's stacked rings (``fe_frame3d_stack``) put the stack's
peaks on the uniform rings' first peaks and its valleys on the first ring's and the higher of the two, to 0.0 %,
so the rule on a model's uniform rings is that model's order for the stack. A stacked solid itself is not run
(its snaps under displacement control are dynamic); the solid's uniform rings are its thresholds. On the solid's
coarse meshes each P1 is some per cent high (the seed's type: +16 % on r = 1, +7 % on r = 2 against the
four-mesh extrapolation), alike for types this close, so the order rests on their differences, given on two
meshes.
"""
import concurrent.futures

import numpy as np

from metamaterial_wb.bench.fe_frame3d_plate import SEED_COMBINATIONS, combination_cells
from metamaterial_wb.bench.fe_frame3d_stack import rule

MESH_R = {"r1": 1, "r2": 2}
D_MAX = 0.7                 # d/L: past the first valley of every seed type (the seed's cell: 0.45)


def solid_ring(g, r, d_max=D_MAX, timeout_s=5400.0):
    """One uniform four-cell ring of cell ``g`` on mesh ``r`` (one brick through the wall, every brick C3D20,
    static, 0.01 d/L per increment): ``{"P1", "P1_d", "valley", "valley_d", "d", "F", "tilt_deg_max", "wall_s",
    "d_reached", "stopped"}`` (``None`` for an extremum the run did not reach)."""
    from metamaterial_wb.fe import sleeve3d
    c, info = sleeve3d.solve_ring3d(g, 4, r, 1, d_max=d_max * g.L, increments=int(round(100 * d_max)),
                                    timeout_s=timeout_s, partial=True, element="C3D20")
    ext = sleeve3d.all_extrema(c["d"], c["F"])
    peak = next(((x, y) for k, x, y in ext if k == "peak"), (None, None))
    valley = next(((x, y) for k, x, y in ext if k == "valley" and peak[0] is not None and x > peak[0]), (None, None))
    tilt = np.degrees(np.hypot(*np.asarray(c["tilt_rad"]).T))
    return {"P1_d": peak[0], "P1": peak[1], "valley_d": valley[0], "valley": valley[1], "extrema": ext,
            "d": np.round(c["d"], 6).tolist(), "F": c["F"].tolist(), "tilt_deg_max": float(tilt.max()),
            "wall_s": info["wall_s"], "d_reached": info["d_reached"], "stopped": info.get("stopped", "")[:300]}


def solid_thresholds(runs=(("2", "r1"), ("2", "r2"), ("1", "r1")), workers=2, timeout_s=5400.0, done=None):
    """Every cell type of each (combination, mesh) of ``runs`` as a uniform solid ring (``solid_ring``), ``workers``
    ccx runs at a time (each on one core): ``{combination: {mesh: [type 0's row, type 1's row]}}``. ``done(key,
    mesh, k, row)`` is called as each run ends (to store it at once)."""
    for key, mesh in runs:
        if key not in SEED_COMBINATIONS or mesh not in MESH_R:
            raise ValueError(f"run ({key!r}, {mesh!r}); allowed: a combination of {sorted(SEED_COMBINATIONS)} "
                             f"on a mesh of {sorted(MESH_R)}")
    jobs = [(key, mesh, k, g) for key, mesh in runs for k, g in enumerate(combination_cells(key))]
    out = {}
    with concurrent.futures.ThreadPoolExecutor(workers) as pool:
        futures = {pool.submit(solid_ring, g, MESH_R[mesh], timeout_s=timeout_s): (key, mesh, k)
                   for key, mesh, k, g in jobs}
        for f in concurrent.futures.as_completed(futures):
            key, mesh, k = futures[f]
            row = f.result()
            out.setdefault(key, {}).setdefault(mesh, [None, None])[k] = row
            if done:
                done(key, mesh, k, row)
    return out


def solid_rule(rows):
    """The two-hysteron order on the solid's uniform rings of one combination and mesh, or ``None`` if a run
    missed a threshold."""
    if not rows or any(r is None or r["P1"] is None or r["valley"] is None for r in rows):
        return None
    return rule(rows)


def differences(rows):
    """Type 1's thresholds against type 0's, in per cent: ``(P1, valley)``."""
    return tuple(100.0 * (rows[1][k] / rows[0][k] - 1.0) for k in ("P1", "valley"))
