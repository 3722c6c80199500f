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
