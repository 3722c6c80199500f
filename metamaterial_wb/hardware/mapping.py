"""Actuator value -> servo channel and angle.

An actuator value ``v`` in [-1, 1] (the solver's node deformation D imposed by a servo) is commanded as the
**simulated relative rotation of its joint** (``joint_angle.JointRotation``: what the lattice models hold that joint
at, the solver's ``joints[].hinge_rotation_deg`` with the servo's sign), not a fixed ``v * 90 deg``. Per channel:

* ``channel``: firmware channel 0..7 (Arduino pins D4..D11); by default the scene's actuators in order;
* ``limits_deg`` [lo, hi]: soft limits of the commanded angle (inside [-90, 90]); default the joint's kinematic
  range, plate contact (v = +1) to full opening (v = -1); the firmware enforces them too and reports clamping;
* ``invert``, ``trim_deg``: calibration applied by the firmware (pulse = f(+-angle + trim)); the servo angle
  +-angle + trim must stay inside [-90, 90] deg (check_servo_reach), else the pulse would stop at min/max_us;
* ``min_us``, ``max_us``: pulse widths at -90 and +90 degrees (default 500 / 2500 us);
* ``park_deg``: where the firmware parks the joint when the host goes silent;
* ``max_slew_dps``: firmware slew limit, a whole number of degrees per second 0..3600 (0 = none);
* ``scale_deg``: only for a servo that does not turn its joint directly: command ``v * scale_deg`` instead.

These come from an actuator's optional ``"servo"`` object in the scene (docs/scene-format.md), then
from ``--map`` / ``--channels`` on the command line. Pure Python: no FreeCAD, no pyserial.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from metamaterial_wb.core.errors import SceneError, check_integer, check_number
from metamaterial_wb.core.numbers import parse_int

from . import protocol as P
from .joint_angle import JointRotation, joint_rotation

MAX_CHANNELS = 8
SERVO_KEYS = ("channel", "scale_deg", "invert", "trim_deg", "limits_deg", "min_us", "max_us", "park_deg",
              "max_slew_dps")


@dataclass
class ChannelConfig:
    name: str
    channel: int
    scale_deg: float = None   # None: the joint's simulated rotation (rotation); a number: v * scale_deg
    invert: bool = False
    trim_deg: float = 0.0
    limits_deg: tuple = (-90.0, 90.0)
    min_us: int = 500
    max_us: int = 2500
    park_deg: float = 0.0
    max_slew_dps: int = 0     # whole deg/s (the protocol's u16); 0: no limit
    extra: dict = field(default_factory=dict)
    rotation: JointRotation = None  # the actuated joint (channel_map sets it); None and no scale_deg: v * 90

    @property
    def source(self):
        if self.scale_deg is not None:
            return f"v * {self.scale_deg:g} deg (servo.scale_deg)"
        if self.rotation is not None:
            return f"simulated rotation of joint {self.rotation.joint}"
        return "v * 90 deg (no joint)"

    def angle_deg(self, value):
        """Commanded joint angle (degrees) for an actuator value or an array of them (no clamping)."""
        if self.scale_deg is None and self.rotation is not None:
            return self.rotation.angle_deg(value)
        v = np.asarray(value, dtype=float) * (90.0 if self.scale_deg is None else self.scale_deg)
        return float(v) if v.ndim == 0 else v

    def cdeg(self, value: float) -> int:
        return int(round(self.angle_deg(value) * 100.0))

    def within_limits(self, angle_deg: float) -> bool:
        lo, hi = self.limits_deg
        return lo - 1e-9 <= angle_deg <= hi + 1e-9

    def config_payload(self) -> bytes:
        lo, hi = self.limits_deg
        slew = self.max_slew_dps
        if slew != int(slew) or not 0 <= slew <= MAX_SLEW_DPS:  # never rounded to 0
            raise SceneError(f"channel {self.channel} ({self.name}).max_slew_dps",
                             f"{slew!r} deg/s; allowed: a whole number 0..{MAX_SLEW_DPS} deg/s (0: no limit)")
        return P.config_ch_payload(self.channel, int(self.min_us), int(self.max_us), int(round(self.trim_deg * 100)),
                                   self.invert, int(round(lo * 100)), int(round(hi * 100)),
                                   int(round(self.park_deg * 100)), int(self.max_slew_dps))

    def to_dict(self):
        d = {k: getattr(self, k) for k in ("name", "channel", "scale_deg", "invert", "trim_deg", "min_us", "max_us",
                                           "park_deg", "max_slew_dps")}
        d["limits_deg"] = list(self.limits_deg)
        d["angle"] = self.source
        if self.rotation is not None:
            d["joint"] = self.rotation.joint
            d["joint_range_deg"] = [round(x, 4) for x in self.rotation.range_deg()]
        return d


def _check_whole(field, value, low, high, unit, note=""):
    """``value`` as an int when it is a whole number in [low, high] (the wire carries integers: 2.5 would be sent
    as 2), else a SceneError naming the field, the value and the range."""
    v = check_number(field, value, low, high, unit)
    if v != int(v):
        raise SceneError(field, f"{value!r} {unit} is not a whole number; allowed: a whole number {low}..{high} "
                                f"{unit}{note}")
    return int(v)


def _check_servo(field_name, spec, n_channels):
    if not isinstance(spec, dict):
        raise SceneError(field_name, f"expected an object with any of {list(SERVO_KEYS)}, got {spec!r}")
    for k in spec:
        if k not in SERVO_KEYS:
            raise SceneError(f"{field_name}.{k}", f"unknown servo field; allowed: {list(SERVO_KEYS)}")
    out = {}
    if "channel" in spec:
        ch = spec["channel"]
        check_integer(f"{field_name}.channel", ch, 0, n_channels - 1, "a channel")
        out["channel"] = ch
    if "scale_deg" in spec:
        out["scale_deg"] = check_number(f"{field_name}.scale_deg", spec["scale_deg"], 0.0, 90.0, "deg",
                                        low_open=True)
    if "invert" in spec:
        if not isinstance(spec["invert"], bool):
            raise SceneError(f"{field_name}.invert", f"expected true or false, got {spec['invert']!r}")
        out["invert"] = spec["invert"]
    if "trim_deg" in spec:
        out["trim_deg"] = check_number(f"{field_name}.trim_deg", spec["trim_deg"], -20.0, 20.0, "deg")
    if "limits_deg" in spec:
        lim = spec["limits_deg"]
        if not isinstance(lim, (list, tuple)) or len(lim) != 2:
            raise SceneError(f"{field_name}.limits_deg", f"expected [lo, hi] in degrees, got {lim!r}")
        lo = check_number(f"{field_name}.limits_deg[0]", lim[0], -90.0, 90.0, "deg")
        hi = check_number(f"{field_name}.limits_deg[1]", lim[1], -90.0, 90.0, "deg")
        if lo >= hi:
            raise SceneError(f"{field_name}.limits_deg", f"[{lo}, {hi}]: lo must be below hi")
        out["limits_deg"] = (lo, hi)
    for k in ("min_us", "max_us"):
        if k in spec:
            out[k] = _check_whole(f"{field_name}.{k}", spec[k], 400, 2600, "us")
    if "park_deg" in spec:
        out["park_deg"] = check_number(f"{field_name}.park_deg", spec["park_deg"], -90.0, 90.0, "deg")
    if "max_slew_dps" in spec:  # the protocol's u16: 2.5 would be sent as 2, 0.4 as 0 = no limit at all
        out["max_slew_dps"] = _check_whole(f"{field_name}.max_slew_dps", spec["max_slew_dps"], 0, MAX_SLEW_DPS, "deg/s",
                                           " (0: no limit)")
    return out


def _finish(cfg: ChannelConfig, origin, given, where, set_in):
    """Checks across fields; ``origin``: ``{field: where it was given}`` (the scene's servo object or --channels;
    for a default, where it comes from); ``given``: the fields someone gave, so that the error names the place to
    fix and never a default as if given; ``where``: the actuator (``actuators[k] (name)``), named for a default;
    ``set_in(field)``: where that field can be set."""
    def note(f, other, value):  # the other field of a clash: where it came from, or that it is the default
        if f in given:
            return f" ({f} from {origin[f]})" if origin[f] != origin[other] else ""
        return f" ({f}: the default {value}, not given)"
    if cfg.min_us >= cfg.max_us:   # the defaults 500 < 2500 never clash: one of them was given
        if "min_us" in given:
            raise SceneError(f"{origin['min_us']}.min_us", f"{cfg.min_us} us must be below max_us {cfg.max_us} us"
                             + note("max_us", "min_us", f"{cfg.max_us} us"))
        raise SceneError(f"{origin['max_us']}.max_us", f"{cfg.max_us} us must be above min_us {cfg.min_us} us"
                         + note("min_us", "max_us", f"{cfg.min_us} us"))
    lo, hi = cfg.limits_deg
    lim = (f" (limits_deg from {origin['limits_deg']})"
           if "limits_deg" not in given or "park_deg" not in given or origin["limits_deg"] != origin["park_deg"]
           else "")
    if not lo <= cfg.park_deg <= hi:
        if "park_deg" not in given:
            raise SceneError(where, f"the default park angle {cfg.park_deg:g} deg (no park_deg given) is outside the "
                                    f"limits [{lo:g}, {hi:g}] deg{lim}; allowed: a park angle within [{lo:g}, "
                                    f"{hi:g}] deg: set {set_in('park_deg')}")
        raise SceneError(f"{origin['park_deg']}.park_deg", f"{cfg.park_deg} deg is outside the limits [{lo}, {hi}] "
                                                           f"deg" + lim)
    servo = float(servo_cdeg(cfg, cfg.park_deg)[0][0])
    if abs(servo) > SERVO_RANGE_CDEG:   # the firmware parks at +-park + trim: past +-90 the pulse stops short
        park = origin["park_deg"]
        field_name = f"{park}.park_deg" if "park_deg" in given else where
        frm = {f: (f" from {origin[f]}" if f in given and origin[f] != park else "") for f in ("invert", "trim_deg")}
        raise SceneError(field_name,
                         f"{cfg.park_deg:g} deg: the servo would park at {servo / 100:.2f} deg ("
                         + (f"inverted{frm['invert']}, " if cfg.invert else "")
                         + f"+ trim_deg {cfg.trim_deg:g}{frm['trim_deg']}); allowed: a servo "
                         f"angle within [-90, 90] deg (min_us {cfg.min_us} .. max_us {cfg.max_us} us)")
    return cfg


def parse_map(text):
    """``"head=0,tail=3"`` -> ``{"head": 0, "tail": 3}``."""
    out = {}
    for item in [s for s in (text or "").split(",") if s.strip()]:
        name, sep, ch = item.partition("=")
        if not sep:
            raise SceneError(f"--map {item}", "expected NAME=CHANNEL, e.g. --map head=0,tail=1")
        if name.strip() in out:
            raise SceneError(f"--map {name.strip()}", f"given twice (channels {out[name.strip()]} and {ch.strip()}); "
                                                      f"map each actuator once")
        try:      # strict: no '1_0', no non-ASCII digits (int() would take them)
            out[name.strip()] = parse_int(f"--map {name.strip()}", ch)
        except SceneError as exc:
            raise SceneError(exc.field, f"{exc.message} (the channel number, e.g. --map head=0)") from None
    return out


def load_channel_file(path):
    """A JSON object ``{actuator_name: {servo fields...}}`` (see docs/firmware.md)."""
    from metamaterial_wb.core.inputfile import read_json

    data = read_json(path, "--channels")   # one error line for unreadable / non-JSON / hostile files
    if not isinstance(data, dict):
        raise SceneError(str(path), "expected an object {actuator name: {servo fields}}")
    return data


def channel_map(scene, mapping=None, overrides=None, n_channels=MAX_CHANNELS):
    """The channel configuration of every actuator of ``scene``.

    ``mapping``: ``{name: channel}`` (from ``--map``); ``overrides``: ``{name: {servo fields}}`` (from
    ``--channels FILE``). Order of precedence: overrides, mapping, the actuator's ``"servo"`` object, defaults
    (channel = position of the actuator in the scene).
    """
    names = [a.name for a in scene.actuators]
    if not names:
        raise SceneError("actuators", "the scene has no actuator to stream")
    if len(names) > n_channels:  # before any channel: the default one (the actuator's position) would not exist
        raise SceneError("actuators", f"{len(names)} actuators, the firmware drives {n_channels} channels "
                                      f"(0..{n_channels - 1}), one actuator each; stream at most {n_channels} "
                                      f"actuators per board (a scene per board)")
    for src, label in ((mapping or {}, "--map"), (overrides or {}, "--channels")):
        for k in src:
            if k not in names:
                raise SceneError(f"{label} {k}", f"no actuator named {k!r}; actuators: {', '.join(names)}")
    out, channel_from = [], {}
    for k, a in enumerate(scene.actuators):
        fname = f"actuators[{k}].servo"
        spec = dict(_check_servo(fname, a.extra.get("servo", {}), n_channels))
        given = set(spec)
        origin = dict.fromkeys(SERVO_KEYS, fname)
        origin["channel"] = f"{fname}.channel" if "channel" in spec else "default, its position in the scene"
        if mapping and a.name in mapping:
            spec.update(_check_servo(f"--map {a.name}", {"channel": mapping[a.name]}, n_channels))
            given.add("channel")
            origin["channel"] = f"--map {a.name}={mapping[a.name]}"
        if overrides and a.name in overrides:
            more = _check_servo(f"--channels {a.name}", overrides[a.name], n_channels)
            spec.update(more)
            given.update(more)
            origin.update({f: f"--channels {a.name}" for f in more})
            if "channel" in more:
                origin["channel"] = f"--channels {a.name}.channel"
        spec.setdefault("channel", k)
        channel_from[a.name] = origin["channel"]
        rot = joint_rotation(scene, a.joint, f"actuators[{k}].joint")
        if "limits_deg" not in spec:
            origin["limits_deg"] = ("the default [-90, 90] deg" if "scale_deg" in spec
                                    else f"actuators[{k}].joint's kinematic range")
        if "limits_deg" not in spec and "scale_deg" not in spec:  # the joint's kinematic range, outward to 0.01 deg
            lo, hi = rot.range_deg()
            spec["limits_deg"] = (max(-90.0, math.floor(lo * 100 - 1e-6) / 100),
                                  min(90.0, math.ceil(hi * 100 + 1e-6) / 100))
        spec["rotation"] = rot

        def set_in(f, k=k, name=a.name):  # where a field can be set (--channels only when the caller takes it)
            return (f"{f} in " + (f"--channels for {name}, or " if overrides is not None else "")
                    + f"the scene's actuators[{k}].servo.{f}")
        out.append(_finish(ChannelConfig(a.name, **spec), origin, given, f"actuators[{k}] ({a.name})", set_in))
    seen = {}
    for c in out:
        if c.channel in seen:
            first = seen[c.channel]
            free = ", ".join(str(ch) for ch in range(n_channels) if ch not in {x.channel for x in out})
            raise SceneError("channels", f"actuators {first!r} and {c.name!r} both use channel {c.channel} ({first}: "
                                         f"{channel_from[first]}; {c.name}: {channel_from[c.name]}); free channels: "
                                         f"{free} (allowed: 0..{n_channels - 1}, one actuator each)")
        seen[c.channel] = c.name
    return out


SERVO_RANGE_CDEG = 9000  # a servo turns within [-90, 90] deg: min_us at -90, max_us at +90 (PROTOCOL.md section 5)


def servo_cdeg(cfg: ChannelConfig, angles_deg):
    """``(invert ? -angle : angle) + trim_deg`` of commanded joint angles, in the whole centidegrees the firmware
    gets and maps to a pulse (so host and firmware agree exactly): ``(servo cdeg, commanded cdeg)`` arrays."""
    cdeg = np.round(np.atleast_1d(np.asarray(angles_deg, dtype=float)) * 100.0)
    return (-cdeg if cfg.invert else cdeg) + round(cfg.trim_deg * 100.0), cdeg


def check_servo_reach(cfg: ChannelConfig, angles_deg, where, times_s=None):
    """Raise SceneError if the servo angle ``(invert ? -angle : angle) + trim_deg`` of a commanded joint angle
    leaves the servo's [-90, 90] deg, where the firmware would stop the pulse at min_us / max_us (and report a
    clamp): the servo would stop short of the commanded angle. The one check of the stream, the on-board
    oscillators and single frames.

    ``angles_deg``: the angles sent (after any clamping to the limits); ``times_s``: their times (named in the
    error) or None. Computed in the centidegrees the firmware gets, so host and firmware agree exactly.
    """
    servo, cdeg = servo_cdeg(cfg, angles_deg)
    bad = np.nonzero(np.abs(servo) > SERVO_RANGE_CDEG)[0]
    if not bad.size:
        return
    i = bad[0]
    at = "" if times_s is None else f" at t = {np.atleast_1d(times_s)[i]:.3f} s"
    how = (f"joint angle {cdeg[i] / 100:.2f} deg" + (", inverted," if cfg.invert else "")
           + f" + trim_deg {cfg.trim_deg:g}")
    stop = cfg.max_us if servo[i] > 0 else cfg.min_us
    raise SceneError(where, f"its servo would turn to {servo[i] / 100:.2f} deg{at} ({how}); the servo of channel "
                            f"{cfg.channel} turns within [-90, 90] deg (min_us {cfg.min_us} .. max_us {cfg.max_us} "
                            f"us): the firmware would stop it at {stop} us; lower the motion or servo.limits_deg, "
                            f"or change trim_deg")


def check_motion(scene, channels, duration_s, rate_hz=50.0, clamp=False, rate_tolerance_deg=None):
    """Check the scene's motion over ``duration_s`` (sampled at the stream rate and at 1 kHz) before streaming.

    Without ``clamp``, raise SceneError if an angle leaves its channel's limits. In both cases (with ``clamp`` on
    the angles clamped to the limits, as they will be sent) raise SceneError if a servo angle (+-angle + trim)
    leaves [-90, 90] deg (check_servo_reach), and if ``rate_hz`` cannot follow the motion within
    ``rate_tolerance_deg`` (check_rate; None: RATE_TOLERANCE_DEG). Returns the largest |angle sent| per actuator
    (degrees)."""
    from metamaterial_wb.core.motion import profile_value

    tol = _check_tolerance(rate_tolerance_deg)
    by_name = {a.name: a for a in scene.actuators}
    peaks = {}
    for c in channels:
        a = by_name[c.name]
        where = f"actuators[{[x.name for x in scene.actuators].index(c.name)}] ({c.name})"
        lo, hi = c.limits_deg
        reach = None  # the first servo-reach error: raised once the limits are checked over the whole motion
        peak = 0.0
        for t in _motion_times(duration_s, rate_hz):
            v = np.atleast_1d(profile_value(a.profile, t, a.value)) * np.ones_like(t)
            ang = np.atleast_1d(c.angle_deg(v))
            if clamp:
                ang = np.clip(ang, lo, hi)
            bad = np.nonzero((ang < lo - 1e-9) | (ang > hi + 1e-9))[0]
            if bad.size:
                i = bad[0]
                raise SceneError(where, f"the motion reaches {ang[i]:.1f} deg at t = {t[i]:.3f} s; channel "
                                        f"{c.channel} allows [{lo:g}, {hi:g}] deg; lower the profile, widen "
                                        f"servo.limits_deg, or pass --clamp")
            if reach is None:
                try:
                    check_servo_reach(c, ang, where, t)
                except SceneError as exc:
                    reach = exc
            if ang.size:
                peak = max(peak, float(np.max(np.abs(ang))))
        if reach is not None:
            raise reach
        peaks[c.name] = peak
    check_rate(scene, channels, duration_s, rate_hz, clamp=clamp, tolerance_deg=tol)
    return peaks


def _motion_times(duration_s, rate_hz):
    """The times check_motion samples, ``union(k / rate_hz, k ms)`` over [0, duration_s], in blocks of at most
    _WINDOW samples at 1 kHz (and the frame times among them) in time order: a day's stream in one array would
    take gigabytes."""
    dense_all = int(math.ceil((duration_s + 1e-9) / 1e-3))            # as np.arange(0, duration_s + 1e-9, 1e-3)
    step = 1.0 / rate_hz
    frames_all = int(math.ceil((duration_s + 1e-9) / step))            # as np.arange(0, duration_s + 1e-9, step)
    for i0 in range(0, dense_all, _WINDOW):
        i1 = min(dense_all, i0 + _WINDOW)
        dense = np.arange(i0, i1) * 1e-3
        t0, t1 = dense[0], (i1 * 1e-3 if i1 < dense_all else math.inf)
        k0 = max(0, int(math.floor(t0 * rate_hz)) - 1)
        k1 = min(frames_all, int(math.ceil(t1 * rate_hz)) + 1) if i1 < dense_all else frames_all
        frames = np.arange(k0, k1) * step
        frames = frames[(frames >= t0) & (frames < t1)] if i0 else frames[frames < t1]
        yield np.union1d(frames, dense)


# --------------------------------------------------------------------------------------------------------------
# Can the frame rate follow the motion?

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
    the leading axes; starts at ``start_deg`` (default the first target)."""
    y = np.asarray(target_deg, dtype=float)
    if not max_slew_dps:
        return y.copy()
    step = max_slew_dps * SLEW_PERIOD_MS / 1000.0
    out = np.empty_like(y)
    cur = y[..., 0].copy() if start_deg is None else np.broadcast_to(np.asarray(start_deg, float), y[..., 0].shape)
    for i in range(y.shape[-1]):
        cur = cur + np.clip(y[..., i] - cur, -step, step)
        out[..., i] = cur
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


