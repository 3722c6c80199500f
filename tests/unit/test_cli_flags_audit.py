"""Flags as a user meets them (audit): a flag that has no effect is refused naming it and why (as ``build --step
--layout`` is), a repeated item is refused the same way everywhere (as ``bench fidelity --amplitudes 0.5,0.5``
is), and the errors raised late name the field or flag the user wrote: a joint override's hinge length out of the
calibration table is ``joints[K].length_mm (JOINT)`` as the scene's own checks write it (it was
``joints.H0,0.length_mm``), a relaxation that fails on a slope names ``--incline`` and its value. Through the real
CLI (tests/clihelpers.run_cli)."""
import json
import os

import pytest

from clihelpers import REPO, one_line_error, run_cli

EX = os.path.join(REPO, "examples")
FISH = os.path.join(EX, "fish.json")
MISSING = os.path.join(REPO, "tests", "no such raw figures.json")  # a refusal must come before it is read


def test_build_step_alone_refuses_tolerance_as_it_refuses_layout(tmp_path):
    out = tmp_path / "o"
    r = run_cli("build", FISH, "--out", out, "--step", "--tolerance", "0.05")
    one_line_error(r, "--tolerance")
    assert "only --step is written" in r.stderr and "add --3mf or drop --tolerance" in r.stderr, r.stderr
    assert not out.exists()


@pytest.mark.parametrize("flag, value, item", [
    ("--scenes", "chain,chain", "'chain'"),
    ("--scenes", "chain, grid10,chain", "'chain'"),
    ("--amplitudes", "0.5,0.5", "0.5"),  # (as it was)
])
def test_bench_refuses_a_repeated_item_in_every_list(flag, value, item):
    r = run_cli("bench", "fidelity", flag, value, "--from-json", MISSING)
    one_line_error(r, flag)
    assert f"{item} is given more than once (items 1 and " in r.stderr and "once (each is run, or read, once)" \
        in r.stderr, r.stderr


def test_bench_refuses_a_repeated_fe_part(tmp_path):
    r = run_cli("bench", "fidelity", "--fe", "--fe-parts", "hinge,hinge", "--fe-json-out", tmp_path / "fe.json")
    one_line_error(r, "--fe-parts")
    assert "'hinge' is given more than once (items 1 and 2 of 'hinge,hinge')" in r.stderr, r.stderr
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("forbid, message", [
    (["V0,1", "V0,1"], "V0,1 is given more than once (joints 1 and 2 of 'V0,1' 'V0,1')"),
    (["V0,1", "--forbid", "v(0,1)"], "V0,1 is given more than once (joints 1 and 2 of 'V0,1' 'v(0,1)')"),
    (["H1,2; V0,1,V0,1"], "V0,1 is given more than once (joints 2 and 3 of 'H1,2; V0,1,V0,1')"),
])
def test_inverse_refuses_a_joint_forbidden_twice(tmp_path, forbid, message):
    # --values-only without --servos: a list that parses is refused with --values-only before any file is read
    r = run_cli("inverse", FISH, "--target", os.path.join(EX, "fish_tail_target.json"), "--out", tmp_path / "o",
                "--values-only", "--forbid", *forbid)
    one_line_error(r, "--forbid")
    assert message in r.stderr and "give each joint once" in r.stderr, r.stderr
    assert not (tmp_path / "o").exists()


def test_a_joint_length_outside_the_calibration_table_names_the_joints_entry(tmp_path):
    with open(FISH, encoding="utf-8") as f:
        scene = json.load(f)
    scene["joints"] = [{"joint": "V0,1", "k1": 0.5}, {"joint": "H0,0", "length_mm": 0.01}]
    path = tmp_path / "short_hinge.json"
    path.write_text(json.dumps(scene), encoding="utf-8")
    r = run_cli("solve", path, "--out", tmp_path / "r.json")
    one_line_error(r, r"joints[1].length_mm (H0,0)")
    assert "0.01 mm is outside the allowed range [0.25, 9.5] of the calibration table" in r.stderr, r.stderr
    assert not (tmp_path / "r.json").exists()


def test_no_equilibrium_on_an_incline_names_the_flag_and_its_value(tmp_path):
    r = run_cli("simulate", os.path.join(EX, "worm_crawl.json"), "--seconds", "1", "--incline=-60",
                "--out", tmp_path / "o")
    one_line_error(r, "--incline")
    assert r.stderr.startswith("error: --incline: -60 deg (allowed [-60, 60] deg): no static equilibrium found"), \
        r.stderr
    assert "a gentler --incline" in r.stderr, r.stderr
    assert not (tmp_path / "o").exists()


def test_inverse_refuses_a_model_evaluated_twice():
    """--evaluate dropped a repeated model without a word (found by the review of the audit's fixes)."""
    from metamaterial_wb.core.errors import SceneError
    from metamaterial_wb.core.inverse.pipeline import parse_models
    assert parse_models("quadratic, linear") == ["quadratic", "linear"]
    with pytest.raises(SceneError) as e:
        parse_models("quadratic,linear,quadratic", "--evaluate")
    assert "--evaluate" in str(e.value) and "'quadratic' is given more than once (items 1 and 3 of " \
        "'quadratic,linear,quadratic'); give each model once" in str(e.value), str(e.value)
