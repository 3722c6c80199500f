"""Animate's real-time factor (docs/gui.md: "1.00 = real time") is the timeline time played per wall second, read
from the rate line the panel shows while playing: ~1.00 at speed 1 and ~2.00 at speed 2, also with Loop ticked and a
short timeline that wraps several times (it read 0.13, 0.41, ..., -0.03: the time before a wrap was compared with
the time after it). What a user expects across the other breaks of the timeline: a pause does not count (after
Resume the factor is that of the playing), a speed change gives the new speed's factor at once (not a mix of both),
a scrub (a key on the focused timeline) is a jump, not time played. Real widgets: the Play button, the Loop box, the
speed and length boxes typed into, keys on the timeline. Timing under Xvfb is noisy: the factor is checked in a
generous band around the speed, and never negative."""
import re

import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

from PySide import QtCore  # noqa: E402

from guihelpers import click, doc, press_ok, process, qtest, run_panel, tracebacks, type_into, workbench  # noqa: E402,F401

BAND = (0.7, 1.3)             # x the speed: generous, the clock runs on wall time (Xvfb, two lanes on two cores)


def factor(p):
    """The real-time factor the rate line shows (None before the line is written)."""
    m = re.search(r"real-time factor (-?[0-9]+\.[0-9]+)", p.rate_label.text())
    return float(m.group(1)) if m else None


def sample(p, seconds, every_ms=200):
    """(animation time, factor shown) every ``every_ms`` while playing for ``seconds``."""
    out = []
    for _ in range(int(seconds * 1000 / every_ms)):
        process(every_ms)
        out.append((round(p.t, 3), factor(p)))
    return out


def assert_factors(samples, speed, what):
    lo, hi = BAND[0] * speed, BAND[1] * speed
    shown = [f for _t, f in samples]
    assert shown and all(f is not None for f in shown), f"{what}: no factor shown: {samples}"
    assert all(f >= 0 for f in shown), f"{what}: a negative real-time factor: {samples}"
    bad = [f for f in shown if not lo <= f <= hi]
    assert not bad, f"{what}: factor outside {lo:.2f}..{hi:.2f} at speed {speed:g}: {samples}"


def wraps(samples):
    return sum(1 for (a, _), (b, _) in zip(samples, samples[1:]) if b < a)


def animate_worm(length):
    p = run_panel("MM_OpenExample")
    p.select("worm")
    assert press_ok()
    p = run_panel("MM_Animate")
    if not p.loop.isChecked():
        click(p.loop)
    assert p.loop.isChecked()
    type_into(p.duration, f"{length:g}")
    assert p.duration.value() == pytest.approx(length)
    return p


def play(p):
    assert p.play_btn.text() == "Play"
    click(p.play_btn)
    assert p.play_btn.text() == "Pause"


def pause(p):
    click(p.play_btn)
    assert p.play_btn.text() == "Play"


@pytest.mark.parametrize("speed", [1.0, 2.0])
def test_the_factor_is_right_across_loop_wraps(doc, tracebacks, speed):
    p = animate_worm(0.5)
    type_into(p.speed, f"{speed:g}")
    assert p.speed.value() == speed
    play(p)
    process(500)                                 # the first frames: the rate window fills
    samples = sample(p, 2.5)
    pause(p)
    assert wraps(samples) >= 2, f"the 0.5 s timeline did not wrap while playing: {samples}"
    assert_factors(samples, speed, "looping")
    assert not tracebacks, tracebacks[0]
    p.reject()


def test_the_factor_after_a_pause_and_a_speed_change_while_looping(doc, tracebacks):
    p = animate_worm(0.5)
    play(p)
    process(1200)
    pause(p)
    process(1000)                                # paused: no time played, none counted
    play(p)
    process(300)
    resumed = sample(p, 1.2)
    assert_factors(resumed, 1.0, "after Resume")
    type_into(p.speed, "2")                      # while playing: the new speed's factor from now on
    assert p.speed.value() == 2.0 and p.play_btn.text() == "Pause"
    process(300)
    faster = sample(p, 1.2)
    pause(p)
    assert wraps(resumed + faster) >= 2
    assert_factors(faster, 2.0, "after a speed change")
    assert not tracebacks, tracebacks[0]
    p.reject()


def test_a_scrub_while_playing_is_not_time_played(doc, tracebacks):
    p = animate_worm(4.0)                        # long: a key on the timeline jumps by seconds
    play(p)
    process(1000)
    assert_factors(sample(p, 0.4), 1.0, "before the scrub")
    p.timeline.setFocus()
    process(20)
    qtest().keyClick(p.timeline, QtCore.Qt.Key.Key_End)   # ~1.4 s -> 4 s: a jump, then the loop wraps to 0
    process(300)
    after = sample(p, 1.2)
    assert p.play_btn.text() == "Pause"
    pause(p)
    assert wraps([(4.0, None)] + after) >= 1, after
    assert_factors(after, 1.0, "after a scrub (End) while playing")
    assert not tracebacks, tracebacks[0]
    p.reject()
