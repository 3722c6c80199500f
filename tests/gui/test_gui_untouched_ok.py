"""An OK that changes nothing writes nothing: the stored values are kept exactly, not as the widgets round
them (a fold of 5.25 deg became 5.3, an amplitude of 0.1234 became 0.123, a keyframes period of 0.8 s became the
timeline's 2 s, a global deformation of 0.123 became 0.12 with an undo step), and a value typed is kept as typed."""
import json

import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

from metamaterial_wb.objects import structure  # noqa: E402
from guihelpers import doc, press_ok, process, run_panel, type_into, workbench  # noqa: E402,F401
from test_gui_panel_details import open_example  # noqa: E402


def folds(sc):
    return [a["fold_deg"] for a in json.loads(sc.SceneJSON)["axes"]]


def test_folded_shape_keeps_untouched_folds_and_typed_ones(doc):
    sc = open_example("fish_axes")
    axes = json.loads(sc.SceneJSON)["axes"]
    for a, f in zip(axes, (5.25, 8.04, 12.0, 15.0)):
        a["fold_deg"] = f
    structure.set_scene_fields(sc, axes=axes, joint_config=None)
    doc.recompute()
    p = run_panel("MM_FoldedShape")
    assert press_ok()
    assert folds(sc) == [5.25, 8.04, 12.0, 15.0]
    p = run_panel("MM_FoldedShape")
    spin = p.spins[2]
    if spin.isVisible():
        type_into(spin, "12.25")
    else:
        spin.setValue(12.25)
    process()
    assert press_ok()
    assert folds(sc) == [5.25, 8.04, 12.25, 15.0]


def test_animate_keeps_untouched_profiles(doc):
    sc = open_example("fish")
    head, tail = sc.Items[0], sc.Items[1]
    head.Amplitude, head.PhaseDeg = 0.1234, 12.25
    tail.ProfileShape = "keyframes"
    tail.ProfileData = json.dumps({"times_s": [0.0, 0.3], "values": [0.0, 0.4], "period_s": 0.8})
    doc.recompute()
    assert sc.isValid()
    before = (head.Amplitude, head.PhaseDeg, tail.ProfileShape, tail.ProfileData)
    undo0 = doc.UndoCount
    run_panel("MM_Animate")
    assert press_ok()
    assert (head.Amplitude, head.PhaseDeg, tail.ProfileShape, tail.ProfileData) == before
    assert doc.UndoCount == undo0


def test_simulate_keeps_an_untouched_global_deformation(doc):
    sc = open_example("fish")
    sc.UseGlobal, sc.GlobalDeformation = True, 0.123
    doc.recompute()
    undo0 = doc.UndoCount
    run_panel("MM_Simulate")
    assert press_ok()
    assert sc.GlobalDeformation == 0.123 and sc.UseGlobal
    assert doc.UndoCount == undo0                       # nothing changed: no undo step
