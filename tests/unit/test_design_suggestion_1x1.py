"""``design`` on a scene without axes suggests one to add; on a 1x1 grid it suggested ``"line": 1``, which that grid
refuses (it has no cell in column 1; user audit, session 35). The suggestion is now made for the scene at hand and
is one the program accepts: pasted into the scene, ``design`` configures it, with no fold that ``build`` would
reject as unprintable."""
import json
import os
import re

import pytest

from clihelpers import REPO, one_line_error, run_cli

FISH = os.path.join(REPO, "examples", "fish.json")


def _scene(tmp_path, layout):
    p = tmp_path / "s.json"
    p.write_text(json.dumps({"format": "metamaterial-scene", "version": 1, "layout": layout}), encoding="utf-8")
    return p


def _suggested(stderr):
    m = re.search(r'add "axes": (\[.*\]) \(docs/design.md\)', stderr)
    assert m, stderr
    return json.loads(m.group(1))


@pytest.mark.parametrize("layout", [{"grid": [1, 1]}, {"grid": [3, 1]}, {"grid": [1, 3]}, {"grid": [4, 6]}, None],
                         ids=["1x1", "3x1", "1x3", "4x6", "fish"])
def test_the_suggested_axis_is_accepted(tmp_path, layout):
    if layout is None:
        with open(FISH, encoding="utf-8") as f:
            data = json.load(f)
        data.pop("axes", None)
        path = tmp_path / "s.json"
        path.write_text(json.dumps(data), encoding="utf-8")
    else:
        path = _scene(tmp_path, layout)
    r = run_cli("design", path, "--out", tmp_path / "o.json")
    one_line_error(r, "axes")
    assert "has no rotary axes" in r.stderr
    axes = _suggested(r.stderr)
    assert not (tmp_path / "o.json").exists()
    data = json.loads(path.read_text(encoding="utf-8"))
    data["axes"] = axes
    path.write_text(json.dumps(data), encoding="utf-8")
    r = run_cli("design", path, "--out", tmp_path / "o.json")
    assert r.returncode == 0, (axes, r.stderr)
    assert "build` will reject" not in r.stderr, (axes, r.stderr)
    assert (tmp_path / "o.json").is_file()


def test_1x1_suggests_its_only_column(tmp_path):
    r = run_cli("design", _scene(tmp_path, {"grid": [1, 1]}), "--out", tmp_path / "o.json")
    ax = _suggested(r.stderr)
    assert len(ax) == 1 and ax[0]["line"] == 0, ax
