"""``python -m metamaterial_wb inverse``: the words of its refusals and what it writes, on the bundled examples
(from an audit). A folder given as ``--target`` is named as a folder; ``--servos`` out of range quotes the
scene's own range (joints without a shared node), not the number of joints; a fold range or a dropped global
deformation is printed without a negative zero, and the answer scene holds no -0.0; node targets in other units
than mm (metres) are refused as surfaces far from the sheet are; a ``solve`` result of another sheet (another node
count) is refused, a renamed copy's result is a target; ``--servos`` / ``--screen`` / ``--workers`` are read
strictly (no ``1_0``, no non-ASCII digits)."""
import json
import math
import os
import re
import subprocess
import sys

import numpy as np
import pytest

from metamaterial_wb import REPO_DIR
from clihelpers import one_line_error, run_cli

EX = os.path.join(REPO_DIR, "examples")
FISH = os.path.join(EX, "fish.json")
WORM = os.path.join(EX, "worm.json")
GRID = os.path.join(EX, "grid_fold.json")
TAIL = os.path.join(EX, "fish_tail_target.json")
GAIT = os.path.join(EX, "worm_gait_target.json")
QUICK = ("--evaluate", "quadratic", "--fab-checks", "off", "--no-picture")


def cli(*args):
    return run_cli("inverse", *args, timeout=600)


def last_line_error(r, field):
    """The error after the progress lines (the servo range is checked by the search, after the target is read)."""
    assert r.returncode == 2, (r.stdout, r.stderr)
    last = r.stderr.strip().splitlines()[-1]
    assert last.startswith(f"error: {field}: "), r.stderr
    assert "Traceback" not in r.stderr
    return last


def _write(path, doc):
    with open(path, "w", encoding="utf-8") as f:
        json.dump(doc, f)
    return str(path)


def _read(path):
    with open(path, encoding="utf-8") as f:
        return json.load(f)


def _solve(scene, out):
    r = subprocess.run([sys.executable, "-m", "metamaterial_wb", "solve", scene, "--out", str(out)], cwd=REPO_DIR,
                       capture_output=True, text=True, timeout=600, env=dict(os.environ, PYTHONPATH=REPO_DIR))
    assert r.returncode == 0, r.stderr
    return str(out)


def test_a_folder_as_target_is_named_a_folder(tmp_path):
    out = tmp_path / "out"
    r = cli(FISH, "--target", EX, "--servos", 2, "--out", out, *QUICK)
    one_line_error(r, "--target")
    assert "folder" in r.stderr and EX in r.stderr, r.stderr
    assert ".json" in r.stderr and ".stl" in r.stderr, r.stderr          # what is expected instead
    assert "mesh type" not in r.stderr, r.stderr
    assert not out.exists()


def test_servos_out_of_range_quotes_the_scenes_range(tmp_path):
    out = tmp_path / "out"
    r = cli(FISH, "--target", TAIL, "--servos", 0, "--out", out, *QUICK)
    err = last_line_error(r, "--servos")
    assert "[1, 10]" in err, r.stderr                  # the fish takes at most 10 servos (no shared node)
    assert "32" not in err, r.stderr                   # its number of joints is not the limit (the error line
                                                       # only: the progress lines name the target's path)
    r = cli(FISH, "--target", TAIL, "--servos", 11, "--out", out, *QUICK)
    last_line_error(r, "--servos")
    assert "11" in r.stderr and "[1, 10]" in r.stderr, r.stderr
    assert not out.exists()


def test_the_range_of_an_untilted_joint_has_no_negative_zero(tmp_path):
    from metamaterial_wb.core.inverse.targets import fold_ranges_deg
    from metamaterial_wb.core.scene import Scene

    lo, hi = fold_ranges_deg(Scene.load(FISH))
    assert not np.any(np.signbit(lo[lo == 0])) and not np.any(np.signbit(hi[hi == 0]))
    t = _write(tmp_path / "fold.json", {"format": "metamaterial-target", "folds": [{"joint": "H0,1", "fold_deg": 5}]})
    r = cli(FISH, "--target", t, "--servos", 1, "--out", tmp_path / "out", *QUICK)
    one_line_error(r, "target folds[0].fold_deg")
    assert "[0, 0] deg" in r.stderr and "-0" not in r.stderr, r.stderr


