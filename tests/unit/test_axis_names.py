"""A rotary axis' name follows the naming rule of actuators, constraints and modules (docs/scene-format.md: letters,
digits and ``_ . -``, starting with a letter or ``_``, at most 64 characters). From an audit: ``"2"`` (ambiguous with
the index keys of ``--fold 2=...``), ``""`` (silently became the default ``v<line>``), ``"my axis!"`` and a
200-character name were all taken, ``design`` exited 0."""
import copy
import glob
import json
import os
import subprocess
import sys

import pytest

from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.core.scene import Scene
from metamaterial_wb.core.scene.names import _short

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
FISH_AXES = os.path.join(ROOT, "examples", "fish_axes.json")


def fish_axes():
    with open(FISH_AXES, encoding="utf-8") as f:
        return json.load(f)


BAD = [("2", "digits"), ("", "empty"), ("my axis!", "space"), ("x" * 200, "long"), ("x" * 65, "65"),
       ("1bad", "digit-first"), ("-a", "dash-first"), ("a\n", "newline"), ("é", "non-ascii")]


@pytest.mark.parametrize("name", [b[0] for b in BAD], ids=[b[1] for b in BAD])
def test_a_bad_axis_name_is_refused(name):
    d = fish_axes()
    d["axes"][1]["name"] = name
    with pytest.raises(SceneError) as e:
        Scene.from_dict(d)
    assert e.value.field == "axes[1].name"
    msg = e.value.message
    assert msg.startswith(_short(name) + " "), msg
    assert "letters, digits, _ . -" in msg and "starting with a letter or _" in msg and "64" in msg, msg


@pytest.mark.parametrize("name", [7, None, ["a"]])
def test_an_axis_name_that_is_not_text_is_refused(name):
    d = fish_axes()
    d["axes"][0]["name"] = name
    with pytest.raises(SceneError) as e:
        Scene.from_dict(d)
    assert e.value.field == "axes[0].name"


@pytest.mark.parametrize("name", ["a", "_", "neck_2", "A.b-c", "_9", "x" * 64])
def test_a_good_axis_name_is_kept(name):
    d = fish_axes()
    d["axes"][0]["name"] = name
    s = Scene.from_dict(d)
    assert s.axes[0].name == name
    assert s.to_dict()["axes"][0]["name"] == name


def test_an_axis_without_a_name_keeps_its_default():
    d = fish_axes()
    del d["axes"][0]["name"]
    s = Scene.from_dict(d)
    assert s.axes[0].name == "" and "name" not in s.to_dict()["axes"][0]


@pytest.mark.parametrize("path", sorted(glob.glob(os.path.join(ROOT, "examples", "*.json"))),
                         ids=lambda p: os.path.basename(p))
def test_every_bundled_scene_still_loads(path):
    with open(path, encoding="utf-8") as f:
        d = json.load(f)
    if d.get("format") != "metamaterial-scene":
        pytest.skip("not a scene")
    s = Scene.load(path)
    for a, given in zip(s.axes, d.get("axes", [])):
        assert a.name == given.get("name", "")


@pytest.mark.parametrize("name, shown", [("2", "'2'"), ("", "''"), ("my axis!", "'my axis!'")])
def test_design_refuses_it_and_writes_nothing(tmp_path, name, shown):
    d = copy.deepcopy(fish_axes())
    d["axes"][0]["name"] = name
    scene = tmp_path / "s.json"
    scene.write_text(json.dumps(d), encoding="utf-8")
    out = tmp_path / "o.json"
    r = subprocess.run([sys.executable, "-m", "metamaterial_wb", "design", str(scene), "--out", str(out)],
                       capture_output=True, text=True, cwd=ROOT, timeout=300, env=dict(os.environ, PYTHONPATH=ROOT))
    assert r.returncode == 2, (r.stdout, r.stderr)
    assert "axes[0].name: " in r.stderr and shown in r.stderr, r.stderr
    assert not out.exists()


@pytest.mark.parametrize("where", ["actuators", "constraints"])
def test_an_actuator_or_constraint_name_ending_in_a_newline_is_refused(where):
    """``$`` also matches before a final newline: "tail\\n" passed the naming rule of actuators and constraints."""
    d = copy.deepcopy(fish_axes())
    d["actuators"], d["constraints"] = [], []
    d[where] = [{"name": "tail\n", "joint": "V1,5", "value": 0.1}]
    with pytest.raises(SceneError, match=r"\.name: 'tail\\n' is not a valid name"):
        Scene.from_dict(d)
