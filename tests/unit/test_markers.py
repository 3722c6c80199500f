"""The pytest markers (docs/testing.md): every test gets one of pure / freecad / gui, from what it imports, and
``pytest -m pure`` collects no FreeCAD test when FreeCAD is hidden."""
import os
import subprocess
import sys

from mm_markers import file_marker

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def t(*parts):
    return os.path.join(REPO, "tests", *parts)


def test_files_are_classified_by_what_they_import(tmp_path):
    assert file_marker(t("gui", "test_gui_workbench.py")) == "gui"
    assert file_marker(t("fc", "test_fc_objects.py")) == "freecad"            # importorskip of FreeCAD
    assert file_marker(t("fc", "test_fc_legacy_document.py")) == "freecad"
    assert file_marker(t("unit", "test_scene.py")) == "pure"
    assert file_marker(t("hardware", "test_protocol.py")) == "pure"
    # through the package, at any depth, function-level imports included
    for name, text, want in (
            ("geometry", "def test_x():\n    from metamaterial_wb.geometry import build  # noqa: F401\n", "freecad"),
            ("core", "def test_x():\n    from metamaterial_wb.core import scene  # noqa: F401\n", "pure"),
            # FreeCAD run in a subprocess (the text split so that this file itself stays pure)
            ("subprocess", "CODE = 'import " + "FreeCAD'\n", "freecad")):
        probe = tmp_path / f"test_probe_{name}.py"   # one file each: the classification is cached per file
        probe.write_text(text)
        assert file_marker(str(probe)) == want, name


def run_collect(*args, hide=True):
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "MM_NO_FREECAD")}
    if hide:
        env["MM_NO_FREECAD"] = "1"
    return subprocess.run([sys.executable, "-m", "pytest", "--collect-only", "-q", "-p", "no:cacheprovider", *args],
                          cwd=REPO, env=env, capture_output=True, text=True, timeout=300)


def test_pure_collects_without_freecad_and_only_pure_tests():
    dirs = ["tests/fc", "tests/unit/test_scene.py", "tests/hardware/test_protocol.py"]
    r = run_collect("-m", "pure", *dirs)
    assert r.returncode == 0, r.stdout[-2000:] + r.stderr[-2000:]
    ids = [ln for ln in r.stdout.splitlines() if "::" in ln]
    files = {i.split("::")[0] for i in ids}
    assert "tests/fc/test_fc_objects.py" not in files and "tests/fc/test_fc_legacy_document.py" not in files, files
    assert "tests/fc/test_fc_trajectory_mapping.py" in files     # core.live only: pure since issue 14
    assert any(i.startswith("tests/unit/test_scene.py::") for i in ids)
    assert "error" not in r.stdout.splitlines()[-1]


def count(r, name):
    assert r.returncode in (0, 5), r.stdout[-2000:] + r.stderr[-2000:]     # 5: nothing collected
    return sum(1 for ln in r.stdout.splitlines() if ln.startswith(name + "::"))


def test_freecad_tests_carry_their_marker():
    f = "tests/fc/test_fc_legacy_document.py"
    everything = count(run_collect(f, hide=False), f)      # 3 with FreeCAD, 0 without (not collected)
    assert count(run_collect("-m", "freecad", f, hide=False), f) == everything
    assert count(run_collect("-m", "pure", f, hide=False), f) == 0
    g = "tests/unit/test_scene.py"
    assert count(run_collect("-m", "pure", g, hide=False), g) == count(run_collect(g, hide=False), g) > 0
