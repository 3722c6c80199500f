"""The modules' solids follow the workbench preferences that shape them (audit aud_gui10): a changed snap-fit
clearance left every module's old solid, and Recompute did not rebuild it (no object was touched) until an
unrelated edit rebuilt it silently; a clearance at or above the socket lip refused every module naming
fabrication.socket_lip_mm, which the user never set, not the preference."""
import pytest

FreeCAD = pytest.importorskip("FreeCAD")

import metamaterial_wb  # noqa: E402
from metamaterial_wb import PREFS_PATH  # noqa: E402
from metamaterial_wb.core.scene import Scene  # noqa: E402
from metamaterial_wb.objects import structure  # noqa: E402
from test_fc_objects import doc  # noqa: E402,F401 - the App tests' document fixture


@pytest.fixture
def clearance():
    """The parameter group with PrinterClearance as it was afterwards (stored value or none)."""
    prm = FreeCAD.ParamGet(PREFS_PATH)
    had = "PrinterClearance" in prm.GetFloats()
    old = prm.GetFloat("PrinterClearance")
    prm.RemFloat("PrinterClearance")
    yield prm
    if had:
        prm.SetFloat("PrinterClearance", old)
    else:
        prm.RemFloat("PrinterClearance")


def touched(doc):
    return sorted(o.Name for o in doc.Objects if "Touched" in o.State)


def fresh_volume(sc, m):
    """Volume of the solid the module's builder makes now (what Export builds for it)."""
    return structure.build_module_shape(m, structure.compose_scene(sc))[0].Volume


def fish_modules(doc):
    sc = structure.make_structure(doc, Scene.load(metamaterial_wb.example_path("fish_modules")))
    doc.recompute()
    assert sc.Modules and all(m.isValid() for m in sc.Modules)
    return sc


def test_a_changed_clearance_touches_the_modules_and_recompute_rebuilds_them(doc, clearance):
    sc = fish_modules(doc)
    m = sc.Modules[0]
    v0 = m.Shape.Volume
    assert touched(doc) == []
    clearance.SetFloat("PrinterClearance", 0.4)          # what OK on the preferences page stores
    assert {o.Name for o in sc.Modules} <= set(touched(doc)), touched(doc)
    doc.recompute()
    assert touched(doc) == [] and m.isValid(), m.getStatusString()
    assert abs(m.Shape.Volume - v0) > 1.0, "the clearance must change the solid (else this proves nothing)"
    assert abs(m.Shape.Volume - fresh_volume(sc, m)) < 1e-6 * m.Shape.Volume
    clearance.SetFloat("PrinterClearance", 0.4)          # OK again with the same value: nothing is stale
    assert touched(doc) == []
    clearance.RemFloat("PrinterClearance")               # back to the scene's own clearance
    assert m.Name in touched(doc)
    doc.recompute()
    assert abs(m.Shape.Volume - v0) < 1e-6 * v0


def test_a_clearance_at_the_socket_lip_names_the_preference_and_recovers(doc, clearance):
    sc = fish_modules(doc)
    clearance.SetFloat("PrinterClearance", 0.6)
    doc.recompute()
    bad = [m for m in sc.Modules if not m.isValid()]
    assert len(bad) == len(sc.Modules), [m.getStatusString() for m in sc.Modules]
    text = bad[0].getStatusString()
    assert "Snap-fit clearance (mm) (PrinterClearance): 0.6 mm is not below the 0.5 mm socket lip" in text, text
    assert "allowed range [0, 0.5) mm" in text, text
    clearance.SetFloat("PrinterClearance", 0.3)          # a value that builds: the invalid modules rebuild
    assert {o.Name for o in sc.Modules} <= set(touched(doc)), touched(doc)
    doc.recompute()
    assert all(m.isValid() for m in sc.Modules), [m.getStatusString() for m in sc.Modules]
