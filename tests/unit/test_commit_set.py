"""core.fileio.commit_set, the one "all files or none" move used by build, simulate, sleeve and the GUI's
exports: a move that fails half-way takes back what it moved and restores the files it replaced."""
import os

import pytest

from metamaterial_wb.core.fileio import commit_set


def _write(folder, name, text):
    with open(os.path.join(folder, name), "w") as f:
        f.write(text)


def test_all_files_arrive_and_replace_the_old_ones(tmp_path):
    tmp, out = tmp_path / "tmp", tmp_path / "out"
    tmp.mkdir(); out.mkdir()
    for n in ("a.step", "b.3mf"):
        _write(tmp, n, "new " + n)
    _write(out, "a.step", "old a.step")
    commit_set(str(tmp), str(out), ["a.step", "b.3mf"])
    assert (out / "a.step").read_text() == "new a.step"
    assert (out / "b.3mf").read_text() == "new b.3mf"


def test_a_failed_move_leaves_the_old_set(tmp_path, monkeypatch):
    tmp, out = tmp_path / "tmp", tmp_path / "out"
    tmp.mkdir(); out.mkdir()
    for n in ("a.step", "b.3mf", "c.png"):
        _write(tmp, n, "new " + n)
    _write(out, "a.step", "old a.step")
    real = os.replace

    def failing(src, dst):                     # the disk fills up when the third file moves in
        if str(dst) == str(out / "c.png"):
            raise OSError(28, "No space left on device")
        return real(src, dst)
    monkeypatch.setattr(os, "replace", failing)
    with pytest.raises(OSError, match="No space"):
        commit_set(str(tmp), str(out), ["a.step", "b.3mf", "c.png"])
    monkeypatch.setattr(os, "replace", real)
    assert (out / "a.step").read_text() == "old a.step", "the replaced file is restored"
    assert not (out / "b.3mf").exists(), "a file moved before the failure is taken back"
    assert not (out / "c.png").exists()
    assert (tmp / "b.3mf").read_text() == "new b.3mf"
