"""Typed numbers and names read strictly in the places ``float()`` / ``int()`` / ``\\d`` still read them: ``render
--view``, ``stream --map``, model options given as text, joint and node names, and the temporary folders the sweep
must recognise. ``1_0``, non-ASCII digits ('٣' is 3 to ``int()``) and inf/nan are refused naming the field."""
import os
import re
import subprocess
import sys

import pytest

from metamaterial_wb import REPO_DIR, example_path
from metamaterial_wb.core.errors import SceneError

ARABIC_3 = "\u0663"          # ARABIC-INDIC DIGIT THREE: int() reads it as 3
FULLWIDTH_1 = "\uff11"       # FULLWIDTH DIGIT ONE


# ---------------------------------------------------------------------------------------------- render --view
def test_view_angles_reads_plain_numbers():
    from metamaterial_wb.core.render import view_angles
    assert view_angles("28,-62") == (28.0, -62.0)
    assert view_angles(" 1e1 , -0.5 ") == (10.0, -0.5)


@pytest.mark.parametrize("text,item", [("1_0,5", "1_0"), (f"{ARABIC_3},5", ARABIC_3), (f"5,{FULLWIDTH_1}", FULLWIDTH_1),
                                       ("inf,0", "inf"), ("0,nan", "nan"), ("0,-infinity", "-infinity")])
def test_view_angles_refuses_what_float_would_take(text, item):
    from metamaterial_wb.core.render import view_angles
    with pytest.raises(SceneError) as ei:
        view_angles(text)
    assert ei.value.field.startswith("--view"), ei.value.field
    assert repr(item) in str(ei.value), str(ei.value)


@pytest.mark.parametrize("text", ["28", "1,2,3", ""])
def test_view_angles_wrong_count_names_the_form(text):
    from metamaterial_wb.core.render import view_angles
    with pytest.raises(SceneError) as ei:
        view_angles(text)
    assert ei.value.field == "--view" and "ELEV,AZIM" in str(ei.value)


def test_view_angles_range_still_checked():
    from metamaterial_wb.core.render import view_angles
    with pytest.raises(SceneError, match=r"elevation 91 is outside"):
        view_angles("91,0")


# ---------------------------------------------------------------------------------------------- stream --map
def test_parse_map_reads_plain_channels():
    from metamaterial_wb.hardware.mapping import parse_map
    assert parse_map("head=0, tail = 3") == {"head": 0, "tail": 3}


@pytest.mark.parametrize("ch", ["1_0", ARABIC_3, FULLWIDTH_1, "1.0", "inf"])
def test_parse_map_refuses_what_int_would_take(ch):
    from metamaterial_wb.hardware.mapping import parse_map
    with pytest.raises(SceneError) as ei:
        parse_map(f"head=0,tail={ch}")
    assert ei.value.field == "--map tail", ei.value.field
    assert repr(ch) in str(ei.value)


# ---------------------------------------------------------------------------------------------- model options
def test_check_option_text_is_read_strictly_and_names_the_allowed_range():
    from metamaterial_wb.core import models
    iopt = models.Option("int", "iterations", low=1, high=100)
    fopt = models.Option("float", "tolerance", low=0.0, high=1.0, low_open=True)
    assert models.check_option("m", "it", " 12 ", iopt) == 12
    assert models.check_option("m", "tol", "1e-3", fopt) == 1e-3
    for opt, key, text in ((iopt, "it", "1_0"), (iopt, "it", ARABIC_3), (iopt, "it", FULLWIDTH_1),
                           (fopt, "tol", "1_0e-3"), (fopt, "tol", f"0.{ARABIC_3}"), (fopt, "tol", "nan"),
                           (fopt, "tol", "inf")):
        with pytest.raises(SceneError) as ei:
            models.check_option("m", key, text, opt)
        assert ei.value.field == f"--option {key}", (text, ei.value.field)
        assert repr(text) in str(ei.value) and "allowed: " in str(ei.value), str(ei.value)
        assert models.allowed_text(opt) in str(ei.value)


def test_allowed_text_is_public_and_solve_uses_it():
    from metamaterial_wb.core import models
    assert models.allowed_text(models.Option("int", low=1, high=9)) == "an integer 1..9"
    src = open(os.path.join(REPO_DIR, "metamaterial_wb", "cli", "solve.py"), encoding="utf-8").read()
    assert "_allowed" not in src.replace("allowed_text", "")


# ---------------------------------------------------------------------------------------------- joint / node names
@pytest.mark.parametrize("text", [f"H{ARABIC_3},1", f"V0,{FULLWIDTH_1}", f"h({ARABIC_3}, 1)"])
def test_parse_joint_refuses_non_ascii_digits(text):
    from metamaterial_wb.core.scene import parse_joint
    with pytest.raises(SceneError) as ei:
        parse_joint(text, "actuators[0].joint")
    assert ei.value.field == "actuators[0].joint"
    assert "joint" in str(ei.value)


def test_parse_joint_still_reads_ascii_with_blanks():
    from metamaterial_wb.core.scene import parse_joint
    assert parse_joint(" H(1, 2) \n") == ("H", 1, 2)
    assert parse_joint("v-1,3") == ("V", -1, 3)


