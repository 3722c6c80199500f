"""A hinge size outside the calibration table is refused by the model that reads the table, after the scene was
loaded: its message named the field (``joints[1].length_mm (H0,0)``, ``hinge.width_mm``) but not the file, while
every error of the load ends in ``(in FILE)`` (session 33). Now it names the scene file too, once, in every
command that runs the model. Through the real CLI."""
import json
import os

import pytest

from clihelpers import REPO, one_line_error, run_cli

FISH = os.path.join(REPO, "examples", "fish.json")


def scene_file(tmp_path, edit):
    with open(FISH, encoding="utf-8") as fh:
        d = json.load(fh)
    edit(d)
    p = tmp_path / "short hinge.json"          # a space: the path is named as given
    p.write_text(json.dumps(d), encoding="utf-8")
    return p


def short_joint(d):
    d["joints"] = [{"joint": "V0,1", "k1": 0.5}, {"joint": "H0,0", "length_mm": 0.01}]


def narrow_base_hinge(d):
    d["hinge"]["width_mm"] = 0.01


CASES = [("joint-length", short_joint, "joints[1].length_mm (H0,0)", "0.01 mm is outside the allowed range [0.25, 9.5]"
          " of the calibration table"),
         ("base-width", narrow_base_hinge, "hinge.width_mm", "0.01 mm is outside the allowed range")]


@pytest.mark.parametrize("edit, field, words", [c[1:] for c in CASES], ids=[c[0] for c in CASES])
@pytest.mark.parametrize("command, out", [("solve", "r.json"), ("render", "r.png"), ("simulate", "sim")])
def test_a_hinge_outside_the_calibration_table_names_the_scene_file(tmp_path, edit, field, words, command, out):
    scene = scene_file(tmp_path, edit)
    extra = ["--seconds", "0.1"] if command == "simulate" else []
    r = run_cli(command, scene, *extra, "--out", tmp_path / out)
    one_line_error(r, field)
    assert words in r.stderr, r.stderr
    assert r.stderr.rstrip().endswith(f"(in {scene})"), r.stderr
    assert r.stderr.count(str(scene)) == 1, r.stderr
    assert not (tmp_path / out).exists()


def test_an_error_of_the_load_is_not_named_twice(tmp_path):
    """A hinge size the load itself refuses already ends in (in FILE): it is not added again."""
    scene = scene_file(tmp_path, lambda d: d["hinge"].update(length_mm=-1))
    r = run_cli("solve", scene, "--out", tmp_path / "r.json")
    one_line_error(r, "hinge.length_mm")
    assert r.stderr.count(str(scene)) == 1 and r.stderr.rstrip().endswith(f"(in {scene})"), r.stderr


def test_a_flag_error_after_the_load_names_no_scene_file(tmp_path):
    r = run_cli("solve", FISH, "--set", "nosuch=0.1", "--out", tmp_path / "r.json")
    assert r.returncode == 2 and r.stderr.startswith("error: --set"), r.stderr
    assert FISH not in r.stderr, r.stderr
