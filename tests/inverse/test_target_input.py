"""Target input is read like a scene: every number checked with its range, no field silently ignored; a bad
target is one line ``error: target FIELD: ...`` (exit 2, nothing written), never a traceback."""
import os
import subprocess
import sys

import pytest

from inverse_helpers import scene_with
from metamaterial_wb import REPO_DIR
from metamaterial_wb.core.errors import MetamaterialError
from metamaterial_wb.core.inverse.targets import load_target, parse_target
from metamaterial_wb.core.scene import Scene

N0 = {"name": "N0,0", "position_mm": [0, 0, 0]}
TRI = [[[0, 0, 0], [35, 0, 0], [0, 35, 0]]]


@pytest.fixture
def scene():
    return scene_with(Scene.grid(4, 4), [("H0,0", 0.5)])


@pytest.mark.parametrize("doc,field,words", [
    # D: every value checked, with its range
    ({"rotation_weight_mm": 1, "nodes": [dict(N0, rotation=[["x", 0, 0], [0, 1, 0], [0, 0, 1]])]},
     "nodes[0].rotation[0][0]", "expected a number, got 'x'"),
    ({"rotation_weight_mm": 1, "nodes": [dict(N0, rotation=[[1, 0], [0, 1, 0], [0, 0, 1]])]},
     "nodes[0].rotation", "3 x 3"),
    ({"surface": {"triangles": [[0, 0, 0]]}}, "surface.triangles[0][0]", "[x, y, z]"),
    ({"surface": {"triangles": "abc"}}, "surface.triangles", "non-empty list of triangles"),
    ({"surface": {"triangles": [[[0, 0, 0], [1, 0, 0], [0, "1", 0]]]}}, "surface.triangles[0][2][1]", "number"),
    ({"nodes": [dict(N0, weight=1e308)]}, "nodes[0].weight", "allowed range [0, 1000000]"),
    ({"nodes": [dict(N0, weight=-1)]}, "nodes[0].weight", "allowed range [0, 1000000]"),
    ({"nodes": [dict(N0, position_mm=[1e300, 0, 0])]}, "nodes[0].position_mm[0]",
     "1e+300 mm is outside the allowed range [-1000000, 1000000]"),
    ({"surface": {"triangles": [[[0, 0, 0], [2e6, 0, 0], [0, 35, 0]]]}}, "surface.triangles[0][1][0]",
     "allowed range [-1000000, 1000000]"),
    ({"rotation_weight_mm": 1e300, "nodes": [N0]}, "rotation_weight_mm", "allowed range"),
    ({"fold_weight_mm_per_deg": 1e300, "folds": [{"joint": "H0,0", "fold_deg": 0}]}, "fold_weight_mm_per_deg",
     "allowed range"),
    ({"nodes": [dict(N0, position_mm=[True, 0, 0])]}, "nodes[0].position_mm[0]", "expected a number"),
    # E: misspelt or misplaced fields are refused, naming what is allowed
    ({"surface": {"node": ["N0,0"], "triangles": TRI}}, "surface.node", "unknown field; allowed: file, nodes"),
    ({"nodes": [dict(N0, wieght=2)]}, "nodes[0].wieght", "unknown field; allowed:"),
    ({"folds": [{"joint": "H0,0", "fold_deg": 0, "wieght": 1}]}, "folds[0].wieght", "unknown field"),
    ({"period_s": -5, "nodes": [N0]}, "period_s", "without keyframes"),
    ({"period_s": 5, "nodes": [N0]}, "period_s", "without keyframes"),
    ({"time_s": -3, "nodes": [N0]}, "time_s", "-3 s is outside the allowed range [0, 1000000]"),
    ({"nodes": [{"i": 0, "j": True, "position_mm": [0, 0, 0]}]}, "nodes[0].j", "True; allowed: an integer 0..4"),
    ({"nodes": [{"i": 0, "position_mm": [0, 0, 0]}]}, "nodes[0].j", "missing"),
    ({"nodes": [{"name": "N1,1", "i": 0, "j": 0, "position_mm": [0, 0, 0]}]}, "nodes[0].i", "another node"),
    ({"keyframes": [{"time_s": 0, "nodes": [N0], "period_s": 2}]}, "keyframes[0].period_s", "unknown field"),
    ({"nodes": [N0], "keyframes": [{"time_s": 0, "nodes": [N0]}]}, "nodes", "unknown field"),
    ({"keyframes": [{"nodes": [N0]}], "period_s": -1}, "period_s", "allowed range"),
])
def test_bad_values_and_unknown_fields_name_the_field(scene, doc, field, words):
    with pytest.raises(MetamaterialError) as e:
        parse_target(scene, doc)
    assert e.value.field == field and words in str(e.value), str(e.value)


