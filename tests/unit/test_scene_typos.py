"""A user audit of the command line: (1) a misspelt key on an actuator or constraint ("vlaue", "Value", "profil",
"jiont") was kept as an extra field and the item silently lost its value (0) and its motion: `solve` exited 0 with
"tail": 0.0 and `stream --dry-run` streamed it; (2) any JSON object without "format" read as a 1 x 1 default scene,
also the files this tool writes itself (a `stream --report`, a `design --report`) and a `--channels` file: `solve`
exited 0 on them. Both now are one-line errors naming the field / the file; genuinely extra fields (user
metadata, documented in docs/scene-format.md) still load, and every bundled scene still loads. Via the real CLI."""
import glob
import json
import os
import subprocess
import sys

import pytest

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from clihelpers import REPO, one_line_error, run_cli  # noqa: E402

FISH = os.path.join(REPO, "examples", "fish.json")
FISH_AXES = os.path.join(REPO, "examples", "fish_axes.json")


def fish():
    with open(FISH, encoding="utf-8") as fh:
        return json.load(fh)


def write(tmp_path, name, data):
    p = tmp_path / name
    p.write_text(json.dumps(data), encoding="utf-8")
    return p


def rename(item, old, new):
    """``item`` with key ``old`` renamed ``new`` (same position, value kept)."""
    return {(new if k == old else k): v for k, v in item.items()}


def fish_with(actuator_edit=None, constraints=None):
    d = fish()
    if actuator_edit:
        d["actuators"][1] = actuator_edit(d["actuators"][1])
    if constraints is not None:
        d["constraints"] = constraints
    return d


# ---- 1: a near miss of a known field is refused, naming the path, what it looks like and the allowed fields ----
TYPOS = [
    ("act-vlaue", fish_with(lambda a: rename(a, "value", "vlaue")), "actuators[1].vlaue", "value"),
    ("act-profil", fish_with(lambda a: rename(a, "profile", "profil")), "actuators[1].profil", "profile"),
    ("act-Value", fish_with(lambda a: rename(a, "value", "Value")), "actuators[1].Value", "value"),
    ("act-jiont", fish_with(lambda a: rename(a, "joint", "jiont")), "actuators[1].jiont", "joint"),
    ("act-Name", fish_with(lambda a: rename(a, "name", "Name")), "actuators[1].Name", "name"),
    ("act-values", fish_with(lambda a: rename(a, "value", "values")), "actuators[1].values", "value"),
    ("act-sevro", fish_with(lambda a: dict(a, sevro={"channel": 1})), "actuators[1].sevro", "servo"),
    ("con-Value", fish_with(constraints=[{"name": "clip", "joint": "H0,3", "Value": -0.5}]),
     "constraints[0].Value", "value"),
    ("con-jiont", fish_with(constraints=[{"name": "clip", "jiont": "H0,3", "value": -0.5}]),
     "constraints[0].jiont", "joint"),
    ("con-vlaue", fish_with(constraints=[{"name": "clip", "joint": "H0,3", "vlaue": -0.5}]),
     "constraints[0].vlaue", "value"),
]


@pytest.mark.parametrize("data, field, looks_like", [t[1:] for t in TYPOS], ids=[t[0] for t in TYPOS])
def test_solve_refuses_a_misspelt_actuator_or_constraint_field(tmp_path, data, field, looks_like):
    scene = write(tmp_path, "typo.json", data)
    out = tmp_path / "r.json"
    r = run_cli("solve", scene, "--out", out)
    one_line_error(r, field)
    assert f'looks like "{looks_like}"' in r.stderr, r.stderr
    assert "allowed: name, joint, value" in r.stderr, r.stderr
    assert str(scene) in r.stderr
    assert not out.exists()


def test_stream_dry_run_refuses_the_audits_typo_scene(tmp_path):
    scene = write(tmp_path, "typo.json", fish_with(lambda a: rename(rename(a, "value", "vlaue"), "profile", "profil")))
    r = run_cli("stream", scene, "--dry-run", "--seconds", "0.1")
    one_line_error(r, "actuators[1].vlaue")          # the first of the two, in the file's order
    assert 'looks like "value"' in r.stderr


