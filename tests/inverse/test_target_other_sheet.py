"""A ``solve`` result of another sheet is no target: a result lists its nodes by name only, and two sheets with
the same node names but another cell pitch (``cell_size_mm``) have other rest positions, so the fit matched
nonsense silently. The result now carries its sheet's ``cell_size_mm`` and a target result of another pitch is
refused before any search, naming the file, the node whose rest position differs most and what is allowed; the
same sheet (a renamed copy), hand-written position targets and results written before the field existed (with a
warning) are still read."""
import json

import numpy as np
import pytest

from clihelpers import one_line_error, run_cli
from inverse_helpers import planted_result, scene_with
from metamaterial_wb.core.inverse.surface import TargetError
from metamaterial_wb.core.inverse.targets import load_target, parse_target
from metamaterial_wb.core.scene import Scene

FAST = ("--values-only", "--no-picture", "--fab-checks", "off", "--evaluate", "quadratic")


def _scene(rows=3, cols=3, cell=20.0, name="sheet"):
    s = scene_with(Scene.grid(rows, cols, cell_size_mm=cell), [("V0,1", 0.4)])
    s.name = name
    return s


def _write(path, text):
    with open(path, "w", encoding="utf-8") as fh:
        fh.write(text)
    return str(path)


def _solved(tmp_path, scene, stem, npz=False):
    """``solve`` (the CLI) of ``scene``: the result's path (the JSON; with --npz its JSON half)."""
    src = _write(tmp_path / f"{stem}_scene.json", scene.to_json())
    out = str(tmp_path / f"{stem}.json")
    r = run_cli("solve", src, "--out", out, *(("--npz",) if npz else ()))
    assert r.returncode == 0, r.stderr
    return out


def test_inverse_refuses_the_result_of_a_sheet_with_another_pitch(tmp_path):
    """The defect: a 3 x 3 sheet of 20 mm cells solved, its result the target of the same grid with 25 mm cells
    (same node names, same node count). Refused at the result's cell_size_mm, nothing written."""
    res = _solved(tmp_path, _scene(cell=20.0, name="small"), "small")
    big = _write(tmp_path / "big.json", _scene(cell=25.0, name="big").to_json())
    out = tmp_path / "out"
    r = run_cli("inverse", big, "--target", res, "--out", str(out), *FAST)
    one_line_error(r, "target cell_size_mm")
    msg = r.stderr
    assert repr(res) in msg, msg                                   # the file
    assert "node N3,3's rest position (60, -60) mm differs from this scene's (75, -75) mm by 21.21 mm" in msg, msg
    assert "cell_size_mm 20 mm in the result, 25 mm in this scene" in msg, msg
    assert "another sheet" in msg and "1e-06 mm" in msg and "allowed:" in msg, msg
    assert not out.exists()


@pytest.mark.parametrize("half", ["json", "npz"])
def test_npz_result_of_another_pitch_is_refused(tmp_path, half):
    res = _solved(tmp_path, _scene(cell=20.0), "r", npz=True)
    path = res if half == "json" else res[:-5] + ".npz"
    with pytest.raises(TargetError) as e:
        load_target(_scene(cell=20.5), path)
    assert e.value.field == "cell_size_mm"
    assert repr(path) in e.value.message and "another sheet" in e.value.message
    assert load_target(_scene(cell=20.0), path).frames[0].nodes.idx.size == 16     # its own sheet: read


def test_renamed_copy_and_other_values_of_the_same_sheet_are_read(tmp_path):
    res = _solved(tmp_path, _scene(cell=20.0, name="original"), "orig")
    with open(res, encoding="utf-8") as fh:
        doc = json.load(fh)
    doc["scene"] = "renamed copy"
    copy = _write(tmp_path / "copy.json", json.dumps(doc))
    other = scene_with(Scene.grid(3, 3, cell_size_mm=20.0, hinge={"length_mm": 2.5}), [("H1,1", -0.3)])
    other.name = "inverse answer"
    for path in (res, copy):
        t = load_target(other, path)
        assert t.frames[0].nodes.idx.size == 16 and not t.info.get("warnings")
        assert np.allclose(t.frames[0].nodes.pos, [n["position_mm"] for n in doc["nodes"]])