@pytest.mark.parametrize("text", [f"V0,1 H{ARABIC_3},1", f"V{FULLWIDTH_1},1"])
def test_joint_list_refuses_non_ascii_digits(text):
    from metamaterial_wb.core.inverse.pipeline import parse_joint_list
    with pytest.raises(SceneError) as ei:
        parse_joint_list([text], "--forbid")
    assert ei.value.field == "--forbid" and "H<i>,<j>" in str(ei.value)


def test_joint_list_still_reads_ascii():
    from metamaterial_wb.core.inverse.pipeline import parse_joint_list
    assert parse_joint_list(["V0,1; h(2, 3)"]) == ["V0,1", "H2,3"]


def test_scene_node_names_refuse_non_ascii_digits():
    from metamaterial_wb.core.scene import Scene
    scene = Scene.load(example_path("worm"))
    assert scene._node(" N(0, 1) ", "f") == (0, 1)
    for text in (f"N{ARABIC_3},1", f"N0,{FULLWIDTH_1}"):
        with pytest.raises(SceneError) as ei:
            scene._node(text, "modules[0].node")
        assert ei.value.field == "modules[0].node" and "N<i>,<j>" in str(ei.value)


def test_dynamics_pad_node_names_refuse_non_ascii_digits():
    from metamaterial_wb.core.dynamics.builders import _parse_node
    assert _parse_node("N0,3", "f") == (0, 3)
    for text in (f"N{ARABIC_3},1", f"N0,{FULLWIDTH_1}", "N0," + "9" * 5000):
        with pytest.raises(SceneError) as ei:
            _parse_node(text, "modules[2].node")
        assert ei.value.field == "modules[2].node" and "node name" in str(ei.value)


# ---------------------------------------------------------------------------------------------- stale temporary folders
def _dead_pid():
    p = subprocess.Popen([sys.executable, "-c", "pass"])
    p.wait()
    return p.pid


def _kinds_in_source():
    """Every literal kind the package passes to make_temp_dir / OutputSet / Staging / temp_prefix."""
    pat = re.compile(r"(?:make_temp_dir|OutputSet|Staging)\([^()\n]*?,\s*\"([^\"]+)\"\)|temp_prefix\(\"([^\"]+)\"\)")
    kinds = {"tmp"}                                   # the default of all of them
    root = os.path.join(REPO_DIR, "metamaterial_wb")
    for d, _, files in os.walk(root):
        for f in files:
            if f.endswith(".py"):
                text = open(os.path.join(d, f), encoding="utf-8").read()
                kinds.update(a or b for a, b in pat.findall(text))
    return kinds


def test_the_source_scan_finds_the_known_kinds():
    assert {"tmp", "tmp-solve", "tmp-simulate", "build", "sleeve", "mmwb", "mm-export",
            "sleeve-export"} <= _kinds_in_source()


def test_every_temporary_kind_the_code_uses_is_swept_when_its_process_is_dead(tmp_path):
    from metamaterial_wb.core.fileio import sweep_stale
    dead = _dead_pid()
    kinds = sorted(_kinds_in_source())
    for k in kinds:
        (tmp_path / f".{k}-{dead}-ab12").mkdir()
        (tmp_path / f".{k}-{dead}-cd34.step").write_text("x", encoding="utf-8")
        (tmp_path / f".{k}-{os.getpid()}-ef56").mkdir()          # a live writer's: kept
    sweep_stale(str(tmp_path))
    left = sorted(os.listdir(tmp_path))
    assert left == sorted(f".{k}-{os.getpid()}-ef56" for k in kinds), left


def test_sweep_keeps_other_names_and_survives_absurd_pids(tmp_path):
    from metamaterial_wb.core.fileio import sweep_stale
    dead = _dead_pid()
    keep = [f".tmpx-{dead}-a", f"tmp-solve-{dead}-a", f".notakind-{dead}-a", f".tmp-solve-{ARABIC_3}-a",
            ".tmp-99999999999999999999999-a", "results.json"]
    for n in keep:
        (tmp_path / n).mkdir()
    sweep_stale(str(tmp_path))
    assert sorted(os.listdir(tmp_path)) == sorted(keep)


def test_temp_prefix_refuses_a_kind_the_sweep_would_not_know():
    from metamaterial_wb.core.fileio import TEMP_KINDS, temp_prefix
    assert "tmp-solve" in TEMP_KINDS
    assert temp_prefix("tmp-solve") == f".tmp-solve-{os.getpid()}-"
    with pytest.raises(ValueError):
        temp_prefix("brand-new-kind")


def test_solve_sweeps_a_crashed_solves_folder(tmp_path):
    from metamaterial_wb.cli import main
    left = tmp_path / f".tmp-solve-{_dead_pid()}-k9x2"          # what a solve killed with -9 leaves
    left.mkdir()
    (left / "fish.npz").write_bytes(b"partial")
    rc = main(["solve", example_path("fish"), "--out", str(tmp_path / "fish.json"), "--npz"])
    assert rc == 0
    assert not left.exists()
    assert (tmp_path / "fish.json").exists() and (tmp_path / "fish.npz").exists()
    assert not [n for n in os.listdir(tmp_path) if n.startswith(".")]      # its own staging folder is gone too
