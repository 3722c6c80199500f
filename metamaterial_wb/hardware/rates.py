"""Can the frames follow the motion? The rate, slew-limit and loop-wrap checks of a stream (split from mapping.py).

* ``rate_deviation`` / ``check_rate``: how far the servos stray from the scene's motion when it is streamed at a
  frame rate (the frames in whole centidegrees, a servo pulse every SERVO_FRAME_MS with the latest frame);
* ``check_slew`` (run by ``check_rate`` once the rate passes): how far a channel's firmware slew limit
  (``max_slew_dps``, ``slew_ticks``: every SLEW_PERIOD_MS) holds its servo off the motion;
* ``wrap_jumps``: the step each servo is sent where a looping timeline wraps from its end back to its start.

``mapping`` re-exports every name here (``mapping.check_motion`` runs the limits, the servo reach and then
``check_rate``). Pure Python + numpy; the channels are ``mapping.ChannelConfig`` objects, used by attribute only
(no import of mapping: it imports this module).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from metamaterial_wb.core.errors import SceneError, check_number

RATE_TOLERANCE_DEG = 3.0  # the fish's tail at 50 Hz strays 1.86 deg (the corner of its joint's two rotation rates)
MAX_RATE_HZ = 100         # the streamer's allowed rates: 1..100 Hz
_DENSE_S = 1e-3           # the motion is compared at 1 kHz (as check_motion samples it)
_WINDOW = 100_000         # dense samples per block (long streams are compared block by block)
_SUGGEST_SPAN_S = 600.0   # the whole rates suggested after a refusal are compared over at most this much motion
# The firmware starts a servo pulse every 20 ms (avr/servo_isr.c FRAME_TICKS; the PCA9685 runs at 50 Hz too) with
# the latest angle: above 50 Hz a servo gets only some of the frames, 20 ms apart (at a phase not tied to them).
SERVO_FRAME_MS = 20
SLEW_PERIOD_MS = 10       # the firmware's slew step (link.h SL_SLEW_PERIOD_MS): max_slew_dps cdeg per 10 ms
MAX_SLEW_DPS = 3600       # the highest slew limit a channel takes (0: none)


def slew_advice(max_slew_dps, what):
    """What to do when a channel's slew limit holds its servo too far from ``what`` (the motion, the sine)."""
    raise_it = f"raise max_slew_dps (at most {MAX_SLEW_DPS}) or " if max_slew_dps < MAX_SLEW_DPS else ""
    return f"{raise_it}slow {what} down"


def servo_gaps(rate_hz, pulse_hz=None):
    """How many frame periods apart the frames a servo gets are (a pulse ``pulse_hz`` times a second of motion,
    None: every SERVO_FRAME_MS, each with the latest frame): (1,) up to 50 Hz, else floor and ceil of
    rate_hz * 20 ms (either one at some phase)."""
    q = rate_hz / (1000.0 / SERVO_FRAME_MS if pulse_hz is None else pulse_hz)
    return (1,) if q <= 1 + 1e-9 else tuple(sorted({int(math.floor(q + 1e-9)), int(math.ceil(q - 1e-9))}))


def slew_ticks(target_deg, max_slew_dps, start_deg=None):
    """The firmware's slew (servo.c sl_slew, every SLEW_PERIOD_MS): the angle moves towards each tick's target
    (``target_deg[..., i]``) by at most max_slew_dps centidegrees (max_slew_dps deg/s); 0: none. Vectorised over
    the leading axes; starts at ``start_deg`` (default the first target).

    The tick law ``cur += clip(target - cur, -step, step)`` is computed without a Python loop per tick
    (_slew_row); equal to that loop within rounding (1e-9 deg; tests/hardware/test_slew_vector.py)."""
    y = np.asarray(target_deg, dtype=float)
    if not max_slew_dps or y.shape[-1] == 0:
        return y.copy()
    step = max_slew_dps * SLEW_PERIOD_MS / 1000.0
    start = y[..., 0] if start_deg is None else np.broadcast_to(np.asarray(start_deg, float), y[..., 0].shape)
    rows, n = y.reshape(-1, y.shape[-1]), y.shape[-1]
    cur = np.array(start, dtype=float).reshape(-1)
    if rows.shape[0] >= n:       # many short rows: the tick loop, vectorised over the rows, is the faster
        out = np.empty_like(rows)
        for i in range(n):
            cur = cur + np.clip(rows[:, i] - cur, -step, step)
            out[:, i] = cur
        return out.reshape(y.shape)
    return np.stack([_slew_row(r, float(c0), step) for r, c0 in zip(rows, cur)]).reshape(y.shape)


