"""The "Fit to target" panel's values-only box and the fields it makes meaningless, driven through the real widgets.

An audit (session 34) ticked "Keep the motors, fit their values only" after typing a servo budget, forbidden joints
and a worker count: the fields stayed editable, Run and OK went through without a word and the motors stayed on the
very joints the user had forbidden. The command line refuses the same request (``inverse --values-only --forbid``,
``--servos``, ``--workers``, ``--scheduler``: "not with --values-only"). Now the ignored fields are greyed (saying
why) while the box is ticked and get back what was typed when it is unticked; a script or a stored state that
combines them is refused with the fields named; a Dask scheduler greys the worker count (the command line's
``--workers`` / ``--scheduler``: one of the two) and a picked target object greys the target file."""
import json
import os

import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

from metamaterial_wb.cli.solve import result_dict  # noqa: E402
from metamaterial_wb.core.models import run_model  # noqa: E402
from metamaterial_wb.core.scene import Scene  # noqa: E402
from metamaterial_wb.objects import structure  # noqa: E402
from guihelpers import click, doc, press_ok, process, run_panel, type_into, workbench  # noqa: E402,F401

EXAMPLES = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))), "examples")
BOX = "Keep the motors, fit their values only"


def press(button):
    """A real click when the task panel is on screen; the button's own click() where Qt 6 under Xvfb keeps
    the task tab hidden (the same signal path, no synthetic mouse event)."""
    if button.isVisible():
        click(button)
    else:
        button.click()
        process()


def set_spin(spin, value):
    if spin.isVisible():
        type_into(spin, str(value))
    if spin.value() != value:
        spin.setValue(value)


def set_text(edit, text):
    if edit.isVisible():
        type_into(edit, text)
    if edit.text() != text:
        edit.setText(text)


def _motors(sc):
    return sorted((it.Joint, round(it.Value, 6)) for it in sc.Items if it.Kind == "actuator")


def _two_motor_grid(doc, tmp_path):
    """A 4 x 4 grid with motors on H1,1 and V2,3, and a target made by the same motors at other values."""
    acts = [("H1,1", 0.2), ("V2,3", 0.1)]
    sc = structure.make_structure(doc, Scene.grid(4, 4, actuators=[{"name": f"a{k}", "joint": j, "value": v}
                                                                   for k, (j, v) in enumerate(acts)]))
    doc.recompute()
    planted = Scene.grid(4, 4, actuators=[{"name": "a0", "joint": "H1,1", "value": 0.6},
                                          {"name": "a1", "joint": "V2,3", "value": 0.5}])
    path = tmp_path / "target.json"
    path.write_text(json.dumps(result_dict(planted, run_model("quadratic", planted))), encoding="utf-8")
    return sc, str(path)


def _ignored(p):
    return {"Servo budget": p.servos, "Forbidden joints": p.forbid, "Workers": p.workers, "Dask scheduler": p.scheduler}


def test_values_only_greys_the_fields_it_ignores_and_gives_back_what_was_typed(doc, tmp_path):
    """The audit's steps on the fish: forbid its motors' joints, 5 servos, 7 workers, tick the box, Run, OK."""
    p = run_panel("MM_OpenExample")
    p.select("fish")
    assert press_ok()
    (sc,) = structure.find_scene_objects(doc)
    before = sorted(it.Joint for it in sc.Items if it.Kind == "actuator")
    assert before == ["V0,1", "V1,5"]
    p = run_panel("MM_FitTarget")
    set_text(p.path, os.path.join(EXAMPLES, "fish_tail_target.json"))
    set_text(p.forbid, "V0,1, V1,5")
    set_spin(p.servos, 5)
    set_spin(p.workers, 7)
    assert all(w.isEnabled() for w in _ignored(p).values())
    press(p.values_only)
    assert p.values_only.isChecked()
    for name, w in _ignored(p).items():
        assert not w.isEnabled(), name                                     # greyed ...
        assert BOX in w.toolTip(), (name, w.toolTip())                    # ... saying why
    # they show what the fit uses: the structure's 2 motors, this process, no forbidden joint, no scheduler
    assert p.servos.value() == 2 and p.workers.value() == 1
    assert p.forbid.text() == "" and "structure's placement" in p.forbid.placeholderText()
    hint = p.values_only_hint                    # and a line under the box says it in full (the dock is narrow)
    assert not hint.isHidden() and "structure's 2 motors" in hint.text(), hint.text()
    assert all(name in hint.text() for name in _ignored(p)), hint.text()
    assert p.scheduler.text() == ""
    p._add_forbidden("H0,0")                     # a hinge clicked in the 3D view goes nowhere while it is greyed
    assert p.forbid.text() == ""
    press(p.values_only)                                                   # unticked: back as typed
    assert not p.values_only.isChecked()
    assert all(w.isEnabled() for w in _ignored(p).values())
    assert (p.forbid.text(), p.servos.value(), p.workers.value()) == ("V0,1, V1,5", 5, 7)
    assert BOX not in p.forbid.toolTip() and BOX not in p.servos.toolTip() and p.values_only_hint.isHidden()
    press(p.values_only)
    p.geometry_checks.setChecked(False)          # (the answer's build checks are not what this test is about)
    press(p.run_btn)
    assert p.wait(600)
    assert p.error.text() == "", p.error.text()
    assert sorted(a.joint for a in p.result.scene.actuators) == ["V0,1", "V1,5"]
    assert press_ok()
    assert sorted(it.Joint for it in sc.Items if it.Kind == "actuator") == ["V0,1", "V1,5"]


