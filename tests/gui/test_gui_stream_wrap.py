"""With Loop ticked the Animate timeline wraps from its end back to its start, and the stream sends the end angle,
then the start angle: a jump no servo follows when the motion does not end where it starts. Connect compared the
motion over the timeline only (the stream command's rate check), so the fish on a 1.25 s timeline (its 1 Hz tail a
quarter period past its start, its 0.5 Hz head 5/8 of a period) streamed with a jump of tens of degrees every
1.25 s without a word. Connect is now refused as for a rate the frames cannot follow, naming each motor, its
channel, the end and the start angle; while streaming, ticking Loop or a new length is warned of. Driven by the
real widgets with port loop:// (a dry run)."""
import re

import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

from PySide import QtCore  # noqa: E402
from guihelpers import click, doc, process, qtest, run_panel, type_into, workbench  # noqa: E402,F401
from test_gui_panel_details import open_example  # noqa: E402

JUMP = re.compile(r"(\w+) \(channel (\d)\) by ([\d.]+) deg, from ([-+][\d.]+) deg to ([-+][\d.]+) deg")


def open_fish():
    from metamaterial_wb.gui.panels import hardware_available
    if not hardware_available():
        pytest.skip("metamaterial_wb.hardware is not in this checkout")
    pytest.importorskip("serial")
    open_example("fish")
    p = run_panel("MM_Animate")
    p.port.setText("loop://")
    assert p.loop.isChecked()          # the panel opens with Loop ticked
    assert p.duration.value() == 2.0   # the head's period: both sines end where they start
    return p


def shown_angle(p, name):
    """The angle the panel shows for ``name`` (values label: ``tail +12.3 deg (+0.45)``)."""
    m = re.search(rf"{name} ([-+][\d.]+) deg", p.values_label.text())
    assert m, p.values_label.text()
    return float(m.group(1))


def said_jumps(text):
    return {m.group(1): (int(m.group(2)), float(m.group(3)), float(m.group(4)), float(m.group(5)))
            for m in JUMP.finditer(text)}


def test_connect_with_loop_refuses_a_jump_at_the_wrap_and_names_it(doc):
    p = open_fish()
    type_into(p.duration, "1.25")
    assert p.duration.value() == 1.25
    # what a person sees at either end of the timeline: at its start, then at its end (End on the slider)
    assert p.time_label.text() == "t = 0.00 s"
    start = {n: shown_angle(p, n) for n in ("head", "tail")}
    p.timeline.setFocus()
    qtest().keyClick(p.timeline, QtCore.Qt.Key.Key_End)
    process()
    assert p.time_label.text() == "t = 1.25 s"
    end = {n: shown_angle(p, n) for n in ("head", "tail")}
    assert abs(end["tail"] - start["tail"]) > 10.0, (end, start)     # a jump no servo follows in one frame

    click(p.connect_btn)
    text = p.error.text()
    assert p.connect_btn.text() == "Connect" and not p.stream.connected, f"streamed a wrap jump: {text!r}"
    assert "Loop" in text and "1.25 s timeline" in text and "at most 3 deg" in text, text
    said = said_jumps(text)
    assert "tail" in said, text
    for name, (channel, jump, e, s) in said.items():
        assert channel == {"head": 0, "tail": 1}[name], text
        assert e == pytest.approx(end[name], abs=0.051) and s == pytest.approx(start[name], abs=0.051), text
        assert jump == pytest.approx(abs(e - s), abs=0.011) and jump > 3.0, text

    click(p.loop)                      # unticked: the clock stops at the end, nothing wraps
    assert not p.loop.isChecked()
    click(p.connect_btn)
    assert p.connect_btn.text() == "Disconnect" and p.stream.connected, p.error.text()
    assert p.error.text() == ""
    click(p.connect_btn)
    assert p.connect_btn.text() == "Connect" and not p.stream.connected


def test_ticking_loop_or_a_new_length_while_streaming_warns_of_the_wrap(doc):
    p = open_fish()
    click(p.loop)
    assert not p.loop.isChecked()
    type_into(p.duration, "1.25")
    click(p.connect_btn)
    assert p.stream.connected and p.error.text() == "", p.error.text()
    click(p.loop)                      # Loop ticked while streaming
    assert p.loop.isChecked()
    text = p.error.text()
    assert text.startswith("warning: Loop:") and "1.25 s timeline" in text, text
    assert said_jumps(text)["tail"][0] == 1, text
    assert p.stream.connected          # a warning, as for a speed the frames cannot follow: the stream goes on
    type_into(p.duration, "2")         # whole periods of both sines: no jump, the warning goes
    assert p.error.text() == "", p.error.text()
    type_into(p.duration, "1.75")      # the tail three quarters on: warned again
    text = p.error.text()
    assert "1.75 s timeline" in text and "tail" in said_jumps(text), text
    click(p.loop)                      # unticked: nothing wraps, the warning goes
    assert p.error.text() == "", p.error.text()
    assert p.stream.connected
    click(p.connect_btn)
    assert p.connect_btn.text() == "Connect" and not p.stream.connected