def test_a_constraint_with_a_misspelt_profile_is_told_constraints_take_none(tmp_path):
    scene = write(tmp_path, "c.json", fish_with(constraints=[{"name": "clip", "joint": "H0,3", "value": 0.1,
                                                              "profil": {"shape": "sine"}}]))
    r = run_cli("solve", scene, "--out", tmp_path / "r.json")
    one_line_error(r, "constraints[0].profil")
    assert 'looks like "profile"' in r.stderr and "only actuators" in r.stderr


def test_genuinely_extra_fields_are_kept_and_the_values_used(tmp_path):
    """User metadata (docs/scene-format.md: "a servo type or a channel number is kept") still loads and is written
    back by `design --out`; the values are the ones written."""
    d = json.load(open(FISH_AXES, encoding="utf-8"))
    d["actuators"][1].update({"note": "tail fin", "servo_type": "MG90S", "channel_no": 3, "label": "T"})
    d["constraints"] = [{"name": "clip", "joint": "H0,3", "value": -0.5, "comment": "printed clip", "colour": "red"}]
    scene = write(tmp_path, "meta.json", d)
    r = run_cli("solve", scene, "--out", tmp_path / "r.json")
    assert r.returncode == 0, r.stderr
    res = json.load(open(tmp_path / "r.json", encoding="utf-8"))
    assert res["actuators"]["tail"] == 0.8 and res["constraints"]["clip"] == -0.5
    r = run_cli("design", scene, "--out", tmp_path / "c.json", "--quiet")
    assert r.returncode == 0, r.stderr
    back = json.load(open(tmp_path / "c.json", encoding="utf-8"))
    assert back["actuators"][1]["servo_type"] == "MG90S" and back["actuators"][1]["note"] == "tail fin"
    assert back["constraints"][0]["comment"] == "printed clip"


def test_a_missing_value_is_the_documented_default_0_for_actuators_and_constraints(tmp_path):
    """No near miss in the item: a missing "value" is 0 (the flat state), as docs/scene-format.md says, for both."""
    d = fish_with(lambda a: {k: v for k, v in a.items() if k != "value"},
                  constraints=[{"name": "clip", "joint": "H0,3"}])
    r = run_cli("solve", write(tmp_path, "s.json", d), "--out", tmp_path / "r.json")
    assert r.returncode == 0, r.stderr
    res = json.load(open(tmp_path / "r.json", encoding="utf-8"))
    assert res["actuators"]["tail"] == 0.0 and res["constraints"]["clip"] == 0.0
    with open(os.path.join(REPO, "docs", "scene-format.md"), encoding="utf-8") as fh:
        doc = fh.read()
    assert "`value` defaults to 0" in doc


# ---- 2: a JSON object that is not a scene is refused, naming the file and what it is --------------------------
NOT_SCENES = [
    ("channels", {"tail": {"channel": 1, "invert": True}}, "'tail'"),
    ("empty-object", {}, "an empty JSON object"),
    ("cell-size-only", {"cell_size_mm": 20, "name": "x"}, "'cell_size_mm'"),
]


@pytest.mark.parametrize("command", ["solve", "build"])
@pytest.mark.parametrize("data, keys", [t[1:] for t in NOT_SCENES], ids=[t[0] for t in NOT_SCENES])
def test_a_json_object_without_format_and_layout_is_not_a_scene(tmp_path, command, data, keys):
    f = write(tmp_path, "c.json", data)
    out = tmp_path / "out"
    r = run_cli(command, f, "--out", out)
    one_line_error(r, "format")
    assert "not a scene" in r.stderr and str(f) in r.stderr and keys in r.stderr, r.stderr
    assert not out.exists()


