"""A change made by a script, the Python console or another command while a task panel is open (session 34).

Session 33 made a panel stale when an Undo / Redo moved its structure away from the values it shows. A change made
any other way (``doc.openTransaction(); ...; doc.commitTransaction()`` in the console, a plain property write, the
property editor, another command) went unnoticed: the panel's OK, an untouched one too, wrote its older values over
it in silence (Simulate wrote the old motor value back, Folded shape put back the axis the script had removed).
Such a change to what the panel writes back now makes it stale like an Undo (``UndoWatch.changed_outside``): the
line at the top names what changed, OK is refused, Cancel closes and leaves the change; the line goes once the
document is back at the panel's state. A change the OK leaves alone (a label, a property the panel does not write,
another object, a new motor, a recompute) keeps the panel usable, and its OK keeps that change."""
import json

import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

from metamaterial_wb.gui.panels import base  # noqa: E402
from metamaterial_wb.objects import structure  # noqa: E402
from guihelpers import (dialog_button, doc, press_cancel, press_ok, process, run_panel,  # noqa: E402,F401
                        tracebacks, type_into, workbench)
from test_gui_message_once import said_once_at_top  # noqa: E402
from test_gui_panel_details import open_example  # noqa: E402
from test_gui_undo_stale import axes, ctrl_z, item  # noqa: E402

WORDS = ["changed under this panel", "Cancel"]


def script(d, change, transaction=True):
    """What a console user types: one undo step (openTransaction / commitTransaction), or a plain write."""
    if transaction:
        d.openTransaction("script")
    change()
    if transaction:
        d.commitTransaction()
    process(100)


def assert_stale(p, *names):
    """The top line names what changed (once), OK is disabled and refused (button and Enter)."""
    text = said_once_at_top(p, "stale", WORDS + list(names))
    assert "Undo / Redo" not in text, text
    return text


def assert_usable(p):
    assert "stale" not in p.problems, p.problems
    assert not p.problem_label("stale").isVisible()
    assert dialog_button("Ok").isEnabled()


# ---- a change to what the panel writes back: stale, OK refused, the change kept ---------------------------------
def test_simulate_refuses_ok_after_a_script_changed_a_motor_value_and_undo_of_it_clears_the_line(doc, tracebacks):
    sc = open_example("fish")
    tail = item(sc, "tail")
    p = run_panel("MM_Simulate")
    assert_usable(p)
    script(doc, lambda: setattr(tail, "Value", 0.1))
    assert_stale(p, "tail.Value")
    assert tail.Value == pytest.approx(0.1), "an untouched OK wrote the panel's older value over the script's"
    assert list(doc.UndoNames)[0] == "script", doc.UndoNames
    ctrl_z()                                     # Undo of the script's step: the document is the panel's again
    assert tail.Value == pytest.approx(0.8)
    assert_usable(p)
    p.set_value("tail", -0.5)
    process()
    assert press_ok(), p.error.text()
    assert tail.Value == pytest.approx(-0.5)
    assert not tracebacks, tracebacks[0]


def test_folded_shape_never_puts_back_an_axis_a_script_removed(doc, tracebacks):
    sc = open_example("fish_axes")
    p = run_panel("MM_FoldedShape")
    assert len(p.spins) == 4
    data = json.loads(sc.SceneJSON)
    script(doc, lambda: structure.set_scene_fields(sc, axes=data["axes"][:-1], joint_config=None))
    doc.recompute()
    process(100)
    assert axes(sc) == [2, 3, 4]
    assert_stale(p, "axes")
    type_into(p.spins[0], "4")                   # a fold edit does not make OK usable again
    assert "stale" in p.problems
    assert press_ok() is False
    assert axes(sc) == [2, 3, 4], "OK put back the axis the script had removed"
    assert press_cancel()
    assert axes(sc) == [2, 3, 4] and base.ACTIVE is None
    assert not tracebacks, tracebacks[0]


def test_animate_a_plain_write_makes_it_stale_and_writing_it_back_clears_the_line(doc, tracebacks):
    sc = open_example("fish")
    head = item(sc, "head")
    p = run_panel("MM_Animate")
    n = doc.UndoCount
    script(doc, lambda: setattr(head, "Amplitude", 0.7), transaction=False)
    assert doc.UndoCount == n                    # no undo step: Undo cannot bring the panel's state back
    assert_stale(p, "head.Amplitude")
    assert head.Amplitude == pytest.approx(0.7)
    script(doc, lambda: setattr(head, "Amplitude", 0.3), transaction=False)
    assert_usable(p)                             # the document is the panel's again
    type_into(p.spins["head"][0], "0.5")
    assert press_ok(), p.error.text()
    assert head.Amplitude == pytest.approx(0.5)
    assert not tracebacks, tracebacks[0]


def test_flexibility_refuses_ok_after_the_hinge_thickness_changed(doc, tracebacks):
    sc = open_example("fish")
    p = run_panel("MM_Flexibility")
    old = float(sc.HingeThickness.Value)
    script(doc, lambda: setattr(sc, "HingeThickness", old + 0.2))
    assert_stale(p, "HingeThickness")
    assert float(sc.HingeThickness.Value) == pytest.approx(old + 0.2)
    assert press_cancel()
    assert float(sc.HingeThickness.Value) == pytest.approx(old + 0.2)
    assert not tracebacks, tracebacks[0]


