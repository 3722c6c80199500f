"""The command line end to end: real subprocesses for the main paths, in-process for the corpus."""
import json
import math
import os
import subprocess
import sys

import numpy as np
import pytest

from metamaterial_wb import REPO_DIR, example_path
from metamaterial_wb.cli import main

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "data"))
from malformed_scenes import CORPUS  # noqa: E402

PY = sys.executable


def run_cli(*args):
    return subprocess.run([PY, "-m", "metamaterial_wb", *args], cwd=REPO_DIR, capture_output=True, text=True,
                          timeout=300)


def test_solve_fish_end_to_end(tmp_path):
    out = tmp_path / "fish.json"
    r = run_cli("solve", example_path("fish"), "--out", str(out))
    assert r.returncode == 0, r.stderr
    res = json.loads(out.read_text())
    assert len(res["nodes"]) == 21  # 3 x 7 nodes
    for n in res["nodes"]:
        assert {"i", "j", "D", "position_mm", "rotation"} <= set(n)
        assert len(n["position_mm"]) == 3
        R = np.array(n["rotation"])
        assert np.allclose(R @ R.T, np.eye(3), atol=1e-12)
    assert isinstance(res["warnings"], list) and "solve_s" in res["timings"]
    scene = json.load(open(example_path("fish")))
    by = {(n["i"], n["j"]): n for n in res["nodes"]}
    for a in scene["actuators"]:
        kind, ij = a["joint"][0], tuple(int(x) for x in a["joint"][1:].split(","))
        other = (ij[0], ij[1] + 1) if kind == "H" else (ij[0] + 1, ij[1])
        assert by[ij]["D"] == a["value"] and by[other]["D"] == a["value"]


def test_set_and_global(tmp_path):
    out = tmp_path / "r.json"
    r = run_cli("solve", example_path("worm"), "--out", str(out), "--set", "front=0.5", "--set", "rear=-0.5")
    assert r.returncode == 0, r.stderr
    res = json.loads(out.read_text())
    D = {(n["i"], n["j"]): n["D"] for n in res["nodes"]}
    assert D[(0, 8)] == 0.5 and D[(0, 0)] == -0.5
    # antisymmetric actuation of a symmetric chain: the middle stays at 0
    assert abs(D[(0, 4)]) < 1e-12
    r = run_cli("solve", example_path("worm"), "--out", str(out), "--global", "0.25")
    assert r.returncode == 0, r.stderr
    res = json.loads(out.read_text())
    assert all(n["D"] == 0.25 for n in res["nodes"])
    # uniform D: every node rotates by the same magnitude, alternating sign (seed's sign rule)
    for n in res["nodes"]:
        sign = 1 if (n["i"] + n["j"]) % 2 == 0 else -1
        assert math.copysign(1, n["rotation_deg"]) == sign


@pytest.mark.parametrize("args,needle", [
    (["--set", "nope=0.5"], "nope"),
    (["--set", "front=2"], "front"),
    (["--set", "front"], "NAME=VALUE"),
    (["--global", "-3"], "global_deformation"),
])
def test_bad_arguments_exit_2_without_output(tmp_path, args, needle):
    out = tmp_path / "never.json"
    r = run_cli("solve", example_path("worm"), "--out", str(out), *args)
    assert r.returncode == 2
    assert needle in r.stderr and r.stderr.count("\n") == 1
    assert not out.exists()


def test_missing_file_exit_2(tmp_path):
    r = run_cli("solve", str(tmp_path / "none.json"), "--out", str(tmp_path / "o.json"))
    assert r.returncode == 2 and "none.json" in r.stderr


@pytest.mark.parametrize("case", CORPUS, ids=[c[0] for c in CORPUS])
def test_corpus_through_cli(case, tmp_path, capsys):
    _id, data, field, _pattern = case
    src = tmp_path / "bad.json"
    src.write_text(data if isinstance(data, str) else json.dumps(data))
    out = tmp_path / "out.json"
    rc = main(["solve", str(src), "--out", str(out)])
    err = capsys.readouterr().err
    assert rc == 2
    assert err.startswith("error: ") and err.count("\n") == 1
    assert field in err
    assert not out.exists() and sorted(os.listdir(tmp_path)) == ["bad.json"]
