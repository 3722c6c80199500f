"""The snap-fit clearance preference in Export's own runs and without sockets (session 34 follow-up): a script's
``exporting.export_structure`` and the Export panel's background job (``gui/export_job.py``) built their fabrication
parameters without the preference's mark, so the snap pins' slot / strain errors named the scene's
fabrication.socket_lip_mm, not the preference the clearance came from; and the modules' build refused a clearance
preference at or above the socket lip in a scene with ``fabrication.sockets: false``, where no snap pin is designed
(the modules fail there for that reason, which their error must name)."""
import json

import pytest

FreeCAD = pytest.importorskip("FreeCAD")

import metamaterial_wb  # noqa: E402
from metamaterial_wb.core.errors import MetamaterialError  # noqa: E402
from metamaterial_wb.core.scene import Scene  # noqa: E402
from metamaterial_wb.gui import export_job, exporting  # noqa: E402
from metamaterial_wb.objects import structure  # noqa: E402
from test_fc_objects import doc  # noqa: E402,F401 - the App tests' document fixture
from test_fc_preference_modules import clearance  # noqa: E402,F401 - PrinterClearance, restored afterwards

PREF = "Edit > Preferences > Metamaterial > Snap-fit clearance (mm) (PrinterClearance)"
SOCKETS_OFF = "modules plug into the node sockets, but fabrication.sockets is false"


def example(doc, name, **fabrication):
    """The example ``name`` with ``fabrication`` as the scene's own section, as a structure in ``doc``."""
    d = Scene.load(metamaterial_wb.example_path(name)).to_dict()
    d["fabrication"] = fabrication
    sc = structure.make_structure(doc, Scene.from_dict(d))
    doc.recompute()
    rebuild(doc, sc)
    return sc


def rebuild(doc, sc):
    """Recompute the modules of ``sc`` again (a module made and failing in one recompute shows only "Error" as
    its status until the next)."""
    for m in sc.Modules:
        m.touch()
    doc.recompute()


def errors(sc):
    return [m.getStatusString() for m in sc.Modules if not m.isValid()]


def written(folder):
    return sorted(p.name for p in folder.iterdir() if not p.name.startswith(".")) if folder.exists() else []


# (the scene's fabrication, the clearance preference, what the snap pin refuses) as in test_fc_clearance_lip.py
PINS = [({"socket_diameter_mm": 2.8}, 0.45, "slot"),     # the 1.9 mm pin has no room for its slot
        ({"module_material": "PLA"}, 0.05, "strained")]  # the barb's 0.45 mm bends the prongs too far


def named_the_preference(text, clr, check):
    assert check in text and PREF in text, text
    assert f"{clr:g} mm" in text and "0.5 mm socket lip" in text and "allowed range [0, 0.5) mm" in text, text


@pytest.mark.parametrize("fabrication, clr, check", PINS)
def test_a_script_export_names_the_preference(doc, clearance, tmp_path, fabrication, clr, check):
    sc = example(doc, "fish_modules", **fabrication)
    assert errors(sc) == [], errors(sc)        # the scene's own 0.2 mm clearance builds
    clearance.SetFloat("PrinterClearance", clr)
    out = tmp_path / "out"
    with pytest.raises(MetamaterialError) as info:
        exporting.export_structure(sc, str(out), step=False)
    named_the_preference(str(info.value), clr, check)
    assert written(out) == []


@pytest.mark.parametrize("fabrication, clr, check", PINS)
def test_the_background_job_names_the_preference(doc, clearance, tmp_path, capsys, fabrication, clr, check):
    """The job file as the Export panel writes it (its overrides are the preferences), run by the child's main."""
    sc = example(doc, "fish_modules", **fabrication)
    clearance.SetFloat("PrinterClearance", clr)
    scene = structure.compose_scene(sc)
    out = tmp_path / "stage"
    out.mkdir()
    job = {"scene": scene.to_dict(), "out_dir": str(out), "step": False, "threemf": True, "modules": True,
           "sockets": True, "overrides": exporting.preference_overrides(), "stem": "fish_modules"}
    assert job["overrides"].get("clearance_mm") == pytest.approx(clr)
    jpath = tmp_path / "job.json"
    jpath.write_text(json.dumps(job), encoding="utf-8")
    assert export_job.main([str(jpath)]) == 2
    err = capsys.readouterr().err
    named_the_preference(err, clr, check)
    assert written(out) == []


def test_without_the_preference_the_scene_is_named(doc, clearance, tmp_path):
    """The scene's own clearance (no preference) is not called the preference: the errors name the scene's
    fields, as the command line's build does."""
    sc = example(doc, "fish_modules", socket_diameter_mm=2.8, clearance_mm=0.45)
    assert errors(sc) and all(PREF not in t and "slot" in t for t in errors(sc)), errors(sc)
    with pytest.raises(MetamaterialError) as info:
        exporting.export_structure(sc, str(tmp_path / "out"), step=False)
    assert "slot" in str(info.value) and PREF not in str(info.value), str(info.value)


def test_scene_without_sockets_is_not_refused_the_clearance(doc, clearance, tmp_path):
    """``fabrication.sockets: false``: the modules are refused for that (they plug into the sockets), not for a
    clearance preference at or above the lip, which builds the sheet (the files are written)."""
    sc = example(doc, "fish_modules", sockets=False)
    before = errors(sc)
    assert len(before) == 4 and all(SOCKETS_OFF in t for t in before), before
    clearance.SetFloat("PrinterClearance", 0.6)
    rebuild(doc, sc)
    bad = errors(sc)
    assert len(bad) == 4 and all(SOCKETS_OFF in t and PREF not in t for t in bad), bad
    assert sc.isValid(), sc.getStatusString()
    out = tmp_path / "sheet"
    files = exporting.export_structure(sc, str(out), step=False, modules=False)
    assert files and written(out) and any(n.endswith(".3mf") for n in written(out)), written(out)
    # with sockets the same preference is refused, naming it (the check is not gone)
    sc2 = example(doc, "fish_modules")
    bad = errors(sc2)
    assert len(bad) == 4 and all(f"{PREF}: 0.6 mm is not below the 0.5 mm socket lip" in t for t in bad), bad
