"""A scene's ``axes`` entries kept every unknown field, also a misspelling of the fields an axis reads: an axis
with ``"fold_dge": 30`` loaded with fold 0 and `design` exited 0 (session 33). Now a near miss of ``direction``,
``line``, ``fold_deg``, ``name``, ``from`` or ``to`` is refused as on actuators and constraints (the path, the
field it looks like, the allowed fields); fields of the user's own (``note``, ``label``) are still kept and
written back."""
import json
import os

import pytest

from clihelpers import REPO, one_line_error, run_cli

from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.core.scene import Scene

FISH_AXES = os.path.join(REPO, "examples", "fish_axes.json")
ALLOWED = "allowed: direction, line, fold_deg, name, from, to, and fields of your own whose names resemble none"


def fish_axes():
    with open(FISH_AXES, encoding="utf-8") as fh:
        return json.load(fh)


def rename(item, old, new):
    return {(new if k == old else k): v for k, v in item.items()}


@pytest.mark.parametrize("old, typo", [("fold_deg", "fold_dge"), ("fold_deg", "Fold_deg"), ("fold_deg", " fold_deg"),
                                       ("fold_deg", "fold_degs"), ("direction", "drection"), ("line", "lines"),
                                       ("name", "Name")])
def test_a_misspelt_axis_field_is_refused_naming_the_path_and_the_field(old, typo):
    d = fish_axes()
    d["axes"][1] = rename(d["axes"][1], old, typo)
    with pytest.raises(SceneError) as e:
        Scene.from_dict(d)
    assert e.value.field == f"axes[1].{typo}", str(e.value)
    assert f'unknown field; it looks like "{old}" (letter case or a misspelling)' in e.value.message, str(e.value)
    assert ALLOWED in e.value.message, str(e.value)


@pytest.mark.parametrize("typo, like", [("frm", "from"), ("too", "to")])
def test_a_misspelt_from_or_to_is_refused(typo, like):
    d = fish_axes()
    d["axes"][0][typo] = 0
    with pytest.raises(SceneError) as e:
        Scene.from_dict(d)
    assert e.value.field == f"axes[0].{typo}" and f'looks like "{like}"' in e.value.message, str(e.value)


def test_fields_of_the_users_own_on_an_axis_are_kept_and_written_back():
    d = fish_axes()
    d["axes"][0].update(note="the neck", label=3, comment={"by": "me"})
    back = Scene.from_dict(d).to_dict()["axes"][0]
    assert (back["note"], back["label"], back["comment"]) == ("the neck", 3, {"by": "me"})
    assert back["fold_deg"] == d["axes"][0]["fold_deg"]


@pytest.mark.parametrize("command", ["design", "solve"])
def test_the_cli_refuses_a_misspelt_fold_in_one_line_naming_the_file(tmp_path, command):
    d = fish_axes()
    d["axes"][2] = rename(d["axes"][2], "fold_deg", "fold_dge")
    scene = tmp_path / "typo.json"
    scene.write_text(json.dumps(d), encoding="utf-8")
    out = tmp_path / "o.json"
    r = run_cli(command, scene, "--out", out)
    one_line_error(r, "axes[2].fold_dge")
    assert 'looks like "fold_deg"' in r.stderr and f"(in {scene})" in r.stderr, r.stderr
    assert not out.exists()