def test_node_by_row_and_column_and_result_nodes_are_read(scene):
    t = parse_target(scene, {"nodes": [{"i": 1, "j": 2, "position_mm": [1, 2, 3]}], "align": "none"})
    assert int(t.frames[0].nodes.idx[0]) == scene.topology.node_id(1, 2)
    # a solve result's node, copied as it is (its D and rotation_deg are not used)
    t = parse_target(scene, {"nodes": [{"i": 1, "j": 2, "name": "N1,2", "D": 0.1, "rotation_deg": 3,
                                        "position_mm": [1, 2, 3]}]})
    assert int(t.frames[0].nodes.idx[0]) == scene.topology.node_id(1, 2)
    t = parse_target(scene, {"surface": {"triangles": TRI, "nodes": ["N0,0", [1, 1]]}})
    assert t.frames[0].surface.idx.tolist() == [scene.topology.node_id(0, 0), scene.topology.node_id(1, 1)]


def test_target_file_is_read_like_a_scene(tmp_path, scene):
    bad = tmp_path / "big.json"
    bad.write_text('{"nodes": [{"name": "N0,0", "position_mm": [' + "1" * 5000 + ', 0, 0]}]}')
    with pytest.raises(MetamaterialError) as e:
        load_target(scene, str(bad))
    assert e.value.field == "nodes[0].position_mm[0]" and "digits" in str(e.value)
    deep = tmp_path / "deep.json"
    deep.write_text('{"nodes": ' + "[" * 200 + "]" * 200 + "}")
    with pytest.raises(MetamaterialError) as e:
        load_target(scene, str(deep))
    assert "too deeply nested" in str(e.value)


@pytest.mark.parametrize("text,words", [
    ('{"nodes": [{"name": "N0,0", "position_mm": [' + "1" * 5000 + ', 0, 0]}]}', "nodes[0].position_mm[0]"),
    ('{"nodes": [{"name": "N0,0", "position_mm": [1e300, 0, 0]}], "align": "none"}', "nodes[0].position_mm[0]"),
    ('{"nodes": [{"name": "N0,0", "position_mm": [0, 0, 0], "weight": 1e308}, '
     '{"name": "N0,1", "position_mm": [35, 0, 0], "weight": 1e308}]}', "nodes[0].weight"),
    ('{"rotation_weight_mm": 1, "nodes": [{"name": "N0,0", "position_mm": [0, 0, 0], '
     '"rotation": [[1, 0], [0, 1, 0], [0, 0, 1]]}]}', "nodes[0].rotation"),
    ('{"surface": {"triangles": [[0, 0, 0]]}}', "surface.triangles[0][0]"),
], ids=["5000-digit integer", "position 1e300", "weight 1e308", "ragged rotation", "triangle of one point"])
def test_cli_bad_target_values_exit_2_with_one_line(tmp_path, text, words):
    sc = tmp_path / "scene.json"
    sc.write_text(Scene.grid(4, 4).to_json())
    tgt = tmp_path / "target.json"
    tgt.write_text(text)
    env = dict(os.environ, PYTHONPATH=REPO_DIR)
    p = subprocess.run([sys.executable, "-m", "metamaterial_wb", "inverse", str(sc), "--target", str(tgt),
                        "--servos", "1", "--out", str(tmp_path / "out")], capture_output=True, text=True, env=env,
                       timeout=600)
    assert p.returncode == 2, p.stderr
    assert "Traceback" not in p.stderr and f"error: target {words}" in p.stderr, p.stderr
    assert not (tmp_path / "out").exists()
