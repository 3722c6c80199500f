"""Target fields that used to slip through: ``version``, the weights of a frame without the term they weigh,
rotations at ``rotation_weight_mm`` 0, and ``solve`` results written with ``--npz`` / ``--fields`` or not
converged. Each is read or refused with one error naming the field, the value and what is allowed."""
import glob
import json
import os
import subprocess
import sys

import numpy as np
import pytest

from inverse_helpers import planted_result, scene_with
from metamaterial_wb import REPO_DIR
from metamaterial_wb.core.errors import MetamaterialError
from metamaterial_wb.core.inverse.targets import load_target, parse_target
from metamaterial_wb.core.scene import Scene

N0 = {"name": "N0,0", "position_mm": [0, 0, 0]}
EYE = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]
FOLD0 = {"joint": "H0,0", "fold_deg": 0}
ENV = dict(os.environ, PYTHONPATH=REPO_DIR)


@pytest.fixture
def scene():
    return scene_with(Scene.grid(4, 4), [("H0,0", 0.5)])


def _refused(scene, doc):
    with pytest.raises(MetamaterialError) as e:
        parse_target(scene, doc)
    return e.value


# -- defect 4: version and the weights are checked whether or not their term is present --------------------------

@pytest.mark.parametrize("doc,field,words", [
    ({"format": "metamaterial-target", "version": "banana", "nodes": [N0]}, "version", "'banana'; allowed: 1"),
    ({"version": 2, "nodes": [N0]}, "version", "2; allowed: 1"),
    ({"version": True, "nodes": [N0]}, "version", "True; allowed: 1"),
    ({"version": 2, "keyframes": [{"nodes": [N0]}]}, "version", "allowed: 1"),
    # fold weight without folds (the audit's "heavy" and 0), and out of range with them
    ({"fold_weight_mm_per_deg": "heavy", "nodes": [N0]}, "fold_weight_mm_per_deg", "expected a number, got 'heavy'"),
    ({"fold_weight_mm_per_deg": 0, "nodes": [N0]}, "fold_weight_mm_per_deg",
     "0 mm/deg is outside the allowed range (0, 1000000]"),
    ({"fold_weight_mm_per_deg": -1, "folds": [FOLD0]}, "fold_weight_mm_per_deg", "allowed range (0, 1000000]"),
    # rotation weight without nodes
    ({"rotation_weight_mm": -1, "folds": [FOLD0]}, "rotation_weight_mm",
     "-1 mm is outside the allowed range [0, 1000000]"),
    ({"rotation_weight_mm": "x", "surface": {"triangles": [[[0, 0, 0], [35, 0, 0], [0, 35, 0]]]}},
     "rotation_weight_mm", "expected a number, got 'x'"),
    # shared (top) weights of keyframes are named at the top, a keyframe's own with its keyframe
    ({"fold_weight_mm_per_deg": 0, "keyframes": [{"nodes": [N0]}]}, "fold_weight_mm_per_deg", "(0, 1000000]"),
    ({"keyframes": [{"nodes": [N0]}, {"nodes": [N0], "fold_weight_mm_per_deg": 0}]},
     "keyframes[1].fold_weight_mm_per_deg", "(0, 1000000]"),
    ({"rotation_weight_mm": 2e6, "keyframes": [{"folds": [FOLD0]}]}, "rotation_weight_mm", "[0, 1000000]"),
    ({"keyframes": [{"folds": [FOLD0], "rotation_weight_mm": -2}]}, "keyframes[0].rotation_weight_mm",
     "[0, 1000000]"),
])
def test_version_and_weights_are_checked_without_their_term(scene, doc, field, words):
    err = _refused(scene, doc)
    assert err.field == field and words in str(err), (err.field, str(err))


def test_version_1_or_absent_and_weights_in_range_are_read(scene):
    for doc in ({"version": 1, "nodes": [N0]}, {"nodes": [N0]},
                {"format": "metamaterial-target", "version": 1, "fold_weight_mm_per_deg": 3, "nodes": [N0]},
                {"rotation_weight_mm": 0, "fold_weight_mm_per_deg": 1e6, "folds": [FOLD0]}):
        assert len(parse_target(scene, doc).frames) == 1


# -- defect 7: rotations that rotation_weight_mm 0 would ignore ---------------------------------------------------

@pytest.mark.parametrize("doc,field", [
    ({"nodes": [dict(N0, rotation=EYE), {"name": "N0,1", "position_mm": [35, 0, 0], "rotation": EYE}]},
     "rotation_weight_mm"),
    ({"rotation_weight_mm": 0, "nodes": [N0, {"name": "N0,1", "position_mm": [35, 0, 0], "rotation": EYE}]},
     "rotation_weight_mm"),
    ({"keyframes": [{"nodes": [N0]}, {"nodes": [dict(N0, rotation=EYE)]}]}, "keyframes[1].rotation_weight_mm"),
])
def test_rotations_at_rotation_weight_0_are_refused(scene, doc, field):
    err = _refused(scene, doc)
    msg = str(err)
    assert err.field == field, (err.field, msg)
    assert "rotations given but rotation_weight_mm is 0: they would be ignored" in msg, msg
    assert "allowed: a weight in (0, 1000000] mm per radian, or drop rotation" in msg, msg


