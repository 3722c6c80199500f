"""Issue 19, documents: the add-on installed in a Mod folder (as the README tells users), a fish document
opened headless in ``freecadcmd`` by a script that never imports ``metamaterial_wb``, then saved.

Nothing may be lost: the saved file must still carry every proxy and all data, and a session that finds
proxies dropped (the file was saved earlier by a session without the add-on) must say so and re-attach
them before anything is saved. Runs on every lane (each lane's own ``freecadcmd`` and Mod folder layout).
"""
import json
import os
import re
import shutil
import subprocess
import sys
import zipfile

import pytest

FreeCAD = pytest.importorskip("FreeCAD")

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
FCLIB = "/usr/lib/freecad-python3/lib"
FREECADCMD = shutil.which("freecadcmd") or shutil.which("FreeCADCmd")
pytestmark = pytest.mark.skipif(FREECADCMD is None, reason="freecadcmd is not installed")

OURS = ["HingeShape", "Motor_head", "Motor_tail", "NodeShape", "Scene"]


def _env(home):
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH" and not k.startswith("XDG_")}
    env["HOME"] = str(home)
    return env


def _home_with_addon(tmp_path):
    """A fresh HOME whose FreeCAD user Mod folder holds a link to this checkout (README's install)."""
    home = tmp_path / "home"
    user_data = os.path.relpath(FreeCAD.getUserAppDataDir(), os.path.expanduser("~"))
    mod = home / user_data / "Mod"
    mod.mkdir(parents=True)
    os.symlink(REPO, mod / "MetamaterialWorkbench")
    return home


def _python(code, cwd, home):
    """FreeCAD as a library in a fresh interpreter, HOME without any add-on."""
    head = f"import sys, json\nsys.path.append({FCLIB!r})\nimport FreeCAD\n"
    r = subprocess.run([sys.executable, "-c", head + code], cwd=cwd, capture_output=True, text=True,
                       timeout=300, env=_env(home))
    assert r.returncode == 0, r.stdout + r.stderr
    return r.stdout + r.stderr


def _freecadcmd(script, cwd, home):
    path = cwd / "headless_script.py"
    path.write_text(script + "\nimport sys\nsys.stdout.flush(); sys.stderr.flush()\n", encoding="utf-8")
    r = subprocess.run([FREECADCMD, str(path)], cwd=cwd, capture_output=True, timeout=300, env=_env(home),
                       stdin=subprocess.DEVNULL)
    out = (r.stdout + r.stderr).decode("utf-8", "replace")
    assert r.returncode == 0, out
    return out


HEADLESS = """
import json, os, FreeCAD
doc = FreeCAD.openDocument({path!r})
print("PROXIES", json.dumps({{o.Name: (type(o.Proxy).__name__ if o.Proxy is not None else None)
                             for o in doc.Objects if "ProxyClass" in o.PropertiesList}}))
before = os.stat({path!r}).st_mtime_ns
try:
    doc.save()
    print("SAVE_OK")
except Exception as exc:
    print("SAVE_FAILED", exc)
print("FILE_CHANGED", json.dumps(os.stat({path!r}).st_mtime_ns != before))
"""

PROBE = """
from metamaterial_wb.objects.common import repair_report
res = {o.Name: (type(o.Proxy).__name__ if o.Proxy is not None else None)
       for o in doc.Objects if "ProxyClass" in o.PropertiesList}
print("PROXIES", json.dumps(res))
sc = doc.getObject("Scene")
print("SCENEJSON", json.dumps(sc.SceneJSON if sc else None))
print("OBJECTS", json.dumps(sorted(o.Name for o in doc.Objects)))
print("REPORT", json.dumps(repair_report(doc)))
doc.recompute()
print("VALID", all(o.isValid() for o in doc.Objects))
"""


def _line(out, key):
    return json.loads(next(ln for ln in out.splitlines() if ln.startswith(key + " "))[len(key) + 1:])


def _open_with_package(path, cwd, home):
    return _python(f"sys.path.insert(0, {REPO!r})\nimport metamaterial_wb.objects.structure\n"
                   f"doc = FreeCAD.openDocument({str(path)!r})\n" + PROBE, cwd, home)


