"""Animate: every shape the profile editor offers round-trips. A motor's row set to a shape (sine / square / triangle /
keyframes, looped over the shape combo's own items) shows the same shape and fields when the panel reopens after OK,
and again after the document is saved, closed and opened. A triangle (stored as the scene format's ``keyframes``
profile) reopened as "keyframes"; a keyframes profile that is not exactly such a triangle stays "keyframes"; a scene
JSON holding a triangle is loaded through the document objects and written back unchanged."""
import json
import os

import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

from metamaterial_wb.objects import structure  # noqa: E402
from guihelpers import click, doc, press_ok, process, run_panel, type_into, workbench  # noqa: E402,F401
from test_gui_panel_details import open_example  # noqa: E402

WAVES = {"sine": (0.45, 0.7, 30.0), "square": (0.35, 0.8, 60.0), "triangle": (0.6, 0.8, 60.0)}
KEYS = ((0.0, 0.1), (0.4, 0.7), (1.1, -0.3))


def items(sc):
    return {i.ItemName: i for i in sc.Items}


def offered(p, name):
    combo = p.shapes[name]
    return [combo.itemData(k) for k in range(combo.count())]


def set_row(p, name, shape, wave=None):
    """Choose ``shape`` in the row through its combo box and type its fields; the fields the row then shows."""
    combo = p.shapes[name]
    combo.setCurrentIndex(combo.findData(shape))
    process()
    if shape == "keyframes":
        tbl = p.keyframes.table
        while tbl.rowCount() > 1:
            click(p.keyframes.del_btn)
        while tbl.rowCount() < len(KEYS):
            click(p.keyframes.add_btn)
        for r, (tk, vk) in reversed(list(enumerate(KEYS))):    # the last key first: times stay increasing
            type_into(tbl.cellWidget(r, 0), f"{tk:g}")
            type_into(tbl.cellWidget(r, 1), f"{vk:g}")
    else:
        for w, v in zip(p.spins[name], wave or WAVES[shape]):
            type_into(w, f"{v:g}")
    return shown(p, name)


def shown(p, name):
    shape = p.shape_of(name)
    if shape == "keyframes":
        return shape, tuple(p.keyframes.points()) if p.key_motor == name else None
    return shape, tuple(round(w.value(), 9) for w in p.spins[name])


def check_reopened(sc, name, want, profile):
    p = run_panel("MM_Animate")
    process(50)
    got = shown(p, name)
    assert got[0] == want[0], f"a stored {want[0]} reopened as {got[0]}"
    assert got == want
    if want[0] != "keyframes":
        assert all(w.isEnabled() for w in p.spins[name]), f"the {want[0]}'s boxes are not editable"
    assert p.profiles()[name] == profile
    n = sc.Document.UndoCount
    assert press_ok(), p.error.text()
    assert sc.Document.UndoCount == n, "OK without edits changed the profile"


def test_every_offered_shape_reopens_the_same(doc, tmp_path):
    sc = open_example("fish")
    p = run_panel("MM_Animate")
    head = list(p.shapes)[0]
    shapes = offered(p, head)
    assert {"sine", "square", "triangle", "keyframes"} <= set(shapes), shapes
    p.reject()
    d = doc
    try:
        for k, shape in enumerate(shapes):
            p = run_panel("MM_Animate")
            want = set_row(p, head, shape)
            assert want[0] == shape and want[1] is not None
            assert not p.problems, p.problems
            profile = p.profiles()[head]
            assert press_ok(), p.error.text()
            assert {a.name: a.profile for a in structure.compose_scene(sc).actuators}[head] == profile
            check_reopened(sc, head, want, profile)
            # save, close, open: the same shape and fields again
            path = os.path.join(str(tmp_path), f"roundtrip{k}.FCStd")
            d.saveAs(path)
            FreeCAD.closeDocument(d.Name)
            d = FreeCAD.openDocument(path)
            FreeCAD.setActiveDocument(d.Name)
            sc = structure.find_scene_objects(d)[0]
            check_reopened(sc, head, want, profile)
    finally:
        if d is not doc and d.Name in FreeCAD.listDocuments():
            FreeCAD.closeDocument(d.Name)