def test_rotations_with_a_weight_and_copied_result_nodes_are_read(scene):
    t = parse_target(scene, {"rotation_weight_mm": 5, "nodes": [dict(N0, rotation=EYE)], "align": "none"})
    assert t.frames[0].nodes.rot_weight_mm == 5 and t.frames[0].nodes.rot.shape == (1, 3, 3)
    # a solve result's nodes list copied as it is (docs/inverse.md): its rotation comes with rotation_deg, unused
    t = parse_target(scene, {"nodes": planted_result(scene)["nodes"]})
    assert t.frames[0].nodes.rot is None and len(t.frames[0].nodes.idx) == scene.topology.n_nodes


# -- defects 5 and 6: solve results written with --npz / --fields, or not converged ------------------------------

def _solve(tmp_path, name, *extra, example=None):
    sc = example or str(tmp_path / "scene.json")
    if example is None and not os.path.exists(sc):
        with open(sc, "w", encoding="utf-8") as f:
            f.write(scene_with(Scene.grid(4, 4), [("H0,0", 0.5)]).to_json())
    out = str(tmp_path / name)
    p = subprocess.run([sys.executable, "-m", "metamaterial_wb", "solve", sc, "--out", out, *extra],
                       capture_output=True, text=True, env=ENV, timeout=600)
    return p, out


def test_npz_result_is_a_target_with_the_positions_of_its_arrays(tmp_path, scene):
    p, full = _solve(tmp_path, "full.json")
    assert p.returncode == 0, p.stderr
    p, half = _solve(tmp_path, "resN.json", "--npz")
    assert p.returncode == 0, p.stderr
    with open(half, encoding="utf-8") as f:
        assert "nodes" not in json.load(f)           # the per-node data is in resN.npz
    ref = load_target(scene, full).frames[0].nodes
    for path in (half, str(tmp_path / "resN.npz")):   # the JSON half, and the .npz itself
        got = load_target(scene, path).frames[0].nodes
        assert got.idx.tolist() == ref.idx.tolist() and len(got.idx) == scene.topology.n_nodes
        assert np.allclose(got.pos, ref.pos) and got.rot is None
    os.remove(str(tmp_path / "resN.npz"))
    with pytest.raises(MetamaterialError) as e:
        load_target(scene, half)
    assert "resN.npz" in str(e.value) and "missing" in str(e.value), str(e.value)


@pytest.mark.parametrize("fields,npz", [("D", False), ("joints", False), ("D,joints", True)])
def test_result_without_poses_names_its_fields(tmp_path, scene, fields, npz):
    p, out = _solve(tmp_path, "r.json", "--fields", fields, *(["--npz"] if npz else []))
    assert p.returncode == 0, p.stderr
    with pytest.raises(MetamaterialError) as e:
        load_target(scene, out)
    msg = str(e.value)
    assert f"written with --fields {fields}; node positions need --fields poses (or all)" in msg, msg
    assert "r.json" in msg and "got None" not in msg, msg


def test_cli_result_without_poses_exit_2_one_line(tmp_path):
    p, out = _solve(tmp_path, "resD.json", "--fields", "D")
    assert p.returncode == 0, p.stderr
    q = subprocess.run([sys.executable, "-m", "metamaterial_wb", "inverse", str(tmp_path / "scene.json"),
                        "--target", out, "--servos", "1", "--out", str(tmp_path / "inv")],
                       capture_output=True, text=True, env=ENV, timeout=600)
    assert q.returncode == 2, q.stderr
    assert "Traceback" not in q.stderr and "written with --fields D; node positions need --fields poses" in q.stderr
    assert not (tmp_path / "inv").exists()


def test_non_converged_result_is_refused(tmp_path, scene):
    res = planted_result(scene)
    res["converged"] = False
    with pytest.raises(MetamaterialError) as e:
        parse_target(scene, res)
    assert e.value.field == "converged" and "did not converge" in str(e.value), str(e.value)
    path = tmp_path / "nc.json"
    path.write_text(json.dumps(res), encoding="utf-8")
    with pytest.raises(MetamaterialError) as e:
        load_target(scene, str(path))
    assert "nc.json" in str(e.value) and "did not converge" in str(e.value), str(e.value)
    res["converged"] = True                                 # the same file, converged: read
    path.write_text(json.dumps(res), encoding="utf-8")
    assert len(load_target(scene, str(path)).frames[0].nodes.idx) == scene.topology.n_nodes


def test_non_converged_solve_output_is_refused(tmp_path):
    grid_fold = os.path.join(REPO_DIR, "examples", "grid_fold.json")
    p, out = _solve(tmp_path, "nc.json", "--model", "nonlinear", "--option", "max_iter=1", "--option",
                    "load_steps=1", "--option", "fallback=false", example=grid_fold)
    assert p.returncode == 1, p.stderr                      # the solve says it did not converge
    with open(out, encoding="utf-8") as f:
        assert json.load(f)["converged"] is False
    with pytest.raises(MetamaterialError) as e:
        load_target(Scene.load(grid_fold), out)
    assert "nc.json" in str(e.value) and "did not converge" in str(e.value), str(e.value)


# -- the bundled targets still load -------------------------------------------------------------------------------

def test_bundled_target_files_load():
    files = sorted(glob.glob(os.path.join(REPO_DIR, "examples", "*target*.json")))
    assert len(files) >= 3
    for path in files:
        scene_name = os.path.basename(path).split("_")[0]
        scene = Scene.load(os.path.join(REPO_DIR, "examples", scene_name + ".json"))
        t = load_target(scene, path)
        assert t.frames and all(f.has_positions for f in t.frames), path
