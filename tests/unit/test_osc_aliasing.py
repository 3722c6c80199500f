"""``stream --mode osc`` accepted sines the chip can only alias: a 50 Hz tail sine streamed with exit 0 and the line
"joint angle -21.88..81.00 deg" while the emulated pin sat near one value for seconds; 25 Hz alternated with a
drifting amplitude. The chip steps its oscillators every 10 ms and starts a servo pulse every 20 ms, so the servo
sees the sine sampled at 50 Hz: osc mode now refuses a sine whose servo path (linear from pulse to pulse, at any
phase of the pulses, stream mode's model) strays from the motion by more than the stream tolerance
(RATE_TOLERANCE_DEG, --rate-tolerance), naming the actuator, its frequency and the highest one that passes.
Closed form for a linear channel: a sine of amplitude A sampled at 50 Hz, linearly interpolated, misses the peak by
A (1 - cos(pi f / 50)). The pins against this model: tests/firmware/test_emulator_osc_render.py."""
import copy
import json
import math
import os
import re

import pytest

from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.core.scene import Scene
from metamaterial_wb.hardware import channel_map
from metamaterial_wb.hardware.mapping import RATE_TOLERANCE_DEG, rate_deviation
from metamaterial_wb.hardware.onboard import osc_params

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
FISH = os.path.join(REPO, "examples", "fish.json")
with open(FISH, encoding="utf-8") as _f:
    FISH_DICT = json.load(_f)


def fish(freq_hz=None, amplitude=None, servo=None):
    d = copy.deepcopy(FISH_DICT)
    tail = next(a for a in d["actuators"] if a["name"] == "tail")
    if freq_hz is not None:
        tail["profile"]["frequency_hz"] = freq_hz
    if amplitude is not None:
        tail["profile"]["amplitude"] = amplitude
    if servo is not None:
        tail["servo"] = servo
    return Scene.from_dict(d)


def params(scene, **kw):
    return osc_params(scene, channel_map(scene), **kw)


def closed_form_fmax(amp_deg, tol_deg, rate_hz=50.0):
    """A (1 - cos(pi f / rate)) = tol."""
    return rate_hz / math.pi * math.acos(1.0 - tol_deg / amp_deg)


@pytest.mark.parametrize("freq", [50.0, 25.0, 10.0])
def test_osc_refuses_a_tail_sine_the_chip_aliases(freq):
    s = fish(freq)
    with pytest.raises(SceneError) as e:  # before: accepted
        params(s)
    msg = str(e.value)
    assert msg.startswith("actuators[1] (tail).profile.frequency_hz: "), msg
    assert f"{freq:g} Hz" in msg and "sampled at 50 Hz" in msg and "allowed: at most 3 deg (--rate-tolerance)" in msg
    assert ("Nyquist" in msg) == (freq >= 25.0), msg
    m = re.search(r"the highest frequency of this swing that passes is ([\d.]+) Hz", msg)
    assert m, msg
    f_ok = float(m.group(1))
    assert 1.0 <= f_ok < 2.0  # the fish's own 1 Hz passes
    # that frequency passes, a little more is refused
    assert params(fish(f_ok))[1].render_deviation_deg <= RATE_TOLERANCE_DEG
    with pytest.raises(SceneError, match="frequency_hz"):
        params(fish(f_ok * 1.02))


def test_linear_channel_follows_the_closed_form():
    """scale_deg 80, amplitude 0.9: a 72 deg sine; its servo path misses by 72 (1 - cos(pi f / 50)) deg."""
    servo = {"scale_deg": 80}
    fmax = closed_form_fmax(72.0, 3.0)          # 4.6145 Hz
    for f in (0.5, 2.0, 4.5):
        p = params(fish(f, servo=servo))[1]
        want = 72.0 * (1.0 - math.cos(math.pi * (1000.0 / p.period_ms) / 50.0))
        assert p.render_deviation_deg == pytest.approx(want, abs=0.02), (f, p.render_deviation_deg, want)
    with pytest.raises(SceneError) as e:
        params(fish(4.8, servo=servo))   # the chip runs a 208 ms period: 4.808 Hz
    want = 72.0 * (1.0 - math.cos(math.pi * (1000.0 / 208) / 50.0))
    assert "4.8 Hz: " in str(e.value) and f"would be {want:.2f} deg off" in str(e.value), str(e.value)
    f_ok = float(re.search(r"passes is ([\d.]+) Hz", str(e.value)).group(1))
    assert fmax - 0.03 <= f_ok <= fmax, (f_ok, fmax)   # the whole centidegrees the chip runs cost a little
    # a smaller swing may go faster: 10 deg at 12 Hz (an 83 ms period) misses by 10 (1 - cos(pi 12.05 / 50)) deg
    p = params(fish(12.0, amplitude=0.125, servo=servo))[1]
    assert p.period_ms == 83
    assert p.render_deviation_deg == pytest.approx(10 * (1 - math.cos(math.pi * (1000 / 83) / 50)), abs=0.02)


def test_the_fish_passes_as_it_streams_at_50_hz():
    """The same model as stream mode: the fish's tail at 50 Hz strays 1.86 deg (the corner of its joint's closing
    and opening rates) whether streamed or generated on the chip."""
    s = fish()
    ps = {p.name: p for p in params(s)}
    streamed = rate_deviation(s, [c for c in channel_map(s) if c.name == "tail"], 2.0, 50.0)
    assert ps["tail"].render_deviation_deg == pytest.approx(streamed.deg, abs=0.02)
    assert 1.8 < ps["tail"].render_deviation_deg <= RATE_TOLERANCE_DEG
    assert ps["head"].render_deviation_deg < 0.5


def test_the_tolerance_is_the_one_given():
    with pytest.raises(SceneError, match=r"tail.*1\.86 deg off .*at most 1 deg"):
        params(fish(), tolerance_deg=1.0)
    assert params(fish(50.0), tolerance_deg=180)[1].render_deviation_deg > 100   # 180 lets anything through


def test_cli_osc_refuses_the_50_hz_tail_before_the_port(tmp_path):
    pytest.importorskip("serial")
    from clihelpers import one_line_error, run_cli
    scene = tmp_path / "tail50.json"
    d = copy.deepcopy(FISH_DICT)
    next(a for a in d["actuators"] if a["name"] == "tail")["profile"]["frequency_hz"] = 50.0
    scene.write_text(json.dumps(d), encoding="utf-8")
    rep = tmp_path / "r.json"
    r = run_cli("stream", scene, "--dry-run", "--mode", "osc", "--seconds", "0.2", "--report", rep, timeout=60)
    one_line_error(r, "actuators[1] (tail).profile.frequency_hz")   # before: exit 0
    assert "50 Hz" in r.stderr and "the highest frequency of this swing that passes is" in r.stderr
    assert not rep.exists() and "joint angle" not in r.stderr
    # --rate-tolerance is the tolerance of osc mode too
    r = run_cli("stream", scene, "--dry-run", "--mode", "osc", "--seconds", "0.2", "--rate-tolerance", "180",
                "--report", rep, timeout=60)
    assert r.returncode == 0, r.stderr
    tail = next(o for o in json.loads(rep.read_text(encoding="utf-8"))["oscillators"] if o["name"] == "tail")
    assert tail["render_deviation_deg"] > 100
    r = run_cli("stream", FISH, "--dry-run", "--mode", "osc", "--seconds", "0.2", "--rate-tolerance", "1",
                timeout=60)
    one_line_error(r, "actuators[1] (tail).profile.frequency_hz")
