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
from ``--map`` / ``--channels`` on the command line. ``check_motion`` checks the motion before a stream: the
limits, the servo reach, then whether the frames and the slew limits follow it (rates.py: ``check_rate``,
``check_slew``, ``wrap_jumps``, re-exported here). Pure Python: no FreeCAD, no pyserial.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from metamaterial_wb.core.errors import SceneError, check_integer, check_number
from metamaterial_wb.core.numbers import parse_int

from . import protocol as P
from .joint_angle import JointRotation, joint_rotation
# The rate / slew / loop-wrap checks live in rates.py; their names stay importable from here.
from .rates import (_DENSE_S, _SUGGEST_SPAN_S, _WINDOW, MAX_RATE_HZ, MAX_SLEW_DPS,  # noqa: F401
                    RATE_TOLERANCE_DEG, SERVO_FRAME_MS, SLEW_PERIOD_MS, RateDeviation, WrapJump, _check_slew,
                    _check_tolerance, _deviations, _rate_tracks, check_rate, check_slew, rate_deviation, servo_gaps,
                    slew_advice, slew_ticks, wrap_jumps)

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
    # where limits_deg was given (``--channels FILE NAME.limits_deg``, ``actuators[k].servo.limits_deg``; None: a
    # default), named when a motion leaves the limits (limits_source)
    limits_from: str = field(default=None, compare=False, repr=False)

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


def limits_source(cfg: ChannelConfig):
    """The field to name when a motion leaves ``cfg``'s limits and they were given on the command line (``--channels
    FILE NAME.limits_deg``), else None: the error then names the scene's actuator (the limits are the scene's own
    ``servo.limits_deg`` or a default), and the command adds the scene file."""
    src = cfg.limits_from
    return src if isinstance(src, str) and src.startswith("--channels") else None


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


def channel_map(scene, mapping=None, overrides=None, n_channels=MAX_CHANNELS, overrides_from=None):
    """The channel configuration of every actuator of ``scene``.

    ``mapping``: ``{name: channel}`` (from ``--map``); ``overrides``: ``{name: {servo fields}}`` (from
    ``--channels FILE``, ``overrides_from`` its name for messages). Order of precedence: overrides, mapping, the
    actuator's ``"servo"`` object, defaults (channel = position of the actuator in the scene); a ``--map`` channel
    that an override's ``channel`` contradicts is refused (the same channel in both is accepted).
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
        if "limits_deg" in spec:
            spec["limits_from"] = f"{fname}.limits_deg"
        given = set(spec)
        origin = dict.fromkeys(SERVO_KEYS, fname)
        origin["channel"] = f"{fname}.channel" if "channel" in spec else "default, its position in the scene"
        if mapping and a.name in mapping:
            spec.update(_check_servo(f"--map {a.name}", {"channel": mapping[a.name]}, n_channels))
            given.add("channel")
            origin["channel"] = f"--map {a.name}={mapping[a.name]}"
        if overrides and a.name in overrides:
            more = _check_servo(f"--channels {a.name}", overrides[a.name], n_channels)
            if mapping and a.name in mapping and "channel" in more and more["channel"] != spec["channel"]:
                src = f"--channels {overrides_from} " if overrides_from else "--channels "
                raise SceneError(f"--map {a.name}", f"{mapping[a.name]} contradicts {src}{a.name}.channel "
                                                    f"{more['channel']}; allowed: one of them, or the same "
                                                    f"channel in both")
            spec.update(more)
            given.update(more)
            origin.update({f: f"--channels {a.name}" for f in more})
            if "limits_deg" in more:
                src = f"--channels {overrides_from} " if overrides_from else "--channels "
                spec["limits_from"] = f"{src}{a.name}.limits_deg"
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
                reach_at = f"reaches {ang[i]:.1f} deg at t = {t[i]:.3f} s"
                src = limits_source(c)
                if src:  # set by --channels: named there, not in the scene file
                    raise SceneError(src, f"[{lo:g}, {hi:g}] deg: the motion of {where} {reach_at}, outside these "
                                          f"limits of channel {c.channel}; widen them, lower the scene's "
                                          f"profile, or pass --clamp")
                raise SceneError(where, f"the motion {reach_at}; channel {c.channel} allows [{lo:g}, {hi:g}] deg; "
                                        f"lower the profile, widen servo.limits_deg, or pass --clamp")
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
    check_rate(scene, channels, duration_s, rate_hz, clamp=clamp, tolerance_deg=tol, window=_WINDOW)
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
