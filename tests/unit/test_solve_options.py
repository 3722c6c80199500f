"""``solve``'s model options, ``--npz`` path, and flags that would be ignored: every bad value is one line
``error: <flag>: <value>; allowed: ...`` with exit 2 and no output (audit of the solve command)."""
import json
import os
import shutil
import subprocess
import sys

import pytest

from metamaterial_wb import REPO_DIR, example_path
from metamaterial_wb.cli import main

FISH = example_path("fish")


def run_cli(*args, cwd=REPO_DIR):
    return subprocess.run([sys.executable, "-m", "metamaterial_wb", *args], cwd=cwd, capture_output=True,
                          text=True, timeout=300)


def _refused(tmp_path, capsys, *args, needle):
    out = tmp_path / "never.json"
    rc = main(["solve", FISH, "--out", str(out), *args])
    err = capsys.readouterr().err
    assert rc == 2, err
    assert err.startswith("error: ") and err.count("\n") == 1, err
    assert needle in err, err
    assert not out.exists()
    return err


# -- defect 1: every --option value is parsed and checked against the model's option table ---------------------
BAD_OPTIONS = [
    ("quadratic", "model=linear"),
    ("nonlinear", "max_iter=abc"), ("nonlinear", "tol=abc"), ("nonlinear", "min_step=abc"),
    ("nonlinear", "load_steps=abc"), ("nonlinear", "dr_max_iter=abc"), ("nonlinear", "contact_stiffness=abc"),
    ("linear", "contact_fraction=abc"), ("linear", "contact_fraction=5"), ("nonlinear", "contact_fraction=-1"),
    ("nonlinear", "contact_stiffness=-1"), ("nonlinear", "load_steps=0"), ("nonlinear", "load_steps=-1"),
    ("nonlinear", "min_step=nan"), ("nonlinear", "predictor=foo"), ("nonlinear", "fallback=maybe"),
    ("nonlinear", "contact=maybe"), ("linear", "planar=maybe"), ("linear", "line_search=maybe"),
    ("nonlinear", "tol=-1"), ("nonlinear", "tol=nan"), ("nonlinear", "max_iter=0"), ("nonlinear", "max_iter=-5"),
    ("nonlinear", "max_iter=2.5"),
]


@pytest.mark.parametrize("model,option", BAD_OPTIONS)
def test_bad_option_values_exit_2(tmp_path, capsys, model, option):
    key, _, val = option.partition("=")
    err = _refused(tmp_path, capsys, "--model", model, "--option", option, needle=f"--option {key}")
    if key != "model":          # an unknown option's message lists the allowed names instead
        assert val in err and "allowed:" in err, err


@pytest.mark.parametrize("model,option", [
    ("nonlinear", "tol=1e-6"), ("nonlinear", "max_iter=50"), ("nonlinear", "contact=no"),
    ("nonlinear", "fallback=1"), ("linear", "planar=true"), ("linear", "contact_fraction=0.9"),
    ("quadratic", "backend=superlu"),
])
def test_good_option_values_solve(tmp_path, model, option):
    out = tmp_path / "r.json"
    assert main(["solve", FISH, "--out", str(out), "--model", model, "--option", option]) == 0
    assert json.loads(out.read_text())["model"] == model


def test_option_table_parses_python_values_too():
    from metamaterial_wb.core.errors import SceneError
    from metamaterial_wb.core.models import check_options

    assert check_options("nonlinear", {"tol": "1e-9", "contact": "yes", "max_iter": "7"}) == \
        {"tol": 1e-9, "contact": True, "max_iter": 7}
    assert check_options("nonlinear", {"tol": 1e-9, "planar": None}) == {"tol": 1e-9, "planar": None}
    with pytest.raises(SceneError, match="--option max_iter"):
        check_options("nonlinear", {"max_iter": 2.0})


def test_existing_option_messages_are_kept(tmp_path, capsys):
    _refused(tmp_path, capsys, "--model", "nonlinear", "--option", "hinge_elements=0", needle="hinge_elements")
    _refused(tmp_path, capsys, "--model", "nonlinear", "--option", "method=magic", needle="newton")
    _refused(tmp_path, capsys, "--model", "linear", "--option", "poses=spline", needle="chain")


# -- defect 2: the .npz path is checked before any work ---------------------------------------------------------
def test_npz_scene_is_never_overwritten(tmp_path):
    scene = tmp_path / "in.npz"
    shutil.copy(FISH, scene)
    before = scene.read_bytes()
    r = run_cli("solve", str(scene), "--out", str(tmp_path / "in.json"), "--npz")
    assert r.returncode == 2 and "--npz" in r.stderr and r.stderr.count("\n") == 1, r.stderr
    assert scene.read_bytes() == before and not (tmp_path / "in.json").exists()


def test_npz_path_that_is_a_folder_is_refused_before_solving(tmp_path, capsys):
    os.mkdir(tmp_path / "r3.npz")
    out = tmp_path / "r3.json"
    assert main(["solve", FISH, "--out", str(out), "--npz"]) == 2
    err = capsys.readouterr().err
    assert "--npz" in err and "r3.npz" in err and ".tmp" not in err, err
    assert not out.exists()


def test_out_ending_in_npz_with_npz_is_refused(tmp_path, capsys):
    _refused(tmp_path, capsys, "--npz", "--out", str(tmp_path / "res2.npz"), needle="--out")
    assert not (tmp_path / "res2.npz").exists() and not (tmp_path / "res2.npz.npz").exists()


# -- defect 3: flags that would be ignored are refused -----------------------------------------------------------
@pytest.mark.parametrize("args,needle", [
    (["--backend", "cholmod", "--model", "linear"], "--backend"),
    (["--backend", "cholmod", "--model", "nonlinear"], "--backend"),
    (["--backend", "cholmod", "--option", "backend=dense"], "--option backend"),
    (["--global", "0.5", "--model", "nonlinear", "--option", "hinge_elements=4", "--option", "tol=-5"], "--global"),
])
def test_ignored_flags_are_refused(tmp_path, capsys, args, needle):
    _refused(tmp_path, capsys, *args, needle=needle)


# -- defect 4: --global names the flag ----------------------------------------------------------------------------
@pytest.mark.parametrize("g", ["2", "-1.5"])
def test_bad_global_names_the_flag(tmp_path, capsys, g):
    err = _refused(tmp_path, capsys, f"--global={g}", needle="--global")
    assert err.startswith(f"error: --global: {float(g)!r}; allowed: a number in [-1, 1]"), err


def test_global_nan_is_not_a_number(tmp_path, capsys):
    # read strictly (core/numbers.py): nan is refused while the flag is read, naming it
    with pytest.raises(SystemExit) as e:
        main(["solve", FISH, "--out", str(tmp_path / "never.json"), "--global", "nan"])
    err = capsys.readouterr().err
    assert e.value.code == 2 and "argument --global: 'nan' is not a number" in err, err
    assert not (tmp_path / "never.json").exists()


# -- defect 5: --help's example works and lists the options --------------------------------------------------------
def test_help_example_works_and_lists_every_option(tmp_path, capsys):
    from metamaterial_wb.core.models import model_options

    with pytest.raises(SystemExit):
        main(["solve", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "--model nonlinear --option tol=1e-10" in text
    for model in ("quadratic", "linear", "nonlinear"):
        for key in model_options(model):
            assert key in text, key
    out = tmp_path / "r.json"
    assert main(["solve", FISH, "--out", str(out), "--model", "nonlinear", "--option", "tol=1e-10"]) == 0