def _saved_proxy_modules(path):
    """module="..." of every saved Python proxy in Document.xml (a dropped proxy is saved without one)."""
    xml = zipfile.ZipFile(path).read("Document.xml").decode("utf-8")
    return re.findall(r'<Python value="[^"]*" encoded="yes" module="(metamaterial_wb[^"]*)"', xml)


@pytest.fixture
def fish(tmp_path):
    bare = tmp_path / "bare"
    bare.mkdir()
    f = tmp_path / "fish.FCStd"
    _python(f"""sys.path.insert(0, {REPO!r})
from metamaterial_wb.core.scene import Scene
from metamaterial_wb.objects import structure
doc = FreeCAD.newDocument("t")
structure.make_structure(doc, Scene.load({os.path.join(REPO, 'examples', 'fish.json')!r}))
doc.recompute()
doc.saveAs({str(f)!r})
""", tmp_path, bare)
    ref = _open_with_package(f, tmp_path, bare)
    assert sorted(_line(ref, "PROXIES")) == OURS and all(_line(ref, "PROXIES").values()), ref
    return f, ref, bare


def _same_as_reference(out, ref):
    assert _line(out, "OBJECTS") == _line(ref, "OBJECTS")
    assert _line(out, "SCENEJSON") == _line(ref, "SCENEJSON")
    assert all(_line(out, "PROXIES").values()) and sorted(_line(out, "PROXIES")) == OURS, out
    assert "VALID True" in out, out


def test_headless_open_and_save_with_the_addon_installed_keeps_everything(fish, tmp_path):
    f, ref, bare = fish
    home = _home_with_addon(tmp_path)
    out = _freecadcmd(HEADLESS.format(path=str(f)), tmp_path, home)
    assert "SAVE_OK" in out and _line(out, "FILE_CHANGED") is True, out
    assert "damaged" not in out and "lost" not in out, out       # a sound file is never called damaged
    assert len(_saved_proxy_modules(f)) == len(OURS), out
    _same_as_reference(_open_with_package(f, tmp_path, bare), ref)


def test_headless_open_of_a_file_whose_proxies_were_dropped_says_so_and_saves_them_back(fish, tmp_path):
    f, ref, bare = fish
    # a session without the add-on (no Mod folder, package never imported) opens and saves: proxies dropped
    _python(f"doc = FreeCAD.openDocument({str(f)!r})\ndoc.save()\n", tmp_path, bare)
    assert _saved_proxy_modules(f) == []
    # freecadcmd with the add-on installed, the script never imports the package
    home = _home_with_addon(tmp_path)
    out = _freecadcmd(HEADLESS.format(path=str(f)), tmp_path, home)
    assert "without the metamaterial_wb package" in out and "re-attached" in out, out
    assert all(_line(out, "PROXIES").values()), out
    assert "SAVE_OK" in out, out
    assert len(_saved_proxy_modules(f)) == len(OURS), out     # the save wrote the proxies back
    _same_as_reference(_open_with_package(f, tmp_path, bare), ref)


def _rewrite(path, old, new):
    tmp = path.with_suffix(".tmp")
    with zipfile.ZipFile(path) as zi, zipfile.ZipFile(tmp, "w") as zo:
        for item in zi.infolist():
            data = zi.read(item.filename)
            if item.filename == "Document.xml":
                assert old.encode() in data
                data = data.replace(old.encode(), new.encode())
            zo.writestr(item, data)
    os.replace(tmp, path)


def test_headless_open_that_cannot_reattach_says_so_and_refuses_to_save_over_the_file(fish, tmp_path):
    """A dropped proxy whose class this add-on does not have (a file of a newer version): the session says
    which object, and save() is refused, so the original file keeps what this session could not read."""
    f, ref, bare = fish
    _python(f"doc = FreeCAD.openDocument({str(f)!r})\ndoc.save()\n", tmp_path, bare)    # proxies dropped
    _rewrite(f, "metamaterial_wb.objects.scene:SceneProxy", "metamaterial_wb.objects.scene:GoneProxy")
    before = f.read_bytes()
    out = _freecadcmd(HEADLESS.format(path=str(f)), tmp_path, _home_with_addon(tmp_path))
    assert "could not be re-attached (Scene)" in out and "not saving over" in out, out
    assert "SAVE_FAILED" in out and _line(out, "FILE_CHANGED") is False, out
    assert f.read_bytes() == before
