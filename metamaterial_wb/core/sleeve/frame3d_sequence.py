"""A sleeve ring's loading and unloading cycle on the nonlinear 3-D frame (issue 18): which cell types snap in
which order, and where the plate leans.

The beam model (``model.py``, ``pipeline.simulated_sequence``) reads the snapping sequence of a mixed ring off
its planar path; its curved ring is 2-4 times too stiff and its lean turned with the mesh (docs/sleeves.md).
Here the same ring - the beam model's mesh as corotational 3-D beams on the cylinder (``frame3d_nl``), with the
curved solid's free, biased top plate - is raised to ``d_max`` and lowered back, and the same rule
(``analysis.snap_order``: a hysteron, an edge pillar with its two beam halves, has snapped when their outer ends
have risen over their inner ends by more than h) gives the order of the cell types on both paths, as
``pipeline.simulated_sequence`` does for the beam model, and the plate's lean on each.
"""
import math
import time
from types import SimpleNamespace

import numpy as np

from metamaterial_wb.core.sleeve.analysis import has_force_drop, lean_direction, sequence_symmetry, snap_order
from metamaterial_wb.core.sleeve.frame3d import RingFrame
from metamaterial_wb.core.sleeve.frame3d_nl import trace_ring


def frame_cycle(cells, pattern, d_max, steps=120, n_el=12, root_extension=0.63, bias=1e-5, bias_angle=0.5,
                progress=None, flat_top=False):
    """Load the ring ``pattern`` of ``cells`` (one row of cell types, or a list of rows: rings stacked, the plates
    between them free) on the frame (plane stress, the free top plate with the bias moment ramped over the
    loading) from 0 to ``d_max`` (d / L) in ``steps`` and unload it back: ``(ring, up, down)``, two
    ``trace_ring`` results. ``progress(path, k, d)`` after every state (``path`` "loading" or "unloading").
    ``flat_top``: ``RingFrame``'s."""
    rows = [list(pattern)] if np.ndim(pattern) == 1 else [list(r) for r in pattern]
    ring = RingFrame(cells, plane="stress", root_extension=root_extension, n_el=n_el, pattern=rows,
                     flat_top=flat_top)
    d = np.linspace(0.0, d_max, steps + 1)

    def tell(path):
        return (lambda k, dk, F: progress(path, k, dk)) if progress else None
    up = trace_ring(ring, d, plate="free", bias=bias, bias_angle=bias_angle, bias_ramp=d_max, progress=tell("loading"))
    down = trace_ring(ring, d[::-1], plate="free", start=up, progress=tell("unloading"))
    return ring, up, down


def sequence(ring, up, down):
    """The snapping order of the cell types on loading and unloading (``analysis.snap_order`` on the frame's
    rises), whether unloading reverses loading (symmetric: null, with a ``note``, when nothing snapped or a type
    could not be ordered on a path, ``analysis.sequence_symmetry``), the events, and the plate's largest lean on
    each path with its direction (deg, ``analysis.lean_direction``) and whether the lean reverses between them."""
    geoms = [ring.cells[t] for t in ring.state_types]
    out = {}
    leans, paths = [], []
    for name, r in (("loading", up), ("unloading", down)):
        path = SimpleNamespace(d=r["d"], F=r.get("F"), states=r["rises"], jumps=[])
        # a snap needs a force drop, as on the beam model's paths (pipeline.simulated_sequence); a path without
        # forces (a stored solid run, read off its beams' ends by bench/fe_ring3d_combinations) is read as it is
        drops = path.F is None or has_force_drop(path)
        order, events = snap_order(path, ring.state_types, geoms, ring.units) if drops else ([], [])
        paths.append((name, order, events, drops, float(np.asarray(r["d"])[-1])))
        tilt = r["tilt"][:, :2]
        k = int(np.argmax(np.hypot(tilt[:, 0], tilt[:, 1])))
        lean = lean_direction(plate_tilt(tilt[k]))
        leans.append(lean)
        out[name] = order
        out[f"events_{name}"] = [{"d": float(e[1]), "units": e[2], "snapped": e[3]} for e in events]
        out[f"max_tilt_{name}_deg"] = float(math.degrees(np.hypot(*tilt[k])))
        out[f"lean_{name}_deg"] = float(math.degrees(math.atan2(lean[1], lean[0]))) if np.any(lean) else None
    # from complete orders only: nothing snapped, or a type not ordered on a path, is neither symmetric nor asymmetric
    out["symmetric"], note = sequence_symmetry(ring.state_types, ring.units, paths)
    if note:
        out["note"] = note
    out["rings"] = ring.rings
    out["lean_reverses"] = bool(np.dot(leans[0], leans[1]) < 0)
    return out


def frame_sequence(cells, pattern, d_max, steps, n_el, root_extension, progress=None, flat_top=False):
    """``sequence`` of ``frame_cycle`` with the run time, for the ``sleeve`` command (``model.frame_nonlinear``),
    or ``{"error", "elements", "seconds"}`` when Newton finds no equilibrium; with the two paths, for what else
    reads the cycle (the walker): ``(that, up, down)``, the paths None after an error. ``flat_top``: ``RingFrame``'s."""
    t0 = time.perf_counter()
    try:
        ring, up, down = frame_cycle(cells, pattern, d_max, steps, n_el, root_extension, progress=progress,
                                     flat_top=flat_top)
    except RuntimeError as e:
        return {"error": str(e), "elements": n_el, "seconds": time.perf_counter() - t0}, None, None
    out = sequence(ring, up, down)
    out.update(elements=n_el, seconds=time.perf_counter() - t0)
    return out, up, down


def plate_tilt(rotation):
    """The plate's rotation vector's in-plane part ``(psi_x, psi_y)`` as the beam model's tilt pair, whose
    convention (``fe/sleeve3d.py``) has a point of the plate at the angle ``phi`` rise by ``R (psi_x sin phi -
    psi_y cos phi)``: a rotation about X by ``a`` raises the point at ``phi`` by ``R a sin phi``, about Y by ``b``
    lowers it by ``R b cos phi`` - the same pair."""
    return np.asarray(rotation[:2], float)
