"""A full disk gave only ``error: No space left on device`` (session 33: ``build --out`` on a small tmpfs): a file
object's ``write`` raises ``OSError(ENOSPC)`` with no file name, and the CLI prints the name an OSError carries.
Now the writers of core/fileio.py (write_atomic, write_together, commit_set, make_temp_dir) raise it naming the
output file as the user knows it (``OUT/a.step``, not the temporary folder it is written in first), and the CLI
says what to do. The disk is simulated (a file object whose write fails, or a failing rename): no mount needed."""
import errno
import os

import pytest

from clihelpers import REPO

from metamaterial_wb import cli as CLI
from metamaterial_wb.core import fileio
from metamaterial_wb.core.fileio import OutputSet, commit_set, make_temp_dir, write_atomic, write_together

FISH = os.path.join(REPO, "examples", "fish.json")
FISH_AXES = os.path.join(REPO, "examples", "fish_axes.json")
FULL = "No space left on device"


class _FullFile:
    """A file whose every write fails as on a full disk: OSError(ENOSPC) without a file name."""

    def __init__(self, f):
        self._f = f

    def write(self, data):
        raise OSError(errno.ENOSPC, FULL)

    def __getattr__(self, name):
        return getattr(self._f, name)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self._f.close()
        return False


@pytest.fixture
def full_disk(monkeypatch):
    """Every file opened by write_atomic (the one user of os.fdopen here) fails to write; returns the call count."""
    real = os.fdopen
    calls = []

    def fdopen(fd, *a, **k):
        calls.append(fd)
        return _FullFile(real(fd, *a, **k))

    monkeypatch.setattr(os, "fdopen", fdopen)
    return calls


def _no_temporaries(folder):
    assert not [n for n in os.listdir(folder) if n.startswith(".")], os.listdir(folder)


def _is_full(exc, path):
    assert exc.errno == errno.ENOSPC and exc.strerror == FULL, exc
    assert exc.filename == str(path), (exc.filename, str(path))


# ---- fileio ---------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("how", ["text", "callable"])
def test_write_atomic_names_the_file(tmp_path, full_disk, how):
    path = tmp_path / "r.json"
    path.write_text("old", encoding="utf-8")

    def savez(fh):          # as np.savez writing into the open file
        fh.write(b"PK")
    with pytest.raises(OSError) as e:
        write_atomic(str(path), "new" if how == "text" else savez, "w" if how == "text" else "wb")
    _is_full(e.value, path)
    assert full_disk and path.read_text(encoding="utf-8") == "old"
    _no_temporaries(tmp_path)


def test_an_error_of_another_file_is_not_renamed(tmp_path):
    """A callable's own error about another file keeps its name: only the file written is put in."""
    def reads(fh):
        raise FileNotFoundError(errno.ENOENT, "No such file or directory", "/elsewhere/in.txt")
    with pytest.raises(FileNotFoundError) as e:
        write_atomic(str(tmp_path / "o.txt"), reads)
    assert e.value.filename == "/elsewhere/in.txt"


def test_a_file_of_a_set_is_named_in_its_output_folder(tmp_path, full_disk):
    """Written first into OUT/.tmp-PID-.../: the error names OUT/a.step, where the user looks for it."""
    out = tmp_path / "out"
    with pytest.raises(OSError) as e:
        with OutputSet(str(out)) as tmp:
            write_atomic(os.path.join(tmp, "a.step"), "x")
    _is_full(e.value, out / "a.step")
    assert not out.exists()                 # the folder the failed set created is removed again


def test_write_together_names_the_file(tmp_path, full_disk):
    a, b = tmp_path / "a.json", tmp_path / "sub" / "b.json"
    with pytest.raises(OSError) as e:
        write_together([(str(a), "x"), (str(b), "y")])
    _is_full(e.value, a)
    assert os.listdir(tmp_path) == []


def test_commit_set_names_the_file_whose_move_failed(tmp_path, monkeypatch):
    tmp, out = tmp_path / "tmp", tmp_path / "out"
    tmp.mkdir()
    out.mkdir()
    for n in ("a.step", "b.3mf"):
        (tmp / n).write_text("new", encoding="utf-8")
    real = os.replace

    def replace(src, dst):
        if str(dst) == str(out / "b.3mf"):
            raise OSError(errno.ENOSPC, FULL)
        return real(src, dst)
    monkeypatch.setattr(os, "replace", replace)
    with pytest.raises(OSError) as e:
        commit_set(str(tmp), str(out), ["a.step", "b.3mf"])
    monkeypatch.setattr(os, "replace", real)
    _is_full(e.value, out / "b.3mf")
    assert os.listdir(out) == []


def test_make_temp_dir_names_the_folder(tmp_path, monkeypatch):
    def mkdtemp(dir=None, prefix=None):
        raise OSError(errno.ENOSPC, FULL, os.path.join(dir, prefix + "abc"))
    monkeypatch.setattr(fileio.tempfile, "mkdtemp", mkdtemp)
    with pytest.raises(OSError) as e:
        make_temp_dir(str(tmp_path), "build")
    _is_full(e.value, tmp_path)


# ---- the CLI, in process (the writer patched) ------------------------------------------------------------------
def _cli_full(capsys, argv, named):
    capsys.readouterr()
    rc = CLI.main([*map(str, argv)])
    err = capsys.readouterr().err
    lines = [ln for ln in err.strip().splitlines() if ln.startswith("error:")]
    assert rc == 2 and len(lines) == 1, err
    assert lines[0].startswith(f"error: {named}: {FULL}; free space there"), err
    assert "write to a folder on another disk" in lines[0], err
    assert "Traceback" not in err


def test_solve_names_its_out_file(tmp_path, capsys, full_disk):
    out = tmp_path / "r.json"
    _cli_full(capsys, ["solve", FISH, "--out", out], out)
    assert os.listdir(tmp_path) == []


def test_simulate_names_the_file_in_its_out_folder(tmp_path, capsys, full_disk):
    out = tmp_path / "sim"
    _cli_full(capsys, ["simulate", FISH, "--seconds", "0.1", "--out", out], out / "trajectory.json")
    assert not os.path.exists(out) or os.listdir(out) == []


def test_design_names_the_file_of_the_pair(tmp_path, capsys, full_disk):
    out, report = tmp_path / "c.json", tmp_path / "rep.json"
    _cli_full(capsys, ["design", FISH_AXES, "--out", out, "--report", report, "--quiet"], out)
    assert os.listdir(tmp_path) == []


def test_another_os_error_keeps_its_words(tmp_path, capsys, monkeypatch):
    """Only a full disk (or quota) gets the advice; a refused write is FILE: REASON as before."""
    def refuse(fd, *a, **k):
        os.close(fd)
        raise PermissionError(errno.EACCES, "Permission denied")
    monkeypatch.setattr(os, "fdopen", refuse)
    out = tmp_path / "r.json"
    capsys.readouterr()
    assert CLI.main(["solve", FISH, "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.strip().splitlines()[-1] == f"error: {out}: Permission denied", err
