"""``python -m metamaterial_wb inverse``: outputs, report fields, bad targets (exit 2, nothing written)."""
import json
import os
import subprocess
import sys

import numpy as np
import pytest

from inverse_helpers import planted_result, scene_with
from metamaterial_wb import REPO_DIR
from metamaterial_wb.core.scene import Scene


def _cli(*args):
    env = dict(os.environ, PYTHONPATH=REPO_DIR)
    return subprocess.run([sys.executable, "-m", "metamaterial_wb", "inverse", *map(str, args)],
                          capture_output=True, text=True, env=env, timeout=600)


@pytest.fixture(scope="module")
def planted(tmp_path_factory):
    d = tmp_path_factory.mktemp("inv")
    s = scene_with(Scene.grid(5, 5), [("H1,1", 0.6), ("V3,3", 0.7)])
    (d / "target.json").write_text(json.dumps(planted_result(s)))
    bare = s.to_dict()
    bare["actuators"] = []
    (d / "scene.json").write_text(json.dumps(bare))
    (d / "valued.json").write_text(json.dumps(dict(bare, actuators=[
        {"name": "a", "joint": "H1,1", "value": 0.0}, {"name": "b", "joint": "V3,3", "value": 0.0}])))
    return d


def test_search_writes_a_loadable_scene_report_and_picture(planted):
    out = planted / "out"
    p = _cli(planted / "scene.json", "--target", planted / "target.json", "--servos", 2, "--out", out)
    assert p.returncode == 0, p.stderr
    assert "inverse:" in p.stderr                                  # progress on stderr
    assert "it is no bound" not in p.stderr                        # an exact fit is at the bound, not below it
    s = Scene.load(out / "scene.json")
    assert {a.joint for a in s.actuators} == {"H1,1", "V3,3"}
    rep = json.loads((out / "report.json").read_text())
    for m in ("quadratic", "linear", "nonlinear"):
        assert rep["errors"][m]["rms_mm"] is not None and rep["errors"][m]["max_mm"] >= rep["errors"][m]["rms_mm"]
        assert len(rep["errors"][m]["per_node"]) == 36
    assert rep["errors"]["quadratic"]["max_mm"] < 1e-6
    # the physical models do not reach the quadratic model's optimum: the report says so honestly
    assert rep["errors"]["nonlinear"]["rms_mm"] > 1e-3
    vals = {p_["joint"]: p_["values"][0] for p_ in rep["placement"]}
    assert vals == pytest.approx({"H1,1": 0.6, "V3,3": 0.7}, abs=1e-6)
    assert rep["candidates_evaluated"]["fits"] >= 1 and rep["run_time_s"] > 0
    assert (out / "result.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    # the written scene solves to the target (a second, independent path: the solve command)
    from metamaterial_wb.core.models import run_model
    got = run_model("quadratic", s).positions_mm
    want = np.array([n["position_mm"] for n in json.loads((planted / "target.json").read_text())["nodes"]])
    assert np.abs(got - want).max() < 1e-6


def test_values_only_keeps_names_and_nonlinear_polish_lowers_the_nonlinear_error(planted):
    out = planted / "vo"
    p = _cli(planted / "valued.json", "--target", planted / "target.json", "--values-only", "--out", out,
             "--model", "nonlinear", "--evaluate", "quadratic,nonlinear", "--no-picture")
    assert p.returncode == 0, p.stderr
    rep = json.loads((out / "report.json").read_text())
    assert [a["name"] for a in rep["placement"]] == ["a", "b"]
    assert set(rep["errors"]) == {"quadratic", "nonlinear"}
    q = _cli(planted / "valued.json", "--target", planted / "target.json", "--values-only", "--out",
             planted / "vo2", "--evaluate", "nonlinear", "--no-picture")
    rep2 = json.loads((planted / "vo2" / "report.json").read_text())
    assert q.returncode == 0
    assert rep["errors"]["nonlinear"]["rms_mm"] < rep2["errors"]["nonlinear"]["rms_mm"]


@pytest.mark.parametrize("doc,words", [
    ({"format": "metamaterial-target"}, "empty"),
    ({"nodes": [{"name": "N0,0", "position_mm": [0, "NaN", 0]}]}, "number"),
    ({"nodes": [{"name": "N7,7", "position_mm": [0, 0, 0]}]}, "N7,7"),
    ({"folds": [{"joint": "H0,0", "fold_deg": 45}]}, "unreachable"),
])
def test_bad_targets_exit_2_and_write_nothing(planted, doc, words):
    bad = planted / "bad.json"
    bad.write_text(json.dumps(doc))
    out = planted / "never"
    p = _cli(planted / "scene.json", "--target", bad, "--servos", 2, "--out", out)
    assert p.returncode == 2 and words in p.stderr and "error" in p.stderr
    assert not out.exists()


def test_nan_literal_and_far_surface_exit_2(planted):
    bad = planted / "nan.json"
    bad.write_text('{"nodes": [{"name": "N0,0", "position_mm": [0, NaN, 0]}]}')
    p = _cli(planted / "scene.json", "--target", bad, "--servos", 2, "--out", planted / "never2")
    assert p.returncode == 2 and "NaN" in p.stderr and not (planted / "never2").exists()
    stl = planted / "far.stl"
    stl.write_text("solid f\n facet normal 0 0 1\n  outer loop\n   vertex 9000 0 0\n   vertex 9010 0 0\n"
                   "   vertex 9000 10 0\n  endloop\n endfacet\nendsolid f\n")
    p = _cli(planted / "scene.json", "--target", stl, "--servos", 2, "--out", planted / "never3")
    assert p.returncode == 2 and "from the flat sheet" in p.stderr and not (planted / "never3").exists()
