"""The answer scene ``inverse`` writes: every actuator field kept with ``--values-only``, servo housings that
follow their servos, and a ``--hinges`` answer that loads and solves like any scene (docs/inverse.md)."""
import json
import os
import subprocess
import sys

import pytest

from inverse_helpers import planted_result, scene_with
from metamaterial_wb import REPO_DIR
from metamaterial_wb.core.inverse import evaluate as ev
from metamaterial_wb.core.inverse import pipeline
from metamaterial_wb.core.inverse.targets import parse_target
from metamaterial_wb.core.models import run_model
from metamaterial_wb.core.scene import Scene

FISH = os.path.join(REPO_DIR, "examples", "fish_axes.json")
G5 = {"format": "metamaterial-scene", "version": 1, "name": "g5", "cell_size_mm": 35,
      "hinge": {"length_mm": 9.5, "width_mm": 0.8, "thickness_mm": 3}, "layout": {"grid": [5, 5]},
      "axes": [{"name": "a", "direction": "vertical", "line": 2, "fold_deg": 30}],
      "actuators": [{"name": "p", "joint": "V0,0", "value": 0.7,
                     "servo": {"channel": 3, "invert": True, "trim_deg": 2.5},
                     "profile": {"shape": "sine", "amplitude": 0.5, "frequency_hz": 1.0, "phase_deg": 0}},
                    {"name": "q", "joint": "H4,4", "value": -0.4, "note": "left flipper"}]}


def _cli(*args):
    env = dict(os.environ, PYTHONPATH=REPO_DIR)
    return subprocess.run([sys.executable, "-m", "metamaterial_wb", *map(str, args)], capture_output=True, text=True,
                          env=env, timeout=600)


def _result(scene, g=None):
    from metamaterial_wb.cli.solve import result_dict
    return result_dict(scene, run_model("quadratic", scene, global_deformation=g), g, "quadratic")


# ---- A: --values-only keeps every field of the scene's actuators --------------------------------------------
def test_values_only_keeps_the_servo_channel_profile_and_other_fields(tmp_path):
    (tmp_path / "scene.json").write_text(json.dumps(G5))
    (tmp_path / "target.json").write_text(json.dumps(_result(Scene.from_dict(G5))))
    p = _cli("inverse", tmp_path / "scene.json", "--target", tmp_path / "target.json", "--values-only",
             "--out", tmp_path / "out", "--no-picture", "--fab-checks", "off", "--evaluate", "quadratic")
    assert p.returncode == 0, p.stderr
    acts = json.loads((tmp_path / "out" / "scene.json").read_text())["actuators"]
    for got, want in zip(acts, G5["actuators"]):
        assert got["value"] == pytest.approx(want["value"], abs=1e-6)
        assert {k: v for k, v in got.items() if k != "value"} == {k: v for k, v in want.items() if k != "value"}


def test_values_only_keyframes_replace_only_value_and_profile():
    s = Scene.from_dict(G5)
    frames = []
    for t, (vp, vq) in enumerate(((0.7, -0.4), (0.2, 0.5))):
        d = json.loads(json.dumps(G5))
        d["actuators"][0]["value"], d["actuators"][1]["value"] = vp, vq
        frames.append({"time_s": t, "nodes": _result(Scene.from_dict(d))["nodes"]})
    target = parse_target(s, {"keyframes": [{"time_s": f["time_s"], "nodes": [
        {"name": n["name"], "position_mm": n["position_mm"]} for n in f["nodes"]]} for f in frames], "period_s": 3})
    run = pipeline.solve(s, target, values_only=True, evaluate=("quadratic",))
    a, b = run.scene.to_dict()["actuators"]
    assert a["servo"] == G5["actuators"][0]["servo"] and b["note"] == "left flipper"
    assert a["profile"]["shape"] == "keyframes" and a["profile"]["period_s"] == 3
    assert a["profile"]["values"] == pytest.approx([0.7, 0.2], abs=1e-6)
    assert b["profile"]["values"] == pytest.approx([-0.4, 0.5], abs=1e-6)


# ---- B: servo housings follow their servos ------------------------------------------------------------------
def test_housings_move_with_the_servos_and_build_accepts_them(tmp_path):
    planted = scene_with(FISH, [("H2,0", -0.5), ("V0,4", 0.6)])
    (tmp_path / "target.json").write_text(json.dumps(planted_result(planted)))
    out = tmp_path / "out"
    p = _cli("inverse", FISH, "--target", tmp_path / "target.json", "--servos", 2, "--out", out, "--no-picture",
             "--fab-checks", "parameters", "--evaluate", "quadratic")
    assert p.returncode == 0, p.stderr
    d = json.loads((out / "scene.json").read_text())
    servo_joints = {a["joint"] for a in d["actuators"]}
    assert servo_joints == {"H2,0", "V0,4"}
    housings = {m["name"]: m["joint"] for m in d["modules"] if m["type"] == "servo_housing"}
    assert set(housings.values()) == servo_joints and set(housings) == {"servo_head", "servo_tail"}
    hubs = [m["joint"] for m in d["modules"] if m["type"] == "stable_hub"]
    assert hubs == ["H0,3", "H2,3"]                                  # other modules stay where they are
    rep = json.loads((out / "report.json").read_text())
    assert any("servo_head" in w and "moved" in w for w in rep["warnings"])
    assert "moved from V0,1" in p.stderr
    assert "modules" in " ".join(rep["fabrication"]["checks_run"]) and rep["printable"] is not False