def _deviations(tracks, duration_s, rates, stop_above=None, pulse_hz=None):
    """``{rate: RateDeviation}``: the worst deviation of each rate over [0, duration_s]. With ``stop_above``, a
    rate is dropped (its entry kept) as soon as it exceeds it."""
    worst = {r: RateDeviation(0.0) for r in rates}
    alive = list(rates)
    n = int(math.floor(duration_s / _DENSE_S + 1e-9)) + 1
    for i0 in range(0, n, _WINDOW):
        td = np.arange(i0, min(n, i0 + _WINDOW)) * _DENSE_S
        if i0 + _WINDOW >= n and td[-1] < duration_s - 1e-12:
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


def check_rate(scene, channels, duration_s, rate_hz, clamp=False, tolerance_deg=None):
    """Raise SceneError naming ``--rate`` when the servos stray from the motion by more than ``tolerance_deg``
    (None: RATE_TOLERANCE_DEG) at ``rate_hz`` (rate_deviation), with the worst place, the Nyquist rate of the
    fastest sine and the whole rates that would pass."""
    tol = _check_tolerance(tolerance_deg)
    tracks = _rate_tracks(scene, channels, clamp)
    d = _deviations(tracks, duration_s, [rate_hz])[rate_hz]
    if d.deg <= tol:
        for c, angles, steps in tracks:
            _check_slew(c, angles, duration_s, rate_hz, tol, steps)
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
    ok = [r for r, w in _deviations(tracks, span, whole, stop_above=tol).items() if w.deg <= tol]
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


