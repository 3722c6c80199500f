"""Per-joint hinge length reaches the printed part (issue 14, "one owner per quantity"): on the built
solids, the free flexible length between the rigid material of two nodes is the joint's own
``hinge_sizes(joint)["length_mm"]`` (rigid stubs fill the rest of the scene-wide gap), not the global gap."""
import pytest


def _gap_mm(r, a, b):
    return r.placed_shape(r.by_name(a)).distToShape(r.placed_shape(r.by_name(b)))[0]


def test_free_hinge_length_on_the_built_solids_is_the_joints_own(grid_result):
    r = grid_result
    sc = r.scene
    assert sc.hinge_sizes("H0,0")["length_mm"] == 1.2 and sc.hinge_sizes("H0,1")["length_mm"] == 2.0
    # H0,0 joins N0,0 and N0,1 (override 1.2 mm); H0,1 joins N0,1 and N0,2 (scene-wide 2.0 mm)
    assert _gap_mm(r, "node_0_0", "node_0_1") == pytest.approx(1.2, abs=1e-6)
    assert _gap_mm(r, "node_0_1", "node_0_2") == pytest.approx(2.0, abs=1e-6)
    assert r.scene.plate_side_mm == pytest.approx(20.0 - 2.0)
    # the flexible hinge itself still bridges the whole gap into both anchors
    hb = r.placed_shape(r.by_name("hinge_H0_0")).BoundBox
    assert hb.XLength > sc.cell_size_mm - sc.plate_side_mm
