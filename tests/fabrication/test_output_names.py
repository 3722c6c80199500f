"""build's output names are known before any geometry: a module named like one of the sheet's files, or a scene
name too long for a file name, is refused at once (one line, exit 2, nothing written, an earlier build in the
folder untouched); the commit refuses duplicate names up front; removals of an earlier build's files are
always said, also with --quiet."""
import json
import os
import subprocess
import sys

import pytest

from metamaterial_wb.core.errors import SceneError

from fabhelpers import REPO


def _scene(tmp_path, **kw):
    d = {"format": "metamaterial-scene", "version": 1, "name": "t", "layout": {"chain": 2}}
    d.update(kw)
    path = tmp_path / "s.json"
    path.write_text(json.dumps(d))
    return str(path)


def _build(scene, out, *args):
    return subprocess.run([sys.executable, "-m", "metamaterial_wb", "build", scene, "--out", str(out), *args],
                          cwd=REPO, capture_output=True, text=True, timeout=600)


def _lines(stderr):
    return [ln for ln in stderr.splitlines() if ln.strip()]


def test_module_named_like_the_sheets_components_file_is_refused_and_an_earlier_build_kept(tmp_path):
    """Audit fz/modname_sc.json: the pad named "sheet_components" wrote t_sheet_components.3mf over the sheet's;
    the failed build (an internal .build-* path error) had replaced the earlier build's file by the pad."""
    out = tmp_path / "o"
    out.mkdir()
    (out / "t_sheet_components.3mf").write_text("the earlier build's sheet")
    (out / "manifest.json").write_text(json.dumps({"format": "metamaterial-build-manifest", "version": 1,
                                                   "files": ["t_sheet_components.3mf"]}))
    scene = _scene(tmp_path, modules=[{"type": "friction_pad", "name": "sheet_components", "node": "N0,0"}])
    r = _build(scene, out, "--modules")
    assert r.returncode == 2, r.stderr
    lines = _lines(r.stderr)
    assert len(lines) == 1 and lines[0].startswith("error: modules[0].name"), r.stderr
    assert "t_sheet_components.3mf" in lines[0] and "allowed" in lines[0] and ".build-" not in lines[0]
    assert sorted(os.listdir(out)) == ["manifest.json", "t_sheet_components.3mf"]
    assert (out / "t_sheet_components.3mf").read_text() == "the earlier build's sheet"


def test_output_names_are_planned_per_format_and_layout():
    from metamaterial_wb.export.package import check_output_names, output_names
    names = [n for n, _, _ in output_names("t", ["servo", "pad"], step=True, threemf=True,
                                           layouts=("prusa", "components"))]
    assert names == ["t_sheet.step", "t_sheet.3mf", "t_sheet_components.3mf", "t_servo.step", "t_servo.3mf",
                     "t_pad.step", "t_pad.3mf", "t_assembly.step", "manifest.json"]
    assert [n for n, _, _ in output_names("t", [], step=False, threemf=True, layouts=("prusa",))] == \
        ["t_sheet.3mf", "manifest.json"]
    with pytest.raises(SceneError) as e:       # a module's files over the sheet's components layout
        check_output_names("t", [(4, "sheet_components")], step=False, threemf=True, layouts=("components",))
    assert e.value.field == "modules[4].name" and "t_sheet_components.3mf" in e.value.message
    with pytest.raises(SceneError) as e:       # names that differ only in case are one file on Windows / macOS
        check_output_names("t", [(0, "pad"), (1, "Pad")], step=True, threemf=False, layouts=())
    assert e.value.field == "modules[1].name" and "t_pad.step" in e.value.message
    check_output_names("t", [(0, "sheet_components")], step=True, threemf=False, layouts=())     # no clash


