"""The inverse answer is what the report says it is: ``scene.json`` solved by ``solve`` reproduces the reported fit
(the input's ``global_deformation`` is dropped, with a warning), the report names the values it describes when
``--model linear|nonlinear`` polished them (``polish``; the ``--model`` model is always evaluated), and ``--screen``
is refused with ``--values-only`` like the other search flags."""
import json
import os
import subprocess
import sys

import numpy as np
import pytest

from metamaterial_wb import REPO_DIR
from metamaterial_wb.core.scene import Scene

FISH = os.path.join(REPO_DIR, "examples", "fish.json")            # motors "head" on V0,1 and "tail" on V1,5
TAIL = os.path.join(REPO_DIR, "examples", "fish_tail_target.json")  # four keyframes; the search finds V0,1 + V1,5


def _run(command, *args):
    env = dict(os.environ, PYTHONPATH=REPO_DIR)
    return subprocess.run([sys.executable, "-m", "metamaterial_wb", command, *map(str, args)],
                          capture_output=True, text=True, env=env, timeout=600)


def _fish_with_global(tmp_path, g=0.5):
    with open(FISH, encoding="utf-8") as f:
        d = json.load(f)
    d["global_deformation"] = g
    path = tmp_path / "fish_g.json"
    path.write_text(json.dumps(d), encoding="utf-8")
    return path


def _target_frame0():
    with open(TAIL, encoding="utf-8") as f:
        t = json.load(f)
    return {n["name"]: np.array(n["position_mm"], dtype=float) for n in t["keyframes"][0]["nodes"]}


def _solved_distance(scene_path, result_path, alignment):
    """Largest distance (mm) from the target's first keyframe of ``scene_path`` solved by the ``solve`` command,
    its poses moved by the report's alignment of that keyframe."""
    p = _run("solve", scene_path, "--out", result_path)
    assert p.returncode == 0, p.stderr
    with open(result_path, encoding="utf-8") as f:
        res = json.load(f)
    sc, R, t = alignment["scale"], np.array(alignment["rotation"]), np.array(alignment["translation_mm"])
    want = _target_frame0()
    names = [n["name"] for n in res["nodes"] if n["name"] in want]
    assert len(names) == len(want)
    got = np.array([n["position_mm"] for n in res["nodes"] if n["name"] in want], dtype=float)
    got = sc * got @ R.T + t
    return float(np.max(np.linalg.norm(got - np.array([want[n] for n in names]), axis=1))), res


# ---- 1. the answer scene solves to the reported fit ----------------------------------------------------------
@pytest.mark.parametrize("mode", [("--servos", "2"), ("--values-only",)], ids=["search", "values-only"])
def test_answer_solves_to_the_reported_fit_without_the_inputs_global_deformation(tmp_path, mode):
    scene = _fish_with_global(tmp_path)
    out = tmp_path / "out"
    p = _run("inverse", scene, "--target", TAIL, *mode, "--out", out, "--fab-checks", "off", "--evaluate",
             "quadratic", "--no-picture")
    assert p.returncode == 0, p.stderr
    rep = json.loads((out / "report.json").read_text(encoding="utf-8"))
    frame0 = rep["errors"]["quadratic"]["per_frame"][0]
    assert frame0["max_mm"] < 1e-5                                   # the fit reaches the tail's first keyframe
    # the solve command of the written answer reproduces the reported fit (positions at keyframe 0)
    dist, res = _solved_distance(out / "scene.json", tmp_path / "solved.json", frame0["alignment"])
    assert dist <= frame0["max_mm"] + 1e-6, (dist, frame0["max_mm"])
    assert res["global_deformation"] is None
    written = json.loads((out / "scene.json").read_text(encoding="utf-8"))
    assert written.get("global_deformation") is None                # the servos act, not a global D
    assert any("global deformation" in w and "0.5" in w for w in rep["warnings"]), rep["warnings"]
    assert "global deformation" in p.stderr
    # the check tells: the same answer with the input's global deformation kept solves to every D = 0.5
    (tmp_path / "kept.json").write_text(json.dumps(dict(written, global_deformation=0.5)), encoding="utf-8")
    dist_kept, res_kept = _solved_distance(tmp_path / "kept.json", tmp_path / "kept_solved.json",
                                           frame0["alignment"])
    assert {n["D"] for n in res_kept["nodes"]} == {0.5}
    assert dist_kept > 1.0, dist_kept


