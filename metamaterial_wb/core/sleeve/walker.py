"""Leg kinematics of an asymmetric sleeve actuator and the four-legged walker (seed 002, fig. 4).

The actuator hangs from the robot body (axis pointing down). Its bottom plate is fixed; the top
plate (the cap, at the leg's end) has the axial displacement ``d`` and tilt ``psi`` from the ring
model. The sleeve bends with constant curvature: a tilt ``psi`` over the sleeve height ``H``
moves the cap centre sideways by ``H (1 - cos psi) / psi`` and along the axis to
``H sin(psi) / psi``; a rigid foot of length ``foot`` continues along the cap's normal.
"""

import numpy as np


def tip_trajectory(d_mm, tilt_rad, height_mm, foot_mm, direction=None):
    """Tip positions (n, 2) in the bending plane: (lateral mm, downward mm) from the sleeve base.

    ``tilt_rad`` (n, 2) tilt vectors; the bending plane is ``direction`` (unit 2-vector of the
    lean, default: the lean of the largest tilt). Lateral is positive towards ``direction``.
    """
    tilt = np.asarray(tilt_rad, float)
    lean = np.stack([tilt[:, 1], -tilt[:, 0]], axis=1)      # horizontal lean of the cap normal
    if direction is None:
        k = int(np.argmax(np.linalg.norm(lean, axis=1)))
        n = np.linalg.norm(lean[k])
        direction = lean[k] / n if n > 0 else np.array([1.0, 0.0])
    psi = lean @ np.asarray(direction, float)                 # signed bending angle in the plane
    Ht = height_mm + np.asarray(d_mm, float)
    small = np.abs(psi) < 1e-9
    ps = np.where(small, 1.0, psi)
    lat = np.where(small, 0.5 * Ht * psi, Ht * (1 - np.cos(ps)) / ps)
    ax = np.where(small, Ht, Ht * np.sin(ps) / ps)
    tip = np.stack([lat + foot_mm * np.sin(psi), ax + foot_mm * np.cos(psi)], axis=1)
    return tip, np.asarray(direction, float)


def loop_area(points):
    """Signed shoelace area of a closed polygon (mm^2); positive when counter-clockwise."""
    p = np.asarray(points, float)
    x, y = p[:, 0], p[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def walker_cycle(load_d_mm, load_tilt, unload_d_mm, unload_tilt, height_mm, foot_mm, contact_band_mm=1.0,
                 direction=None):
    """One inflation (load) / deflation (unload) cycle of a leg and the quadruped gait.

    Returns a dict: the closed tip loop (lateral, down) of one leg, its swept area, lateral stroke,
    lift, and the stance estimate: the foot touches the ground while it is within
    ``contact_band_mm`` of its lowest point; the lateral travel of the foot during that contact
    (with the body moving the other way) is the step per cycle. Legs 1 and 3 run in phase, legs 2
    and 4 half a cycle later (diagonal pairs in antiphase). ``direction``: the walking direction
    (unit 2-vector; default the lean of the largest tilt). The sleeve pipeline passes the design's
    axis (from the first cell type to the second), along which the lean reverses: the lean's
    component across it is kept on unloading and sweeps no area in the walking plane.
    """
    d = np.concatenate([load_d_mm, unload_d_mm])
    tilt = np.concatenate([load_tilt, unload_tilt])
    tip, direction = tip_trajectory(d, tilt, height_mm, foot_mm, direction)
    area = loop_area(tip)
    down = tip[:, 1]
    contact = down >= down.max() - contact_band_mm
    idx = np.nonzero(contact)[0]
    step = float(tip[idx, 0].max() - tip[idx, 0].min()) if len(idx) else 0.0
    n = len(tip)
    phase = np.linspace(0, 1, n, endpoint=False)
    legs = {}
    for leg, shift in ((1, 0.0), (2, 0.5), (3, 0.0), (4, 0.5)):
        k = int(round(shift * n)) % n
        legs[leg] = np.roll(tip, -k, axis=0)
    return {"tip": tip, "phase": phase, "legs": legs, "direction": direction.tolist(),
            "area_mm2": abs(area), "orientation": "counter-clockwise" if area > 0 else "clockwise",
            "lateral_stroke_mm": float(np.ptp(tip[:, 0])), "lift_mm": float(np.ptp(tip[:, 1])),
            "step_per_cycle_mm": step}