@pytest.mark.parametrize("amp, f, ph", [(0.6, 0.8, 60.0), (0.5, 0.5, 90.0), (0.25, 1.3, -90.0), (1.0, 0.7, 180.0),
                                        (0.2, 0.603, 37.5), (0.0, 2.0, 10.0), (0.4, 0.9, -179.9)])
def test_a_stored_triangle_reopens_as_a_triangle(doc, amp, f, ph):
    sc = open_example("fish")
    p = run_panel("MM_Animate")
    tail = list(p.shapes)[1]
    want = set_row(p, tail, "triangle", (amp, f, ph))
    assert press_ok(), p.error.text()
    it = items(sc)[tail]
    assert it.ProfileShape == "keyframes"
    stored = it.ProfileData
    check_reopened(sc, tail, want, dict(json.loads(stored), shape="keyframes"))
    assert it.ProfileData == stored
    # an edit of the recognised triangle writes the triangle with the new value, the others kept
    p = run_panel("MM_Animate")
    type_into(p.spins[tail][0], "0.15")
    assert press_ok(), p.error.text()
    p = run_panel("MM_Animate")
    assert shown(p, tail) == ("triangle", (0.15, f, ph))
    assert max(json.loads(items(sc)[tail].ProfileData)["values"]) == pytest.approx(0.15)
    p.reject()


@pytest.mark.parametrize("data", [
    {"times_s": [0.0, 0.5, 1.0], "values": [0.0, 0.5, -0.25], "period_s": 2.0},          # not +-A
    {"times_s": [0.0, 0.7], "values": [0.5, -0.5], "period_s": 2.0},                      # not a half period
    {"times_s": [0.0, 0.5000001], "values": [0.5, -0.5], "period_s": 1.0},               # a hair off
    {"times_s": [0.0, 0.5], "values": [0.5, -0.5]},                                       # no period: plays once
    {"times_s": [0.0, 0.5, 1.0, 1.5], "values": [0.5, -0.5, 0.5, -0.5], "period_s": 2.0},  # two cycles
])
def test_other_keyframes_stay_keyframes(doc, data):
    sc = open_example("fish")
    head = [i.ItemName for i in sc.Items if i.Kind == "actuator"][0]
    it = items(sc)[head]
    doc.openTransaction("keyframes")
    it.ProfileShape = "keyframes"
    it.ProfileData = json.dumps(data)
    doc.commitTransaction()
    doc.recompute()
    stored = it.ProfileData
    p = run_panel("MM_Animate")
    process(50)
    assert p.shape_of(head) == "keyframes"
    assert p.profiles()[head] == dict(data, shape="keyframes")
    assert press_ok(), p.error.text()
    assert it.ProfileData == stored


def test_a_scene_file_with_a_triangle_is_kept_through_the_objects(doc, tmp_path):
    from metamaterial_wb.core.scene import Scene
    from metamaterial_wb.gui.panels.profiles import wave_profile
    from metamaterial_wb.objects.make import load_scene_file
    here = os.path.dirname(os.path.abspath(__file__))
    with open(os.path.join(here, "..", "..", "examples", "fish.json"), encoding="utf-8") as fh:
        d = json.load(fh)
    tri = wave_profile("triangle", 0.7, 0.6, -45.0)
    d["actuators"][1]["profile"] = tri
    path = os.path.join(str(tmp_path), "tri.json")
    with open(path, "w", encoding="utf-8") as fh:
        json.dump(d, fh)
    sc = load_scene_file(doc, path)
    written = json.loads(structure.scene_json(sc))
    assert written["actuators"][1]["profile"] == tri
    assert Scene.from_dict(written).actuators[1].profile == tri
    name = d["actuators"][1]["name"]
    p = run_panel("MM_Animate")
    process(50)
    assert shown(p, name) == ("triangle", (0.7, 0.6, -45.0))
    p.reject()
