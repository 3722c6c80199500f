"""Numbers typed on the command line are read strictly (core/numbers.py): ``1_0``, non-ASCII digits (Arabic-Indic,
full-width), inf / nan and subnormals such as 5e-320 are refused naming the flag (and the key of ``--set``,
``--fold``, ``--option``) and the text, before anything is written; negative numbers still read. ``solve --fields``
refuses a field given twice. ``design`` writes ``--out`` and ``--report`` together or not at all."""
import json
import os

import pytest

from metamaterial_wb import cli as CLI
from clihelpers import one_line_error, run_cli

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
STRIP = os.path.join(REPO, "examples", "strip_fold.json")         # actuator "left", axes first/second/third
FISH_AXES = os.path.join(REPO, "examples", "fish_axes.json")      # axes neck, body, peduncle, tail
BAD = ["1_0", "\u0663", "\uff11", "inf", "nan", "5e-320"]          # all numbers to Python's float()


cli = run_cli


def flag_refused(r, flag, text):
    """argparse's refusal of a typed flag: exit 2, the flag and the text named, the strict reader's reason."""
    assert r.returncode == 2, (r.stdout, r.stderr)
    assert f"argument {flag}: " in r.stderr, r.stderr
    assert repr(text) in r.stderr and "Traceback" not in r.stderr, r.stderr
    assert "not a" in r.stderr or "subnormal" in r.stderr or "beyond" in r.stderr, r.stderr


# ---- 1: flags read by argparse -------------------------------------------------------------------------------
# The scene does not exist: a flag read strictly is refused before it is opened (float() took these texts, so
# the old code went on to the scene, or to --port, and failed there instead).
ARGPARSE_FLAGS = [
    ("build", "--tolerance", ["--out", "{tmp}/b"]),
    ("build", "--clearance", ["--out", "{tmp}/b"]),
    ("render", "--global", ["--out", "{tmp}/r.png"]),
    ("solve", "--global", ["--out", "{tmp}/s.json"]),
    ("stream", "--seconds", []),
    ("stream", "--baud", []),
    ("stream", "--rate", []),
    ("stream", "--rate-tolerance", []),
    ("stream", "--watchdog-ms", []),
    ("stream", "--park-after-ms", []),
    ("stream", "--release-after-ms", []),
    ("stream", "--max-lost", []),
]


@pytest.mark.parametrize("text", BAD)
@pytest.mark.parametrize("command, flag, extra", ARGPARSE_FLAGS, ids=[f"{c}{f}" for c, f, _ in ARGPARSE_FLAGS])
def test_typed_flag_refuses_what_float_takes(tmp_path, command, flag, extra, text):
    extra = [a.format(tmp=tmp_path) for a in extra]
    r = cli(command, tmp_path / "missing.json", *extra, f"{flag}={text}")
    flag_refused(r, flag, text)
    assert os.listdir(tmp_path) == []


@pytest.mark.parametrize("command, flag, text", [("stream", "--baud", "115200.0"), ("stream", "--max-lost", "1e3")])
def test_whole_number_flags_refuse_decimals(tmp_path, command, flag, text):
    r = cli(command, tmp_path / "missing.json", flag, text)
    flag_refused(r, flag, text)


def test_negative_numbers_still_read(tmp_path):
    for form in (["--global=-0.5"], ["--global", "-0.5"]):
        r = cli("solve", STRIP, "--out", tmp_path / "s.json", *form)
        assert r.returncode == 0, r.stderr
        assert json.loads((tmp_path / "s.json").read_text(encoding="utf-8"))["global_deformation"] == -0.5
    r = cli("solve", STRIP, "--out", tmp_path / "t.json", "--set", "left=-0.5")
    assert r.returncode == 0, r.stderr
    assert json.loads((tmp_path / "t.json").read_text(encoding="utf-8"))["actuators"]["left"] == -0.5
    r = cli("design", FISH_AXES, "--out", tmp_path / "d.json", "--fold", "neck=-10", "--fold=body=-12.5", "--quiet")
    assert r.returncode == 0, r.stderr
    folds = [a["fold_deg"] for a in json.loads((tmp_path / "d.json").read_text(encoding="utf-8"))["axes"]]
    assert folds[:2] == [-10.0, -12.5]


# ---- 1: values read by hand (KEY=VALUE) ----------------------------------------------------------------------
@pytest.mark.parametrize("text", BAD)
def test_solve_set_value_read_strictly(tmp_path, text):
    r = cli("solve", STRIP, "--out", tmp_path / "s.json", "--set", f"left={text}")
    one_line_error(r, "--set left")
    assert repr(text) in r.stderr
    assert not (tmp_path / "s.json").exists()


@pytest.mark.parametrize("text", BAD)
def test_design_fold_read_strictly(tmp_path, text):
    r = cli("design", FISH_AXES, "--out", tmp_path / "d.json", "--report", tmp_path / "r.json", "--fold",
            f"neck={text}")
    one_line_error(r, "--fold neck")
    assert repr(text) in r.stderr and ("not a number" in r.stderr or "subnormal" in r.stderr
                                       or "beyond" in r.stderr), r.stderr
    assert os.listdir(tmp_path) == []


