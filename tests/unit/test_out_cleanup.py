"""A run that failed or was stopped (SIGTERM) after it created its output folder left that folder behind, empty
(``simulate / build / sleeve --out NEW``, ``solve --out NEW/r.json``). Now the folders a run created itself (the
output folder and any parents it made) are removed again when they are still empty; a folder that existed before,
and anything in it that the run did not write, stays. The commands run in process (``cli.main``, whose handler turns
SIGTERM into an exception); the signal is a real SIGTERM sent to this process while the run writes."""
import errno
import os
import signal
import time

import pytest

from clihelpers import REPO

from metamaterial_wb import cli as CLI
from metamaterial_wb.core import fileio

FISH = os.path.join(REPO, "examples", "fish.json")
STRIP = os.path.join(REPO, "examples", "strip_fold.json")


def _sigterm(*a, **k):
    """Stands for a writer: the run is stopped by SIGTERM while it writes."""
    os.kill(os.getpid(), signal.SIGTERM)
    time.sleep(30)                 # not reached: the CLI's handler raises at once
    raise AssertionError("SIGTERM did not stop the run")


def _full(*a, **k):
    """Stands for a writer (or ``os.fdopen``, whose descriptor it closes) on a full disk."""
    if a and isinstance(a[0], int):
        os.close(a[0])
    raise OSError(errno.ENOSPC, "No space left on device")


def _main(capsys, *argv):
    capsys.readouterr()
    rc = CLI.main([*map(str, argv)])
    return rc, capsys.readouterr().err


def _stopped(rc, err, how):
    if how == "sigterm":
        assert rc == 128 + signal.SIGTERM and "terminated by signal" in err, (rc, err)
    else:
        assert rc == 2 and err.startswith("error: ") and "No space left on device" in err, (rc, err)


HOW = {"sigterm": _sigterm, "error": _full}


# ---- solve ----------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("how", ["sigterm", "error"])
@pytest.mark.parametrize("npz", [False, True], ids=["json", "npz"])
def test_solve_removes_the_folders_it_made(tmp_path, capsys, monkeypatch, how, npz):
    from metamaterial_wb.core import resultfile
    if npz:
        monkeypatch.setattr(resultfile, "write_npz", HOW[how])
    else:
        monkeypatch.setattr(os, "fdopen", HOW[how])       # write_atomic's file (solve's one writer)
    rc, err = _main(capsys, "solve", FISH, "--out", tmp_path / "new" / "deeper" / "r.json", *(["--npz"] if npz else []))
    _stopped(rc, err, how)
    assert os.listdir(tmp_path) == []                     # new/deeper/ and new/ are gone


# ---- simulate -------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("how", ["sigterm", "error"])
def test_simulate_removes_the_folder_it_made(tmp_path, capsys, monkeypatch, how):
    monkeypatch.setattr(fileio, "write_json", HOW[how])   # its trajectory.json, the first file of the set
    rc, err = _main(capsys, "simulate", FISH, "--seconds", "0.1", "--no-dt-check", "--out", tmp_path / "a" / "sim")
    _stopped(rc, err, how)
    assert os.listdir(tmp_path) == []


def test_simulate_keeps_a_folder_that_was_there(tmp_path, capsys, monkeypatch):
    out = tmp_path / "sim"
    out.mkdir()
    (out / "notes.txt").write_text("mine", encoding="utf-8")
    empty = tmp_path / "empty"
    empty.mkdir()
    monkeypatch.setattr(fileio, "write_json", _sigterm)
    for folder in (out, empty):
        rc, err = _main(capsys, "simulate", FISH, "--seconds", "0.1", "--no-dt-check", "--out", folder)
        _stopped(rc, err, "sigterm")
    assert sorted(os.listdir(tmp_path)) == ["empty", "sim"] and os.listdir(empty) == []
    assert os.listdir(out) == ["notes.txt"] and (out / "notes.txt").read_text(encoding="utf-8") == "mine"


# ---- sleeve ---------------------------------------------------------------------------------------------------
@pytest.fixture
def quick_sleeve(monkeypatch, tmp_path):
    """The sleeve analysis replaced by a stub (its minutes are not what is tested); returns the spec's path."""
    import shutil
    from metamaterial_wb.core.sleeve import pipeline
    monkeypatch.setattr(pipeline, "analyse", lambda spec, progress=None, log=None: (
        {"format": "metamaterial-sleeve-summary", "accuracy": {"notes": []}}, {}))
    spec = tmp_path / "spec" / "sleeve.json"
    spec.parent.mkdir()
    shutil.copy(os.path.join(REPO, "examples", "sleeve.json"), spec)
    return spec


