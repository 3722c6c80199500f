"""A user audit: a misspelt TOP-LEVEL scene key ("Layout", "cell_size", "Actuators", "actuator",
"global_deformaton", "dynamic", "axis") was kept as an unknown key and its default used: `solve` solved the
default 1 x 1 grid with no actuator and exited 0. Fields inside sections already got a near-miss refusal; the top
level now gets the same one, naming the key and the known key it resembles. Keys that resemble no known key are
still the user's (kept and written back, docs/scene-format.md), and every bundled scene still loads."""
import glob
import json
import os
import sys

import pytest

from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.core.scene import Scene

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from clihelpers import REPO, one_line_error, run_cli  # noqa: E402

BASE = {"format": "metamaterial-scene", "version": 1, "layout": {"grid": [1, 2]}}

# (written key, its value, the known key it resembles)
NEAR = [
    ("Layout", {"grid": [3, 3]}, "layout"),
    ("cell_size", 30, "cell_size_mm"),
    ("Actuators", [{"joint": "V0,0", "value": 0.5}], "actuators"),
    ("actuator", [{"joint": "V0,0", "value": 0.5}], "actuators"),
    ("global_deformaton", 0.7, "global_deformation"),
    ("dynamic", {"gravity_m_s2": 0}, "dynamics"),
    ("axis", [{"direction": "vertical", "line": 1, "fold_deg": 20}], "axes"),
    ("constraint", [{"joint": "H0,1", "value": 0.1}], "constraints"),
    ("Fabrication", {}, "fabrication"),
    (" hinge", {"length_mm": 2}, "hinge"),
    ("joint_configs", {}, "joint_config"),
    ("Version", 1, "version"),
]


@pytest.mark.parametrize("key,value,like", NEAR, ids=[n[0].strip() for n in NEAR])
def test_a_near_miss_of_a_top_level_key_is_refused_naming_both(key, value, like):
    d = dict(BASE)
    d[key] = value
    with pytest.raises(SceneError) as exc:
        Scene.from_dict(d)
    assert exc.value.field == key.strip() or exc.value.field == key
    msg = str(exc.value)
    assert f'"{like}"' in msg and "unknown top-level key" in msg, msg


def test_the_near_miss_is_named_before_what_it_caused():
    """"Layout" 3 x 3 with an actuator on V0,2: the default 1 x 1 grid has no V0,2, but the error names the
    misspelling, not the missing joint."""
    d = {"format": "metamaterial-scene", "version": 1, "Layout": {"grid": [3, 3]},
         "actuators": [{"joint": "V0,2", "value": 0.5}]}
    with pytest.raises(SceneError) as exc:
        Scene.from_dict(d)
    assert exc.value.field == "Layout" and '"layout"' in str(exc.value)


def test_a_file_without_format_whose_layout_is_misspelt_says_so(tmp_path):
    """No "format" and "Layout" instead of "layout": not "not a scene", but the misspelling."""
    p = tmp_path / "s.json"
    p.write_text(json.dumps({"Layout": {"grid": [3, 3]}}), encoding="utf-8")
    with pytest.raises(SceneError) as exc:
        Scene.load(str(p))
    assert exc.value.field == "Layout" and '"layout"' in str(exc.value)


@pytest.mark.parametrize("key", ["my_tool", "notes", "comment", "author", "metadata", "source", "x-gui",
                                 "_comment", "history", "title", "tags"])
def test_keys_that_resemble_no_known_key_are_still_kept(key):
    d = dict(BASE)
    d[key] = {"anything": [1, 2]}
    s = Scene.from_dict(d)
    assert s.extra[key] == {"anything": [1, 2]}
    assert Scene.from_dict(s.to_dict()).to_dict() == s.to_dict()


def test_the_audit_file_via_the_cli(tmp_path):
    """The audit's T1: exit 2, one line naming "Layout" and "layout" (it was exit 0 with a 1 x 1 solve)."""
    p = tmp_path / "T1.json"
    p.write_text(json.dumps({"format": "metamaterial-scene", "version": 1, "Layout": {"grid": [3, 3]},
                             "actuators": [{"joint": "V0,0", "value": 0.5}]}), encoding="utf-8")
    r = run_cli("solve", str(p), "--out", str(tmp_path / "r.json"))
    one_line_error(r, "Layout")
    assert '"layout"' in r.stderr and not (tmp_path / "r.json").exists()


def test_every_bundled_scene_has_no_near_miss_top_level_key():
    """Every scene file shipped in examples/ and the tests' data loads (top level checked here; the full load of
    the examples is test_scene_typos's)."""
    found = 0
    for path in sorted(glob.glob(os.path.join(REPO, "examples", "*.json"))
                       + glob.glob(os.path.join(REPO, "tests", "**", "*.json"), recursive=True)):
        with open(path, encoding="utf-8") as fh:
            try:
                d = json.load(fh)
            except ValueError:
                continue
        if not isinstance(d, dict) or d.get("format", "metamaterial-scene" if "layout" in d else None) \
                != "metamaterial-scene":
            continue
        found += 1
        Scene.from_dict(d)
    assert found >= 10


@pytest.mark.parametrize("name,what", [("walker.json", "is not a scene (it is a sleeve spec"),
                                       ("worm_inverse_report.json", "is not a scene")])
def test_another_document_is_named_as_such_before_its_keys_are_judged(name, what):
    """A sleeve spec or an inverse report given as a scene: "not a scene (it is ...)", not a misspelt key of a scene
    ('actuator' of a sleeve spec looked like "actuators")."""
    path = os.path.join(REPO, "examples", name)
    with pytest.raises(SceneError) as e:
        Scene.load(path)
    assert what in str(e.value) and "top-level key" not in str(e.value), str(e.value)