@pytest.mark.parametrize("option", ["max_iter=1_0", "load_steps=\u0663", "tol=5e-320", "contact_fraction=\uff11"])
def test_solve_option_value_read_strictly(tmp_path, option):
    key, _, text = option.partition("=")
    r = cli("solve", STRIP, "--out", tmp_path / "s.json", "--model", "nonlinear", "--option", option)
    one_line_error(r, f"--option {key}")
    assert repr(text) in r.stderr and ("not a" in r.stderr or "subnormal" in r.stderr), r.stderr
    assert not (tmp_path / "s.json").exists()


def test_solve_option_plain_numbers_still_read(tmp_path):
    r = cli("solve", STRIP, "--out", tmp_path / "s.json", "--model", "nonlinear", "--option", "max_iter=50",
            "--option", "tol=1e-9")
    assert r.returncode in (0, 1), r.stderr       # 1: did not converge in 50 iterations (the file is written)
    assert (tmp_path / "s.json").exists()


def test_render_size_read_strictly(tmp_path):
    r = cli("render", STRIP, "--out", tmp_path / "r.png", "--size", "1_200x800")
    one_line_error(r, "--size")
    assert "'1_200x800'" in r.stderr
    assert os.listdir(tmp_path) == []


# ---- 2: solve --fields with a field twice --------------------------------------------------------------------
@pytest.mark.parametrize("fields", ["D,D", "D, poses,D", "joints,poses,joints"])
def test_solve_fields_refuses_a_repeated_field(tmp_path, fields):
    r = cli("solve", STRIP, "--out", tmp_path / "s.json", "--fields", fields)
    one_line_error(r, "--fields")
    twice = fields.replace(" ", "").split(",")[-1]
    assert f"{twice} given twice" in r.stderr, r.stderr
    assert os.listdir(tmp_path) == []


# ---- 3: design writes --out and --report together, or neither ------------------------------------------------
def test_design_report_where_out_needs_a_folder_writes_nothing(tmp_path):
    # --out R/c.json needs the folder R that --report R would be as a file: refused before anything is written
    r = cli("design", FISH_AXES, "--report", tmp_path / "R", "--out", tmp_path / "R" / "c.json", "--quiet")
    one_line_error(r, "--report")
    assert os.listdir(tmp_path) == []
    r = cli("design", FISH_AXES, "--out", tmp_path / "R", "--report", tmp_path / "R" / "r.json", "--quiet")
    one_line_error(r, "--report")
    assert os.listdir(tmp_path) == []


@pytest.mark.parametrize("failing", ["out", "report"])
@pytest.mark.parametrize("same_folder", [True, False], ids=["same-folder", "two-folders"])
def test_design_failed_write_leaves_both_files_as_they_were(tmp_path, monkeypatch, capsys, failing, same_folder):
    out = tmp_path / "c.json"
    report = tmp_path / ("r.json" if same_folder else "sub/r.json")
    report.parent.mkdir(exist_ok=True)
    out.write_text("old scene\n", encoding="utf-8")
    report.write_text("old report\n", encoding="utf-8")
    target = os.path.abspath(out if failing == "out" else report)
    real_replace = os.replace
    state = {"failed": False}

    def replace(src, dst, *a, **k):      # the disk refuses the one move of a new file onto ``target``
        if not state["failed"] and os.path.abspath(dst) == target:
            state["failed"] = True
            raise OSError(28, "No space left on device", str(dst))
        return real_replace(src, dst, *a, **k)

    monkeypatch.setattr(os, "replace", replace)
    rc = CLI.main(["design", FISH_AXES, "--out", str(out), "--report", str(report), "--quiet"])
    monkeypatch.setattr(os, "replace", real_replace)
    assert state["failed"] and rc == 2, capsys.readouterr().err
    assert out.read_text(encoding="utf-8") == "old scene\n"
    assert report.read_text(encoding="utf-8") == "old report\n"
    leftovers = sorted(os.listdir(tmp_path)) + (sorted(os.listdir(report.parent)) if not same_folder else [])
    assert sorted(leftovers) == sorted(["c.json", "r.json"] if same_folder else ["c.json", "sub", "r.json"])


def test_design_writes_both_files(tmp_path):
    r = cli("design", FISH_AXES, "--out", tmp_path / "new" / "c.json", "--report", tmp_path / "other" / "r.json",
            "--quiet")
    assert r.returncode == 0, r.stderr
    assert json.loads((tmp_path / "new" / "c.json").read_text(encoding="utf-8"))["joint_config"]
    assert json.loads((tmp_path / "other" / "r.json").read_text(encoding="utf-8"))
    assert sorted(os.listdir(tmp_path / "new")) == ["c.json"] and sorted(os.listdir(tmp_path / "other")) == ["r.json"]


def test_core_parse_fields_refuses_a_repeated_field():
    """The refusal lives in core (``resultfile.parse_fields``), for every caller, not only the command line."""
    from metamaterial_wb.core.errors import SceneError
    from metamaterial_wb.core.resultfile import parse_fields
    with pytest.raises(SceneError) as e:
        parse_fields("poses,D,poses")
    assert "poses given twice" in str(e.value) and "--fields" in str(e.value), str(e.value)
    assert parse_fields("joints,D") == ("D", "joints")
