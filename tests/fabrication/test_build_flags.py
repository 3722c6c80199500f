"""build's flags and its output folder as a user meets them twice: contradictory flags are refused before any
work, and a second build into the same folder leaves the folder as that build says (no files of the first
build left beside a manifest that no longer lists them)."""
import json
import os
import subprocess
import sys

import pytest

from fabhelpers import EXAMPLES, REPO

STRIP = os.path.join(EXAMPLES, "strip_fold.json")


def build(*args):
    return subprocess.run([sys.executable, "-m", "metamaterial_wb", "build", STRIP, *args], cwd=REPO,
                          capture_output=True, text=True, timeout=600)


@pytest.mark.parametrize("args, message", [
    (("--check", "--no-check"), "--no-check: contradicts --check"),
    (("--step", "--layout", "prusa"), "--layout: 'prusa' chooses a 3MF layout, but only --step is written"),
])
def test_contradictory_flags_are_refused(tmp_path, args, message):
    r = build("--out", str(tmp_path / "o"), *args)
    assert r.returncode == 2 and message in r.stderr, r.stderr
    assert not (tmp_path / "o").exists()


def test_a_second_build_removes_the_first_builds_files(fc, tmp_path):
    out = tmp_path / "o"
    assert build("--out", str(out), "--quiet").returncode == 0
    first = sorted(os.listdir(out))
    assert "strip_fold_sheet.step" in first and "strip_fold_sheet_components.3mf" in first
    (out / "notes.txt").write_text("mine")                      # not the build's: kept
    r = build("--out", str(out), "--3mf", "--layout", "prusa")
    assert r.returncode == 0, r.stderr
    assert sorted(os.listdir(out)) == ["manifest.json", "notes.txt", "strip_fold_sheet.3mf"]
    assert json.loads((out / "manifest.json").read_text())["files"] == ["strip_fold_sheet.3mf"]
    assert "removed 2 file(s) of the earlier build" in r.stderr


@pytest.mark.parametrize("flag, value, field", [("--clearance", "-1", "clearance_mm"),
                                                ("--tolerance", "0", "tolerance_mm")])
def test_a_bad_flag_value_names_the_flag(tmp_path, flag, value, field):
    """The error named fabrication.clearance_mm, a field the user never wrote (it came from the flag)."""
    r = build("--out", str(tmp_path / "o"), flag, value)
    assert r.returncode == 2 and r.stderr.startswith(f"error: {flag} (fabrication.{field}): "), r.stderr
    assert not (tmp_path / "o").exists()