def test_a_scene_without_format_but_with_a_layout_still_loads(tmp_path):
    r = run_cli("solve", write(tmp_path, "s.json", {"layout": {"grid": [1, 2]},
                                                    "actuators": [{"joint": "V0,0", "value": 0.2}]}),
                "--out", tmp_path / "r.json")
    assert r.returncode == 0, r.stderr


def test_a_stream_report_carries_a_format_and_is_refused_as_a_scene(tmp_path):
    rep = tmp_path / "rep.json"
    r = run_cli("stream", FISH, "--dry-run", "--seconds", "0.1", "--report", rep)
    assert r.returncode == 0, r.stderr
    d = json.load(open(rep, encoding="utf-8"))
    assert d["format"] == "metamaterial-stream-report" and d["version"] == 1
    r = run_cli("solve", rep, "--out", tmp_path / "r.json")
    one_line_error(r, "format")
    assert "stream --report" in r.stderr and str(rep) in r.stderr
    assert not (tmp_path / "r.json").exists()


def test_a_design_report_carries_a_format_and_is_refused_as_a_scene(tmp_path):
    rep = tmp_path / "rep.json"
    r = run_cli("design", FISH_AXES, "--out", tmp_path / "c.json", "--report", rep, "--quiet")
    assert r.returncode == 0, r.stderr
    d = json.load(open(rep, encoding="utf-8"))
    assert d["format"] == "metamaterial-design-report" and d["version"] == 1 and d["axes"]
    for command in ("solve", "build"):
        r = run_cli(command, rep, "--out", tmp_path / "o")
        one_line_error(r, "format")
        assert "design --report" in r.stderr and str(rep) in r.stderr
    assert not (tmp_path / "o").exists()


def test_a_solve_result_is_named_when_read_as_a_scene(tmp_path):
    r = run_cli("solve", FISH, "--out", tmp_path / "r.json")
    assert r.returncode == 0, r.stderr
    r = run_cli("solve", tmp_path / "r.json", "--out", tmp_path / "r2.json")
    one_line_error(r, "format")
    assert "metamaterial-result" in r.stderr and "solve" in r.stderr


def test_every_bundled_scene_still_loads():
    """Every examples/*.json whose format is a scene loads, with the GUI's fields (objects/item.py: name, joint,
    value, profile and its ExtraJSON) and the scene's extras; one process, one line per example."""
    paths = []
    for p in sorted(glob.glob(os.path.join(REPO, "examples", "*.json"))):
        with open(p, encoding="utf-8") as fh:
            if json.load(fh).get("format") == "metamaterial-scene":
                paths.append(p)
    assert len(paths) >= 15
    code = ("import sys\nfrom metamaterial_wb.core.scene import Scene\n"
            "for p in sys.argv[1:]:\n    s = Scene.load(p)\n    Scene.from_json(s.to_json())\n    print('ok', p)\n")
    r = subprocess.run([sys.executable, "-c", code, *paths], cwd=REPO, capture_output=True, encoding="utf-8",
                       timeout=300, env=dict(os.environ, PYTHONPATH=REPO))
    assert r.returncode == 0, r.stderr
    assert r.stdout.count("ok ") == len(paths)


def test_a_gui_item_with_its_extra_fields_round_trips():
    """objects/item.py writes name, joint, value, profile plus the item's ExtraJSON (e.g. a servo object)."""
    d = fish()
    d["actuators"][0]["servo"] = {"channel": 2, "invert": True}
    d["actuators"][0]["note"] = "head"
    code = ("import json, sys\nfrom metamaterial_wb.core.scene import Scene\n"
            "s = Scene.from_json(sys.stdin.read())\nprint(json.dumps(s.actuators[0].to_dict()))\n")
    r = subprocess.run([sys.executable, "-c", code], input=json.dumps(d), cwd=REPO, capture_output=True,
                       encoding="utf-8", timeout=120, env=dict(os.environ, PYTHONPATH=REPO))
    assert r.returncode == 0, r.stderr
    back = json.loads(r.stdout)
    assert back["servo"] == {"channel": 2, "invert": True} and back["note"] == "head"
    assert back["value"] == 0.3