@pytest.mark.parametrize("field,setter,shown", [
    ("Servo budget", lambda p: p.servos.setValue(3), "3"),
    ("Forbidden joints", lambda p: p.forbid.setText("H0,0"), "H0,0"),
    ("Workers", lambda p: p.workers.setValue(3), "3"),
    ("Dask scheduler", lambda p: p.scheduler.setText("tcp://127.0.0.1:8786"), "tcp://127.0.0.1:8786"),
])
def test_a_script_setting_an_ignored_field_under_values_only_is_refused_naming_it(doc, tmp_path, field, setter,
                                                                                  shown):
    sc, target = _two_motor_grid(doc, tmp_path)
    before = _motors(sc)
    p = run_panel("MM_FitTarget")
    set_text(p.path, target)
    press(p.values_only)
    setter(p)                                    # a script writes the greyed field
    press(p.run_btn)
    assert not p.job.running and p.result is None
    text = p.error.text()
    assert field in text and shown in text and BOX in text, text
    assert "--" not in text, text
    others = [f for f in _ignored(p) if f != field]
    assert not any(f in text for f in others), text                       # only the field that was set
    assert not press_ok() and "run the fit first" in p.error.text()
    assert _motors(sc) == before


def test_a_stored_state_combining_values_only_with_the_fields_is_refused_naming_all_of_them(doc, tmp_path):
    """The box ticked with its signal blocked (a restored state, a script): the fields still hold the user's values;
    Run refuses them all in one message instead of dropping them."""
    sc, target = _two_motor_grid(doc, tmp_path)
    before = _motors(sc)
    p = run_panel("MM_FitTarget")
    set_text(p.path, target)
    set_spin(p.servos, 3)
    set_text(p.forbid, "H0,0, V1,1")
    set_spin(p.workers, 3)
    p.values_only.blockSignals(True)
    p.values_only.setChecked(True)
    p.values_only.blockSignals(False)
    press(p.run_btn)
    assert not p.job.running and p.result is None
    text = p.error.text()
    for f, v in (("Servo budget", "3"), ("Forbidden joints", "H0,0, V1,1"), ("Workers", "3")):
        assert f + " " + v in text, (f, text)
    assert BOX in text and "Dask scheduler" not in text, text
    assert not press_ok()
    assert _motors(sc) == before
    # the fields set back to what values-only uses: the fit runs
    p.servos.setValue(2)
    p.forbid.setText("")
    p.workers.setValue(1)
    press(p.run_btn)
    assert p.wait(600)
    assert p.error.text() == "", p.error.text()
    assert press_ok()
    assert [j for j, _ in _motors(sc)] == ["H1,1", "V2,3"] and _motors(sc) != before


def test_a_dask_scheduler_greys_the_worker_count_and_an_object_greys_the_target_file(doc, tmp_path):
    """The command line takes --workers or --scheduler, not both; the panel used the scheduler and dropped the
    worker count without a word. Likewise a picked target object made the typed target file count for nothing."""
    _sc, target = _two_motor_grid(doc, tmp_path)
    box = doc.addObject("Part::Box", "TargetBox")
    doc.recompute()
    p = run_panel("MM_FitTarget")
    set_text(p.path, target)
    set_text(p.scheduler, "nowhere")             # checked before the fit starts, as the command line does, and
    press(p.run_btn)                             # named as the panel's field (it said "fit: --scheduler: ...")
    assert not p.job.running and p.result is None
    assert "Dask scheduler: 'nowhere'" in p.error.text() and "--" not in p.error.text(), p.error.text()
    set_text(p.scheduler, "")
    set_spin(p.workers, 3)
    set_text(p.scheduler, "tcp://127.0.0.1:8786")
    assert not p.workers.isEnabled() and "Dask scheduler" in p.workers.toolTip(), p.workers.toolTip()
    set_text(p.scheduler, "")
    assert p.workers.isEnabled() and p.workers.value() == 3
    assert "Dask scheduler" not in p.workers.toolTip()
    # values-only, then unticked with a scheduler typed before: Workers stays greyed by the scheduler
    set_text(p.scheduler, "tcp://127.0.0.1:8786")
    press(p.values_only)
    press(p.values_only)
    assert p.scheduler.text() == "tcp://127.0.0.1:8786" and p.scheduler.isEnabled()
    assert not p.workers.isEnabled() and p.workers.value() == 3
    # a target object greys the file field (what it holds is kept); "(use the file)" gives it back
    set_text(p.path, "/nowhere/target.json")
    k = p.target_obj.findData(box.Name)
    assert k > 0
    p.target_obj.setCurrentIndex(k)
    process()
    assert not p.path.isEnabled() and "target object" in p.path.toolTip(), p.path.toolTip()
    p.target_obj.setCurrentIndex(0)
    process()
    assert p.path.isEnabled() and p.path.text() == "/nowhere/target.json"
