"""The linear lattice's poses: positions through the hinge chain from the plate rotations (``poses="chain"``).

Independent references: the rotating-squares closed form (pitch of the uniform mechanism), a rigid
rotation of the whole sheet, the second-order agreement with the old rule (flat positions plus the solved
displacements) at small amplitude, and the nonlinear model at the working amplitude.
"""
import math

import numpy as np
import pytest

from metamaterial_wb.bench import fidelity
from metamaterial_wb.core.lattice.geometry import LatticeGeometry
from metamaterial_wb.core.lattice.mechanics import expm_so3
from metamaterial_wb.core.lattice.solve import ChainPositions, kabsch, node_twist
from metamaterial_wb.core.models import run_model
from metamaterial_wb.core.scene import Scene
from metamaterial_wb.core.errors import SceneError


def grid(n, actuators=(), **extra):
    d = {"format": "metamaterial-scene", "version": 1, "layout": {"grid": [n, n]}, "actuators": list(actuators)}
    d.update(extra)
    return Scene.from_dict(d)


def _all_joints_actuated(n, value):
    sc = grid(n)
    return grid(n, [{"name": f"a{k}", "joint": name, "value": value} for k, name in enumerate(sc.topology.joint_names)])


@pytest.mark.parametrize("value", [0.5, 1.0, -0.3, -0.6])
def test_uniform_mechanism_pitch_is_the_closed_form(value):
    """Every joint actuated alike: the linear model's rotations are the exact mechanism (the constraints fix
    every relative rotation), and the chain poses give the rotating-squares pitch lh sin(phi)/phi +
    s (cos phi -+ sin phi) (the same closed form the nonlinear model is tested against), and, aligned to the
    flat sheet, D = value at every node. Adding the linear displacements keeps the flat pitch instead
    (first-order motion of the mechanism is a pure rotation), and the rigid alignment of those positions
    turns the sheet, so that D alternates around the value."""
    sc = _all_joints_actuated(3, value)
    geo = LatticeGeometry(sc)
    phi = abs(value) * (geo.closing_rad if value > 0 else geo.opening_rad)
    lh, s = sc.hinge["length_mm"], geo.plate_side_mm
    pitch_closed = lh * math.sin(phi) / phi + s * (math.cos(phi) - math.copysign(1, value) * math.sin(phi))
    a, b = sc.topology.node_index[(1, 0)], sc.topology.node_index[(1, 3)]
    out = {}
    for poses in ("chain", "linear"):
        res = run_model("linear", sc, poses=poses, about="flat")
        assert res.converged and res.info["poses"] == poses
        out[poses] = (np.linalg.norm(res.positions_mm[b] - res.positions_mm[a]) / 3, np.abs(res.D - value).max())
    assert out["chain"][0] == pytest.approx(pitch_closed, rel=1e-8)
    assert out["chain"][1] <= 1e-7          # (at value 1 the contact springs give a little, ~1e-8)
    assert abs(out["linear"][0] - pitch_closed) > 5e-4 * pitch_closed
    assert out["linear"][1] > 1e-3


def test_rigid_rotation_gives_the_rotated_flat_sheet():
    """Every plate turned by one and the same (3-D) rotation: no hinge bends, positions = rotated flat sheet."""
    sc = grid(4, joint_config={"H1,1": {"tilt_deg": 20.0}})
    geo = LatticeGeometry(sc)
    Q = expm_so3(np.array([[0.3, -0.5, 0.9]]))[0]
    R = np.broadcast_to(Q, (geo.n, 3, 3)).copy()
    X = ChainPositions(geo)(R, geo.X0)
    want = geo.X0 @ Q.T
    want += X.mean(axis=0) - want.mean(axis=0)
    assert np.abs(X - want).max() <= 1e-10 * sc.cell_size_mm


def test_chain_poses_agree_with_linear_displacements_to_second_order():
    """Both pose rules are the same to first order: their difference shrinks 4 x when the actuation halves
    (contact off, so that the solution itself scales with the actuation)."""
    acts = [{"name": "m1", "joint": "H2,1", "value": 0.04}, {"name": "m2", "joint": "V1,3", "value": -0.02}]
    diffs = []
    for f in (1.0, 0.5, 0.25):
        sc = grid(5, [dict(a, value=a["value"] * f) for a in acts])
        c = run_model("linear", sc, poses="chain", contact=False, about="flat")
        l = run_model("linear", sc, poses="linear", contact=False, about="flat")
        assert _same_up_to_a_rigid_turn(c, l)             # rotations untouched (alignment aside)
        diffs.append(np.abs(c.positions_mm - l.positions_mm).max())
    assert diffs[0] > 0
    for d1, d2 in zip(diffs, diffs[1:]):
        assert 3.5 <= d1 / d2 <= 4.5


def _same_up_to_a_rigid_turn(r1, r2):
    """Same node rotations apart from one in-plane turn of the whole sheet (the rigid alignment follows the
    positions, which the pose rules place differently)."""
    d = node_twist(np.asarray(r1.rotations)) - node_twist(np.asarray(r2.rotations))
    return np.ptp(d) <= 1e-12


def _pos_error(sc, res, ref):
    P, Q = np.asarray(res.positions_mm), np.asarray(ref.positions_mm)
    Rm, tv = kabsch(P, Q)
    return np.linalg.norm(P @ Rm.T + tv - Q, axis=1).max() / sc.cell_size_mm


def test_chain_poses_halve_the_position_error_at_the_working_amplitude():
    """A 10 x 10 sheet at amplitude 0.5 (plates turn by up to ~30 degrees): against the nonlinear model the
    chain poses' largest position error is under half that of the linear displacements (measured: 0.36 vs
    0.99 cells) and under 0.5 cells; the node angles are the same."""
    sc = dict((k, s) for k, _, s in fidelity.standard_scenes(0.5))["grid10"]
    ref = run_model("nonlinear", sc)
    assert ref.converged
    chain = run_model("linear", sc, about="flat")
    old = run_model("linear", sc, poses="linear", about="flat")
    e_chain, e_old = _pos_error(sc, chain, ref), _pos_error(sc, old, ref)
    assert e_chain < 0.5 * e_old and e_chain < 0.5
    assert _same_up_to_a_rigid_turn(chain, old)


def test_unknown_pose_rule_is_rejected():
    with pytest.raises(SceneError, match="poses"):
        run_model("linear", grid(3, [{"name": "m", "joint": "H1,1", "value": 0.2}]), poses="spline")



def test_planar_shortcut_equals_the_general_chords():
    """Planar scenes take a 2-D shortcut for the hinge chords; it equals the general 3-D formula."""
    sc = grid(5, [{"name": "m1", "joint": "H2,1", "value": 0.6}, {"name": "m2", "joint": "V1,3", "value": -0.7}])
    geo = LatticeGeometry(sc)
    assert geo.planar
    rng = np.random.default_rng(7)
    R = expm_so3(np.column_stack([np.zeros((geo.n, 2)), rng.uniform(-1.2, 1.2, geo.n)]))
    strain = rng.normal(size=(geo.m, 3)) * 0.1
    strain[:, 2] = 0.0
    cp = ChainPositions(geo)
    planar = cp.chords(R, strain)
    geo.planar = False
    general = cp.chords(R, strain)
    assert np.abs(planar - general).max() <= 1e-12 * sc.cell_size_mm
