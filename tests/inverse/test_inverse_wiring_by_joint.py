"""The servo wiring (``servo`` {channel, invert, trim_deg}) of the replaced motors goes by joint, not by list
order: a new servo on an old motor's joint keeps that motor's wiring; only motors whose joint gets no new servo
pass theirs on, to the new servos without wiring in order s1, s2, ... (docs/inverse.md; found by a user audit:
with the actuators listed tail first, s1 on the head's joint got the tail's channel and stream drove each servo
with the other's motion)."""
import json
import os
from types import SimpleNamespace

from metamaterial_wb import REPO_DIR
from metamaterial_wb.core.inverse import evaluate as ev
from metamaterial_wb.core.scene import Scene

HEAD = {"channel": 4, "invert": True, "trim_deg": 2.5}
TAIL = {"channel": 7}


def _fish(reverse):
    with open(os.path.join(REPO_DIR, "examples", "fish_modules.json"), encoding="utf-8") as f:
        d = json.load(f)
    acts = {a["name"]: a for a in d["actuators"]}
    assert acts["head"]["joint"] == "V0,1" and acts["tail"]["joint"] == "V1,5"
    acts["head"]["servo"], acts["tail"]["servo"] = dict(HEAD), dict(TAIL)
    d["actuators"] = [acts["tail"], acts["head"]] if reverse else [acts["head"], acts["tail"]]
    return Scene.from_dict(d)


def _answer(scene, joints):
    problem = SimpleNamespace(scene=scene, target=SimpleNamespace(frames=[None], period_s=None))
    notes = []
    s = ev.answer_scene(problem, joints, [[0.1 * (k + 1) for k in range(len(joints))]], warnings=notes)
    d = s.to_dict()
    return {a["joint"]: a for a in d["actuators"]}, d, notes


def test_new_servos_on_the_old_joints_keep_their_wiring_whatever_the_list_order():
    for reverse in (False, True):
        acts, _, notes = _answer(_fish(reverse), ["V0,1", "V1,5"])
        assert acts["V0,1"]["name"] == "s1" and acts["V0,1"]["servo"] == HEAD, (reverse, acts)
        assert acts["V1,5"]["name"] == "s2" and acts["V1,5"]["servo"] == TAIL, (reverse, acts)
        assert not any("V1,5" in n and "'s1'" in n for n in notes), notes
        assert any("'s1'" in n and "'head'" in n and "channel 4" in n for n in notes), notes


def test_only_motors_whose_joint_gets_no_servo_pass_their_wiring_on_in_order():
    # s3 lands on the tail's joint: it keeps channel 7 (and the tail's housing stays there); the head's joint
    # V0,1 gets no servo, so its wiring goes to the first new servo without wiring, s1 on H0,0, like its housing
    for reverse in (False, True):
        acts, d, notes = _answer(_fish(reverse), ["H0,0", "H1,0", "V1,5"])
        assert acts["V1,5"]["name"] == "s3" and acts["V1,5"]["servo"] == TAIL, (reverse, acts)
        assert acts["H0,0"]["servo"] == HEAD, (reverse, acts)
        assert "servo" not in acts["H1,0"], (reverse, acts)
        housings = {m["name"]: m["joint"] for m in d["modules"] if m["type"] == "servo_housing"}
        assert housings == {"servo_head": "H0,0", "servo_tail": "V1,5"}
        assert any("'s1'" in n and "'head'" in n and "invert" in n for n in notes), notes


def test_two_freed_motors_pass_their_wiring_in_scene_order_to_new_servos_in_name_order():
    acts, _, notes = _answer(_fish(True), ["H1,0", "H0,0"])          # neither old joint keeps a servo
    assert acts["H1,0"]["name"] == "s1" and acts["H1,0"]["servo"] == TAIL   # tail is listed first here
    assert acts["H0,0"]["name"] == "s2" and acts["H0,0"]["servo"] == HEAD
