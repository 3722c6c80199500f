"""Issue 19, documents: a file opened without the package, or a damaged file, loses nothing for good.

Every scenario runs FreeCAD (App only) in a fresh /usr/bin/python3 subprocess, because the point is
what happens in a session where ``metamaterial_wb`` was *not* imported before the document opened.
"""
import json
import os
import subprocess
import sys
import zipfile

import pytest

pytest.importorskip("FreeCAD")

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
FCLIB = "/usr/lib/freecad-python3/lib"
HEAD = f"import sys, json\nsys.path.append({FCLIB!r})\nimport FreeCAD\n"
WITH_PKG = f"sys.path.insert(0, {REPO!r})\nimport metamaterial_wb.objects.structure\n"


def run(code, cwd):
    r = subprocess.run([sys.executable, "-c", HEAD + code], cwd=cwd, capture_output=True, text=True, timeout=300,
                       env={k: v for k, v in os.environ.items() if k != "PYTHONPATH"})
    assert r.returncode == 0, r.stdout + r.stderr
    return r.stdout + r.stderr


def make_doc(path, cwd):
    run(WITH_PKG + f"""
from metamaterial_wb.core.scene import Scene
from metamaterial_wb.objects import structure
doc = FreeCAD.newDocument("t")
structure.make_structure(doc, Scene.load({os.path.join(REPO, 'examples', 'fish.json')!r}))
doc.recompute()
doc.saveAs({str(path)!r})
""", cwd)


PROBE = """
res = {}
for o in doc.Objects:
    if "ProxyClass" in o.PropertiesList:
        res[o.Name] = type(o.Proxy).__name__ if o.Proxy is not None else None
print("PROXIES", json.dumps(res))
sc = doc.getObject("Scene")
print("SCENEJSON", len(sc.SceneJSON) if sc else -1)
"""


def proxies(out):
    line = next(ln for ln in out.splitlines() if ln.startswith("PROXIES "))
    return json.loads(line[len("PROXIES "):])


def test_open_without_package_then_save_loses_nothing_for_good(tmp_path):
    f = tmp_path / "fish.FCStd"
    make_doc(f, tmp_path)
    # 1. a session without the package: FreeCAD cannot (or may not) import the proxies: all None
    out = run(f"doc = FreeCAD.openDocument({str(f)!r})\n" + PROBE + "doc.save()\n", tmp_path)
    lost = proxies(out)
    assert lost and all(v is None for v in lost.values()), lost
    # 2. the file saved by that session, opened with the package: every proxy is back, data intact
    out = run(WITH_PKG + f"doc = FreeCAD.openDocument({str(f)!r})\n" + PROBE + """
from metamaterial_wb.objects.common import repair_report
print("REPORT", json.dumps(repair_report(doc)))
doc.recompute()
print("VALID", all(o.isValid() for o in doc.Objects))
""", tmp_path)
    back = proxies(out)
    assert set(back) == set(lost) and all(v for v in back.values()), back
    assert "re-attached" in out and "VALID True" in out


def test_package_imported_after_opening_repairs_open_documents(tmp_path):
    f = tmp_path / "fish.FCStd"
    make_doc(f, tmp_path)
    out = run(f"doc = FreeCAD.openDocument({str(f)!r})\n" + WITH_PKG + PROBE, tmp_path)
    assert all(proxies(out).values()) and "without the metamaterial_wb package" in out


def _truncate(src, dst, keep_fraction):
    with zipfile.ZipFile(src) as zi, zipfile.ZipFile(dst, "w") as zo:
        for item in zi.infolist():
            data = zi.read(item.filename)
            if item.filename == "Document.xml":
                data = data[:int(len(data) * keep_fraction)]
            zo.writestr(item, data)


def test_truncated_document_reports_what_was_lost_and_refuses_to_overwrite(tmp_path):
    f = tmp_path / "fish.FCStd"
    make_doc(f, tmp_path)
    bad = tmp_path / "damaged.FCStd"
    _truncate(f, bad, 0.6)
    before = bad.read_bytes()
    out = run(WITH_PKG + f"""
try:
    doc = FreeCAD.openDocument({str(bad)!r})
except Exception as exc:
    print("OPEN FAILED", exc)
    doc = FreeCAD.ActiveDocument
from metamaterial_wb.objects.common import repair_report
print("REPORT", json.dumps(repair_report(doc)))
try:
    doc.save()
    print("SAVED")
except Exception as exc:
    print("SAVE REFUSED", exc)
""", tmp_path)
    rep = json.loads(next(ln for ln in out.splitlines() if ln.startswith("REPORT "))[7:])
    assert rep["locked"] and rep["lost"], rep
    assert "damaged" in out and "SAVE REFUSED" in out and "SAVED" not in out.split("SAVE REFUSED")[0][-10:]
    assert bad.read_bytes() == before
