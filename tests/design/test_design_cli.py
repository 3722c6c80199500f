"""CLI: design, solve (auto-configuration, rotations, joint folds) and render, end to end."""
import json
import math
import os
import subprocess
import sys

import numpy as np
import pytest

from metamaterial_wb.core.design import inward

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
EXAMPLES = os.path.join(REPO, "examples")


def cli(*args):
    return subprocess.run([sys.executable, "-m", "metamaterial_wb", *args], cwd=REPO, capture_output=True,
                          text=True, timeout=120)


def write(tmp_path, name, data):
    p = tmp_path / name
    p.write_text(json.dumps(data))
    return str(p)


STRIP = {"format": "metamaterial-scene", "version": 1, "name": "strip", "layout": {"chain": 6},
         "hinge": {"length_mm": 5, "width_mm": 0.8, "thickness_mm": 7},
         "axes": [{"direction": "vertical", "line": 2, "fold_deg": 50, "name": "fold"}],
         "actuators": [{"name": "m", "joint": "V0,0", "value": 0.5}]}


def test_design_writes_configured_scene_and_report(tmp_path):
    src = write(tmp_path, "s.json", STRIP)
    out, rep = str(tmp_path / "c.json"), str(tmp_path / "r.json")
    r = cli("design", src, "--out", out, "--report", rep)
    assert r.returncode == 0, r.stderr
    assert "max +-" in r.stdout and "fold 50" in r.stdout
    cfg = json.load(open(out))["joint_config"]
    assert sorted(cfg) == ["H0,2", "H1,2"]
    assert cfg["H0,2"]["tilt_deg"] == pytest.approx(-cfg["H1,2"]["tilt_deg"])
    report = json.load(open(rep))
    assert report["axes"][0]["max_fold_deg"] > 50
    # the printable fold (what the hinge can be printed to) is printed beside the kinematic maximum
    assert f"printable +-{inward(report['axes'][0]['printable_fold_deg'])} deg" in r.stdout


def test_design_rejects_too_large_fold_with_the_maximum_and_writes_nothing(tmp_path):
    src = write(tmp_path, "s.json", dict(STRIP, axes=[{"direction": "vertical", "line": 2, "fold_deg": 80}]))
    out = tmp_path / "c.json"
    r = cli("design", src, "--out", str(out))
    assert r.returncode == 2
    mx = math.degrees(2 * math.atan(5 / 7))
    assert inward(mx) in r.stderr and "axes[0].fold_deg" in r.stderr
    assert not out.exists()
    # --fold overrides a fold by axis name
    r = cli("design", src, "--out", str(out), "--fold", "0=30")
    assert r.returncode == 0, r.stderr
    assert json.load(open(out))["axes"][0]["fold_deg"] == 30


def test_design_rejects_crossing_axes(tmp_path):
    src = write(tmp_path, "s.json", {"layout": {"grid": [2, 2]},
                                     "axes": [{"direction": "vertical", "line": 0, "fold_deg": 5},
                                              {"direction": "horizontal", "line": 1, "fold_deg": 5}]})
    r = cli("design", src, "--out", str(tmp_path / "c.json"))
    assert r.returncode == 2 and "cross" in r.stderr and "axes[0]" in r.stderr and "axes[1]" in r.stderr


def test_solve_configures_axes_and_reports_rotations_and_joint_folds(tmp_path):
    src = write(tmp_path, "s.json", STRIP)
    out = str(tmp_path / "r.json")
    r = cli("solve", src, "--out", out, "--global", "1")
    assert r.returncode == 0, r.stderr
    res = json.load(open(out))
    for n in res["nodes"]:
        R = np.array(n["rotation"])
        assert np.allclose(R @ R.T, np.eye(3), atol=1e-12)
    folds = {j["name"]: j["fold_deg"] for j in res["joints"]}
    assert folds["H0,2"] == pytest.approx(50.0, abs=1e-6) and folds["H1,2"] == pytest.approx(50.0, abs=1e-6)
    assert all(abs(v) < 1e-9 for k, v in folds.items() if k not in ("H0,2", "H1,2"))
    # end normals: 50 deg apart
    nodes = {n["name"]: np.array(n["rotation"]) for n in res["nodes"]}
    assert math.degrees(math.acos(nodes["N0,0"][:, 2] @ nodes["N0,6"][:, 2])) == pytest.approx(50.0, abs=1e-6)


