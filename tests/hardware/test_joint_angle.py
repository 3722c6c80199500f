"""Issue 16 item 9: what the servo is told is what was simulated. The angle the stream sends for an actuator value
equals the actuated joint's relative rotation in the solver's result (signed from the node rotations; its
magnitude is the result's ``joints[].hinge_rotation_deg``), for the quadratic and the linear lattice models."""
import json
import math
import os
import subprocess
import sys

import pytest

from metamaterial_wb.core.models import run_model
from metamaterial_wb.core.scene import Scene
from metamaterial_wb.hardware import channel_map
from metamaterial_wb.hardware.joint_angle import signed_joint_rotation_deg

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def grid_scene(v, hinge_mm=2.0):
    """The issue's repro: a 2 x 6 grid of 20 mm cells with 2 mm hinges and an actuator on V0,2."""
    d = json.load(open(os.path.join(REPO, "examples", "fish.json")))
    d["hinge"]["length_mm"] = hinge_mm
    d["cell_size_mm"] = 20
    d["actuators"] = [{"name": "a", "joint": "V0,2", "value": v}]
    return Scene.from_dict(d)


@pytest.mark.parametrize("v", [1.0, 0.5, -0.5, -1.0])
def test_sent_angle_is_the_solved_joint_rotation(v):
    s = grid_scene(v)
    c = channel_map(s)[0]
    for model in ("quadratic", "linear"):
        res = run_model(model, s)
        assert c.angle_deg(v) == pytest.approx(signed_joint_rotation_deg(s, res.rotations, "V0,2"), abs=1e-6), model
    # the numbers: v = +1 -> 6.37 deg (plate contact on both sides of the joint), -1 -> 90 deg (wide open)
    assert abs(c.angle_deg(v)) == pytest.approx({1.0: 6.37, 0.5: 3.18, -0.5: 45.0, -1.0: 90.0}[v], abs=0.01)
    # not v * 90 any more (45 deg at v = 0.5 would be 14x past plate contact)
    assert v < 0 or abs(c.angle_deg(v)) < abs(v) * 90 / 10


def test_solve_cli_hinge_rotation_matches_the_stream_angle(tmp_path):
    s = grid_scene(1.0)
    path = tmp_path / "g.json"
    path.write_text(json.dumps(s.to_dict()))
    out = tmp_path / "r.json"
    r = subprocess.run([sys.executable, "-m", "metamaterial_wb", "solve", str(path), "--out", str(out)],
                       capture_output=True, text=True, cwd=REPO, timeout=120)
    assert r.returncode == 0, r.stderr
    joints = {j["name"]: j for j in json.loads(out.read_text())["joints"]}
    c = channel_map(s)[0]
    assert abs(c.angle_deg(1.0)) == pytest.approx(joints["V0,2"]["hinge_rotation_deg"], abs=1e-6)
    # the channel's default limits are that joint's kinematic range, plate contact to full opening
    lo, hi = c.limits_deg
    assert lo == pytest.approx(min(c.angle_deg(1.0), c.angle_deg(-1.0)), abs=0.01)
    assert hi == pytest.approx(max(c.angle_deg(1.0), c.angle_deg(-1.0)), abs=0.01)
    assert math.isclose(max(abs(lo), abs(hi)), 90.0, abs_tol=0.01)


def test_tilted_joint_rotation_and_the_on_board_check():
    """A tilted hinge (60 deg) also folds: |angle| = psi with cos(psi/2) = cos(gamma/2) cos(phi), tan(gamma/2) =
    -tan(tilt) sin(p_A phi), phi = v phi_max (written out here); not proportional to v, so OSC mode refuses it."""
    from dataclasses import replace

    from metamaterial_wb.core.errors import SceneError
    from metamaterial_wb.hardware.onboard import osc_params
    s = Scene.load(os.path.join(REPO, "examples", "fish.json"))
    ch = channel_map(s)
    tilt = math.radians(60)
    rot = replace(ch[1].rotation, tilt_rad=tilt)
    for v in (1.0, 0.4, -0.3, -1.0):
        phi = v * (rot.closing_rad if v >= 0 else rot.opening_rad)
        gamma = -2 * math.atan(math.tan(tilt) * math.sin(rot.parity_a * phi))
        psi = 2 * math.acos(math.cos(gamma / 2) * math.cos(phi))
        assert abs(rot.angle_deg(v)) == pytest.approx(math.degrees(psi), abs=1e-9)
        assert math.copysign(1, rot.angle_deg(v)) == -math.copysign(1, rot.parity_a * v)
    ch[1].rotation, ch[1].limits_deg = rot, (-90.0, 90.0)
    with pytest.raises(SceneError, match=r"tail.*tilted hinge.*off by 1\d\.\d\d deg \(allowed 0.25\)"):
        osc_params(s, ch)