_SLEW_CHUNK = 64   # ticks a slew phase is first computed over (doubled while the phase goes on)


def _slew_row(y, cur, step):
    """slew_ticks of one row of targets ``y`` from ``cur``, by phases. In a rising phase the lower limit never
    binds, so ``x[k] = min(y[k], x[k-1] + step)``, whose closed form is ``k step + min(cur + step,
    cummin(y[m] - m step))`` (k, m counted from the phase's start); the phase ends at the first tick whose target
    lies more than ``step`` below the angle before it (the lower limit binds: a falling phase, the same in
    mirror image). One numpy pass per phase: a phase per turn of a motion the limit holds back, one in all while
    it follows."""
    n = y.size
    out = np.empty(n)
    i, sign, chunk = 0, (-1.0 if y[0] < cur - step else 1.0), _SLEW_CHUNK
    while i < n:
        j = min(n, i + chunk)
        ys, c = sign * y[i:j], sign * cur
        ks = np.arange(j - i) * step
        x = np.minimum(ys, ks + np.minimum(c + step, np.minimum.accumulate(ys - ks)))
        before = np.concatenate(([c], x[:-1]))
        turn = np.flatnonzero(ys < before - step)
        if turn.size:                # the other limit binds at i + b: the phase ends there, the mirror one starts
            b = int(turn[0])
            out[i:i + b] = sign * x[:b]
            cur, i, sign, chunk = sign * before[b], i + b, -sign, _SLEW_CHUNK
        else:
            out[i:j] = sign * x
            cur, i, chunk = sign * x[-1], j, 2 * chunk
    return out


@dataclass
class RateDeviation:
    """The worst distance (``deg``) between the motion and the servo's path through the frames, at ``t``."""
    deg: float
    name: str = None          # actuator
    channel: int = None
    t: float = None           # s
    servo_deg: float = None   # where the servo is (on its path between frames)
    motion_deg: float = None  # where the motion is


def _check_tolerance(tolerance_deg, field_name="rate_tolerance_deg"):
    if tolerance_deg is None:
        return RATE_TOLERANCE_DEG
    return check_number(field_name, tolerance_deg, 0, 180, "deg", low_open=True)


def _rate_tracks(scene, channels, clamp):
    """``[(cfg, angles(t), steps)]`` of the channels whose motion changes: ``angles`` gives the commanded angles
    (clamped to the limits with ``clamp``, as they are sent); ``steps``: the profile jumps."""
    from metamaterial_wb.core.motion import profile_value

    by_name = {a.name: a for a in scene.actuators}
    out = []
    for c in channels:
        a = by_name[c.name]
        p = a.profile
        if p is None or p.get("shape", "sine") == "constant":
            continue

        def angles(t, a=a, c=c):
            v = np.atleast_1d(profile_value(a.profile, t, a.value)) * np.ones_like(t)
            ang = np.atleast_1d(np.asarray(c.angle_deg(v), dtype=float))
            return np.clip(ang, *c.limits_deg) if clamp else ang
        out.append((c, angles, p.get("shape") == "steps"))
    return out