def test_no_negative_zero_in_the_answer_scene_or_its_warnings(tmp_path):
    from metamaterial_wb.core.inverse.evaluate import round_value

    assert not math.copysign(1.0, round_value(-0.0)) < 0
    d = _read(FISH)
    d["global_deformation"] = -0.0
    scene = _write(tmp_path / "fish.json", d)
    t = _read(TAIL)
    t["keyframes"][0]["time_s"] = -0.0
    target = _write(tmp_path / "tail.json", t)
    out = tmp_path / "out"
    r = cli(scene, "--target", target, "--servos", 2, "--out", out, *QUICK)
    assert r.returncode == 0, r.stderr
    assert "global deformation (0)" in r.stderr and "(-0)" not in r.stderr and "D = -0" not in r.stderr, r.stderr
    text = (out / "scene.json").read_text(encoding="utf-8")
    assert not re.search(r"(?<![0-9eE.])-0\.0(?![0-9])", text), text
    ans = json.loads(text)
    assert all(a["profile"]["times_s"][0] == 0 and not math.copysign(1.0, a["profile"]["times_s"][0]) < 0
               for a in ans["actuators"])
    rep = (out / "report.json").read_text(encoding="utf-8")
    assert "(-0)" not in rep


def _in_metres(doc):
    for fr in doc.get("keyframes", [doc]):
        for n in fr.get("nodes", []):
            n["position_mm"] = [x / 1000 for x in n["position_mm"]]
    return doc


def test_node_targets_in_metres_are_refused_like_a_far_surface(tmp_path):
    out = tmp_path / "out"
    t = _write(tmp_path / "gait_m.json", _in_metres(_read(GAIT)))
    r = cli(WORM, "--target", t, "--servos", 2, "--out", out, *QUICK)
    one_line_error(r, "target keyframes[0].nodes")
    assert "mm" in r.stderr and "units" in r.stderr, r.stderr
    assert not out.exists()
    one = _read(TAIL)["keyframes"][1]                 # a single frame: the field is nodes
    t = _write(tmp_path / "one_m.json", _in_metres(dict(one, format="metamaterial-target")))
    r = cli(FISH, "--target", t, "--servos", 2, "--out", out, *QUICK)
    one_line_error(r, "target nodes")
    # the same shape with align: similarity fits its scale: not refused
    from metamaterial_wb.core.inverse.targets import load_target, parse_target
    from metamaterial_wb.core.scene import Scene
    fish = Scene.load(FISH)
    doc = _in_metres(dict(one, format="metamaterial-target", align="similarity"))
    assert parse_target(fish, doc).frames[0].align == "similarity"
    # the bundled targets (in mm) still load
    assert len(load_target(fish, TAIL).frames) == 4
    assert len(load_target(Scene.load(WORM), GAIT).frames) == 4


def test_a_result_of_another_sheet_is_refused_by_its_nodes(tmp_path):
    res = _solve(FISH, tmp_path / "fish_result.json")     # 21 nodes N0,0 .. N2,6: every one is in grid_fold too
    out = tmp_path / "out"
    r = cli(GRID, "--target", res, "--servos", 2, "--out", out, *QUICK)
    one_line_error(r, "target nodes")
    assert "21" in r.stderr and "35" in r.stderr and "'fish'" in r.stderr, r.stderr
    assert not out.exists()
    # the scene's own result is still a target
    r = cli(FISH, "--target", res, "--servos", 2, "--out", out, *QUICK)
    assert r.returncode == 0, r.stderr


def test_a_result_of_a_renamed_copy_is_a_target(tmp_path):
    # an inverse answer is the scene under a new name (fish_tail_inverse): its solved result is a target of the
    # original scene (a review found the name check refused it)
    d = _read(_solve(FISH, tmp_path / "fish_result.json"))
    d["scene"] = "fish_tail_inverse"
    out = tmp_path / "out"
    r = cli(FISH, "--target", _write(tmp_path / "renamed.json", d), "--servos", 2, "--out", out, *QUICK)
    assert r.returncode == 0, r.stderr


@pytest.mark.parametrize("flag,value", [("--servos", "1_0"), ("--servos", "\u0661"), ("--screen", "1_2"),
                                        ("--workers", "\u0662"), ("--servos", "2.0")])
def test_integer_flags_are_read_strictly(tmp_path, flag, value):
    out = tmp_path / "out"
    args = [FISH, "--target", TAIL, "--out", out, *QUICK]
    if flag != "--servos":
        args += ["--servos", 2]
    r = cli(*args, flag, value)
    assert r.returncode == 2, r.stderr
    assert flag in r.stderr and "Traceback" not in r.stderr, r.stderr
    assert "inverse:" not in r.stderr.replace("inverse: error", ""), r.stderr    # refused before any work
    assert not out.exists()
