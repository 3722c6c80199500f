"""Connect compares the whole timeline, as the ``stream`` command does: it compared only the first minute
(``StreamController.FOLLOW_SPAN_S``), so a two-minute timeline whose tail jumps at t = 70 s (a keyframes profile
without a period: at rest, then 0.9 -> 0 within 10 ms, between two of the link's frames) was streamed without a word
and the servo, moving straight from frame to frame, strayed ~11 deg from the motion. Driven by the real Connect
button with port loop:// (a dry run); the per-edit warning while streaming says which span it compared."""
import json

import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

from guihelpers import click, doc, process, run_panel, type_into, workbench  # noqa: E402,F401
from test_gui_panel_details import open_example  # noqa: E402

# no period: plays once. A ramp at 1.0 .. 1.1 s (on the 50 Hz frames, too fast for 10x), then at rest until
# 0.9 -> 0 within 10 ms between two frames at 70.01 s (1x strays ~11 deg there, 0.5x follows)
LATE_JUMP = {"times_s": [0.0, 1.0, 1.1, 70.01, 70.02], "values": [0.0, 0.0, 0.9, 0.9, 0.0]}


def open_fish_with_a_late_jump(doc):
    from metamaterial_wb.gui.panels import hardware_available
    if not hardware_available():
        pytest.skip("metamaterial_wb.hardware is not in this checkout")
    pytest.importorskip("serial")
    sc = open_example("fish")
    tail = [it for it in sc.Items if it.ItemName == "tail"][0]
    tail.ProfileShape = "keyframes"
    tail.ProfileData = json.dumps(LATE_JUMP)
    doc.recompute()
    assert sc.isValid()
    p = run_panel("MM_Animate")
    p.port.setText("loop://")
    type_into(p.duration, "120")
    assert p.duration.value() == 120.0
    return p


def test_connect_compares_the_whole_timeline(doc):
    p = open_fish_with_a_late_jump(doc)
    assert p.speed.value() == 1.0
    click(p.connect_btn)
    process()
    text = p.error.text()
    assert p.connect_btn.text() == "Connect" and not p.stream.connected, f"streamed a motion it cannot follow: {text!r}"
    assert "1x" in text and "tail" in text and "deg off" in text and "t = 70.01 s" in text, text
    assert "first" not in text, text                      # the whole timeline was compared: no span named
    # the speed offered follows the whole timeline (the stream command's check over all 120 s passes at it)
    follows = float(text.split("; ")[-1].split("x follows it")[0])
    assert follows < 1.0, text
    from metamaterial_wb.hardware.mapping import channel_map, rate_deviation, RATE_TOLERANCE_DEG
    scene = p.preview_scene
    # (at that speed both the frames and the servos' 20 ms pulses come 50 / follows times a second of motion)
    assert rate_deviation(scene, channel_map(scene), 120.0, 50.0 / follows, pulse_hz=50.0 / follows).deg \
        <= RATE_TOLERANCE_DEG
    type_into(p.speed, f"{follows:g}")
    click(p.connect_btn)
    process()
    assert p.connect_btn.text() == "Disconnect" and p.stream.connected, p.error.text()
    assert p.error.text() == ""
    click(p.connect_btn)
    assert p.connect_btn.text() == "Connect" and not p.stream.connected


def test_the_per_edit_warning_names_the_span_it_compared(doc):
    """While streaming, an edit compares the first FOLLOW_SPAN_S of the timeline (the whole of a 10 min one takes
    seconds): a longer timeline is said so, and a speed found too fast names the span and what Connect does."""
    p = open_fish_with_a_late_jump(doc)
    span = p.stream.FOLLOW_SPAN_S
    assert span < 120.0
    type_into(p.speed, "0.5")
    click(p.connect_btn)
    process()
    assert p.stream.connected, p.error.text()
    type_into(p.speed, "1")            # too fast after 70 s only: beyond the span compared per edit
    process()
    assert p.speed.value() == 1.0
    text = p.error.text()
    assert f"first {span:g} s of the 120 s timeline" in text and "Connect" in text, text
    type_into(p.speed, "10")           # the tail's ramp at 1 s is too fast at 10x, within the span
    process()
    text = p.error.text()
    assert "10x" in text and "tail" in text and "t = 1.10 s" in text, text
    assert f"(the first {span:g} s of the 120 s timeline compared)" in text, text
    # 5x follows the first minute, not the jump at 70 s: the suggestion says which span it follows
    assert f"; 5x follows its first {span:g} s (Connect compares the whole timeline)" in text, text
    click(p.connect_btn)
    assert p.connect_btn.text() == "Connect" and not p.stream.connected


def test_a_timeline_lengthened_while_streaming_is_compared_and_said(doc):
    """Lengthening the timeline while streaming was never compared (only a speed or profile edit was): the first
    span is compared at once and the panel says the rest is not; shortened again, the note goes."""
    p = open_fish_with_a_late_jump(doc)
    span = p.stream.FOLLOW_SPAN_S
    click(p.loop)                      # the tail ends at 0.9 on 40 / 50 s, starts at 0: a wrap jump (stream_wrap)
    assert not p.loop.isChecked()
    type_into(p.duration, "50")        # the jump at 70 s is beyond the timeline: 1x follows all of it
    click(p.connect_btn)
    process()
    assert p.stream.connected and p.error.text() == "", p.error.text()
    type_into(p.duration, "120")
    process()
    text = p.error.text()
    assert f"first {span:g} s of the 120 s timeline" in text and "Disconnect and Connect" in text, text
    type_into(p.duration, "40")
    process()
    assert p.error.text() == "", p.error.text()
    click(p.connect_btn)
    assert p.connect_btn.text() == "Connect" and not p.stream.connected