def _deviations(tracks, duration_s, rates, stop_above=None, pulse_hz=None, window=None):
    """``{rate: RateDeviation}``: the worst deviation of each rate over [0, duration_s]. With ``stop_above``, a
    rate is dropped (its entry kept) as soon as it exceeds it. ``window``: dense samples per block (None:
    _WINDOW)."""
    window = window or _WINDOW
    worst = {r: RateDeviation(0.0) for r in rates}
    alive = list(rates)
    n = int(math.floor(duration_s / _DENSE_S + 1e-9)) + 1
    for i0 in range(0, n, window):
        td = np.arange(i0, min(n, i0 + window)) * _DENSE_S
        if i0 + window >= n and td[-1] < duration_s - 1e-12:
            td = np.append(td, duration_s)
        for c, angles, steps in tracks:
            m = angles(td)
            for r in alive:
                # the frames around the block: t = k / r (the one after the last sent one included), and of them
                # the ones a servo gets: every g-th (servo_gaps), frame 0 included, for each offset o
                for g in servo_gaps(r, pulse_hz):
                    k0 = int(math.floor(td[0] * r - 1e-9)) - g
                    k1 = max(k0 + 1, int(math.ceil(td[-1] * r + 1e-9))) + g
                    for o in range(g):
                        k = np.arange(max(k0, 0), k1 + 1)
                        k = k[((k - o) % g == 0) | (k == 0)]
                        tf = k / r
                        f = np.round(angles(tf) * 100.0) / 100.0    # in the whole centidegrees sent
                        path = np.interp(td, tf, f)
                        if steps:  # no servo follows a jump: the nearer of the two frames around t counts
                            j = np.clip(np.searchsorted(tf, td, side="right") - 1, 0, len(tf) - 2)
                            cand = np.stack([path, f[j], f[j + 1]])
                            path = cand[np.argmin(np.abs(cand - m), axis=0), np.arange(td.size)]
                        dev = np.abs(m - path)
                        i = int(np.argmax(dev >= dev.max() - 1e-6))   # the earliest place of the worst (rounding)
                        if dev[i] > worst[r].deg + 1e-6:
                            worst[r] = RateDeviation(float(dev[i]), c.name, c.channel, float(td[i]),
                                                     float(path[i]), float(m[i]))
        if stop_above is not None:
            alive = [r for r in alive if worst[r].deg <= stop_above]
            if not alive:
                break
    return worst


def rate_deviation(scene, channels, duration_s, rate_hz, clamp=False, pulse_hz=None):
    """How far the servos stray from the scene's motion when it is streamed at ``rate_hz``.

    The frames go out at t = k / rate_hz (in whole centidegrees; with ``clamp`` clamped to the limits); the
    firmware gives the servo a pulse ``pulse_hz`` times a second of motion (None: 50, every SERVO_FRAME_MS of
    wall time; a player at speed s sending 50 frames a wall second passes 50 / s, so that every frame counts) with
    the latest frame, so above that rate a servo gets only some of them (servo_gaps, the worst phase), and it
    moves linearly from one frame's angle it gets to the next; the motion is sampled at 1 kHz over [0, duration_s]
    (the frames' age at a pulse is a timing jitter, not counted, as for the chip's oscillators). For
    a ``steps`` profile, whose jumps no servo follows, the distance at t is to the nearer of the two frames around
    t (a level shorter than a frame period that falls between two frames counts). Returns the worst
    RateDeviation (``deg`` 0 when nothing moves)."""
    return _deviations(_rate_tracks(scene, channels, clamp), duration_s, [rate_hz], pulse_hz=pulse_hz)[rate_hz]


def check_rate(scene, channels, duration_s, rate_hz, clamp=False, tolerance_deg=None, window=None):
    """Raise SceneError naming ``--rate`` when the servos stray from the motion by more than ``tolerance_deg``
    (None: RATE_TOLERANCE_DEG) at ``rate_hz`` (rate_deviation), with the worst place, the Nyquist rate of the
    fastest sine and the whole rates that would pass; when the rate passes, naming a channel's max_slew_dps when
    its slew limit holds the servo further off (check_slew). ``window``: the motion's samples per block (None:
    _WINDOW; check_motion passes its own)."""
    tol = _check_tolerance(tolerance_deg)
    tracks = _rate_tracks(scene, channels, clamp)
    d = _deviations(tracks, duration_s, [rate_hz], window=window)[rate_hz]
    if d.deg <= tol:
        for c, angles, steps in tracks:
            _check_slew(c, angles, duration_s, rate_hz, tol, steps, window=window)
        return d
    gaps = servo_gaps(rate_hz)
    apart = " or ".join(f"{1000.0 * g / rate_hz:.4g}" for g in gaps)
    pulse = ("" if gaps == (1,) else f" (its servo gets a pulse every {SERVO_FRAME_MS} ms with the latest of the "
                                     f"frames sent {1000.0 / rate_hz:.4g} ms apart)")
    msg = (f"{rate_hz:g} Hz cannot follow the motion: {d.name} (channel {d.channel}), moving linearly between "
           f"frames {apart} ms apart{pulse}, would be {d.deg:.2f} deg off it at t = {d.t:.3f} s (at "
           f"{d.servo_deg:.2f} deg where the motion is at {d.motion_deg:.2f} deg); allowed: at most {tol:g} deg "
           f"(--rate-tolerance)")
    sines = [(float(a.profile.get("frequency_hz", 1.0)), a.name) for a in scene.actuators
             if a.name in {c.name for c, _, _ in tracks} and a.profile.get("shape", "sine") == "sine"
             and a.profile.get("amplitude", 1.0) > 0]
    if sines:
        f, name = max(sines)
        if rate_hz <= 2 * f:
            msg += f"; {rate_hz:g} Hz is not above {2 * f:g} Hz, twice the {f:g} Hz of {name}'s sine (Nyquist)"
        elif gaps != (1,) and 1000.0 / SERVO_FRAME_MS <= 2 * f:
            msg += (f"; the servo gets a pulse every {SERVO_FRAME_MS} ms: {1000.0 / SERVO_FRAME_MS:g} Hz is not above "
                    f"{2 * f:g} Hz, twice the {f:g} Hz of {name}'s sine (Nyquist)")
    # the whole rates that pass (over at most _SUGGEST_SPAN_S of motion: 100 rates over a day would take minutes;
    # the rate then chosen is checked over the whole stream like any other)
    span = min(duration_s, _SUGGEST_SPAN_S)
    over = "" if span == duration_s else f" (over the first {span:g} s)"
    whole = list(range(1, MAX_RATE_HZ + 1))
    ok = [r for r, w in _deviations(tracks, span, whole, stop_above=tol, window=window).items() if w.deg <= tol]
    if MAX_RATE_HZ not in ok:
        msg += (f"; no rate up to {MAX_RATE_HZ} Hz passes{over}: slow the motion down, or allow more with "
                f"--rate-tolerance")
    else:
        every = MAX_RATE_HZ
        while every - 1 in ok:
            every -= 1
        if ok[0] == every:
            msg += f"; every whole rate from {every} to {MAX_RATE_HZ} Hz passes{over} (none lower): --rate {every}"
        else:
            msg += (f"; the lowest whole rate that passes{over} is {ok[0]} Hz, and every whole rate from {every} "
                    f"to {MAX_RATE_HZ} Hz does (some in between do not)")
    raise SceneError("--rate", msg)