def test_answer_of_a_scene_without_global_deformation_has_no_such_warning(tmp_path):
    out = tmp_path / "out"
    p = _run("inverse", FISH, "--target", TAIL, "--values-only", "--out", out, "--fab-checks", "off",
             "--evaluate", "quadratic", "--no-picture")
    assert p.returncode == 0, p.stderr
    rep = json.loads((out / "report.json").read_text(encoding="utf-8"))
    assert not any("global deformation" in w for w in rep["warnings"]), rep["warnings"]


# ---- 3. a lattice polish is reported; fit_cost_mm2 names the values it describes --------------------------------
def test_polish_is_reported_and_its_model_is_always_evaluated(tmp_path):
    from metamaterial_wb.core.inverse import evaluate as ev
    from metamaterial_wb.core.inverse import pipeline
    from metamaterial_wb.core.inverse.targets import load_target

    scene = Scene.load(FISH)
    target = load_target(scene, TAIL)
    run = pipeline.solve(scene, target, values_only=True, model="linear", evaluate=("quadratic",))
    rep = pipeline.report_dict(run, fit_model="linear")
    # the model the values were polished under is evaluated though --evaluate left it out, and the report says so
    assert set(rep["errors"]) == {"quadratic", "linear"}
    assert any("linear" in w and "--evaluate" in w for w in rep["warnings"]), rep["warnings"]
    pol = rep["polish"]
    assert pol["model"] == "linear"
    assert pol["cost_mm2"] <= pol["start_cost_mm2"]
    # the written values are the polished ones; the report's linear error describes them
    written = np.array([p["values"] for p in rep["placement"]]).T
    assert np.allclose(written, run.values)
    assert rep["errors"]["linear"]["cost_mm2"] <= pol["cost_mm2"] * (1 + 1e-6) + 1e-9
    # fit_cost_mm2 is the quadratic fit of the values before the polish (polish.fit_values) ...
    fit_values = np.array([p["values"] for p in pol["fit_values"]]).T
    assert [p["name"] for p in pol["fit_values"]] == [p["name"] for p in rep["placement"]]
    assert not np.allclose(fit_values, written)                    # the polish moved them
    before = ev.answer_scene(run.problem, run.joints, fit_values, run.names)
    q_before = ev.evaluate_model(run.problem, before, fit_values, "quadratic",
                                 alignments=ev.fit_alignments(run.fit))["cost_mm2"]
    assert q_before <= rep["fit_cost_mm2"] * (1 + 1e-9) + 1e-12   # docs: "this or lower" for the values it names
    # ... and not of the written values (their quadratic error is what errors.quadratic reports)
    assert rep["errors"]["quadratic"]["cost_mm2"] > rep["fit_cost_mm2"]


def test_quadratic_answer_has_no_polish_and_fit_cost_bounds_the_quadratic_error(tmp_path):
    from metamaterial_wb.core.inverse import pipeline
    from metamaterial_wb.core.inverse.targets import load_target

    scene = Scene.load(FISH)
    run = pipeline.solve(scene, load_target(scene, TAIL), values_only=True, evaluate=("quadratic",))
    rep = pipeline.report_dict(run)
    assert rep["polish"] is None
    assert rep["errors"]["quadratic"]["cost_mm2"] <= rep["fit_cost_mm2"] * (1 + 1e-9) + 1e-12
    assert not any("--evaluate" in w for w in rep["warnings"]), rep["warnings"]


# ---- 8a. --screen is a search flag ----------------------------------------------------------------------------
def test_screen_with_values_only_is_refused_and_nothing_written(tmp_path):
    out = tmp_path / "out"
    p = _run("inverse", FISH, "--target", TAIL, "--values-only", "--screen", 500, "--out", out,
             "--fab-checks", "off", "--evaluate", "quadratic", "--no-picture")
    assert p.returncode == 2, (p.returncode, p.stderr)
    last = p.stderr.strip().splitlines()[-1]
    assert last.startswith("error: --screen") and "500 with --values-only" in last, p.stderr
    assert "allowed: only without --values-only" in last
    assert not out.exists()
