"""What a scene file holds is checked when it loads, with the range the code that uses it enforces (an audit,
session 26): the material section, joint_config keys that name one joint twice, duplicate JSON keys, ``units``,
values a few units in the last place past a fixed bound, and ``render --global``'s own name in its error."""
import json
import os
import subprocess
import sys

import pytest

from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.core.scene import Scene

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def scene(**kw):
    d = {"format": "metamaterial-scene", "version": 1, "layout": {"grid": [3, 4]},
         "actuators": [{"joint": "V0,0", "value": 0.5}]}
    d.update(kw)
    return d


@pytest.mark.parametrize("material, field, words", [
    ({"hinge_strain_limit": 7}, "material.hinge_strain_limit", "(0, 5]"),        # loaded up to 10, used up to 5
    ({"hinge_modulus_MPa": -5}, "material.hinge_modulus_MPa", "(0, 1000000"),
    ({"hinge_poisson_ratio": 0.7}, "material.hinge_poisson_ratio", "[0, 0.5)"),    # failed only under linear
    ({"hinge_modulus_mpa": 30}, "material.hinge_modulus_mpa", "hinge_modulus_MPa"),  # a misspelt key: ignored
])
def test_the_material_section_is_checked_on_load(material, field, words):
    with pytest.raises(SceneError) as e:
        Scene.from_dict(scene(material=material))
    assert e.value.field == field and words in str(e.value), str(e.value)


def test_the_material_section_loads_at_its_limits():
    s = Scene.from_dict(scene(material={"hinge_strain_limit": 5, "hinge_modulus_MPa": 1e6,
                                        "hinge_poisson_ratio": 0}))
    assert s.material["hinge_strain_limit"] == 5


def test_two_joint_config_keys_for_one_joint_are_refused():
    """``"H0,2"`` and ``"H(0,2)"`` are one joint: the later entry silently replaced the earlier one."""
    d = scene(joint_config={"H0,2": {"tilt_deg": 10}, "H(0,2)": {"tilt_deg": -30}})
    with pytest.raises(SceneError) as e:
        Scene.from_dict(d)
    assert "H0,2" in str(e.value) and "H(0,2)" in str(e.value), str(e.value)


def test_a_key_given_twice_in_a_json_object_is_refused():
    text = '{"format": "metamaterial-scene", "version": 1, "cell_size_mm": 20, "cell_size_mm": 30, ' \
           '"layout": {"grid": [2, 2]}}'
    with pytest.raises(SceneError) as e:
        Scene.from_json(text)
    assert "cell_size_mm" in str(e.value) and "twice" in str(e.value), str(e.value)


def test_units_other_than_millimetres_are_refused():
    assert Scene.from_dict(scene(units="mm")).to_dict()["units"] == "mm"
    with pytest.raises(SceneError) as e:
        Scene.from_dict(scene(units="inch"))
    assert e.value.field == "units" and "'mm'" in str(e.value), str(e.value)


@pytest.mark.parametrize("where", ["value", "global"])
def test_a_value_just_past_one_is_refused_on_load(where):
    """1.0000000000000009 loaded (a margin meant for computed bounds) and then failed in solve as ``values.m1``."""
    past = 1.0000000000000009
    d = scene(actuators=[{"joint": "V0,0", "value": past}]) if where == "value" else scene(global_deformation=past)
    with pytest.raises(SceneError) as e:
        Scene.from_dict(d)
    assert "outside the allowed range [-1.0, 1.0]" in str(e.value), str(e.value)
    assert e.value.field.startswith("actuators[0].value" if where == "value" else "global_deformation")


def test_render_names_its_global_flag(tmp_path):
    r = subprocess.run([sys.executable, "-m", "metamaterial_wb", "render", os.path.join(REPO, "examples",
                        "grid_fold.json"), "--global", "1.0000001", "--out", str(tmp_path / "g.png")],
                       capture_output=True, text=True, cwd=REPO, timeout=120)
    assert r.returncode == 2, r.stderr
    assert "--global" in r.stderr and "Traceback" not in r.stderr, r.stderr
    assert not (tmp_path / "g.png").exists()


def test_the_format_doc_states_the_material_ranges():
    with open(os.path.join(REPO, "docs", "scene-format.md"), encoding="utf-8") as f:
        doc = f.read()
    assert "`material.hinge_strain_limit` (optional, default 0.5; range (0, 5])" in doc
    assert "`units`" in doc
    json.dumps(doc)  # (the doc is text)


def test_a_constraint_with_a_motion_profile_is_refused():
    """A constraint's profile was kept, never checked (even ``{"shape": "bogus"}``) and never used."""
    d = scene(constraints=[{"name": "c1", "joint": "V1,2", "value": 0.2, "profile": {"shape": "bogus"}}])
    with pytest.raises(SceneError) as e:
        Scene.from_dict(d)
    assert e.value.field.startswith("constraints[0].profile") and "only actuators move" in str(e.value)


def test_an_unnamed_item_after_a_named_one_gets_a_free_default_name():
    """``[{"name": "m2", ...}, {...}]`` was refused as "'m2' is already used": the default of the second item."""
    s = Scene.from_dict(scene(actuators=[{"name": "m2", "joint": "V0,0", "value": 0.5}, {"joint": "V2,3"}]))
    assert [a.name for a in s.actuators] == ["m2", "m3"]
    s = Scene.from_dict(scene(actuators=[{"joint": "V0,0"}, {"joint": "V2,3"}]))
    assert [a.name for a in s.actuators] == ["m1", "m2"]                      # unchanged where nothing collides
