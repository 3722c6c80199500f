"""``--out`` naming a symbolic link replaced the link by a regular file (the atomic write renames a temporary file
over the path; session 33): the file the link points to kept its old content. A user expects what ``cp`` and
editors do, the target written and the link kept. A dangling link is written to its target when the target's
folder exists, and otherwise refused (one line naming the link and its target; nothing written). Through the real
CLI (solve: write_atomic; design --report: write_together; stream --report: write_json) and fileio itself."""
import os

import pytest

from clihelpers import REPO, one_line_error, run_cli

from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.core.fileio import check_output, write_atomic, write_together

FISH = os.path.join(REPO, "examples", "fish.json")
FISH_AXES = os.path.join(REPO, "examples", "fish_axes.json")


def linked(tmp_path, content="old"):
    """``(link, target)``: ``tmp/out/r.json`` -> ``tmp/real/target.json`` (another folder, a relative link)."""
    (tmp_path / "out").mkdir()
    (tmp_path / "real").mkdir()
    target = tmp_path / "real" / "target.json"
    if content is not None:
        target.write_text(content, encoding="utf-8")
    link = tmp_path / "out" / "r.json"
    os.symlink(os.path.join("..", "real", "target.json"), link)
    return link, target


def assert_written_through(link, target, words):
    assert os.path.islink(link), "the link was replaced by a file"
    assert os.path.samefile(link, target)
    text = target.read_text(encoding="utf-8")
    assert words in text, text[:200]
    for folder in {link.parent, target.parent}:
        assert not [n for n in os.listdir(folder) if n.startswith(".")], os.listdir(folder)     # no temporaries


@pytest.mark.parametrize("content", ["old", None], ids=["existing", "dangling"])
def test_solve_out_through_a_link_writes_the_target(tmp_path, content):
    link, target = linked(tmp_path, content)
    r = run_cli("solve", FISH, "--out", link)
    assert r.returncode == 0, r.stderr
    assert_written_through(link, target, '"metamaterial-result"')


def test_design_out_and_report_through_links(tmp_path):
    link, target = linked(tmp_path)
    rep_target = tmp_path / "real" / "rep.json"
    rep_link = tmp_path / "out" / "rep.json"
    os.symlink(rep_target, rep_link)                     # dangling, absolute
    r = run_cli("design", FISH_AXES, "--out", link, "--report", rep_link, "--quiet")
    assert r.returncode == 0, r.stderr
    assert_written_through(link, target, '"metamaterial-scene"')
    assert_written_through(rep_link, rep_target, '"metamaterial-design-report"')


def test_stream_report_through_a_link(tmp_path):
    link, target = linked(tmp_path)
    r = run_cli("stream", FISH, "--dry-run", "--seconds", "0.1", "--report", link)
    assert r.returncode == 0, r.stderr
    assert_written_through(link, target, '"metamaterial-stream-report"')


def test_a_dangling_link_into_a_missing_folder_is_refused_naming_both(tmp_path):
    link = tmp_path / "r.json"
    os.symlink(os.path.join("nowhere", "r.json"), link)
    r = run_cli("solve", FISH, "--out", link)
    one_line_error(r, "--out")
    assert f"{link} is a symbolic link to {os.path.join('nowhere', 'r.json')}" in r.stderr, r.stderr
    assert f"whose folder {tmp_path / 'nowhere'} is not an existing folder" in r.stderr, r.stderr
    assert os.path.islink(link) and not (tmp_path / "nowhere").exists()


def test_a_link_to_the_scene_is_still_refused_as_the_input(tmp_path):
    scene = tmp_path / "s.json"
    scene.write_bytes(open(FISH, "rb").read())
    link = tmp_path / "l.json"
    os.symlink(scene, link)
    r = run_cli("solve", scene, "--out", link)
    one_line_error(r, "--out")
    assert "is the scene this command reads" in r.stderr and scene.read_bytes() == open(FISH, "rb").read()


# ---- the helpers themselves (one place: fileio.write_target) ----------------------------------------------------
@pytest.mark.parametrize("content", ["old", None], ids=["existing", "dangling"])
def test_write_atomic_and_write_together_write_through(tmp_path, content):
    link, target = linked(tmp_path, content)
    write_atomic(str(link), "new one")
    assert os.path.islink(link) and target.read_text(encoding="utf-8") == "new one"
    write_together([(str(link), "newer")])
    assert os.path.islink(link) and target.read_text(encoding="utf-8") == "newer"
    assert check_output(str(link), "file", "--json") == str(link)


def test_the_helpers_refuse_a_link_into_a_missing_folder_before_writing(tmp_path):
    link = tmp_path / "l.txt"
    os.symlink(tmp_path / "no" / "t.txt", link)
    other = tmp_path / "other.txt"
    for call in (lambda: check_output(str(link), "file", "--json"), lambda: write_atomic(str(link), "x"),
                 lambda: write_together([(str(other), "y"), (str(link), "x")])):
        with pytest.raises(SceneError) as e:
            call()
        assert f"{link} is a symbolic link to {tmp_path / 'no' / 't.txt'}" in str(e.value), str(e.value)
    assert not other.exists() and not (tmp_path / "no").exists()