def test_a_motor_removed_without_a_transaction_is_named_and_cancel_keeps_it_removed(doc, tracebacks):
    sc = open_example("fish")
    tail = item(sc, "tail")
    p = run_panel("MM_Simulate")
    name = tail.Name
    script(doc, lambda: doc.removeObject(name), transaction=False)
    text = p.problem_label("items").text()
    assert "'tail'" in text and "deleted" in text, (text, p.problems)
    assert press_ok() is False
    assert doc.getObject(name) is None, "OK brought back the motor the script had removed"
    assert press_cancel()
    assert doc.getObject(name) is None
    assert not tracebacks, tracebacks[0]


# ---- a change the OK leaves alone: the panel stays usable, its OK keeps the change ------------------------------
def test_changes_simulate_does_not_write_keep_it_usable_and_ok_keeps_them(doc, tracebacks):
    sc = open_example("fish")
    tail, head = item(sc, "tail"), item(sc, "head")
    p = run_panel("MM_Simulate")
    script(doc, lambda: setattr(tail, "Label", "tail motor"))              # a label
    script(doc, lambda: setattr(head, "Amplitude", 0.6))                   # Animate's property, not Simulate's
    script(doc, lambda: doc.addObject("Part::Box", "Box"))                 # another object
    script(doc, lambda: setattr(sc, "SceneJSON", json.dumps(json.loads(sc.SceneJSON))), transaction=False)
    doc.recompute()                                                        # a recompute by another command
    process(100)
    assert_usable(p)
    p.set_value("tail", -0.5)
    process()
    assert press_ok(), p.error.text()
    assert tail.Value == pytest.approx(-0.5)
    assert tail.Label == "tail motor" and head.Amplitude == pytest.approx(0.6) and doc.getObject("Box") is not None
    assert not tracebacks, tracebacks[0]


def test_folded_shape_stays_usable_when_a_motor_changes(doc, tracebacks):
    sc = open_example("fish_axes")
    p = run_panel("MM_FoldedShape")
    tail = item(sc, "tail")
    script(doc, lambda: setattr(tail, "Value", 0.1))                       # Folded shape writes axes, not motors
    doc.recompute()
    process(100)
    assert_usable(p)
    assert press_ok(), p.error.text()
    assert tail.Value == pytest.approx(0.1) and axes(sc) == [2, 3, 4, 5]
    assert not tracebacks, tracebacks[0]


def test_the_panels_own_previews_and_failed_ok_keep_it_usable(doc, tracebacks):
    sc = open_example("fish_axes")
    p = run_panel("MM_RotaryAxes")
    p.set_axis("vertical", 5, on=False)          # the preview of an edit: nothing written
    process(100)
    assert_usable(p)
    assert press_cancel()
    p = run_panel("MM_FoldedShape")
    type_into(p.spins[0], "4")
    process(300)
    assert_usable(p)
    assert press_cancel()
    p = run_panel("MM_Flexibility")
    type_into(p.thick, str(float(sc.HingeThickness.Value) + 0.1))
    process(100)
    assert_usable(p)
    assert press_ok(), p.error.text()            # the panel's own writes close it, no stale line on the way
    assert not tracebacks, tracebacks[0]


def test_fit_to_target_watches_the_structure_its_fit_starts_from(doc, tracebacks):
    # its answer replaces every motor and moves modules: any change of the structure's inputs counts, a label not
    from test_gui_fit_target import _structure
    sc = _structure(doc)
    doc.recompute()
    p = run_panel("MM_FitTarget")
    old = list(sc.Items)[0]
    script(doc, lambda: setattr(old, "Label", "renamed"))
    assert "stale" not in p.problems, p.problems
    script(doc, lambda: setattr(old, "Value", 0.4), transaction=False)
    assert_stale(p, "renamed.Value")
    script(doc, lambda: setattr(old, "Value", 0.2), transaction=False)
    assert "stale" not in p.problems, p.problems
    assert press_cancel()
    assert not tracebacks, tracebacks[0]


def test_folded_shape_stays_usable_when_a_recompute_derives_the_tilts_again(doc, tracebacks):
    # other hinge sizes: the Scene's recompute derives the tilts of the axes again (its joint_config entries with
    # "axis"); the folds the panel writes are kept, and its OK's recompute derives the tilts for the new sizes
    sc = open_example("fish_axes")
    p = run_panel("MM_FoldedShape")
    before = json.loads(sc.SceneJSON)["joint_config"]
    old = float(sc.HingeLength.Value)
    script(doc, lambda: setattr(sc, "HingeLength", old + 1.0))
    doc.recompute()
    process(100)
    after = json.loads(sc.SceneJSON)["joint_config"]
    assert after != before and all("axis" in e for e in after.values()), (before, after)
    assert_usable(p)
    type_into(p.spins[0], "4")
    process(300)
    assert press_ok(), p.error.text()
    assert float(sc.HingeLength.Value) == pytest.approx(old + 1.0)
    assert json.loads(sc.SceneJSON)["axes"][0]["fold_deg"] == pytest.approx(4)
    assert not tracebacks, tracebacks[0]
