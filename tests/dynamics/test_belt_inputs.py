"""Belt scenes with fields the belt model never reads (an audit of the dynamics journey, session 26): each gave
exactly the unmodified belt's travel, without a word. They are refused, naming the field and what it belongs to."""
import copy
import json

import pytest

from metamaterial_wb import example_path
from metamaterial_wb.core.dynamics.builders import dynamics_config
from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.core.scene import Scene


def belt(edit):
    with open(example_path("belt8")) as f:
        d = json.load(f)
    d = copy.deepcopy(d)
    edit(d)
    return Scene.from_dict(d)


@pytest.mark.parametrize("key, value", [("density_kg_m3", 30000), ("hinge_modulus_mpa", 1e6),
                                        ("servo_mass_g", 1e4)])
def test_sheet_only_fields_on_a_belt_are_refused(key, value):
    s = belt(lambda d: d["dynamics"].update({key: value}))
    with pytest.raises(SceneError) as e:
        dynamics_config(s)
    assert e.value.field == f"dynamics.{key}" and "sheet" in str(e.value), str(e.value)


def test_actuators_beside_a_gait_are_refused():
    s = belt(lambda d: d.update(actuators=[{"joint": "V0,0", "value": 1.0}]))
    assert dynamics_config(belt(lambda d: None))["gait"]["type"] == "closed_loop"
    with pytest.raises(SceneError) as e:
        dynamics_config(s)
    assert e.value.field == "actuators" and "gait" in str(e.value), str(e.value)


def test_friction_pads_on_a_belt_are_refused():
    s = belt(lambda d: d.update(modules=[{"type": "friction_pad", "node": "N0,0", "mu": 0.0}]))
    with pytest.raises(SceneError) as e:
        dynamics_config(s)
    assert e.value.field.startswith("modules") and "belt" in str(e.value), str(e.value)


def test_a_closed_loop_gait_that_never_inflates_is_refused():
    s = belt(lambda d: d["dynamics"]["gait"].update(n1=0, n2=0))
    with pytest.raises(SceneError) as e:
        dynamics_config(s)
    assert e.value.field == "dynamics.gait" and "n1" in str(e.value), str(e.value)


def test_two_pads_on_one_face_of_a_sheet_node_are_refused():
    """A second friction pad on the same node face was accepted: it doubled the pad's mass and contact point and
    changed the crawl."""
    from metamaterial_wb.core.dynamics.builders import build
    with open(example_path("worm_crawl")) as f:
        d = json.load(f)
    pad = next(m for m in d["modules"] if m["type"] == "friction_pad")
    d["modules"].append(dict(pad, name="again") if "name" in pad else dict(pad))
    with pytest.raises(SceneError) as e:
        build(Scene.from_dict(d))
    assert e.value.field.startswith("modules[") and "one friction pad per face" in str(e.value), str(e.value)
