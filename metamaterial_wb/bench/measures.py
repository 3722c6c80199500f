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