def _check_slew(c, angles, duration_s, rate_hz, tol, steps=False):
    """SceneError naming ``c``'s max_slew_dps when the firmware's slew (slew_ticks, its targets the servo's path
    through the frames) holds the servo more than ``tol`` off the motion; nothing when the path never outruns it
    (the ticks where the slew does not act are the path the rate check accepted). ``steps``: a jump no servo
    follows is forgiven there (the nearer frame counts), so the slewed servo is compared with that path instead."""
    if not c.max_slew_dps:
        return
    cur, peak = None, 0.0
    n = int(math.floor(duration_s / _DENSE_S + 1e-9)) + 1
    for i0 in range(0, n, _WINDOW):   # ticks every 10 ms from t = 0, the motion at 1 kHz for its peak speed
        td = np.arange(i0, min(n, i0 + _WINDOW)) * _DENSE_S
        peak = max(peak, float(np.max(np.abs(np.diff(angles(np.append(td, td[-1] + _DENSE_S)))))) / _DENSE_S)
        tt = td[(np.round(td / _DENSE_S).astype(int) % SLEW_PERIOD_MS) == 0]
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


def expected_pulse_us(cfg: ChannelConfig, angle_deg: float) -> float:
    """Real-valued pulse width for a commanded angle (for reports; the firmware rounds to 1 us):
    lo <= angle <= hi, then mid + (±angle + trim) * (max - min) / 180."""
    lo, hi = cfg.limits_deg
    a = min(max(angle_deg, lo), hi)
    a = (-a if cfg.invert else a) + cfg.trim_deg
    us = (cfg.min_us + cfg.max_us) / 2.0 + a * (cfg.max_us - cfg.min_us) / 180.0
    return min(max(us, cfg.min_us), cfg.max_us)


def runs(channels):
    """Group channels into contiguous runs ``[(first, [cfg, ...]), ...]`` (one SET_ANGLES frame each)."""
    cs = sorted(channels, key=lambda c: c.channel)
    out = []
    for c in cs:
        if out and out[-1][0] + len(out[-1][1]) == c.channel:
            out[-1][1].append(c)
        else:
            out.append((c.channel, [c]))
    return out


def isfinite_all(values):
    return all(math.isfinite(v) for v in values)