def test_hand_written_position_targets_are_not_affected():
    big = _scene(cell=25.0)
    t = parse_target(big, {"nodes": [{"name": "N3,3", "position_mm": [60, -60, 0]},
                                     {"name": "N0,0", "position_mm": [0, 0, 0]}]})
    assert t.frames[0].nodes.idx.size == 2
    # a subset of a result's nodes copied into a target JSON (rotation_deg and D are read as they are)
    doc = planted_result(_scene(cell=20.0))
    t = parse_target(big, {"nodes": doc["nodes"][:5]})
    assert t.frames[0].nodes.idx.size == 5


def test_result_of_another_grid_shape_is_refused():
    """3 x 4 against 4 x 3 cells (20 nodes each): a node name the scene lacks is refused, as before."""
    doc = planted_result(scene_with(Scene.grid(3, 4), [("V0,1", 0.4)]))
    with pytest.raises(TargetError) as e:
        parse_target(scene_with(Scene.grid(4, 3), [("V0,1", 0.4)]), doc)
    assert "does not exist in this scene" in e.value.message


def test_result_without_cell_size_is_read_with_a_warning(tmp_path):
    """A result written before results carried cell_size_mm: its sheet cannot be told; read, with a warning
    (on the inverse command's stderr too)."""
    doc = planted_result(_scene(cell=20.0))
    doc.pop("cell_size_mm", None)
    old = _write(tmp_path / "old.json", json.dumps(doc))
    t = load_target(_scene(cell=20.0), old)
    assert len(t.info["warnings"]) == 1 and "cell_size_mm" in t.info["warnings"][0] \
        and repr(old) in t.info["warnings"][0]
    scene = _write(tmp_path / "s.json", _scene(cell=20.0).to_json())
    r = run_cli("inverse", scene, "--target", old, "--out", str(tmp_path / "out"), *FAST)
    assert r.returncode == 0, r.stderr
    assert "warning: " in r.stderr and r.stderr.count("has no cell_size_mm") == 1, r.stderr
    lines = r.stderr.splitlines()                      # said when the target is read, before the search
    said = next(i for i, l in enumerate(lines) if "has no cell_size_mm" in l)
    assert said == next(i for i, l in enumerate(lines) if "keyframe(s)" in l) + 1, r.stderr
    report = json.loads((tmp_path / "out" / "report.json").read_text(encoding="utf-8"))
    assert any("has no cell_size_mm" in w for w in report["warnings"]), report["warnings"]   # the GUI shows these


@pytest.mark.parametrize("value,words", [("20", "expected a number, got '20'"),
                                         (0, "outside the allowed range"), (None, "expected a number")])
def test_bad_cell_size_in_a_result_is_refused(value, words):
    doc = planted_result(_scene(cell=20.0))
    doc["cell_size_mm"] = value
    with pytest.raises(TargetError) as e:
        parse_target(_scene(cell=20.0), doc)
    assert e.value.field == "cell_size_mm" and words in e.value.message, e.value.message


def test_a_name_of_no_node_is_named_as_such_not_as_another_sheet():
    """'X3,3' is no node name: refused as that (the node list's check), not read as N3,3 of another cell size."""
    doc = planted_result(_scene(cell=20.0))
    doc["nodes"][-1]["name"] = "X" + doc["nodes"][-1]["name"][1:]
    with pytest.raises(TargetError) as e:
        parse_target(_scene(cell=25.0), doc)
    assert e.value.field != "cell_size_mm" and "X" in e.value.message, (e.value.field, e.value.message)