def test_render_writes_png_for_global_and_set_states(tmp_path):
    src = write(tmp_path, "s.json", STRIP)
    for extra in (["--global", "0.7"], ["--set", "m=-0.5"]):
        out = tmp_path / "p.png"
        r = cli("render", src, "--out", str(out), "--size", "400x300", *extra)
        assert r.returncode == 0, r.stderr
        data = out.read_bytes()
        assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 5000
        out.unlink()
    r = cli("render", src, "--out", str(tmp_path / "q.png"), "--set", "nobody=0.5")
    assert r.returncode == 2 and "nobody" in r.stderr and not (tmp_path / "q.png").exists()


@pytest.mark.parametrize("name", ["strip_fold.json", "grid_fold.json", "fish_axes.json"])
def test_examples_design_and_fold_exactly(name, tmp_path):
    from metamaterial_wb.core import design, kinematics as K
    from metamaterial_wb.core.scene import Scene

    s = Scene.load(os.path.join(EXAMPLES, name))
    assert s.axes
    design.configure(s)
    kin = K.Kinematics(s)
    pos, R, phi = kin.poses(np.ones(s.topology.n_nodes))
    assert kin.closure_residual(phi, pos) < 1e-9
    fold, _ = K.joint_angles(s, R)
    for ax in s.axes:
        names = [n for n, c in s.joint_config.items() if c["axis"] == (ax.name or f"{ax.direction[0]}{ax.line}")]
        assert names
        for n in names:
            assert fold[s.topology.joint_index[n]] == pytest.approx(ax.fold_deg, abs=1e-7)


@pytest.mark.parametrize("cmd", ["render", "solve"])
def test_global_and_set_together_are_refused_not_one_ignored(tmp_path, cmd):
    """``--global`` (every D = G) and ``--set`` (an actuator's value, then solve) describe two states; given both,
    one was silently ignored. Now: exit 2, one line naming both, nothing written."""
    src = write(tmp_path, "s.json", STRIP)
    out = tmp_path / ("p.png" if cmd == "render" else "r.json")
    r = cli(cmd, src, "--out", str(out), "--global", "0.7", "--set", "m=-0.5")
    assert r.returncode == 2 and "--global" in r.stderr and "--set" in r.stderr, r.stderr
    assert len(r.stderr.strip().splitlines()) == 1 and not out.exists()


def test_solve_set_overrides_the_scenes_stored_global_deformation(tmp_path):
    """A scene saved in its global state (``global_deformation``) solved with ``--set``: the set actuator's value
    is solved for (as ``render`` does), not the stored global state."""
    src = write(tmp_path, "s.json", dict(STRIP, global_deformation=0.7))
    out = tmp_path / "r.json"
    r = cli("solve", src, "--out", str(out), "--set", "m=-0.5")
    assert r.returncode == 0, r.stderr
    res = json.loads(out.read_text())
    assert res["global_deformation"] is None
    D = {n["name"]: n["D"] for n in res["nodes"]}
    assert min(D.values()) == pytest.approx(-0.5, abs=1e-9)


def test_design_flags_are_named_and_never_silently_lost(tmp_path):
    fish = os.path.join(EXAMPLES, "fish_axes.json")
    out = tmp_path / "c.json"
    # a fold beyond the maximum given on the command line names the flag (it named axes[3].fold_deg only)
    r = cli("design", fish, "--out", str(out), "--fold", "tail=120")
    assert r.returncode == 2 and r.stderr.startswith("error: --fold tail (axes[3].fold_deg): 120 deg"), r.stderr
    # one axis given twice: the last one won without a word
    r = cli("design", fish, "--out", str(out), "--fold", "tail=10", "--fold", "tail=20")
    assert r.returncode == 2 and "axis 3 given twice (tail=10 and tail=20)" in r.stderr, r.stderr
    # an axis named "1" would be ambiguous with the axis at index 1: such a name is refused as the scene loads
    d = json.load(open(fish, encoding="utf-8"))
    d["axes"][3]["name"] = "1"
    src = write(tmp_path, "named.json", d)
    r = cli("design", src, "--out", str(out), "--fold", "1=3")
    assert r.returncode == 2 and "axes[3].name: '1' is not a valid name" in r.stderr, r.stderr
    # the report and the scene in one file: the scene overwrote the report
    r = cli("design", fish, "--out", str(out), "--report", str(out))
    assert r.returncode == 2 and r.stderr.startswith("error: --report: ") and "also --out" in r.stderr
    assert not out.exists()
    # --quiet hides the report, not a warning that build will reject the design
    r = cli("design", fish, "--out", str(out), "--fold", "tail=20", "--quiet")
    assert r.returncode == 0 and r.stdout == ""
    assert "warning: axis tail" in r.stderr and "`build` will reject" in r.stderr
