"""The belt examples under the sheet commands (`solve`, `render`, `build`).

* ``examples/belt1000.json`` is a belt for `simulate` (1 mm cells; its 0.1 mm hinge is a placeholder the belt model
  never reads, and no hinge that fits a 1 mm cell lies in the calibration table). `solve` and `render` refuse it,
  and the message says what to do: the hinge's field, value and the table's range as before, plus that the scene is
  a belt that `simulate` runs (``--frames`` draws it), and how to set k1 directly. Nothing is written.
* The hint is only for belts: a hinge sheet with the same hinge gets the plain calibration message, and a belt whose
  hinge lies in the table (belt8) still solves and renders.
* ``examples/belt8*.json`` (pneumatic silicone bimorph cells with valves and electronics) are not printable as
  modelled: they declare ``fabrication.simulation_only`` and `build` refuses them with that reason, writing nothing;
  `simulate` still runs them.
"""
import json
import os
import subprocess
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
EX = os.path.join(ROOT, "examples")
BELT8 = ["belt8.json", "belt8_open_loop.json", "belt8_open_loop_high_torque.json"]


def cli(*args, timeout=300):
    return subprocess.run([sys.executable, "-m", "metamaterial_wb", *args], capture_output=True, text=True,
                          cwd=ROOT, timeout=timeout, env=dict(os.environ, PYTHONPATH=ROOT))


def load(name):
    with open(os.path.join(EX, name), encoding="utf-8") as fh:
        return json.load(fh)


@pytest.mark.parametrize("command,out", [("solve", "res.json"), ("render", "pic.png")])
def test_solve_and_render_of_belt1000_say_to_simulate_it(tmp_path, command, out):
    target = tmp_path / out
    r = cli(command, os.path.join(EX, "belt1000.json"), "--out", str(target))
    assert r.returncode == 2, (r.stdout, r.stderr)
    err = r.stderr
    # the old facts stay: field, value, the table's range
    assert "hinge.length_mm: 0.1 mm is outside the allowed range [0.25, 9.5]" in err, err
    assert "calibration table" in err, err
    # ... and what to do for this scene
    assert "'belt1000' is a belt" in err, err
    assert "simulate" in err and "--frames" in err, err
    assert '"k1"' in err and '"joints"' in err, err
    assert not target.exists() and list(tmp_path.iterdir()) == []


def test_a_sheet_with_the_same_hinge_gets_no_belt_hint(tmp_path):
    d = load("belt1000.json")
    del d["dynamics"]
    d["name"] = "strip"
    scene = tmp_path / "strip.json"
    scene.write_text(json.dumps(d), encoding="utf-8")
    r = cli("solve", str(scene), "--out", str(tmp_path / "res.json"))
    assert r.returncode == 2, (r.stdout, r.stderr)
    assert "hinge.length_mm: 0.1 mm is outside the allowed range [0.25, 9.5]" in r.stderr, r.stderr
    assert '"k1"' in r.stderr, r.stderr
    assert "is a belt" not in r.stderr and "simulate" not in r.stderr, r.stderr
    assert not (tmp_path / "res.json").exists()


def test_a_belt_with_hinges_in_the_table_still_solves_and_renders(tmp_path):
    res, pic = tmp_path / "res.json", tmp_path / "pic.png"
    r = cli("solve", os.path.join(EX, "belt8.json"), "--out", str(res))
    assert r.returncode == 0, (r.stdout, r.stderr)
    with open(res, encoding="utf-8") as fh:
        assert json.load(fh)
    r = cli("render", os.path.join(EX, "belt8.json"), "--out", str(pic))
    assert r.returncode == 0, (r.stdout, r.stderr)
    assert pic.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.parametrize("name", BELT8)
def test_belt8_scenes_declare_simulation_only(name):
    why = (load(name).get("fabrication") or {}).get("simulation_only")
    assert isinstance(why, str) and "pneumatic" in why and len(why) > 40, why


@pytest.mark.parametrize("name", BELT8)
def test_build_refuses_belt8_scenes_with_the_reason_and_writes_nothing(tmp_path, name):
    out = tmp_path / "out"
    r = cli("build", os.path.join(EX, name), "--out", str(out), "--3mf")
    assert r.returncode == 2, (r.stdout, r.stderr)
    stem = name[:-5]
    assert f"fabrication.simulation_only: scene '{stem}' is simulation-only: " in r.stderr, r.stderr
    assert "pneumatic" in r.stderr, r.stderr
    assert not out.exists() or list(out.iterdir()) == []


def test_belt8_still_simulates(tmp_path):
    out = tmp_path / "sim"
    r = cli("simulate", os.path.join(EX, "belt8.json"), "--seconds", "0.1", "--out", str(out), "--no-dt-check")
    assert r.returncode == 0, (r.stdout, r.stderr)
    with open(out / "summary.json", encoding="utf-8") as fh:
        assert json.load(fh)
