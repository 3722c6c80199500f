"""The snap pin's errors say where its clearance came from (geometry/snapfit.py, session 34): a FabParams whose
maker names the clearance's origin (``clearance_origin``: the workbench's preference, objects/module.py) gets
errors naming it with its value, the socket lip and the allowed range; without one (the scene's
fabrication.clearance_mm, the command line's --clearance) they name no preference. The slot's error asks for a
smaller socket lip only when the barb sets the slot: when the nozzle's narrowest slot does, the clearance."""
import json

import pytest

import metamaterial_wb
from metamaterial_wb.core.design import effective_tilts_deg
from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.core.fabrication import fabrication_params
from metamaterial_wb.core.scene import Scene
from metamaterial_wb.geometry.snapfit import design_snap_fit

from clihelpers import one_line_error, run_cli

PREF = "Edit > Preferences > Metamaterial > Snap-fit clearance (mm) (PrinterClearance)"


def fish_modules(**fabrication):
    d = Scene.load(metamaterial_wb.example_path("fish_modules")).to_dict()
    d["fabrication"] = fabrication
    return d


def params(clr, origin=None, **fabrication):
    sc = Scene.from_dict(fish_modules(**fabrication))
    p = fabrication_params(sc, effective_tilts_deg(sc), clearance_mm=clr)
    if origin:
        p.clearance_origin = origin
    return p


def refusal(p, material="ABS"):
    with pytest.raises(SceneError) as e:
        design_snap_fit(p, material, "modules[0]")
    return e.value


def test_no_latch_names_the_origin_or_the_lip():
    e = refusal(params(0.6))
    assert (e.field, e.message) == ("fabrication.socket_lip_mm", "0.5 mm with a clearance of 0.6 mm leaves the barb "
                                                                 "no interference to latch; allowed range (0.6, ...) mm")
    e = refusal(params(0.6, PREF))
    assert e.field == PREF, str(e)
    assert e.message.startswith("0.6 mm is not below the 0.5 mm socket lip (fabrication.socket_lip_mm)"), str(e)
    assert "allowed range [0, 0.5) mm" in e.message


def test_the_slot_names_what_sets_it():
    # the nozzle's narrowest slot sets it (barb 0.05 mm): a smaller clearance widens the pin, a smaller lip does not
    e = refusal(params(0.45, socket_diameter_mm=2.8))
    assert e.field == "fabrication.socket_diameter_mm", str(e)
    assert e.message.endswith("use a larger socket_diameter_mm or a smaller clearance"), str(e)
    assert "Preferences" not in str(e)
    e = refusal(params(0.45, PREF, socket_diameter_mm=2.8))
    assert e.message.endswith(f"or a smaller {PREF} (now 0.45 mm; allowed range [0, 0.5) mm, below the 0.5 mm "
                              f"socket lip fabrication.socket_lip_mm)"), str(e)
    # the barb sets it (1 mm lip): the lip, as before, whatever the clearance's origin
    for origin in (None, PREF):
        e = refusal(params(0.2, origin, socket_lip_mm=1.0), "TPU")     # (a prong that bends far enough)
        assert e.message.endswith("use a larger socket_diameter_mm or a smaller fabrication.socket_lip_mm"), str(e)
        assert str(e).count(PREF) == (1 if origin else 0), str(e)


def test_the_strain_names_the_origin():
    e = refusal(params(0.05), "PLA")
    assert e.field == "modules[0].material" and "strained 1.75 %" in e.message, str(e)
    assert "Preferences" not in str(e) and e.message.endswith("or a larger socket_diameter_mm"), str(e)
    e = refusal(params(0.05, PREF), "PLA")
    assert e.message.endswith(f"(the barb's 0.45 mm is the 0.5 mm socket lip less the 0.05 mm clearance of {PREF}, "
                              f"allowed range [0, 0.5) mm: a larger clearance bends the prongs less)"), str(e)


@pytest.mark.parametrize("clr, field, text", [
    ("0.6", "fabrication.socket_lip_mm", "with a clearance of 0.6 mm leaves the barb no interference"),
    ("0.45", "fabrication.socket_diameter_mm", "(after the 0.45 mm clearance) has no room")])
def test_the_command_line_names_no_preference(tmp_path, clr, field, text):
    src = tmp_path / "fish.json"
    src.write_text(json.dumps(fish_modules(socket_diameter_mm=2.8)), encoding="utf-8")
    r = run_cli("build", src, "--modules", "--clearance", clr, "--out", tmp_path / "out")
    one_line_error(r, field)
    assert text in r.stderr and "Preferences" not in r.stderr, r.stderr
    assert not (tmp_path / "out").exists()
