"""A set of files moved in together (core/fileio.commit_set: ``solve --npz``, and the files inside ``build`` /
``simulate`` / ``sleeve`` / ``inverse`` output folders) replaced a destination that is a symbolic link by a regular
file, while a single output (write_atomic, write_together) is written through to the file the link points to
(session 33, as ``cp`` does). Now the set writes through too, also to a file in another folder, and stays all or
nothing: a failed move restores the link's file; two names that are one file through a link, or a link into a
missing folder, are refused before anything moves."""
import json
import os

import pytest

from clihelpers import REPO, run_cli

from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.core.fileio import commit_set

FISH = os.path.join(REPO, "examples", "fish.json")


def _set(tmp_path, names=("a.json", "b.json")):
    """``(tmp, out, real)``: new files in ``tmp``, the output folder ``out``, another folder ``real``."""
    tmp, out, real = tmp_path / "tmp", tmp_path / "out", tmp_path / "real"
    for d in (tmp, out, real):
        d.mkdir()
    for n in names:
        (tmp / n).write_text("new " + n, encoding="utf-8")
    return tmp, out, real


def _link(link, target):
    os.symlink(os.path.relpath(target, os.path.dirname(link)), link)


def _no_temporaries(*folders):
    for f in folders:
        assert not [n for n in os.listdir(f) if n.startswith(".")], os.listdir(f)


@pytest.mark.parametrize("where", ["other-folder", "same-folder"])
@pytest.mark.parametrize("content", ["old", None], ids=["existing", "dangling"])
def test_a_link_is_written_through(tmp_path, where, content):
    tmp, out, real = _set(tmp_path)
    target = (real if where == "other-folder" else out) / "target.json"
    if content is not None:
        target.write_text(content, encoding="utf-8")
    _link(out / "a.json", target)
    commit_set(str(tmp), str(out), ["a.json", "b.json"])
    assert os.path.islink(out / "a.json"), "the link was replaced by a file"
    assert target.read_text(encoding="utf-8") == "new a.json"
    assert (out / "b.json").read_text(encoding="utf-8") == "new b.json"
    _no_temporaries(out, real)


def test_a_failed_move_restores_the_links_file(tmp_path, monkeypatch):
    tmp, out, real = _set(tmp_path)
    target = real / "target.json"
    target.write_text("old", encoding="utf-8")
    _link(out / "a.json", target)
    real_replace = os.replace

    def replace(src, dst):
        if str(dst) == str(out / "b.json"):
            raise OSError(28, "No space left on device")
        return real_replace(src, dst)
    monkeypatch.setattr(os, "replace", replace)
    with pytest.raises(OSError):
        commit_set(str(tmp), str(out), ["a.json", "b.json"])
    monkeypatch.setattr(os, "replace", real_replace)
    assert os.path.islink(out / "a.json") and target.read_text(encoding="utf-8") == "old"
    assert not (out / "b.json").exists()
    _no_temporaries(out, real)


@pytest.mark.parametrize("second", ["a link to it", "its own name"])
def test_two_names_that_are_one_file_are_refused(tmp_path, second):
    tmp, out, real = _set(tmp_path)
    target = (real / "t.json") if second == "a link to it" else (out / "b.json")
    target.write_text("old", encoding="utf-8")
    _link(out / "a.json", target)
    if second == "a link to it":
        _link(out / "b.json", target)
    with pytest.raises(SceneError) as e:
        commit_set(str(tmp), str(out), ["a.json", "b.json"])
    assert "one file" in str(e.value) and str(target) in str(e.value), str(e.value)
    assert target.read_text(encoding="utf-8") == "old" and os.path.islink(out / "a.json")
    assert sorted(os.listdir(tmp)) == ["a.json", "b.json"]


def test_a_link_into_a_missing_folder_is_refused_before_any_move(tmp_path):
    tmp, out, real = _set(tmp_path)
    os.symlink(os.path.join("nowhere", "a.json"), out / "a.json")
    with pytest.raises(SceneError) as e:
        commit_set(str(tmp), str(out), ["b.json", "a.json"])
    assert f"{out / 'a.json'} is a symbolic link to" in str(e.value), str(e.value)
    assert sorted(os.listdir(out)) == ["a.json"] and os.path.islink(out / "a.json")


def test_solve_npz_out_through_links(tmp_path):
    """The .json and the .npz of ``solve --npz``, both links into another folder: both targets written."""
    (tmp_path / "out").mkdir()
    (tmp_path / "real").mkdir()
    out, npz = tmp_path / "out" / "r.json", tmp_path / "out" / "r.npz"
    tj, tn = tmp_path / "real" / "r.json", tmp_path / "real" / "r.npz"
    tj.write_text("old", encoding="utf-8")
    _link(out, tj)
    _link(npz, tn)
    r = run_cli("solve", FISH, "--out", out, "--npz")
    assert r.returncode == 0, r.stderr
    assert os.path.islink(out) and os.path.islink(npz)
    assert json.loads(tj.read_text(encoding="utf-8"))["format"] == "metamaterial-result"
    assert tn.read_bytes()[:2] == b"PK"
    _no_temporaries(tmp_path / "out", tmp_path / "real")