def test_a_housing_that_fits_no_new_servo_is_dropped_with_a_warning():
    d = Scene.load(FISH).to_dict()
    mods, notes = ev.move_housings(d, ["V0,1", "V1,5"], ["H0,2", "V0,4"])     # H0,2 is tilted (axis)
    housings = [m for m in mods if m["type"] == "servo_housing"]
    assert [(m["name"], m["joint"]) for m in housings] == [("servo_head", "V0,4")]
    assert len(mods) == len(d["modules"]) - 1
    dropped = [n for n in notes if "dropped" in n]
    assert len(dropped) == 1 and "servo_tail" in dropped[0] and "H0,2" in dropped[0] and "tilted" in dropped[0]


def test_a_module_check_problem_refuses_the_move():
    d = Scene.load(FISH).to_dict()

    def check(scene):
        bad = [m["name"] for m in scene.to_dict().get("modules", []) if m.get("joint") == "V0,4"]
        return f"{bad[0]} collides" if bad else None

    mods, notes = ev.move_housings(d, ["V0,1", "V1,5"], ["V0,4", "H2,0"], module_check=check)
    assert sorted(m["joint"] for m in mods if m["type"] == "servo_housing") == ["H2,0"]
    assert any("dropped" in n and "collides" in n for n in notes)


# ---- C: --hinges answers load, solve, and are compared honestly ---------------------------------------------
def test_hinge_answer_loads_solves_and_reports_its_own_cost(tmp_path):
    g5 = dict(G5, actuators=[{"name": "p", "joint": "V0,0", "value": 0.7}, {"name": "q", "joint": "H4,4",
                                                                           "value": -0.4}])
    (tmp_path / "scene.json").write_text(json.dumps(g5))
    (tmp_path / "target.json").write_text(json.dumps(_result(Scene.from_dict(g5), 0.8)))
    out = tmp_path / "out"
    p = _cli("inverse", tmp_path / "scene.json", "--target", tmp_path / "target.json", "--servos", 2, "--hinges",
             "--out", out, "--no-picture", "--fab-checks", "off", "--evaluate", "quadratic")
    assert p.returncode == 0, p.stderr
    q = _cli("solve", out / "scene.json", "--out", tmp_path / "solved.json")
    assert q.returncode == 0, q.stderr                                  # the written scene loads and solves
    rep = json.loads((out / "report.json").read_text())
    # the kept answer's fit cost is the cost of the scene written (its own rotation limits)
    assert rep["fit_cost_mm2"] == pytest.approx(rep["errors"]["quadratic"]["cost_mm2"], rel=1e-6)
    # and no worse than the answer without --hinges
    r = _cli("inverse", tmp_path / "scene.json", "--target", tmp_path / "target.json", "--servos", 2,
             "--out", tmp_path / "plain", "--no-picture", "--fab-checks", "off", "--evaluate", "quadratic")
    assert r.returncode == 0, r.stderr
    plain = json.loads((tmp_path / "plain" / "report.json").read_text())
    assert rep["errors"]["quadratic"]["cost_mm2"] <= plain["errors"]["quadratic"]["cost_mm2"] * (1 + 1e-9)
    assert any("--hinges" in w for w in rep["warnings"])                # the full fitted sizes broke axis a


# ---- C: the servo channels of replaced motors go to the new servos --------------------------------------------
def test_new_servos_take_the_replaced_motors_servo_channels():
    """A new servo had no ``servo`` object while the motor it replaced was wired to channel 3 (trim, invert): the
    answer streamed on another channel than the wiring (found in session 25, mended in 26)."""
    from types import SimpleNamespace
    problem = SimpleNamespace(scene=Scene.from_dict(G5), target=SimpleNamespace(frames=[None], period_s=None))
    notes = []
    s = ev.answer_scene(problem, ["V2,0", "H4,4"], [[0.3, -0.2]], names=["s1", "q"], warnings=notes)
    a = {x["name"]: x for x in s.to_dict()["actuators"]}
    assert a["s1"]["servo"] == G5["actuators"][0]["servo"]          # p's wiring, now on V2,0
    assert a["q"]["note"] == "left flipper" and "servo" not in a["q"]  # kept motor: its own fields only
    assert any("channel 3" in n and "s1" in n for n in notes), notes
