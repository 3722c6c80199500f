"""Export and the workbench preferences, through the real path: a structure made (New structure panel) from a scene
file with its own ``fabrication`` section, exported by the Export panel (and by ``exporting.export_structure``),
the materials read back from the 3MF. A preference the user never stored leaves the scene's value (as ``build``
does); a stored one wins; a text field cleared to '' is not set."""
import json
import os
import xml.etree.ElementTree as ET
import zipfile

import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

import metamaterial_wb  # noqa: E402
from metamaterial_wb import PREFS_PATH  # noqa: E402
from metamaterial_wb.core.design import effective_tilts_deg  # noqa: E402
from metamaterial_wb.core.fabrication import fabrication_params  # noqa: E402
from metamaterial_wb.gui import exporting, preferences  # noqa: E402
from metamaterial_wb.objects import module as module_obj  # noqa: E402
from metamaterial_wb.objects import structure  # noqa: E402
from guihelpers import click, doc, press_ok, run_panel, type_into, workbench  # noqa: E402,F401

NS = {"m": "http://schemas.microsoft.com/3dmanufacturing/core/2015/02"}
KEYS = {"PrinterClearance": "Float", "RigidMaterial": "String", "FlexibleMaterial": "String",
        "ModuleMaterial": "String"}


@pytest.fixture
def clean_prefs():
    """None of the four fabrication preferences stored during the test; the user's values restored afterwards."""
    prm = FreeCAD.ParamGet(PREFS_PATH)
    saved = {}
    for k, kind in KEYS.items():
        if k in getattr(prm, f"Get{kind}s")():
            saved[k] = getattr(prm, f"Get{kind}")(k)
        getattr(prm, f"Rem{kind}")(k)
    yield prm
    for k, kind in KEYS.items():
        getattr(prm, f"Rem{kind}")(k)
        if k in saved:
            getattr(prm, f"Set{kind}")(k, saved[k])


def threemf_materials(out):
    names = [n for n in os.listdir(out) if n.endswith(".3mf")]
    assert names, os.listdir(out)
    mats = set()
    for n in names:
        model = ET.fromstring(zipfile.ZipFile(os.path.join(out, n)).read("3D/3dmodel.model"))
        mats |= {b.get("name") for b in model.findall(".//m:basematerials/m:base", NS)}
    return mats


def structure_from_scene_with_fabrication(doc, tmp_path):
    with open(metamaterial_wb.example_path("fish"), encoding="utf-8") as f:
        d = json.load(f)
    d["fabrication"] = {"rigid_material": "PETG", "clearance_mm": 0.3}
    path = tmp_path / "fish_petg.json"
    path.write_text(json.dumps(d), encoding="utf-8")
    p = run_panel("MM_NewStructure")
    type_into(p.file, str(path))
    assert press_ok(), p.error.text()
    return structure.find_scene_objects(doc)[-1]


def clearance_used(sc):
    """The clearance Export's parameters and the modules' check (objects/module) use for this structure."""
    scene = structure.compose_scene(sc)
    export_p = fabrication_params(scene, effective_tilts_deg(scene), **exporting.preference_overrides())
    module_p = module_obj._fabricated(scene, [])[1]
    return export_p.clearance_mm, module_p.clearance_mm


def test_export_uses_the_scene_fabrication_unless_a_preference_is_stored(doc, tmp_path, clean_prefs):
    prm = clean_prefs
    sc = structure_from_scene_with_fabrication(doc, tmp_path)
    # no preference stored: the panel's export carries the scene's own rigid material and clearance
    p = run_panel("MM_Export")
    out = str(tmp_path / "unset")
    type_into(p.path, out)
    click(p.export_btn)
    assert p.wait(300), "export did not finish"
    assert p.job.outcome == "done", p.error.text()
    assert threemf_materials(out) == {"PETG", "TPU"}
    assert clearance_used(sc) == (pytest.approx(0.3), pytest.approx(0.3))
    # a stored preference wins over the scene's section
    prm.SetString("RigidMaterial", "ABS")
    prm.SetFloat("PrinterClearance", 0.25)
    out2 = str(tmp_path / "stored")
    exporting.export_structure(sc, out2, step=False, modules=False)
    assert threemf_materials(out2) == {"ABS", "TPU"}
    assert clearance_used(sc) == (pytest.approx(0.25), pytest.approx(0.25))
    # a text field cleared on the preferences page ('') is not set: the scene's value again
    prm.SetString("RigidMaterial", "")
    prm.RemFloat("PrinterClearance")
    out3 = str(tmp_path / "cleared")
    exporting.export_structure(sc, out3, step=False, modules=False)
    assert threemf_materials(out3) == {"PETG", "TPU"}
    assert clearance_used(sc) == (pytest.approx(0.3), pytest.approx(0.3))
    # OK on the preferences page stores every field it shows: at their defaults they are no choice
    prm.SetString("RigidMaterial", "PLA")
    prm.SetFloat("PrinterClearance", 0.2)
    prm.SetString("FlexibleMaterial", "TPU")
    prm.SetString("ModuleMaterial", "ABS")
    assert exporting.preference_overrides() == {}
    assert clearance_used(sc) == (pytest.approx(0.3), pytest.approx(0.3))


def test_a_cleared_text_preference_is_not_set(clean_prefs):
    prm = clean_prefs
    assert exporting.preference_overrides() == {}
    assert module_obj.fabrication_overrides() == {}
    prm.SetString("ModuleMaterial", "")          # what the page stores when the field is cleared
    assert preferences.get("ModuleMaterial") == "ABS"
    assert preferences.stored("ModuleMaterial") is None
    assert "module_material" not in exporting.preference_overrides()
    assert module_obj.fabrication_overrides() == {}
    prm.SetString("ModuleMaterial", "PETG")
    assert preferences.get("ModuleMaterial") == "PETG"
    assert exporting.preference_overrides() == {"module_material": "PETG"}
    assert module_obj.fabrication_overrides() == {"module_material": "PETG"}
