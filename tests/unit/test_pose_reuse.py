"""Leave out what did not change: a frame whose D field equals the last one reuses the poses."""
import numpy as np

from metamaterial_wb import example_path
from metamaterial_wb.core.scene import Scene
from metamaterial_wb.core.live import LiveSolver


def test_unchanged_frame_reuses_poses_and_changed_frame_recomputes():
    s = Scene.load(example_path("fish_axes"))
    live = LiveSolver(s)
    f1 = live.frame(values={"tail": 0.4})
    assert live.pose_evaluations == 1
    f2 = live.frame(values={"tail": 0.4})          # same values: no pose computation
    assert live.pose_evaluations == 1 and f2.timings.get("reused")
    assert np.array_equal(f1.positions, f2.positions)
    f3 = live.frame(values={"tail": 0.5})          # changed: recomputed, and different
    assert live.pose_evaluations == 2 and not f3.timings.get("reused")
    assert not np.allclose(f3.positions, f1.positions)
    # the reused frame is what a fresh computation would give
    fresh = LiveSolver(s).frame(values={"tail": 0.4})
    assert np.allclose(fresh.positions, f2.positions) and np.allclose(fresh.rotations, f2.rotations)