@pytest.mark.parametrize("where", ["write", "commit"])
@pytest.mark.parametrize("how", ["sigterm", "error"])
def test_sleeve_removes_the_folders_it_made(tmp_path, capsys, monkeypatch, quick_sleeve, how, where):
    """``write``: stopped while the summary is written (the parents of --out made, --out not yet); ``commit``: while
    the files are moved into --out (made by then)."""
    monkeypatch.setattr(fileio, "write_json" if where == "write" else "commit_set", HOW[how])
    rc, err = _main(capsys, "sleeve", quick_sleeve, "--out", tmp_path / "new" / "a" / "out", "--no-plots", "--quiet")
    _stopped(rc, err, how)
    assert os.listdir(tmp_path) == ["spec"]


def test_sleeve_keeps_the_folders_that_were_there(tmp_path, capsys, monkeypatch, quick_sleeve):
    out = tmp_path / "out"
    out.mkdir()
    monkeypatch.setattr(fileio, "commit_set", _sigterm)
    rc, err = _main(capsys, "sleeve", quick_sleeve, "--out", out, "--no-plots", "--quiet")
    _stopped(rc, err, "sigterm")
    assert sorted(os.listdir(tmp_path)) == ["out", "spec"] and os.listdir(out) == []


# ---- build ----------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("how", ["sigterm", "error"])
def test_build_removes_the_folders_it_made(tmp_path, capsys, monkeypatch, how):
    """The geometry replaced by an empty result (FreeCAD is not what is tested); stopped while it writes."""
    from types import SimpleNamespace
    import metamaterial_wb.export.package as package
    import metamaterial_wb.geometry.build as gb
    monkeypatch.setattr(gb, "build_scene", lambda *a, **k: SimpleNamespace(modules=[], groups=lambda: {"sheet": []}))
    monkeypatch.setattr(package, "_write_files", HOW[how])
    rc, err = _main(capsys, "build", STRIP, "--out", tmp_path / "new" / "b", "--3mf", "--no-check", "--quiet")
    _stopped(rc, err, how)
    assert os.listdir(tmp_path) == []


# ---- the helpers ----------------------------------------------------------------------------------------------
def test_only_the_new_folders_that_are_empty_are_removed(tmp_path):
    from metamaterial_wb.core.outdir import make_dirs, missing_dirs, remove_new_dirs
    (tmp_path / "had").mkdir()
    made = make_dirs(str(tmp_path / "had" / "x" / "y"))
    assert made == [str(tmp_path / "had" / "x" / "y"), str(tmp_path / "had" / "x")]
    (tmp_path / "had" / "x" / "theirs.txt").write_text("kept", encoding="utf-8")     # not the run's: x stays
    remove_new_dirs(made)
    assert os.listdir(tmp_path / "had" / "x") == ["theirs.txt"]
    assert missing_dirs(tmp_path / "had") == [] and make_dirs(str(tmp_path / "had")) == []


# ---- the input that is one of the outputs is named for what it is ----------------------------------------------
def test_a_sleeve_spec_among_the_outputs_is_called_the_sleeve_spec(tmp_path, capsys):
    """``sleeve DIR/summary.json --out DIR`` called the spec "the scene this command reads"."""
    import shutil
    spec = tmp_path / "summary.json"
    shutil.copy(os.path.join(REPO, "examples", "sleeve.json"), spec)
    before = spec.read_bytes()
    rc, err = _main(capsys, "sleeve", spec, "--out", tmp_path, "--no-plots", "--quiet")
    assert rc == 2 and err.strip().count("\n") == 0, err
    assert err.startswith(f"error: --out: {spec} is the sleeve spec this command reads; the sleeve run writes "
                          f"summary.json there and it would be overwritten: choose another output folder or move the "
                          f"sleeve spec"), err
    assert "scene" not in err and spec.read_bytes() == before and os.listdir(tmp_path) == ["summary.json"]


def test_a_scene_among_the_outputs_is_still_the_scene(tmp_path):
    from metamaterial_wb.core.errors import SceneError
    scene = tmp_path / "manifest.json"
    scene.write_text("{}", encoding="utf-8")
    with pytest.raises(SceneError, match=r"manifest\.json is the scene this command reads; the build writes "
                                         r"manifest\.json there .* or move the scene$"):
        fileio.check_scene_not_output(str(tmp_path), ["manifest.json"], str(scene), writer="the build")
