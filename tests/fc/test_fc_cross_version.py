"""A document saved on FreeCAD 1.1 opens whole on every FreeCAD (0.20, 1.0, 1.1).

FreeCAD 1.1 gives ``Part::FeaturePython`` two properties 0.20 does not have (``ShapeMaterial``,
``_ElementMapVersion``). The save-time record of our objects counted all their properties, so on FreeCAD 0.20
every node and hinge shape of a file saved on 1.1 counted two short: "the file is damaged: 8 object(s) lost",
the file name cleared and ``save()`` refused. The fixtures were saved on FreeCAD 1.1
(``tests/fixtures/make_fc11_documents.py``): one by the code that recorded counts, one by today's code. Each is
opened in a fresh session (the workbench imported as FreeCAD's restore finds it), recomputed and saved again.
"""
import json
import os
import shutil
import subprocess
import sys

import pytest

pytest.importorskip("FreeCAD")

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
FIXTURES = os.path.join(REPO, "tests", "fixtures")
sys.path.insert(0, os.path.dirname(HERE))
from scriptload import load_script  # noqa: E402

PROBE = r"""
import sys, json
sys.path.append("/usr/lib/freecad-python3/lib"); sys.path.append("/usr/lib/freecad/lib")
import FreeCAD
sys.path.insert(0, REPO)
import metamaterial_wb.objects.structure
from metamaterial_wb.objects import structure
from metamaterial_wb.objects.common import repair_report
doc = FreeCAD.openDocument(PATH)
rep = repair_report(doc)
out = {"report": rep, "file_name": doc.FileName, "version": FreeCAD.Version()[:2]}
doc.recompute()
out["invalid"] = [o.Name for o in doc.Objects if not o.isValid()]
sc = next(o for o in doc.Objects if getattr(getattr(o, "Proxy", None), "Type", "") == "MetamaterialScene")
out["scene"] = structure.compose_scene(sc).to_dict()
try:
    doc.save()
    out["saved"] = True
except Exception as exc:
    out["saved"] = repr(exc)
json.dump(out, open(OUT, "w"))
"""


@pytest.mark.parametrize("name", ["fc11_count_manifest.FCStd", "fc11_structure.FCStd"])
def test_a_document_saved_on_freecad_1_1_opens_whole_and_saves(name, tmp_path):
    src = os.path.join(FIXTURES, name)
    path, out = tmp_path / name, tmp_path / "probe.json"
    shutil.copy(src, path)
    code = f"REPO = {REPO!r}\nPATH = {str(path)!r}\nOUT = {str(out)!r}\n" + PROBE
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300, cwd=str(tmp_path),
                       env={k: v for k, v in os.environ.items() if k != "PYTHONPATH"})
    assert out.exists(), r.stdout[-2000:] + r.stderr[-2000:]
    res = json.loads(out.read_text())
    rep = res["report"]
    assert rep["lost"] == [] and rep["unknown"] == [] and not rep["locked"], (res["version"], rep, r.stderr[-1500:])
    assert res["file_name"] == str(path) and res["saved"] is True, res
    assert res["invalid"] == [], res
    scene = load_script("tests/fixtures/make_legacy_structure.py", "make_legacy_structure").SCENE
    got = res["scene"]
    for key in ("layout", "cell_size_mm", "hinge"):
        assert got[key] == scene[key], key
    assert [a["joint"] for a in got["actuators"]] == ["V0,0"] and [c["joint"] for c in got["constraints"]] == ["H0,1"]
    assert sorted(m["type"] for m in got["modules"]) == ["friction_pad", "servo_housing"]


def test_the_record_names_only_the_workbenchs_own_properties():
    """The record of a file saved on FreeCAD 1.1 names properties the workbench adds (``ProxyClass`` and the
    like), never FreeCAD's own (``ShapeMaterial``, ``Placement``), which differ between FreeCAD versions."""
    import html
    import re
    import zipfile
    with zipfile.ZipFile(os.path.join(FIXTURES, "fc11_structure.FCStd")) as z:
        xml = z.read("Document.xml").decode()
    m = re.search(r'key="metamaterial_wb\.objects\.2" value="([^"]*)"', xml)
    assert m, "no metamaterial_wb.objects.2 record"
    rec = json.loads(html.unescape(m.group(1)))
    assert rec and all("ProxyClass" in props for props in rec.values()), rec
    named = set().union(*map(set, rec.values()))
    assert not named & {"ShapeMaterial", "_ElementMapVersion", "Placement", "Shape", "Label", "Proxy"}, named
