"""The two parts of the servo model behind ``stream``'s rate check and ``--mode osc``'s render check, on the
emulated ATmega328P (simavr, firmware/test/sim):

1. the firmware starts a servo pulse every 20 ms with the latest angle it was sent (no slewing between frames
   without max_slew_dps): frames sent 10 ms apart (--rate 100) reach the pins at most once per 20 ms, so a servo
   gets only some of them (mapping.servo_gaps: every second frame at 100 Hz);
2. max_slew_dps: every 10 ms the angle moves towards the target by at most max_slew_dps centidegrees
   (servo.c sl_slew): a 72 deg sine at 1 Hz (452 deg/s at its steepest) under a 300 deg/s limit is flattened on the
   pins as onboard.slew_deviation / mapping.slew_ticks model it.

Angles from pulse widths with the default 500..2500 us range: 1500 us + angle / 90 deg * 1000 us."""
import math
import time

import numpy as np

from metamaterial_wb.hardware import protocol as P
from metamaterial_wb.hardware.mapping import ChannelConfig, servo_gaps, slew_ticks
from test_emulator_osc_render import AMP_DEG, TOL_US, _observed_deviation, _run_sine


def test_frames_10_ms_apart_reach_the_pins_at_most_once_per_20_ms_pulse(link, sim):
    assert servo_gaps(100) == (2,) and servo_gaps(50) == (1,) and servo_gaps(75) == (1, 2)
    link.arm()
    n0 = len(sim.pulse_lines())
    t_next = time.perf_counter()
    for k in range(100):   # 1 s of frames alternating 0 / 30 deg, 10 ms apart
        link.request(P.SET_ANGLES, P.set_angles_payload(0, [3000 if k % 2 else 0]))
        t_next += 0.01
        time.sleep(max(0.0, t_next - time.perf_counter()))
    time.sleep(0.1)
    ts = [t for t, ch, w in sim.pulse_lines()[n0:] if ch == 0 and w is not None]
    widths = {w for t, ch, w in sim.pulse_lines()[n0:] if ch == 0 and w is not None}
    link.disarm()
    assert widths <= {1500.0, 1833.0, 1834.0} or all(abs(w - 1500) < 2 or abs(w - 1833.3) < 2 for w in widths), widths
    gaps = np.diff(ts)
    # a width changes only at a pulse start, 20 ms apart (the log stamps a pulse at its end: the widths differ)
    assert len(ts) <= 55 and (gaps.size == 0 or float(np.min(gaps)) >= 0.0195), (len(ts), gaps[:10])


def test_the_pins_slew_the_osc_sine_as_the_check_models_it(link, sim):
    from metamaterial_wb.hardware.onboard import OSC_STEP_MS, slew_deviation

    def lin(v):
        return np.asarray(v, dtype=float) * AMP_DEG

    link.configure([ChannelConfig("s", 0, scale_deg=90, max_slew_dps=300)])
    link.arm()
    model, peak = slew_deviation(lin, lin, 1.0, 0.0, 1000, 300)
    assert 452 < peak < 453 and model > 3.0          # refused with the default 3 deg
    t0, pts = _run_sine(link, sim, 1000, seconds=3.0)
    link.disarm()
    tol_deg = TOL_US * 90 / 1000
    seen = _observed_deviation(t0, [p for p in pts if p[0] >= t0 + 1.0], 1.0)   # settled: from the second period
    step_timing = AMP_DEG * 2 * math.pi * (OSC_STEP_MS / 2 + 1) / 1000.0
    # the model counts the slew's lag too; the observation allows the best constant delay (up to 30 ms)
    assert model - 452 * 0.03 - tol_deg <= seen <= model + step_timing + tol_deg, (seen, model)
    # the path on the pins against the model's slewed sine, after the best constant delay (0..30 ms)
    t = np.arange(0, 3000, 10) / 1000.0
    slewed = slew_ticks(lin(np.sin(2 * math.pi * t + math.pi / 2)), 300)
    ts = np.array([p[0] for p in pts if p[0] >= t0 + 1.0]) - t0
    ang = np.array([p[1] for p in pts if p[0] >= t0 + 1.0])
    off = min(float(np.max(np.abs(ang - np.interp(ts - lag, t, slewed)))) for lag in np.arange(0.0, 0.0305, 0.0005))
    assert off <= step_timing + tol_deg, (off, seen, model)