def check_slew(scene, channels, duration_s, rate_hz, clamp=False, tolerance_deg=None, speed=1.0, window=None):
    """Raise SceneError naming a channel's max_slew_dps when the firmware's slew limit holds its servo more than
    ``tolerance_deg`` (None: RATE_TOLERANCE_DEG) off the motion over [0, duration_s] (_check_slew), the frames
    going out at ``rate_hz`` per second of motion (with ``clamp`` clamped to the limits). ``speed``: the motion
    is played ``speed`` times faster than wall time (the Animate panel's speed). What check_rate runs once the
    rate passes (the ``stream`` command); the Animate panel's Connect runs it too."""
    tol = _check_tolerance(tolerance_deg)
    speed = check_number("speed", speed, 0.0, None, "x", low_open=True)
    for c, angles, steps in _rate_tracks(scene, channels, clamp):
        _check_slew(c, angles, duration_s, rate_hz, tol, steps, speed=speed, window=window)


def _check_slew(c, angles, duration_s, rate_hz, tol, steps=False, speed=1.0, window=None):
    """SceneError naming ``c``'s max_slew_dps when the firmware's slew (slew_ticks, its targets the servo's path
    through the frames) holds the servo more than ``tol`` off the motion; nothing when the path never outruns it
    (the ticks where the slew does not act are the path the rate check accepted). ``steps``: a jump no servo
    follows is forgiven there (the nearer frame counts), so the slewed servo is compared with that path instead.

    The firmware ticks every SLEW_PERIOD_MS of wall time and its limit is per wall second: with the motion played
    ``speed`` times faster, a tick comes every SLEW_PERIOD_MS * speed of motion (``rate_hz``: frames per second
    of motion) and the speed named in the message is the played motion's (deg per wall second); times are the
    motion's. The motion is sampled at 1 kHz (its peak speed) in blocks of ``window`` samples (None: _WINDOW)."""
    if not c.max_slew_dps:
        return
    window = window or _WINDOW
    cur, peak = None, 0.0
    n = int(math.floor(duration_s / _DENSE_S + 1e-9)) + 1
    tick = SLEW_PERIOD_MS * speed    # dense samples (ms of motion) from one tick to the next
    for i0 in range(0, n, window):   # ticks every 10 ms (of wall time) from t = 0, the motion at 1 kHz for its peak
        i1 = min(n, i0 + window)
        td = np.arange(i0, i1) * _DENSE_S
        peak = max(peak, speed * float(np.max(np.abs(np.diff(angles(np.append(td, td[-1] + _DENSE_S)))))) / _DENSE_S)
        j0 = int(math.ceil(i0 / tick - 1e-9))          # the ticks in [i0, i1) ms (the last block: to its last sample)
        j1 = int(math.ceil(i1 / tick - 1e-9)) if i1 < n else int(math.floor((n - 1) / tick + 1e-9)) + 1
        if j1 <= j0:
            continue
        tt = np.arange(j0, j1) * SLEW_PERIOD_MS * _DENSE_S * speed
        k = np.arange(max(0, int(math.floor(tt[0] * rate_hz)) - 1), int(math.ceil(tt[-1] * rate_hz)) + 2)
        path = np.interp(tt, k / rate_hz, np.round(angles(k / rate_hz) * 100.0) / 100.0)
        slewed = slew_ticks(path, c.max_slew_dps, cur)
        cur = slewed[-1]
        held = np.abs(slewed - path) > 0.005           # ticks where the limit holds the servo back (0.5 cdeg)
        dev = np.where(held, np.abs(slewed - (path if steps else angles(tt))), 0.0)
        i = int(np.argmax(dev))
        if dev[i] > tol:
            raise SceneError(f"channel {c.channel} ({c.name}).max_slew_dps",
                             f"{c.max_slew_dps} deg/s: the firmware turns {c.name}'s servo at most {c.max_slew_dps} "
                             f"deg/s, but the motion moves at up to {peak:.0f} deg/s: the servo would be "
                             f"{dev[i]:.2f} deg off it at t = {tt[i]:.3f} s (at {slewed[i]:.2f} deg where the "
                             f"motion is at {float(angles(tt[i:i + 1])[0]):.2f} deg); allowed: at most {tol:g} deg "
                             f"(--rate-tolerance); " + slew_advice(c.max_slew_dps, "the motion"))


