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


def test_a_folder_is_never_replaced_by_a_file(tmp_path):
    """A user's folder that has an output file's name (with their notes in it) was moved aside and deleted with
    the temporary folder: ``build --out`` silently removed it. Now the set is refused before any move."""
    from metamaterial_wb.core.errors import SceneError
    tmp, out = tmp_path / "tmp", tmp_path / "out"
    tmp.mkdir(); out.mkdir()
    for n in ("a.step", "b.3mf"):
        _write(tmp, n, "new " + n)
    (out / "b.3mf").mkdir()
    _write(out / "b.3mf", "notes.txt", "precious")
    with pytest.raises(SceneError, match=r"b\.3mf exists and is a folder; it is not replaced"):
        commit_set(str(tmp), str(out), ["a.step", "b.3mf"])
    assert (out / "b.3mf" / "notes.txt").read_text() == "precious"
    assert not (out / "a.step").exists()                    # nothing half-way
    # and a folder of the set never replaces a file either
    (tmp / "modules").mkdir()
    _write(out, "modules", "a file of the user's")
    with pytest.raises(SceneError, match=r"modules exists and is a file; it is not replaced"):
        commit_set(str(tmp), str(out), ["modules"])
    assert (out / "modules").read_text() == "a file of the user's"


def test_simulate_refuses_a_folder_named_like_its_summary(tmp_path):
    import subprocess
    import sys
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    out = tmp_path / "run"
    (out / "summary.json").mkdir(parents=True)
    _write(out / "summary.json", "notes.txt", "precious")
    r = subprocess.run([sys.executable, "-m", "metamaterial_wb", "simulate", os.path.join(root, "examples",
                        "worm_crawl.json"), "--seconds", "0.05", "--no-dt-check", "--out", str(out)],
                       capture_output=True, text=True, cwd=root, timeout=300, env=dict(os.environ, PYTHONPATH=root))
    assert r.returncode == 2 and "summary.json exists and is a folder" in r.stderr, r.stderr
    assert (out / "summary.json" / "notes.txt").read_text() == "precious"
    assert sorted(p.name for p in out.iterdir()) == ["summary.json"]
