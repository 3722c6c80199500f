"""The angle sent for an actuator on a **tilted** joint (a bending line of examples/fish_axes.json) is the
rotation the lattice models hold that joint at; the quadratic kinematics' least-squares fold frames turn it by up
to 3.6 % less (docs/firmware.md states both). An audit found the docs claiming every model holds it exactly."""
import json
import os

import pytest

from metamaterial_wb import REPO_DIR
from metamaterial_wb.core.models import run_model
from metamaterial_wb.core.scene import Scene
from metamaterial_wb.hardware import channel_map
from metamaterial_wb.hardware.joint_angle import signed_joint_rotation_deg

AXES = os.path.join(REPO_DIR, "examples", "fish_axes.json")


def _one_actuator(joint, v):
    d = json.load(open(AXES, encoding="utf-8"))
    d["actuators"] = [{"name": "a", "joint": joint, "value": v}]
    d.pop("modules", None)
    return Scene.from_dict(d)


@pytest.mark.parametrize("joint", ["H0,2", "H0,5"])          # tilts -14 and +32 deg
@pytest.mark.parametrize("v", [1.0, 0.5, -0.5])
def test_tilted_joint_sent_angle_is_the_lattice_rotation(joint, v):
    s = _one_actuator(joint, v)
    sent = channel_map(s)[0].angle_deg(v)
    solved = {m: signed_joint_rotation_deg(s, run_model(m, s).rotations, joint)
              for m in ("quadratic", "linear", "nonlinear")}
    for m in ("linear", "nonlinear"):
        assert solved[m] == pytest.approx(sent, rel=2e-3), (m, solved, sent)
    # the quadratic model: same sign, at most the documented 3.6 % short of it
    q = solved["quadratic"] / sent
    assert 0.96 <= q <= 1.0 + 1e-9, (solved, sent)
