"""The snap-fit clearance preference against a scene's own socket lip (session 34): the modules' errors name the
preference (not fabrication.socket_lip_mm) whichever of the snap pin's checks refuses it, and the Scene's
SolveWarnings say a cause every module shares once, with how many modules and which, not once per module."""
import pytest

FreeCAD = pytest.importorskip("FreeCAD")

import metamaterial_wb  # noqa: E402
from metamaterial_wb.core.scene import Scene  # noqa: E402
from metamaterial_wb.objects import structure  # noqa: E402
from test_fc_objects import doc  # noqa: E402,F401 - the App tests' document fixture
from test_fc_preference_modules import clearance  # noqa: E402,F401 - PrinterClearance, restored afterwards

PREF = "Edit > Preferences > Metamaterial > Snap-fit clearance (mm) (PrinterClearance)"


def fish_modules(doc, clearance, clr=None, **fabrication):
    """The fish_modules example (four modules) with ``fabrication`` as the scene's own section, built with the
    scene's own clearance, then with the clearance preference ``clr`` (if given), as the preferences page's OK
    sets it (a module made and failing in one recompute shows only "Error" as its status until the next)."""
    d = Scene.load(metamaterial_wb.example_path("fish_modules")).to_dict()
    d["fabrication"] = fabrication
    sc = structure.make_structure(doc, Scene.from_dict(d))
    doc.recompute()
    assert errors(sc) == [], errors(sc)
    if clr is not None:
        clearance.SetFloat("PrinterClearance", clr)
        doc.recompute()
    return sc


def errors(sc):
    return [m.getStatusString() for m in sc.Modules if not m.isValid()]


def module_lines(sc):
    return [w for w in sc.SolveWarnings if "module" in w]


# (socket lip, clearance preference, other fabrication): a lip below the 0.5 mm default that the clearance reaches,
# one above it that the clearance does not (the wider socket its prongs and slot need, further from the plate edge,
# in a material that takes the 0.6 mm barb of the scene's own 0.2 mm clearance)
LIPS = [(0.4, 0.45, {}), (0.8, 0.6, {"socket_diameter_mm": 4.0, "socket_inset_mm": 4.0, "module_material": "PETG"})]


@pytest.mark.parametrize("lip, clr, more", LIPS)
def test_the_scene_socket_lip_decides_with_the_preference(doc, clearance, lip, clr, more):
    """What Export's up-front check must agree with (tests/gui/test_gui_export_clearance.py): the module build
    compares the clearance preference with the scene's own socket lip, not the default 0.5 mm."""
    sc = fish_modules(doc, clearance, clr, socket_lip_mm=lip, **more)
    builds = clr < lip
    if builds:
        assert errors(sc) == [] and module_lines(sc) == [], errors(sc)
        return
    bad = errors(sc)
    assert len(bad) == len(sc.Modules) == 4, bad
    want = f"{PREF}: {clr:g} mm is not below the {lip:g} mm socket lip (fabrication.socket_lip_mm)"
    assert all(want in t and f"allowed range [0, {lip:g}) mm" in t for t in bad), bad


def test_a_shared_cause_is_one_solve_warning(doc, clearance):
    sc = fish_modules(doc, clearance, 0.6)
    labels = [m.Label for m in sc.Modules]
    assert len(errors(sc)) == len(labels) == 4
    for _ in range(2):          # the modules' own runs (first recompute) and their stored errors (the next)
        lines = module_lines(sc)
        assert len(lines) == 1, lines
        assert lines[0].startswith(f"4 modules ({', '.join(labels)}): {PREF}: 0.6 mm is not below the 0.5 mm "
                                   f"socket lip"), lines
        assert "allowed range [0, 0.5) mm" in lines[0] and lines[0].count(PREF) == 1, lines
        sc.touch()
        doc.recompute()
    clearance.RemFloat("PrinterClearance")
    doc.recompute()
    assert errors(sc) == [] and module_lines(sc) == [], sc.SolveWarnings


def test_a_module_failing_for_its_own_reason_keeps_its_line(doc, clearance):
    sc = fish_modules(doc, clearance)
    m = sc.Modules[0]
    m.ModuleData = '{"name": "servo_head", "servo": "NOPE"}'
    doc.recompute()
    lines = module_lines(sc)
    assert len(lines) == 1 and lines[0].startswith(f"module {m.Label}: ") and "NOPE" in lines[0], lines


@pytest.mark.parametrize("fabrication, clr, check", [
    ({"socket_diameter_mm": 2.8}, 0.45, "slot"),            # the 1.9 mm pin has no room for its slot
    ({"module_material": "PLA"}, 0.05, "strained")])        # the barb's 0.45 mm bends the prongs too far
def test_the_snap_pin_errors_name_the_preference(doc, clearance, fabrication, clr, check):
    """A clearance preference below the lip the snap pin still refuses (its slot, its strain): the error names
    the preference with its value, the lip and the allowed range; the scene's own clearance builds."""
    sc = fish_modules(doc, clearance, clr, **fabrication)
    bad = errors(sc)
    assert len(bad) == 4 and all(check in t for t in bad), bad
    for t in bad:
        assert t.count(PREF) == 1 and "0.5 mm socket lip" in t and "allowed range [0, 0.5) mm" in t, t
    if check == "slot":     # the nozzle's narrowest slot sets it: a smaller lip would not help, a smaller clearance
        assert "smaller fabrication.socket_lip_mm" not in bad[0], bad[0]
        assert f"a smaller {PREF} (now 0.45 mm; allowed range [0, 0.5) mm" in bad[0], bad[0]
    else:                   # a larger clearance bends the prongs less
        assert f"less the 0.05 mm clearance of {PREF}, allowed range [0, 0.5) mm" in bad[0], bad[0]
    lines = module_lines(sc)
    assert len(lines) == 1 and lines[0].startswith("4 modules ("), lines
