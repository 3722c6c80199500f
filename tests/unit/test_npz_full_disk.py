"""``solve SCENE --out R.json --npz`` on a full disk printed the clean ``error: R.npz: No space left on device; ...``
line and then a traceback (``Exception ignored in: ZipFile.__del__ ... ValueError: seek of closed file``):
``np.savez`` leaves its ZipFile open when a write fails, and the ZipFile, collected after ``write_atomic`` closed the
file, wrote a zip's directory into it. Now the writer's file drops what comes after the failure: one error line
naming the file, no traceback, nothing written (neither half of the set, no temporary file). The disk is simulated
(a file object whose writes fail once a byte budget is spent, as a real disk fills part-way through): no mount."""
import errno
import gc
import os
import sys

import pytest

from clihelpers import REPO

from metamaterial_wb import cli as CLI

FISH = os.path.join(REPO, "examples", "fish.json")
FULL = "No space left on device"


class _FillingFile:
    """A file on a disk with ``budget[0]`` bytes free: a write beyond them fails with OSError(ENOSPC), no file
    name, as the kernel's does."""

    def __init__(self, f, budget):
        self._f, self._budget = f, budget

    def write(self, data):
        if len(data) > self._budget[0]:
            raise OSError(errno.ENOSPC, FULL)
        self._budget[0] -= len(data)
        return self._f.write(data)

    def __getattr__(self, name):
        return getattr(self._f, name)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self._f.close()
        return False


def _unraisable(monkeypatch):
    """What Python would print as ``Exception ignored in ...`` (a ``__del__`` that raised), collected. Called in the
    test's body: pytest puts its own hook in place for the body, over one a fixture set."""
    seen = []
    monkeypatch.setattr(sys, "unraisablehook", lambda u: seen.append(f"{u.object!r}: {u.exc_type.__name__}: "
                                                                     f"{u.exc_value}"))
    return seen


def _full_after(monkeypatch, free):
    real = os.fdopen
    budget = [free]
    monkeypatch.setattr(os, "fdopen", lambda fd, *a, **k: _FillingFile(real(fd, *a, **k), budget))


# 0: the zip's first header; 100 / 3000: inside an array; 9000: the zip's directory (fish: a 10 kB .npz)
@pytest.mark.parametrize("free", [0, 100, 3000, 9000])
def test_a_full_disk_gives_one_error_and_no_traceback(tmp_path, capsys, monkeypatch, free):
    unraisable = _unraisable(monkeypatch)
    out = tmp_path / "r.json"
    _full_after(monkeypatch, free)
    capsys.readouterr()
    rc = CLI.main(["solve", FISH, "--out", str(out), "--npz", "--model", "quadratic"])
    gc.collect()                    # whatever the failed write left is collected now, as at the process's exit
    err = capsys.readouterr().err
    assert rc == 2, err
    assert err.strip().splitlines() == [f"error: {tmp_path / 'r.npz'}: {FULL}; free space there (or ask for a larger "
                                         f"quota), or write to a folder on another disk, and run the command again"]
    assert unraisable == [], unraisable                           # the ZipFile's __del__ traceback
    assert os.listdir(tmp_path) == []                             # no .npz, no .json, no temporary file


def test_the_disk_filling_at_the_json_half_leaves_neither(tmp_path, capsys, monkeypatch):
    """The .npz written, the .json refused: the set is both or neither, and the error names the .json."""
    unraisable = _unraisable(monkeypatch)
    out = tmp_path / "r.json"
    opened = 0
    real = os.fdopen
    budget = [0]

    def fdopen(fd, *a, **k):     # the first file (the .npz) has room, the next (the .json) none
        nonlocal opened
        opened += 1
        budget[0] = 10 ** 6 if opened == 1 else 0
        return _FillingFile(real(fd, *a, **k), budget)
    monkeypatch.setattr(os, "fdopen", fdopen)
    capsys.readouterr()
    assert CLI.main(["solve", FISH, "--out", str(out), "--npz"]) == 2
    gc.collect()
    err = capsys.readouterr().err
    assert err.strip().splitlines()[-1].startswith(f"error: {out}: {FULL}; free space there"), err
    assert "Traceback" not in err and unraisable == [] and opened == 2
    assert os.listdir(tmp_path) == []
