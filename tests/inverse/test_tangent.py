"""Exact pose sensitivities (core/inverse/tangent.py) against central finite differences."""
import numpy as np
import pytest

from metamaterial_wb.core import design, kinematics
from metamaterial_wb.core.inverse.residuals import FrameResidual
from metamaterial_wb.core.inverse.targets import Frame, FoldTerm
from metamaterial_wb.core.inverse.tangent import PoseTangent
from metamaterial_wb.core.scene import Scene

CASES = [None, "examples/grid_fold.json", "examples/fish.json", "examples/gripper.json"]


def _scene(path):
    from metamaterial_wb import REPO_DIR
    import os
    s = Scene.grid(5, 6) if path is None else Scene.load(os.path.join(REPO_DIR, path))
    design.ensure_configured(s)
    return s


@pytest.mark.parametrize("path", CASES)
def test_pose_tangents_equal_finite_differences(path):
    s = _scene(path)
    kin = kinematics.Kinematics(s)
    tg = PoseTangent(kin)
    rng = np.random.default_rng(3)
    D = rng.uniform(0.1, 0.8, kin.n)          # away from the D = 0 kink of phi(D)
    dD = rng.normal(size=(3, kin.n))
    pos, R, dpos, dR, F, dF = tg.poses(D, dD)
    p0, R0, _ = kin.poses(D)
    assert np.abs(pos - p0).max() == 0.0 and np.abs(R - R0).max() == 0.0   # same forward pass
    h = 1e-6
    for i in range(3):
        pp, Rp, phip = kin.poses(D + h * dD[i])
        pm, Rm, phim = kin.poses(D - h * dD[i])
        scale = max(1.0, np.abs(dpos[i]).max())
        assert np.abs((pp - pm) / (2 * h) - dpos[i]).max() < 1e-6 * scale
        assert np.abs((Rp - Rm) / (2 * h) - dR[i]).max() < 1e-7
        if not kin.planar:
            Fp, Fm = kin.fold_frames(phip), kin.fold_frames(phim)
            assert np.abs((Fp - Fm) / (2 * h) - dF[i]).max() < 1e-7


@pytest.mark.parametrize("path", ["examples/grid_fold.json", "examples/gripper.json"])
def test_fold_sensitivities_equal_finite_differences_and_measured_fold(path):
    s = _scene(path)
    kin = kinematics.Kinematics(s)
    tg = PoseTangent(kin)
    m = s.topology.n_joints
    fr = FrameResidual(s, Frame(folds=FoldTerm(np.eye(m), np.arange(m), np.zeros(m), [])))
    rng = np.random.default_rng(5)
    D = rng.uniform(0.2, 0.9, kin.n)
    dD = rng.normal(size=(2, kin.n))
    pos, R, dpos, dR, F, dF = tg.poses(D, dD)
    fold, dfold = fr.smooth_folds(R, F, dR, dF, np.arange(m))
    h = 1e-6
    for i in range(2):
        fp = fr.smooth_folds(*_RF(kin, D + h * dD[i]), None, None, np.arange(m))[0]
        fm = fr.smooth_folds(*_RF(kin, D - h * dD[i]), None, None, np.arange(m))[0]
        assert np.abs((fp - fm) / (2 * h) - dfold[i]).max() < 1e-5
    measured, _ = kinematics.joint_angles(s, R)
    t = kin.tilted                    # the bending joints, where fold targets are reachable
    if len(kin.groups) == 1:          # one fold direction: the smooth fold is the measured fold
        assert np.abs(fold[t] - measured[t]).max() < 1e-9
    else:                             # several fold directions: close, not equal
        assert np.abs(fold[t] - measured[t]).max() < 5.0


def _RF(kin, D):
    phi = kin.angles(D)
    return kin.poses_from_angles(phi)[1], kin.fold_frames(phi)


def _regional_lengths(path, lengths):
    """``path``'s scene with the hinges of the left half (by column) at ``lengths[0]`` mm, the rest at
    ``lengths[1]`` (both at most the sheet's hinge length: shorter hinges get rigid stubs)."""
    s = _scene(path)
    d = s.to_dict()
    names = s.topology.joint_names
    cols = s.topology.joint_ij()[:, 1]
    d["joints"] = [dict(o) for o in d.get("joints", [])]
    have = {o["joint"]: o for o in d["joints"]}
    for k, n in enumerate(names):
        o = have.setdefault(n, {"joint": n})
        o["length_mm"] = lengths[0] if cols[k] < cols.max() / 2 else lengths[1]
    d["joints"] = list(have.values())
    out = Scene.from_dict(d)
    design.ensure_configured(out)
    return out


@pytest.mark.parametrize("path", [None, "examples/grid_fold.json"])
def test_per_joint_hinge_lengths_reach_the_quadratic_poses(path):
    """Hinges that differ per region change the kinematic poses at the same D (they did not: the chord
    was the sheet's hinge length everywhere), and the geometry is the fabricated one: each hinge's
    flexible part keeps its own length L between two rigid stubs of (lh - L) / 2 that turn with their
    plates; the tangents stay exact."""
    base = _scene(path)
    s = _regional_lengths(path, (0.6 * base.hinge["length_mm"], 0.8 * base.hinge["length_mm"]))
    kb, ks = kinematics.Kinematics(base), kinematics.Kinematics(s)
    rng = np.random.default_rng(5)
    D = rng.uniform(0.1, 0.8, ks.n)
    pb_, Rb, _ = kb.poses(D)
    ps, Rs, _ = ks.poses(D)
    assert np.abs(Rs - Rb).max() < 1e-12                       # rotations are D's alone
    assert np.abs(ps - pb_).max() > 1e-4                       # positions see the lengths (0 before)
    # the chords are the fabricated geometry: plate corner, stub (turns with its plate), flexible part
    # (turns with the mean rotation), stub, plate corner
    lh = s.hinge["length_mm"]
    lj = kinematics.joint_hinge_arrays(s)[0]
    assert len(set(np.round(lj, 9))) == 2
    u = kb.d0 / lh
    stub = 0.5 * (lh - lj)[:, None] * u
    phi = kinematics.node_angles(s, D, ks.limits)
    F, theta = ks._fold_state(phi)
    R = ks.rotations(phi, F)
    flex = kb._chords(phi, F, R, theta) - np.einsum("mij,mj->mi", R[kb.a], kb.ra) + \
        np.einsum("mij,mj->mi", R[kb.b], kb.rb)                   # the base chord lh u, turned
    want = (np.einsum("mij,mj->mi", R[kb.a], kb.ra + stub) + (lj / lh)[:, None] * flex +
            np.einsum("mij,mj->mi", R[kb.b], stub - kb.rb))
    assert np.abs(ks._chords(phi, F, R, theta) - want).max() < 1e-12
    tg = PoseTangent(ks)
    dD = rng.normal(size=(2, ks.n))
    _p, _R, dpos, _dR, _F, _dF = tg.poses(D, dD)
    h = 1e-6
    for i in range(2):
        fd = (ks.poses(D + h * dD[i])[0] - ks.poses(D - h * dD[i])[0]) / (2 * h)
        assert np.abs(fd - dpos[i]).max() < 1e-6 * max(1.0, np.abs(fd).max())