@dataclass
class WrapJump:
    """The step a channel is sent when a looping timeline wraps from its end back to its start, in the whole
    centidegrees of the frames (commanded joint angles, before the firmware's invert / trim)."""
    name: str                 # actuator
    channel: int
    end_cdeg: int             # the angle sent at t = duration_s
    start_cdeg: int           # the angle sent at t = 0

    @property
    def end_deg(self):
        return self.end_cdeg / 100

    @property
    def start_deg(self):
        return self.start_cdeg / 100

    @property
    def deg(self):
        """The size of the jump (degrees, >= 0)."""
        return abs(self.end_cdeg - self.start_cdeg) / 100


def wrap_jumps(scene, channels, duration_s, clamp=False):
    """The jump each channel's servo is sent when a timeline of ``duration_s`` that loops (the Animate panel's
    Loop) wraps from its end back to its start: the frames go from the angle at t = ``duration_s`` to the one at
    t = 0 (the clock wraps its time with ``fmod``), a step no servo follows unless the motion ends where it
    starts (a sine over a whole number of its periods, keyframes that end at their first value, ...). The
    frames around the wrap also carry up to a frame period of ordinary motion, which ``rate_deviation`` covers.

    Angles as the Streamer sends them: whole centidegrees of ``ChannelConfig.angle_deg`` (with ``clamp``,
    clamped to the channel's limits first). A periodic profile (``period_s``) at a whole number of its periods
    counts as at its start (floating-point ``mod`` would put a ``steps`` profile on its last level there).
    ``rate_deviation`` / ``check_rate`` compare the motion over [0, duration_s] only: this is the wrap's part.

    Returns a ``WrapJump`` per channel, in the order of ``channels`` (``deg`` 0 where nothing jumps)."""
    from metamaterial_wb.core.motion import profile_value

    dur = check_number("duration_s", duration_s, 0.0, None, "s", low_open=True)
    by_name = {a.name: a for a in scene.actuators}
    out = []
    for c in channels:
        a = by_name[c.name]
        t_end = dur
        period = (a.profile or {}).get("period_s")
        if period:
            cycles = dur / float(period)
            if abs(cycles - round(cycles)) <= 1e-9 * max(1.0, cycles):
                t_end = 0.0

        def sent(t, a=a, c=c):
            ang = float(c.angle_deg(float(profile_value(a.profile, t, a.value))))
            if clamp and not c.within_limits(ang):
                ang = min(max(ang, c.limits_deg[0]), c.limits_deg[1])
            return int(round(ang * 100))   # as Streamer.frame_payloads: the wire carries whole centidegrees
        out.append(WrapJump(c.name, c.channel, sent(t_end), sent(0.0)))
    return out
