"""Error measures of the fidelity ladder: a model result against a reference (plate twists, node positions
after the best rigid alignment), shared by the ladder (fidelity.py) and the converged reference
(reference.py)."""
import math

import numpy as np

REFERENCE_OPTIONS = {"tol": 1e-11, "load_steps": 4, "max_iter": 60}


def twist(R):
    from metamaterial_wb.core.lattice.solve import node_twist
    return node_twist(np.asarray(R, float))


def kabsch_error(P, Q):
    """Distances between points P and reference points Q after the best rigid alignment of P onto Q."""
    from metamaterial_wb.core.lattice.solve import kabsch
    if len(P) < 2:
        return np.zeros(len(P))
    Rm, tv = kabsch(P, Q)
    return np.linalg.norm(P @ Rm.T + tv - Q, axis=1)


def compare(scene, result, reference):
    """Error of one model result against the reference (dict of RMS/max in D units and cell sizes)."""
    from metamaterial_wb.core.lattice.geometry import LatticeGeometry

    geo = LatticeGeometry(scene)
    phi = twist(result.rotations)
    phi_ref = reference.phi if hasattr(reference, "phi") else twist(reference.rotations)
    diff = phi - phi_ref
    w = float(np.mean(diff))
    Dref = geo.D_from_phi(phi_ref)
    dD = geo.parity * (diff - w) / np.where(Dref >= 0, geo.closing_rad, geo.opening_rad)
    dpos = kabsch_error(np.asarray(result.positions_mm, float), np.asarray(reference.positions_mm, float))
    dpos = dpos / scene.cell_size_mm
    sq = np.sort(dD ** 2)[::-1]
    return {"rms_D": float(np.sqrt(np.mean(dD ** 2))), "max_D": float(np.abs(dD).max()),
            "rms_pos": float(np.sqrt(np.mean(dpos ** 2))), "max_pos": float(dpos.max()),
            "rigid_rotation_deg": math.degrees(w),
            # where the error sits: share of the squared angle error in the 5 worst nodes, and how far the
            # result and the reference turn their plates (in-plane, rigid rotation removed)
            "worst5_share": float(sq[:5].sum() / sq.sum()) if sq.sum() > 0 else 0.0,
            "max_turn_deg": math.degrees(float(np.abs(phi - w).max())),
            "reference_max_turn_deg": math.degrees(float(np.abs(phi_ref).max()))}


def convergence_error(h, values, order=None):
    """Error of the finest member of a refinement sequence (issue 18: every figure with its reference's error).

    ``h``: the step or mesh sizes, coarse to fine (each a constant ratio ``r`` apart); ``values``: the figure at
    each (scalars or arrays). Returns ``(extrapolated, error, order)``: Richardson extrapolation to ``h -> 0``
    from the last three values with the observed order (``order`` given, or only two values: that order, 2 by
    default), and as the error the correction it makes to the finest value. Where the last two differences
    change sign or the observed order is outside 0.5..4.5 (a drop far faster than any of our discretisations
converges is a coincidence, e.g. of contact events, not convergence) the sequence is not in its asymptotic
range; then the
    error is the larger of that correction and the last difference (no extrapolation is trusted) and the
    extrapolated value is the finest one."""
    v = [np.asarray(x, float) for x in values]
    h = [float(x) for x in h]
    if len(v) != len(h) or len(v) < 2:
        raise ValueError(f"convergence_error needs at least two sizes and as many values, got {len(h)} and {len(v)}")
    r = h[-2] / h[-1]
    d2 = v[-1] - v[-2]
    asym = np.ones_like(d2, bool)
    if order is not None:
        p = np.full_like(d2, float(order))
    elif len(v) >= 3:
        d1 = v[-2] - v[-3]
        with np.errstate(divide="ignore", invalid="ignore"):
            p = np.log(np.abs(d1 / d2)) / np.log(h[-3] / h[-2])
        asym = np.isfinite(p) & (p >= 0.5) & (p <= 4.5) & (d1 * d2 >= 0)
        p = np.where(asym, p, np.nan)
    else:
        p = np.full_like(d2, 2.0)
    with np.errstate(invalid="ignore"):
        corr = np.where(asym, d2 / (r ** np.where(asym, p, 1.0) - 1.0), 0.0)
    ext = v[-1] + corr
    err = np.where(asym, np.abs(corr), np.maximum(np.abs(corr), np.abs(d2)))
    if err.ndim == 0:
        return float(ext), float(err), float(p)
    return ext, err, p
