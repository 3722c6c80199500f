"""A file output ending in a path separator (``--out out/keep.txt/``) had its separator dropped
(``os.path.abspath`` strips it): the file keep.txt was replaced, and ``--out out/newdir/`` created a FILE named
newdir (user audit, session 35). POSIX reads ``name/`` as a folder, so a file output ending in a separator is
refused: one line naming the flag, the path, that it names a folder and to give a file name; nothing written.
Folder outputs (``--out DIR`` of simulate / sleeve / build / inverse) keep accepting a trailing separator."""
import os

import pytest

from clihelpers import REPO, one_line_error, run_cli

from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.core.fileio import check_output

FISH = os.path.join(REPO, "examples", "fish.json")
FISH_AXES = os.path.join(REPO, "examples", "fish_axes.json")


def _snapshot(folder):
    return {n: (folder / n).read_bytes() if (folder / n).is_file() else "dir" for n in sorted(os.listdir(folder))}


def _commands(out):
    """``(flag, argv)`` of every command with a file output, the output being ``out``."""
    return [
        ("--out", ("solve", FISH, "--out", out)),
        ("--out", ("design", FISH_AXES, "--out", out, "--quiet")),
        ("--report", ("design", FISH_AXES, "--out", os.path.join(os.path.dirname(out.rstrip(os.sep)), "ok.json"),
                      "--report", out, "--quiet")),
        ("--out", ("render", FISH, "--out", out)),
        ("--out", ("calibrate", "model", "--out", out)),
        ("--report", ("stream", FISH, "--dry-run", "--seconds", "0.1", "--report", out)),
        ("--out", ("bench", "fidelity", "--out", out)),
        ("--img", ("bench", "fidelity", "--img", out)),
    ]


@pytest.mark.parametrize("existing", [True, False], ids=["existing-file", "new-name"])
@pytest.mark.parametrize("i", range(len(_commands("x/"))))
def test_a_file_output_ending_in_a_separator_is_refused(tmp_path, existing, i):
    (tmp_path / "out").mkdir()
    if existing:
        (tmp_path / "out" / "keep.txt").write_text("keep\n", encoding="utf-8")
    out = str(tmp_path / "out" / "keep.txt") + os.sep
    flag, argv = _commands(out)[i]
    before = _snapshot(tmp_path / "out")
    r = run_cli(*argv)
    one_line_error(r, flag)
    assert f"{out} ends in '{os.sep}'" in r.stderr, r.stderr
    assert "names a folder" in r.stderr and "give a file name" in r.stderr, r.stderr
    assert _snapshot(tmp_path / "out") == before, "something was written"


def test_check_output_refuses_a_file_name_that_names_a_folder(tmp_path):
    for p in (str(tmp_path / "a.json") + os.sep, str(tmp_path / "a.json") + os.sep + os.sep,
              str(tmp_path / "a.json") + os.sep + ".", str(tmp_path) + os.sep + ".."):
        with pytest.raises(SceneError) as e:
            check_output(p, "file", "--json")
        assert e.value.field == "--json" and "names a folder" in str(e.value), str(e.value)
    assert os.listdir(tmp_path) == []
    assert check_output(str(tmp_path / "a.json"), "file", "--json") == str(tmp_path / "a.json")


def test_a_folder_output_keeps_accepting_a_trailing_separator(tmp_path):
    assert check_output(str(tmp_path / "new") + os.sep, "dir", "--out") == str(tmp_path / "new")
    assert check_output(str(tmp_path) + os.sep, "dir", "--out") == str(tmp_path)
    out = str(tmp_path / "sim") + os.sep
    r = run_cli("simulate", FISH, "--out", out, "--seconds", "0.2")
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "sim" / "summary.json").is_file()