def test_the_commit_refuses_duplicate_names_before_moving_anything(tmp_path):
    """Defence in depth: a set that names one file twice is refused before any move (commit_set had moved the
    first, then restored the second copy over the earlier file); every writer of a set goes through commit_set."""
    from metamaterial_wb.core.fileio import commit_set
    out = tmp_path / "o"
    out.mkdir()
    (out / "a.3mf").write_text("old")
    tmp = tmp_path / "new"
    tmp.mkdir()
    (tmp / "a.3mf").write_text("new")
    with pytest.raises(SceneError, match="a.3mf"):
        commit_set(str(tmp), str(out), ["a.3mf", "b.step", "A.3mf"])
    assert (out / "a.3mf").read_text() == "old" and sorted(os.listdir(out)) == ["a.3mf"]


def test_export_result_checks_the_names_before_writing(tmp_path):
    """The GUI's export calls export_result directly: it refuses a clash before it writes (or creates) anything."""
    from types import SimpleNamespace

    from metamaterial_wb.export.package import export_result

    class Result:
        modules = [SimpleNamespace(index=0, name="sheet_components")]

        def groups(self):
            return {"sheet": [], "sheet_components": []}

    out = tmp_path / "new" / "o"
    with pytest.raises(SceneError) as e:
        export_result(Result(), str(out), stem="t", checks=(), progress=False)
    assert e.value.field == "modules[0].name"
    assert not (tmp_path / "new").exists()


def test_a_failed_export_removes_the_folders_it_created(tmp_path, monkeypatch):
    from metamaterial_wb.export import manifest, package

    class Result:
        modules = []
        parts = []
        checks_ran = ()

        def groups(self):
            return {}

    def boom(*a, **k):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(manifest, "build_manifest", boom)
    out = tmp_path / "new" / "o"
    with pytest.raises(OSError):
        package.export_result(Result(), str(out), stem="t", checks=(), progress=False)
    assert not (tmp_path / "new").exists()
    kept = tmp_path / "kept"
    kept.mkdir()
    with pytest.raises(OSError):
        package.export_result(Result(), str(kept), stem="t", checks=(), progress=False)
    assert kept.is_dir() and os.listdir(kept) == []


def test_a_scene_name_too_long_for_a_file_name_is_refused_before_any_work(tmp_path):
    """Audit fz/longname.json: 240 letters failed only after the whole build ("File name too long" on an internal
    path) and left an empty --out folder."""
    out = tmp_path / "o"
    r = _build(_scene(tmp_path, name="a" * 240), out)
    assert r.returncode == 2, r.stderr
    lines = _lines(r.stderr)
    assert len(lines) == 1 and lines[0].startswith("error: name: "), r.stderr
    assert "255 bytes" in lines[0] and "allowed" in lines[0] and "at most 234 bytes" in lines[0], lines[0]
    assert "sheet parts" not in r.stderr and not out.exists()


def test_a_module_name_that_makes_a_file_name_too_long_is_named(tmp_path):
    from metamaterial_wb.export.package import check_output_names
    stem = "b" * 200
    check_output_names(stem, [(0, "m" * 40)], step=True, threemf=True, layouts=("prusa", "components"))
    with pytest.raises(SceneError) as e:
        check_output_names(stem, [(0, "p"), (1, "m" * 60)], step=True, threemf=True, layouts=("prusa",))
    assert e.value.field == "modules[1].name" and "255 bytes" in e.value.message


def test_quiet_still_names_the_removed_files(fc, tmp_path):
    """docs/fabrication.md: files of an earlier build that this one does not write are removed and named on
    stderr; --quiet silenced that too (it is not progress)."""
    out = tmp_path / "o"
    out.mkdir()
    (out / "t_old.step").write_text("old")
    (out / "manifest.json").write_text(json.dumps({"format": "metamaterial-build-manifest", "version": 1,
                                                   "files": ["t_old.step"]}))
    r = _build(_scene(tmp_path), out, "--quiet", "--3mf", "--layout", "prusa", "--no-sockets")
    assert r.returncode == 0, r.stderr
    assert "removed 1 file(s) of the earlier build that this one does not write: t_old.step" in r.stderr
    assert sorted(os.listdir(out)) == ["manifest.json", "t_sheet.3mf"]
