"""The Sleeve actuator panel keeps a spec's own values (audit): its spin boxes show three decimals, but a spec's
t 1.0985 mm or G 0.0005 MPa goes back into the spec unrounded and unclamped unless the user edits that box."""
import json

import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

from guihelpers import doc, run_panel, workbench  # noqa: E402,F401

SPEC = {"format": "metamaterial-sleeve", "version": 1, "name": "exact", "L_mm": 18, "c_mm": 4, "delta_mm": 0.2504,
        "T_mm": 1.8, "shear_modulus_MPa": 0.0005,
        "cell_types": [{"t_mm": 1.0985, "h_mm": 7.092}, {"t_mm": 1.098, "h_mm": 7.4884}], "ring": [0, 0, 1, 1]}


def test_sleeve_panel_keeps_the_specs_exact_values_until_edited(doc, tmp_path):
    from metamaterial_wb.core.sleeve.spec import SleeveSpec

    path = tmp_path / "exact.json"
    path.write_text(json.dumps(SPEC))
    p = run_panel("MM_Sleeve")
    assert p.load_spec(str(path)) is True
    d = p.spec_dict()
    assert d["delta_mm"] == 0.2504 and d["shear_modulus_MPa"] == 0.0005
    assert d["cell_types"] == SPEC["cell_types"]
    assert SleeveSpec(d).G == 0.0005
    # an edited box gives what it shows
    p.types.cellWidget(0, 0).setValue(1.2)
    p.dims["delta_mm"].setValue(0.3)
    d = p.spec_dict()
    assert d["cell_types"][0]["t_mm"] == 1.2 and d["delta_mm"] == 0.3
    assert d["cell_types"][1] == SPEC["cell_types"][1] and d["shear_modulus_MPa"] == 0.0005
    p.reject()
