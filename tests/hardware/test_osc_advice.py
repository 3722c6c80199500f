"""``stream --mode osc`` refuses a sine the chip cannot render and names "the highest frequency of this swing that
passes" (onboard._highest_passing). That number was the bisection's last passing frequency when its 3-digit
rounding failed (the deviation is not quite monotone in the whole-ms period), printed with 6 digits to the
nearest: the fish's head (amplitude 0.3) at 2.06 Hz with --rate-tolerance 0.099 was told 0.157592 Hz, which
typed back runs a 6345 ms period instead of 6346 and is refused. The number is now rounded down to the 3 digits
the message shows, the next lower ones tried until one passes: typed back, it is accepted."""
import copy
import json
import os
import re

import pytest

from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.core.scene import Scene
from metamaterial_wb.hardware import channel_map
from metamaterial_wb.hardware import onboard
from metamaterial_wb.hardware.onboard import osc_params

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
with open(os.path.join(REPO, "examples", "fish.json"), encoding="utf-8") as _f:
    FISH = json.load(_f)
ADVICE = re.compile(r"the highest frequency of this swing that passes is (\S+) Hz")


def head_alone(freq_hz):
    d = copy.deepcopy(FISH)
    d["actuators"] = [a for a in d["actuators"] if a["name"] == "head"]
    d["actuators"][0]["profile"]["frequency_hz"] = freq_hz
    return Scene.from_dict(d)


def advice(scene, tol):
    with pytest.raises(SceneError) as e:
        osc_params(scene, channel_map(scene), tolerance_deg=tol)
    assert e.value.field == "actuators[0] (head).profile.frequency_hz", str(e.value)
    m = ADVICE.search(str(e.value))
    assert m, str(e.value)
    return m.group(1)


def significant_digits(text):
    return len(text.split("e")[0].replace(".", "").lstrip("0"))


@pytest.mark.parametrize("freq", [2.06, 4.26])
def test_the_frequency_advised_passes_when_typed_back(freq):
    text = advice(head_alone(freq), 0.099)
    typed = head_alone(float(text))                    # the number as the message shows it, typed back
    p, = osc_params(typed, channel_map(typed), tolerance_deg=0.099)   # before: 0.157592, refused (6345 ms period)
    assert p.render_deviation_deg <= 0.099
    assert significant_digits(text) <= 3, text        # before: 6 digits, rounded to the nearest
    assert 0.150 <= float(text) < 0.1576, text          # just below the highest passing period (6346 ms: 0.1576 Hz)


def test_the_tails_advice_is_unchanged():
    """Where the 3-digit frequency passes, it is the one named (tests/unit/test_osc_aliasing.py's 72 deg sine)."""
    d = copy.deepcopy(FISH)
    tail = d["actuators"][1]
    tail["profile"]["frequency_hz"] = 4.8
    tail["servo"] = {"scale_deg": 80}
    s = Scene.from_dict(d)
    with pytest.raises(SceneError, match=r"the highest frequency of this swing that passes is 4\.61 Hz"):
        osc_params(s, channel_map(s))


def test_a_rounded_frequency_that_fails_is_passed_over(monkeypatch):
    """A deviation that fails at the period the 3-digit rounding lands on (and passes around it): the advice goes
    down to the next 3-digit frequency that passes, never to the bisection's unrounded last value."""
    def render(exact, board, amp, off, freq_hz, rate_hz=50.0):
        period = round(1000.0 / freq_hz)
        return 0.0 if period >= 624 and period != 625 else 10.0   # 1.6 Hz (625 ms) fails, 1.59 Hz (629 ms) passes
    monkeypatch.setattr(onboard, "render_deviation", render)
    with pytest.raises(SceneError) as e:     # requested 25 Hz: not a period that passes
        onboard._check_render("x.frequency_hz", "x", None, None, 1.0, 0.0, 25.0, 40, 3.0)
    text = ADVICE.search(str(e.value)).group(1)
    assert text == "1.59", str(e.value)       # before: 1.60385 (1000 / 1.60385 = 623.50 ms: runs 623, fails)
    assert render(None, None, 1.0, 0.0, 1000.0 / round(1000.0 / float(text))) == 0.0


@pytest.mark.parametrize("x", [25.0, 4.6132, 4.61, 0.113701, 1.0, 9.9999999, 0.001, 1.53e-5, 99.99])
def test_down3_is_the_largest_three_digit_decimal_not_above(x):
    m, e = onboard._down3(x)
    f = float(f"{m}e{e}")
    assert 100 <= m <= 999 and f <= x and significant_digits(f"{f:g}") <= 3
    assert float(f"{m + 1}e{e}") > x                   # the next 3-digit decimal is above x
