"""The Animate panel's Connect checks the firmware's slew limit (an actuator's ``servo.max_slew_dps``) as the
``stream`` command does: the command refused the fish whose tail servo may turn 300 deg/s (its motion peaks at
509 deg/s: the servo would lag tens of degrees behind), while Connect compared the frames only and streamed it
without a word. Connect now refuses it with the command's message (``mapping.check_slew``, run by check_motion
once the rate passes), at the panel's speed: the firmware's limit is per wall second, so 0.5x follows where 1x does
not, and 2x does not follow a limit 1x does. Driven by the real widgets with port loop:// (a dry run)."""
import json

import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

from guihelpers import click, doc, process, run_panel, type_into, workbench  # noqa: E402,F401
from test_gui_panel_details import open_example  # noqa: E402


def open_fish_with_tail_slew(doc, dps):
    from metamaterial_wb.gui.panels import hardware_available
    if not hardware_available():
        pytest.skip("metamaterial_wb.hardware is not in this checkout")
    pytest.importorskip("serial")
    sc = open_example("fish")
    tail = [it for it in sc.Items if it.ItemName == "tail"][0]
    extra = json.loads(tail.ExtraJSON or "{}")
    extra["servo"] = {"max_slew_dps": dps}
    tail.ExtraJSON = json.dumps(extra)
    doc.recompute()
    assert sc.isValid()
    p = run_panel("MM_Animate")
    p.port.setText("loop://")
    click(p.loop)                  # no wrap in question: the timeline plays once (the fish's 2 s ends where it starts)
    assert not p.loop.isChecked() and p.duration.value() == 2.0 and p.speed.value() == 1.0
    return p


def cli_refusal(scene, seconds):
    """What ``stream SCENE --seconds S`` refuses with (cli/stream.py runs check_motion at its default 50 Hz)."""
    from metamaterial_wb.core.errors import SceneError
    from metamaterial_wb.hardware import channel_map, check_motion
    try:
        check_motion(scene, channel_map(scene), seconds, 50.0)
    except SceneError as exc:
        return str(exc)
    return None


def connected(p):
    return p.connect_btn.text() == "Disconnect" and p.stream.connected


def test_connect_refuses_a_slew_limit_the_stream_command_refuses(doc):
    p = open_fish_with_tail_slew(doc, 300)
    want = cli_refusal(p.preview_scene, 2.0)
    assert want and want.startswith("channel 1 (tail).max_slew_dps: 300 deg/s:"), want
    click(p.connect_btn)
    process()
    text = p.error.text()
    assert not connected(p), f"streamed a slew limit the stream command refuses: {text!r}"
    assert text == f"cannot stream to loop://: {want}", text      # the command's message, word for word
    assert "deg off it at t = " in text and "raise max_slew_dps" in text, text

    type_into(p.speed, "0.5")      # 255 deg/s of wall time: within 300 deg/s
    click(p.connect_btn)
    process()
    assert connected(p), p.error.text()
    assert p.error.text() == ""
    click(p.connect_btn)
    assert not connected(p)


def test_connect_checks_the_limit_at_the_panels_speed(doc):
    p = open_fish_with_tail_slew(doc, 600)
    assert cli_refusal(p.preview_scene, 2.0) is None     # at 1x the limit never holds the tail back
    click(p.connect_btn)
    process()
    assert connected(p), p.error.text()
    click(p.connect_btn)
    assert not connected(p)

    type_into(p.speed, "2")        # the tail then moves at ~1018 deg/s of wall time
    click(p.connect_btn)
    process()
    text = p.error.text()
    assert not connected(p), f"streamed at 2x past the slew limit: {text!r}"
    assert text.startswith("cannot stream to loop://: at 2x: channel 1 (tail).max_slew_dps: 600 deg/s:"), text
    peak = float(text.split("moves at up to ")[1].split(" deg/s")[0])
    assert 950 < peak < 1050, text                       # the speed the servo would have to turn (wall time)
    t = float(text.split("at t = ")[1].split(" s")[0])
    assert 0.0 <= t <= 2.0, text                         # a time of the timeline
