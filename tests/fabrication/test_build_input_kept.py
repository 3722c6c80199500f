"""``build`` never overwrites the scene it reads (from an audit): with the scene at ``DIR/manifest.json`` and
``--out DIR`` it exited 0 and the scene was replaced by the build manifest. Any planned output (the manifest, the
sheet's STEP / 3MF files, a module's files) that is the scene file (also through a link) is refused before any
geometry, with ``--out``, the file and "the scene this command reads" named; the scene is left as it was."""
import os
import shutil
import subprocess
import sys

import pytest

from fabhelpers import EXAMPLES, REPO

STRIP = os.path.join(EXAMPLES, "strip_fold.json")
FISH_MODULES = os.path.join(EXAMPLES, "fish_modules.json")


class GeometryReached(Exception):
    pass


@pytest.fixture
def no_geometry(monkeypatch):
    """``build_scene`` fails the test if called: a refusal must come before any geometry."""
    import metamaterial_wb.geometry.build as gb

    def fail(*a, **k):
        raise GeometryReached("build_scene was called")
    monkeypatch.setattr(gb, "build_scene", fail)


def build(*args):
    from metamaterial_wb.cli import main
    return main(["build", *map(str, args)])


def assert_refused(rc, capsys, out_file, scene, before):
    err = capsys.readouterr().err
    assert rc == 2, err
    assert err.startswith("error: --out: "), err
    assert f"{out_file} is the scene this command reads" in err and str(scene) in err, err
    assert "it would be overwritten" in err, err
    assert err.strip().count("\n") == 0
    assert scene.read_bytes() == before


def test_the_audit_command_is_refused_and_the_scene_is_kept(tmp_path):
    """As the user runs it (a process); the tests below patch the builder to show the refusal comes first."""
    d = tmp_path / "m"
    d.mkdir()
    scene = d / "manifest.json"
    shutil.copy(STRIP, scene)
    before = scene.read_bytes()
    r = subprocess.run([sys.executable, "-m", "metamaterial_wb", "build", str(scene), "--out", str(d), "--3mf",
                        "--quiet"], capture_output=True, text=True, cwd=REPO, timeout=300,
                       env=dict(os.environ, PYTHONPATH=REPO))
    assert r.returncode == 2, (r.stdout, r.stderr)
    assert r.stderr.startswith(f"error: --out: {d / 'manifest.json'} is the scene this command reads"), r.stderr
    assert "it would be overwritten" in r.stderr
    assert r.stdout == ""
    assert scene.read_bytes() == before
    assert sorted(os.listdir(d)) == ["manifest.json"]        # nothing written, no temporary folder left


@pytest.mark.parametrize("flags", [("--3mf",), ("--step",), ()], ids=["3mf", "step", "both"])
def test_manifest_json_as_the_scene_is_refused_before_any_geometry(tmp_path, capsys, no_geometry, flags):
    scene = tmp_path / "manifest.json"
    shutil.copy(STRIP, scene)
    before = scene.read_bytes()
    rc = build(scene, "--out", tmp_path, *flags, "--quiet")
    assert_refused(rc, capsys, tmp_path / "manifest.json", scene, before)


def test_a_hard_link_and_a_linked_out_folder_are_the_same_file(tmp_path, capsys, no_geometry):
    scene = tmp_path / "scene.json"
    shutil.copy(STRIP, scene)
    before = scene.read_bytes()
    out = tmp_path / "out"
    out.mkdir()
    os.link(scene, out / "manifest.json")               # the scene under the manifest's name
    rc = build(scene, "--out", out, "--3mf", "--quiet")
    assert_refused(rc, capsys, out / "manifest.json", scene, before)
    os.unlink(out / "manifest.json")
    ln = tmp_path / "ln"
    os.symlink(tmp_path, ln)                             # --out through a link to the scene's own folder
    shutil.copy(STRIP, tmp_path / "manifest.json")
    m = tmp_path / "manifest.json"
    before = m.read_bytes()
    rc = build(m, "--out", ln, "--3mf", "--quiet")
    assert_refused(rc, capsys, ln / "manifest.json", m, before)


def test_the_scene_as_the_sheet_file_is_refused(tmp_path, capsys, no_geometry):
    """A scene file named like the sheet's STEP (its stem comes from the scene's ``name``)."""
    scene = tmp_path / "strip_fold_sheet.step"
    shutil.copy(STRIP, scene)
    before = scene.read_bytes()
    rc = build(scene, "--out", tmp_path, "--step", "--quiet")
    assert_refused(rc, capsys, tmp_path / "strip_fold_sheet.step", scene, before)


def test_the_scene_as_a_module_file_is_refused(tmp_path, capsys, no_geometry):
    scene = tmp_path / "fish_modules_servo_head.3mf"
    shutil.copy(FISH_MODULES, scene)
    before = scene.read_bytes()
    rc = build(scene, "--out", tmp_path, "--3mf", "--modules", "--quiet")
    assert_refused(rc, capsys, tmp_path / "fish_modules_servo_head.3mf", scene, before)


def test_a_scene_beside_the_outputs_is_built(tmp_path, no_geometry):
    """Not over-eager: a scene in --out that no output is named like reaches the geometry."""
    scene = tmp_path / "strip_fold.json"
    shutil.copy(STRIP, scene)
    with pytest.raises(GeometryReached):
        build(scene, "--out", tmp_path, "--3mf", "--quiet")
