"""``solve`` flags audit (auditE): an explicit --model that a global deformation makes irrelevant is refused
(defect 2), a repeated --option key is refused (8b), and ``--npz`` outputs are written as one set with an
earlier run's arrays removed only when provably ours (9)."""
import json
import os

import numpy as np
import pytest

from metamaterial_wb import example_path
from metamaterial_wb.cli import main
from metamaterial_wb.core.resultfile import read_result


def _scene_with_global(tmp_path, g=0.3):
    with open(example_path("fish"), encoding="utf-8") as f:
        d = json.load(f)
    d["global_deformation"] = g
    p = tmp_path / "scene_global.json"
    p.write_text(json.dumps(d), encoding="utf-8")
    return str(p)


def _load(path):
    with open(path, encoding="utf-8") as f:
        return json.load(f)


# -- defect 2: --model with a global deformation -------------------------------------------------------------------
@pytest.mark.parametrize("model", ["nonlinear", "linear"])
def test_global_flag_with_another_model_is_refused(tmp_path, capsys, model):
    out = tmp_path / "r.json"
    rc = main(["solve", example_path("fish"), "--out", str(out), "--global", "0.2", "--model", model])
    err = capsys.readouterr().err
    assert rc == 2, err
    assert err.startswith("error: --global: 0.2 with --model " + model) and err.count("\n") == 1, err
    assert "would be ignored" in err, err
    assert not out.exists()


@pytest.mark.parametrize("model", ["nonlinear", "linear"])
def test_scene_global_with_another_model_is_refused(tmp_path, capsys, model):
    scene = _scene_with_global(tmp_path)
    out = tmp_path / "r.json"
    rc = main(["solve", scene, "--out", str(out), "--model", model])
    err = capsys.readouterr().err
    assert rc == 2, err
    assert err.startswith("error: global_deformation: 0.3 stored in the scene with --model " + model), err
    assert "would be ignored" in err and "drop --model" in err, err
    assert not out.exists()


def test_unknown_model_with_global_names_the_model(tmp_path, capsys):
    rc = main(["solve", example_path("fish"), "--out", str(tmp_path / "r.json"), "--global", "0.2",
               "--model", "nope"])
    err = capsys.readouterr().err
    assert rc == 2 and err.startswith("error: --model: 'nope'; allowed:"), err


@pytest.mark.parametrize("extra", [[], ["--model", "quadratic"]])
def test_global_result_says_what_was_used(tmp_path, capsys, extra):
    out = tmp_path / "r.json"
    assert main(["solve", example_path("fish"), "--out", str(out), "--global", "0.2", *extra]) == 0, \
        capsys.readouterr().err
    res = _load(out)
    assert res["model"] == "quadratic" and res["global_deformation"] == 0.2
    assert "closed-form" in res["info"]["method"]
    assert all(n["D"] == 0.2 for n in res["nodes"])
    # the actuators' values are listed (same keys) but marked as not applied
    assert set(res["actuators"]) and res["values_applied"] is False
    assert "global deformation" in res["values_note"] and "not applied" in res["values_note"]


def test_solved_result_marks_values_applied(tmp_path, capsys):
    out = tmp_path / "r.json"
    assert main(["solve", example_path("fish"), "--out", str(out)]) == 0, capsys.readouterr().err
    res = _load(out)
    assert res["model"] == "quadratic" and res["values_applied"] is True and "values_note" not in res


# -- defect 8b: a repeated --option key --------------------------------------------------------------------------
def test_repeated_option_key_is_refused(tmp_path, capsys):
    out = tmp_path / "r.json"
    rc = main(["solve", example_path("fish"), "--out", str(out), "--model", "linear",
               "--option", "planar=1", "--option", "planar=0"])
    err = capsys.readouterr().err
    assert rc == 2, err
    assert err.startswith("error: --option planar: given twice") and err.count("\n") == 1, err
    assert not out.exists()


# -- defect 9: --npz outputs are one set ---------------------------------------------------------------------------
def test_npz_and_json_are_written_together(tmp_path, capsys, monkeypatch):
    """An interrupt after the first file is moved leaves neither new file (and the old pair intact)."""
    from metamaterial_wb.core import fileio

    out = tmp_path / "R.json"
    assert main(["solve", example_path("fish"), "--out", str(out), "--npz"]) == 0
    old_json, old_npz = out.read_bytes(), (tmp_path / "R.npz").read_bytes()
    real_replace = os.replace
    calls = []

    def flaky(src, dst):        # the second move into the output folder is interrupted
        if os.path.dirname(os.path.abspath(dst)) == str(tmp_path):
            calls.append(dst)
            if len(calls) == 2:
                raise KeyboardInterrupt
        return real_replace(src, dst)

    monkeypatch.setattr(fileio.os, "replace", flaky)
    assert main(["solve", example_path("fish"), "--out", str(out), "--npz", "--global", "0.4"]) == 130
    monkeypatch.setattr(fileio.os, "replace", real_replace)
    assert len(calls) >= 2, calls            # both files went through one set (moves into the folder)
    assert out.read_bytes() == old_json and (tmp_path / "R.npz").read_bytes() == old_npz
    assert sorted(os.listdir(tmp_path)) == ["R.json", "R.npz"]


def test_json_only_run_removes_our_earlier_npz(tmp_path, capsys):
    out = tmp_path / "R.json"
    assert main(["solve", example_path("fish"), "--out", str(out), "--npz", "--global", "0.4"]) == 0
    assert (tmp_path / "R.npz").exists()
    assert main(["solve", example_path("fish"), "--out", str(out)]) == 0, capsys.readouterr().err
    assert not (tmp_path / "R.npz").exists()
    meta, a = read_result(out)
    assert "arrays" not in meta and not np.all(a["D"] == 0.4)


def test_json_only_run_keeps_an_npz_it_did_not_write(tmp_path, capsys):
    out = tmp_path / "R.json"
    theirs = tmp_path / "R.npz"
    np.savez(theirs, x=np.arange(3))
    out.write_text(json.dumps({"format": "metamaterial-result", "nodes": []}), encoding="utf-8")
    assert main(["solve", example_path("fish"), "--out", str(out)]) == 0, capsys.readouterr().err
    assert theirs.exists()
    # an earlier JSON of another kind naming R.npz does not make it ours either
    out.write_text(json.dumps({"format": "something-else", "arrays": {"file": "R.npz"}}), encoding="utf-8")
    assert main(["solve", example_path("fish"), "--out", str(out)]) == 0, capsys.readouterr().err
    assert theirs.exists()
