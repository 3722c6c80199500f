"""On-board motion: let the firmware generate the scene's sine profiles itself (OSC mode).

The seed's worm / fish / butterfly gaits are sinusoids; sent once as oscillator parameters they run on the
microcontroller with its own clock, so the host's timing jitter (a busy FreeCAD, a loaded PC) no longer
matters. The host then only keeps the link watchdog fed with PINGs.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from metamaterial_wb.core.errors import SceneError, check_number

from . import protocol as P
from .mapping import (RATE_TOLERANCE_DEG, SERVO_FRAME_MS, SLEW_PERIOD_MS, check_servo_reach, limits_source, slew_advice,
                      slew_ticks)

# How the chip renders an oscillator: sl_link_tick (firmware/src/core/link.c) evaluates it every SL_SLEW_PERIOD_MS
# (10 ms, link.h) and the servo back end starts a pulse every 20 ms (avr/servo_isr.c FRAME_TICKS; the PCA9685
# runs at 50 Hz too), carrying the latest value: the servo sees the sine sampled at 50 Hz, at a phase not locked
# to the sine's start. Streamed frames reach the pins the same way.
OSC_STEP_MS = SLEW_PERIOD_MS
OSC_RENDER_HZ = 1000.0 / SERVO_FRAME_MS
_PHASES = 720   # sample phases compared over a period of the sine (0.5 deg apart)
_SUB = 41       # points compared between two samples (0.5 ms apart at 50 Hz; stream mode compares at 1 kHz)


@dataclass
class OscParams:
    name: str
    channel: int
    amp_cdeg: int
    offset_cdeg: int
    period_ms: int
    phase_cdeg: int
    frequency_error: float = 0.0  # relative error of the frequency after rounding the period to 1 ms
    gain_pos: int = None          # Q14 joint gains (None: amp/offset are angles already)
    gain_neg: int = None
    angle_range_deg: tuple = None  # the joint angles the swing reaches (after the gains)
    gain_error_deg: float = 0.0    # largest difference between the on-board angle and the simulated one
    render_deviation_deg: float = 0.0  # worst distance of the servo (the sine sampled at 50 Hz) from the motion

    def payload(self):
        return P.osc_set_payload(self.channel, self.amp_cdeg, self.offset_cdeg, self.period_ms, self.phase_cdeg,
                                 self.gain_pos, self.gain_neg)


def osc_params(scene, channels, tolerance_deg=None):
    """Oscillator parameters of every channel from its actuator's profile (sine or constant, or none = the
    actuator's value). Raises SceneError for other profile shapes, frequencies the firmware cannot run, and sines
    the chip cannot render: the servo sees the sine sampled at 50 Hz (OSC_RENDER_HZ) and moves linearly between
    the samples (stream mode's model, mapping.rate_deviation); refused when that path strays from the motion by
    more than ``tolerance_deg`` (None: RATE_TOLERANCE_DEG, stream's --rate-tolerance) at any phase."""
    tol = RATE_TOLERANCE_DEG if tolerance_deg is None else check_number("rate_tolerance_deg", tolerance_deg, 0, 180,
                                                                        "deg", low_open=True)
    by_name = {a.name: (k, a) for k, a in enumerate(scene.actuators)}
    out = []
    for c in channels:
        k, a = by_name[c.name]
        p = a.profile or {"shape": "constant", "value": a.value}
        shape = p.get("shape", "sine")
        field = f"actuators[{k}] ({a.name}).profile"
        if shape == "constant":
            amp, off, period, phase, ferr, f = 0.0, p.get("value", 0.0), 0, 0.0, 0.0, 0.0
        elif shape == "sine":
            amp, off = p.get("amplitude", 1.0), p.get("offset", 0.0)
            f = float(p.get("frequency_hz", 1.0))
            if f == 0.0:
                amp, off, period, ferr = 0.0, off + amp * math.sin(math.radians(p.get("phase_deg", 0.0))), 0, 0.0
            else:
                period = int(round(1000.0 / f))
                if not 20 <= period <= 65535:
                    raise SceneError(f"{field}.frequency_hz", f"{f} Hz: the on-board generator runs periods of "
                                                              f"20 ms .. 65.5 s, i.e. 0.0153 .. 50 Hz")
                ferr = (1000.0 / period) / f - 1.0
            phase = p.get("phase_deg", 0.0)
        else:
            raise SceneError(f"{field}.shape", f"{shape!r}: the on-board generator runs sine and constant "
                                               f"profiles only; stream this scene instead (--mode stream)")
        if abs(off) + abs(amp) > 1.0 + 1e-9:
            raise SceneError(field, f"swings over [{off - amp:g}, {off + amp:g}]; actuator values are in [-1, 1]")
        lo, hi = c.limits_deg
        phase_cdeg = int(round((phase % 360.0) * 100)) % 36000
        t_swing, v_swing = _one_period(amp, off, f, phase)  # for the servo's reach (+-angle + trim), once in limits
        where = f"actuators[{k}] ({a.name})"

        def joint_deg(v, c=c):  # the simulated angle of a value (the motion the chip's servo is compared with)
            return np.asarray(c.angle_deg(v), dtype=float)
        if c.scale_deg is not None or c.rotation is None:  # linear: amplitude and offset are angles
            amp_deg, off_deg = c.angle_deg(amp), c.angle_deg(off)
            if off_deg - amp_deg < lo - 1e-9 or off_deg + amp_deg > hi + 1e-9:
                raise _outside_limits(c, field, f"swings over [{off_deg - amp_deg:.1f}, {off_deg + amp_deg:.1f}] deg")
            check_servo_reach(c, c.angle_deg(v_swing), where, t_swing)

            def board(v):  # the chip runs the angle in whole centidegrees
                return np.round(joint_deg(v) * 100.0) / 100.0
            dev = _check_chip(c, where, joint_deg, board, amp, off, f, period, tol)
            out.append(OscParams(c.name, c.channel, int(round(amp_deg * 100)), int(round(off_deg * 100)), period,
                                 phase_cdeg, ferr, angle_range_deg=(off_deg - amp_deg, off_deg + amp_deg),
                                 render_deviation_deg=dev))
            continue
        # the simulated joint rotation: the sine runs in units of v (9000 = 1) and the firmware maps it with one
        # gain per sign of v (closing and opening differ); exact for untilted joints, checked for tilted ones
        a_pos, a_neg = c.angle_deg(1.0), c.angle_deg(-1.0)
        g_pos, g_neg = int(round(a_pos / 90.0 * P.GAIN_ONE)), int(round(-a_neg / 90.0 * P.GAIN_ONE))
        if max(abs(g_pos), abs(g_neg)) > 32767:
            raise SceneError(field, f"joint {c.rotation.joint} turns by {a_pos:.1f} / {a_neg:.1f} deg at v = +1 / -1: "
                                    f"the on-board generator maps at most 180 deg per unit; stream it instead")
        v = np.linspace(off - amp, off + amp, 401)
        exact = np.asarray(c.angle_deg(v))
        board = v * 90.0 * np.where(v >= 0, g_pos, g_neg) / P.GAIN_ONE
        err = float(np.max(np.abs(board - exact)))
        if err > 0.25:
            raise SceneError(field, f"the rotation of joint {c.rotation.joint} (a tilted hinge) is not proportional "
                                    f"to v over this swing: the on-board generator would be off by {err:.2f} deg "
                                    f"(allowed 0.25); stream this scene instead (--mode stream)")
        a_lo, a_hi = float(np.min(exact)), float(np.max(exact))
        if a_lo < lo - 1e-9 or a_hi > hi + 1e-9:
            raise _outside_limits(c, field, f"swings over [{a_lo:.2f}, {a_hi:.2f}] deg of joint rotation")
        for angles in (c.angle_deg(v_swing), v_swing * 90.0 * np.where(v_swing >= 0, g_pos, g_neg) / P.GAIN_ONE):
            check_servo_reach(c, angles, where, t_swing)  # the simulated and the chip's

        def board(v, g_pos=g_pos, g_neg=g_neg):  # v in units of 1/9000, the gains in Q14, whole centidegrees
            vq = np.round(np.asarray(v, dtype=float) * 9000.0) / 9000.0
            return np.round(vq * 9000.0 * np.where(vq >= 0, g_pos, g_neg) / P.GAIN_ONE) / 100.0
        dev = _check_chip(c, where, joint_deg, board, amp, off, f, period, tol)
        out.append(OscParams(c.name, c.channel, int(round(amp * 9000)), int(round(off * 9000)), period, phase_cdeg,
                             ferr, g_pos, g_neg, (a_lo, a_hi), err, dev))
    return out


def _outside_limits(c, field, swing):
    """SceneError: the sine of ``field`` (``actuators[k] (name).profile``) ``swing``s past channel ``c``'s limits,
    named where they were given: ``--channels FILE NAME.limits_deg`` (mapping.limits_source), else the profile (in
    the scene file)."""
    lo, hi = c.limits_deg
    src = limits_source(c)
    if src:
        return SceneError(src, f"[{lo:g}, {hi:g}] deg: {field} {swing}, outside these limits of channel "
                               f"{c.channel}; widen them, or lower the scene's profile")
    return SceneError(field, f"{swing}; channel {c.channel} allows [{lo:g}, {hi:g}] deg")


def render_deviation(exact, board, amp, off, freq_hz, rate_hz=OSC_RENDER_HZ):
    """How far a servo strays (deg) from the motion ``exact(off + amp sin(2 pi freq_hz t + phi))`` when it gets
    the chip's angles ``board(v)`` of that sine ``rate_hz`` times a second and moves linearly from one to the next
    (the model of stream mode, mapping.rate_deviation). The samples' phase against the sine is not controlled (the
    chip's servo frames run from its power-up), so the worst over every phase (_PHASES of them), compared at _SUB
    points between two samples. 0 for a constant."""
    if not amp or not freq_hz:
        return 0.0
    step = 2.0 * math.pi * freq_hz / rate_hz  # the sine's phase from one sample to the next
    phi = np.linspace(0.0, 2.0 * math.pi, _PHASES, endpoint=False)[:, None]
    sub = np.linspace(0.0, 1.0, max(_SUB, int(math.ceil(step / (2.0 * math.pi) * 64)) + 1))[None, :]
    # plus, between each pair of samples, where the sine peaks and where v crosses 0 (a joint's corner from closing
    # to opening): the worst places
    marks = [math.pi / 2, 3 * math.pi / 2]
    if abs(off) < abs(amp):
        marks += [math.asin(-off / amp), math.pi - math.asin(-off / amp)]
    at = np.mod(np.asarray(marks)[None, :] - phi, 2.0 * math.pi) / step
    sub = np.hstack([np.broadcast_to(sub, (_PHASES, sub.shape[1])), np.where(at <= 1.0, at, 0.0)])
    y0 = board(off + amp * np.sin(phi))
    y1 = board(off + amp * np.sin(phi + step))
    motion = exact(off + amp * np.sin(phi + step * sub))
    return float(np.max(np.abs(y0 + (y1 - y0) * sub - motion)))


def slew_deviation(exact, board, amp, off, period_ms, max_slew_dps, phases=10):
    """(deg, peak deg/s): how far the chip's slew (mapping.slew_ticks: towards the oscillator's value ``board(v)``
    of each 10 ms step by at most ``max_slew_dps`` deg/s) holds the servo from the motion ``exact(v)`` once settled
    (the third period), the worst over ``phases`` offsets of the steps in the sine; and the motion's peak speed."""
    if not amp or not period_ms:
        return 0.0, 0.0
    n = int(math.ceil(period_ms / OSC_STEP_MS))
    t = (np.arange(3 * n)[None, :] * OSC_STEP_MS + np.linspace(0, OSC_STEP_MS, phases, endpoint=False)[:, None])
    v = off + amp * np.sin(2.0 * math.pi * t / period_ms)
    dense = exact(off + amp * np.sin(2.0 * math.pi * np.arange(period_ms + 1) / period_ms))
    peak = float(np.max(np.abs(np.diff(dense)))) * 1000.0
    if not max_slew_dps or peak <= max_slew_dps:
        return 0.0, peak
    dev = np.abs(slew_ticks(board(v), max_slew_dps) - exact(v))[:, 2 * n:]
    return float(np.max(dev)), peak


def _check_chip(c, where, exact, board, amp, off, freq_hz, period_ms, tol):
    """The sine of ``where`` as the chip runs it (``board``) against the motion (``exact``): how its servo renders it
    (_check_render, naming the profile's frequency) and its channel's slew limit (_check_slew); SceneError beyond
    ``tol``. Returns the render deviation."""
    dev = _check_render(f"{where}.profile.frequency_hz", c.name, exact, board, amp, off, freq_hz, period_ms, tol)
    _check_slew(c, where, exact, board, amp, off, period_ms, tol)
    return dev


def _check_slew(c, where, exact, board, amp, off, period_ms, tol):
    dev, peak = slew_deviation(exact, board, amp, off, period_ms, c.max_slew_dps)
    if dev > tol:
        raise SceneError(f"channel {c.channel} ({c.name}).max_slew_dps",
                         f"{c.max_slew_dps} deg/s: the chip turns the servo of {where} at most {c.max_slew_dps} "
                         f"deg/s, but its sine moves at up to {peak:.0f} deg/s: the servo would be {dev:.2f} deg off "
                         f"the motion; allowed: at most {tol:g} deg (--rate-tolerance); "
                         + slew_advice(c.max_slew_dps, "the sine"))


def _check_render(field, name, exact, board, amp, off, freq_hz, period_ms, tol):
    """render_deviation of the sine the chip runs (its period in whole ms); SceneError naming ``field`` when it
    exceeds ``tol``, with the highest frequency of this swing that passes. Returns the deviation."""
    if not amp or not period_ms:
        return 0.0
    f_chip = 1000.0 / period_ms
    dev = render_deviation(exact, board, amp, off, f_chip)
    if dev <= tol:
        return dev
    nyq = OSC_RENDER_HZ / 2.0
    msg = (f"{freq_hz:g} Hz: the chip steps its sine every {OSC_STEP_MS} ms and gives the servo a pulse every "
           f"{SERVO_FRAME_MS} ms, so {name}'s servo sees it sampled at {OSC_RENDER_HZ:g} Hz; moving linearly from "
           f"pulse to pulse it would be {dev:.2f} deg off the motion; allowed: at most {tol:g} deg (--rate-tolerance)")
    if f_chip >= nyq:
        msg += f"; {freq_hz:g} Hz is not below {nyq:g} Hz, half of {OSC_RENDER_HZ:g} Hz (Nyquist): the pins alias it"
    f_ok = _highest_passing(exact, board, amp, off, min(f_chip, nyq), tol)
    if f_ok is None:
        msg += ("; no frequency passes: even a slow swing is off by more (the chip's joint gains, whole "
                "centidegrees); allow more with --rate-tolerance")
    else:
        msg += (f"; the highest frequency of this swing that passes is {f_ok:g} Hz: slow it down, lower its "
                f"amplitude, or allow more with --rate-tolerance")
    raise SceneError(field, msg)


def _highest_passing(exact, board, amp, off, f_hi, tol):
    """The highest frequency in (0, f_hi] whose render_deviation, at the frequency the chip runs (its period in
    whole ms), is within ``tol`` (it grows with the frequency up to the Nyquist rate), rounded down to 3
    significant digits, or None when even a slow swing is not. The number returned is the one the message shows
    (``{:g}``) and passes itself: typed back as the profile's frequency it is accepted. The deviation is not quite
    monotone in the period (whole centidegrees, the joint gains): where the frequency found, rounded down, fails,
    the next lower 3-digit frequencies are tried until one passes."""
    def ok(f):
        return render_deviation(exact, board, amp, off, 1000.0 / min(65535, max(1, round(1000.0 / f)))) <= tol
    lo, hi = f_hi * 1e-4, f_hi
    if ok(f_hi):
        lo = f_hi
    elif not ok(lo):
        return None
    while hi - lo > 1e-4 * hi:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if ok(mid) else (lo, mid)
    m, e = _down3(lo)
    for _ in range(1000):               # 3-digit frequencies from lo down (lo itself, not one of them, passes)
        f = float(f"{m}e{e}")           # the decimal m * 10**e, as the message prints it and as it is typed back
        if ok(f):
            return f
        m, e = (m - 1, e) if m > 100 else (999, e - 1)
    return None


def _down3(x):
    """``(m, e)``: the largest decimal ``m * 10**e`` <= ``x`` with 3 significant digits (m in 100..999)."""
    e = math.floor(math.log10(x)) - 2
    m = min(999, math.floor(x / 10.0 ** e))
    while float(f"{m}e{e}") > x:        # 10**e is not exact in binary: never above x
        m, e = (m - 1, e) if m > 100 else (999, e - 1)
    return m, e


def _one_period(amp, off, freq_hz, phase_deg):
    """Times over the first period (1 ms apart, plus the two extremes of the sine) and the values v(t) there."""
    if not amp or not freq_hz:
        return np.zeros(1), np.full(1, float(off))
    period, ph = 1.0 / freq_hz, math.radians(phase_deg)
    extremes = [((s * math.pi / 2 - ph) / (2 * math.pi * freq_hz)) % period for s in (1, -1)]
    t = np.union1d(np.arange(0.0, period, 1e-3), extremes)
    return t, off + amp * np.sin(2 * math.pi * freq_hz * t + ph)


def keepalive_interval(watchdog_ms, cap_s=0.1):
    """Seconds between keep-alive frames: the device must hear from the host more often than every
    ``watchdog_ms / 3`` (firmware/PROTOCOL.md section 6), and at least every ``cap_s``. None: the default 500 ms."""
    if not watchdog_ms:
        return cap_s
    return min(cap_s, watchdog_ms / 3000.0)


def link_watchdog_ms(link):
    """The watchdog the link was configured with (CONFIG_LINK), else the device's (HELLO_ACK), else None."""
    wd = getattr(link, "watchdog_ms", None)
    if wd is None and getattr(link, "info", None) is not None:
        wd = link.info.watchdog_ms
    return wd


def raise_on_trip(link, since, context="during on-board motion"):
    """LinkError if the device reported an EVENT among ``link.events[since:]`` (a servo-driver fault, or the link
    watchdog tripped ``context``); the one check of the streamed and the on-board modes. Returns ``len(link.events)``,
    where the next check starts."""
    from .link import LinkError
    for _, e in link.events[since:]:
        if e.kind == "EVENT" and e.code == P.EV_SERVO_FAULT:
            raise LinkError(f"{link.name}: EVENT SERVO_FAULT: {P.SERVO_FAULT_HELP}")
        if e.kind == "EVENT":
            raise LinkError(f"{link.name}: the firmware's link watchdog tripped "
                            f"({P.EVENT_NAMES.get(e.code, hex(e.code))} at {e.time_ms} ms) {context}: the host was "
                            f"silent for longer than the link watchdog; the servos hold, then park; connect again "
                            f"to re-ARM")
    return len(link.events)


def rtt_key(ms):
    """A round trip (ms) as kept in a round-trip table (StreamStats.rtt_counts, run_oscillators' rtt_counts): to the
    microsecond (the summary's precision) below 10 ms, to 4 significant digits above (10 us up to 100 ms, ...), so
    the table stays small however long the stream runs (a reply waits for at most 254 frames before its seq is
    reused)."""
    return round(ms, 3) if ms < 10.0 else float(f"{ms:.4g}")


def count_rtt(counts, ms):
    """Count the round trip ``ms`` in the table ``counts`` ({rtt_key(ms): n}, changed in place)."""
    k = rtt_key(ms)
    counts[k] = counts.get(k, 0) + 1


def rtt_stats(counts):
    """(median, 99th percentile, max) of the round trips counted in ``counts`` ({ms: n}), as
    ``statistics.median`` and ``sorted(r)[min(n - 1, int(0.99 n))]`` of the list they stand for; Nones if empty."""
    n = sum(counts.values())
    if not n:
        return None, None, None
    want = sorted({(n - 1) // 2, n // 2, min(n - 1, int(0.99 * n))})
    at, seen = {}, 0
    for ms in sorted(counts):
        seen += counts[ms]
        while want and want[0] < seen:  # the sorted list's items [seen - counts[ms], seen) are all ms
            at[want.pop(0)] = ms
        if not want:
            break
    return (at[(n - 1) // 2] + at[n // 2]) / 2, at[min(n - 1, int(0.99 * n))], max(counts)


def rtt_summary(counts):
    """{"rtt_ms_median", "rtt_ms_p99", "rtt_ms_max"} of a round-trip table, to the microsecond (None if empty)."""
    return {f"rtt_ms_{k}": None if v is None else round(v, 3)
            for k, v in zip(("median", "p99", "max"), rtt_stats(counts))}


def run_oscillators(link, params, seconds, keepalive_s=None, stop=None, result=None):
    """Send the oscillators, switch to OSC mode, keep the link alive for ``seconds`` (or until ``stop()``
    returns true) with a PING every ``keepalive_s`` (default: ``keepalive_interval`` of the link's watchdog).
    Raises LinkError as soon as the firmware reports a watchdog trip.

    Returns ``result`` (a new dict if None), filled in as it runs so that a caller has what ran when this raises:
    "started" (the firmware switched to OSC mode), "t_start_ms" (its time then: the oscillators' origin),
    "pings", "rtt_counts" (the PINGs' round trips as a bounded table, {rtt_key(ms): n}, as StreamStats keeps the
    frames'; memory does not grow with ``seconds``) and, at the end, rtt_summary's "rtt_ms_median", "rtt_ms_p99",
    "rtt_ms_max"."""
    res = {} if result is None else result
    res.update(started=False, t_start_ms=None, pings=0, rtt_counts={})
    if keepalive_s is None:
        keepalive_s = keepalive_interval(link_watchdog_ms(link))
    n_events = len(link.events)
    for p in params:
        link.request(P.OSC_SET, p.payload())
    r = link.request(P.SET_MODE, bytes([P.MODE_OSC]))
    # the oscillators' time origin
    res.update(started=True, t_start_ms=int.from_bytes(r.data[:4], "little") if len(r.data) >= 4 else None)
    end = time.perf_counter() + seconds
    while time.perf_counter() < end and not (stop and stop()):
        t0 = time.perf_counter()
        link.request(P.PING)
        count_rtt(res["rtt_counts"], (time.perf_counter() - t0) * 1000.0)
        res["pings"] += 1
        raise_on_trip(link, n_events)
        while True:  # wait for the next PING, reading (events) meanwhile
            left = min(t0 + keepalive_s, end) - time.perf_counter()
            if left <= 0 or (stop and stop()):
                break
            link.poll(min(left, 0.01))
            raise_on_trip(link, n_events)
    raise_on_trip(link, n_events)
    res.update(rtt_summary(res["rtt_counts"]))
    return res


class FirmwareGait:
    """The distributed gait rule (seed 001, Algorithm 1) evaluated by the firmware.

    ``step(c_air)`` has the meaning of ``metamaterial_wb.core.gait.gait_rule_step``: ``c_air[i] = 1`` when cell
    i is in the air; returns 1 for the cells to inflate. With ``pins=True`` the board reads its own contact
    switches instead: cell k on A0 + k (port C, PC0..PC5: A0..A5, up to 6 cells; A0..A3 with the PCA9685 back
    end, whose I2C bus takes A4 / A5), a switch closed to ground = on the ground (internal pull-ups).
    ``start()`` lets the board drive its servos (GAIT mode; needs ARM): channel k shows cell ``first_cell + k``
    at ``inflate_deg`` or ``vent_deg``."""

    def __init__(self, link, n_cells, n1, n2, closed=True, pins=False, first_cell=0, inflate_deg=45.0,
                 vent_deg=0.0):
        self.link, self.n = link, int(n_cells)
        link.request(P.GAIT_SET, P.gait_set_payload(self.n, int(n1), int(n2), closed=closed, pins=pins,
                                                    first_cell=first_cell, inflate_cdeg=int(round(inflate_deg * 100)),
                                                    vent_cdeg=int(round(vent_deg * 100))))

    def step(self, c_air):
        if len(c_air) != self.n:
            raise SceneError("gait contacts", f"{len(c_air)} sensor values for {self.n} cells")
        r = self.link.request(P.GAIT_CONTACTS, P.pack_mask(c_air))
        return P.unpack_mask(r.data, self.n)

    def start(self):
        return self.link.request(P.SET_MODE, bytes([P.MODE_GAIT]))
