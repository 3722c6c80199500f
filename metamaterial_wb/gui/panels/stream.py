"""Stream controller: the motor values of the animation's wall-clock time to the servo firmware.

The :class:`~metamaterial_wb.hardware.Streamer` thread asks for values at 50 Hz; the controller answers
with ``values_at(clock())``: the values for *now* on the animation clock (which follows wall time), not
the last frame the view managed to draw, so real servos move in real time even when rendering drops
frames. Errors from the streaming thread are kept and reported by the panel in the GUI thread. Connect is
refused when those frames, at the animation's speed, cannot follow the motion over the whole timeline, or when a
channel's firmware slew limit (``max_slew_dps``) holds its servo too far off it (``follow_problem``: the stream
command's rate and slew checks, with its message); while streaming, each edit compares the first
``FOLLOW_SPAN_S`` and the panel says so for a longer timeline. With Loop ticked the timeline wraps from its end
back to its start: a jump there larger than the rate tolerance (``mapping.wrap_jumps``) is treated the same way
(Connect refused; while streaming, ticking Loop, a new length or an edit is warned of).
"""
from metamaterial_wb.gui.i18n import translate


def hardware_available():
    """True when the hardware package (serial link + streamer) can be imported."""
    try:
        from metamaterial_wb.hardware import Link, Streamer, channel_map  # noqa: F401
        return True
    except ImportError:
        return False


class ServoAngles:
    """The angle each actuator's servo is commanded for a value: what ``stream`` sends, shown by the panels.

    ``ChannelConfig.angle_deg`` of :func:`metamaterial_wb.hardware.mapping.channel_map`: the simulated rotation
    of the actuator's joint with the servo's sign (closing and opening differ), or ``v * scale_deg`` when the
    actuator's ``"servo"`` object sets ``scale_deg``; the firmware's ``invert`` / ``trim_deg`` calibration
    comes after and is not shown. When ``channel_map`` refuses the scene as a whole (e.g. more actuators than
    the firmware's channels, two on one channel), each actuator's mapping is built alone from the same
    ``joint_rotation`` and ``scale_deg`` (``note`` says why). An actuator whose angle cannot be computed has
    no angle (``?``) and its reason in ``errors``; nothing falls back to ``v * 90 deg``.
    """

    def __init__(self, scene):
        self.channels = {}    # name -> ChannelConfig (only its angle is used)
        self.errors = {}      # name -> why there is no angle
        self.note = ""        # why channel_map could not be used for the whole scene
        if not scene.actuators:
            return
        try:
            from metamaterial_wb.core.errors import SceneError
            from metamaterial_wb.hardware.mapping import channel_map
        except ImportError as exc:     # a checkout without the hardware package: say so, show no angle
            why = translate("Metamaterial", "no servo mapping (metamaterial_wb.hardware: {0})").format(exc)
            self.errors = {a.name: why for a in scene.actuators}
            return
        try:
            self.channels = {c.name: c for c in channel_map(scene)}
        except SceneError as exc:
            self.note = translate("Metamaterial", "channel map: {0}; each motor's angle is its own joint's").format(exc)
            for k, a in enumerate(scene.actuators):
                try:
                    self.channels[a.name] = _channel_alone(scene, k, a)
                except SceneError as err:
                    self.errors[a.name] = str(err)

    def deg(self, name, value):
        """Commanded angle (degrees) of actuator ``name`` for ``value`` (a number or an array); None when it
        has none (see ``errors``)."""
        c = self.channels.get(name)
        return None if c is None else c.angle_deg(value)

    def text(self, name, value):
        """``"+7.3 deg"`` (``"? deg"`` without an angle)."""
        d = self.deg(name, value)
        return translate("Metamaterial", "? deg") if d is None else translate("Metamaterial", "{0:+.1f} deg").format(d)

    def span(self, name, lo, hi, samples=201):
        """(lowest, highest) angle over the values ``lo..hi`` (the mapping is not symmetric: closing and opening
        differ, and the sign is the servo's); None without an angle."""
        import numpy as np
        c = self.channels.get(name)
        if c is None:
            return None
        a = np.atleast_1d(c.angle_deg(np.linspace(float(lo), float(hi), samples)))
        return float(a.min()), float(a.max())

    def describe(self, name):
        """How the angle of ``name`` is computed, or why there is none (for tooltips)."""
        if name in self.errors:
            return translate("Metamaterial", "{0}: no servo angle: {1}").format(name, self.errors[name])
        c = self.channels.get(name)
        if c is None:
            return translate("Metamaterial", "{0}: not an actuator").format(name)
        return translate("Metamaterial", "{0}: {1}").format(name, c.source)

    def tooltip(self, names=None):
        """One line per actuator (``describe``), then ``note``."""
        lines = [self.describe(n) for n in (names if names is not None else list(self.channels) + list(self.errors))]
        return "\n".join(lines + ([self.note] if self.note else []))


def joint_angle_text(scene, joint, value):
    """``("+12.2 deg", how)``: the rotation ``joint`` of ``scene`` turns for an actuator value (the angle a
    servo without ``scale_deg`` would be sent, ``hardware.joint_angle.joint_rotation``), or ``("? deg", why)``."""
    from metamaterial_wb.core.errors import SceneError
    try:
        from metamaterial_wb.hardware.joint_angle import joint_rotation
    except ImportError as exc:
        return (translate("Metamaterial", "? deg"),
                translate("Metamaterial", "no servo mapping (metamaterial_wb.hardware: {0})").format(exc))
    try:
        rot = joint_rotation(scene, joint)
    except SceneError as exc:
        return translate("Metamaterial", "? deg"), str(exc)
    return (translate("Metamaterial", "{0:+.1f} deg").format(rot.angle_deg(value)),
            translate("Metamaterial", "simulated rotation of joint {0}").format(rot.joint))


def _channel_alone(scene, k, actuator):
    """The ChannelConfig of one actuator without the scene-wide channel checks: its joint's rotation and its
    servo's ``scale_deg`` (checked as channel_map checks it)."""
    from metamaterial_wb.hardware.joint_angle import joint_rotation
    from metamaterial_wb.hardware.mapping import MAX_CHANNELS, ChannelConfig, _check_servo

    servo = actuator.extra.get("servo", {})
    if not isinstance(servo, dict):
        _check_servo(f"actuators[{k}].servo", servo, MAX_CHANNELS)      # raises, naming the field
    scale = None
    if "scale_deg" in servo:
        scale = _check_servo(f"actuators[{k}].servo", {"scale_deg": servo["scale_deg"]}, MAX_CHANNELS)["scale_deg"]
    rot = joint_rotation(scene, actuator.joint, f"actuators[{k}].joint")
    return ChannelConfig(actuator.name, k, scale_deg=scale, rotation=rot)


class StreamController:
    """Open / close the link and run the streamer. ``values_at(t)`` -> {actuator: value};
    ``clock()`` -> the animation time now."""

    def __init__(self, values_at, clock, looping=None):
        self.values_at = values_at
        self.clock = clock
        self.looping = looping or (lambda: False)    # whether the timeline wraps (the Animate panel's Loop)
        self.link = None
        self.streamer = None
        self.error = None
        self.sent = 0

    @property
    def connected(self):
        return self.streamer is not None

    def source(self, _stream_t):
        vals = self.values_at(self.clock())
        self.sent += 1
        return vals

    RATE_HZ = 50.0                    # the link's frames per wall second (Streamer's default)
    # The span the per-edit warning compares while streaming (``follow_problem(..., span_s=FOLLOW_SPAN_S)``):
    # rate_deviation samples the motion at 1 kHz, so the whole of a 10 min timeline takes ~0.2 s per moving
    # actuator and speed (~0.4 s for the fish's two, ~1 s for four; a refusal with its speed suggestion
    # compares up to 12 speeds: 1.4 / 4.4 s), too slow for every keystroke in a spin box while the link
    # streams. Connect compares the whole timeline; a shorter span is said in the message (and by the panel).
    FOLLOW_SPAN_S = 60.0
    SPEEDS = (5.0, 4.0, 3.0, 2.0, 1.5, 1.0, 0.75, 0.5, 0.25, 0.1, 0.05)   # offered when a speed is too fast

    def follow_problem(self, scene, duration_s, speed, span_s=None, loop=None):
        """None when the link's frames (``RATE_HZ`` a wall second, so ``RATE_HZ / speed`` per second of motion)
        follow the motion of ``scene`` over ``duration_s`` within the stream command's tolerance
        (``mapping.check_rate``, which the ``stream`` command runs over the whole duration), no channel's slew limit
        holds its servo further off (``slew_problem``, the same check's second part), and, when the timeline
        loops (``loop``; None: ``looping()``), no servo jumps by more than that tolerance where it wraps
        (``wrap_problem``); else the message(s), a rate one with the fastest of ``SPEEDS`` below ``speed`` that
        follows the motion.

        ``span_s`` (the per-edit warning while streaming): compare only the first ``span_s`` seconds of a longer
        timeline; a message then names the span compared, and a speed it suggests is said to follow that span
        (``follow_span_note`` is the panel's line when nothing is found there). The wrap is always compared."""
        from metamaterial_wb.hardware.mapping import channel_map
        channels = channel_map(scene)
        rate = self._rate_problem(scene, channels, duration_s, speed, span_s)
        if rate is None:     # as check_rate: the slew limits once the frames follow the motion
            rate = self.slew_problem(scene, channels, duration_s, speed, span_s)
        looping = self.looping() if loop is None else loop
        wrap = self.wrap_problem(scene, channels, duration_s) if looping else None
        return "\n".join(m for m in (rate, wrap) if m) or None

    def wrap_problem(self, scene, channels, duration_s):
        """None when, at the wrap of a looping timeline of ``duration_s``, every servo is sent a jump of at most
        ``RATE_TOLERANCE_DEG`` (``mapping.wrap_jumps``: from the angle at its end to the one at its start);
        else the message naming each motor that jumps more, its channel, the end and the start angle. The
        same tolerance as the servos' distance from the motion: a jump is a distance no servo covers in a frame."""
        from metamaterial_wb.hardware.mapping import RATE_TOLERANCE_DEG, wrap_jumps
        big = [j for j in wrap_jumps(scene, channels, duration_s) if j.deg > RATE_TOLERANCE_DEG]
        if not big:
            return None
        each = ", ".join(translate("Metamaterial", "{0} (channel {1}) by {2:.2f} deg, from {3:+.2f} deg to {4:+.2f} "
                                   "deg").format(j.name, j.channel, j.deg, j.end_deg, j.start_deg) for j in big)
        return translate("Metamaterial", "Loop: where the {0:g} s timeline wraps from its end back to its start the "
                         "servos are sent a jump no servo follows: {1} (at most {2:g} deg, the stream command's "
                         "rate tolerance); untick Loop, or set a length at which the motion ends where it "
                         "starts").format(duration_s, each, RATE_TOLERANCE_DEG)

    def slew_problem(self, scene, channels, duration_s, speed, span_s=None):
        """None when no channel's firmware slew limit (``max_slew_dps``: the servo turns at most that many deg per
        wall second, every 10 ms) holds its servo more than the stream command's tolerance off the motion played at
        ``speed`` (``mapping.check_slew``, the check the ``stream`` command runs once the rate passes); else that
        command's message (naming ``channel N (name).max_slew_dps``), said at which speed when not 1x, and the span
        compared when ``span_s`` is shorter than the timeline."""
        from metamaterial_wb.core.errors import SceneError
        from metamaterial_wb.hardware.mapping import check_slew
        span = duration_s if span_s is None or span_s >= duration_s else float(span_s)
        try:
            check_slew(scene, channels, span, self.RATE_HZ / speed, speed=speed)
        except SceneError as exc:
            msg = str(exc) if speed == 1.0 else translate("Metamaterial", "at {0:g}x: {1}").format(speed, exc)
            if span < duration_s:
                msg += translate("Metamaterial", " (the first {0:g} s of the {1:g} s timeline compared)").format(
                    span, duration_s)
            return msg
        return None

    def _rate_problem(self, scene, channels, duration_s, speed, span_s):
        """The rate part of ``follow_problem`` (None when the frames follow the motion)."""
        from metamaterial_wb.hardware.mapping import RATE_TOLERANCE_DEG, SERVO_FRAME_MS, rate_deviation
        span = duration_s if span_s is None or span_s >= duration_s else float(span_s)

        def dev(s):
            # frames and servo pulses both come at wall-clock rates: per second of motion, divided by the speed
            return rate_deviation(scene, channels, span, self.RATE_HZ / s, pulse_hz=(1000.0 / SERVO_FRAME_MS) / s)
        d = dev(speed)
        if d.deg <= RATE_TOLERANCE_DEG:
            return None
        msg = translate("Metamaterial", "at {0:g}x the link's {1:g} frames a second cannot follow the motion: {2}, "
                        "moving straight from frame to frame, would be {3:.1f} deg off it at t = {4:.2f} s (at most "
                        "{5:g} deg, as the stream command allows)").format(speed, self.RATE_HZ, d.name, d.deg, d.t,
                                                                           RATE_TOLERANCE_DEG)
        if span < duration_s:
            msg += translate("Metamaterial", " (the first {0:g} s of the {1:g} s timeline compared)").format(
                span, duration_s)
        ok = next((s for s in self.SPEEDS if s < speed and dev(s).deg <= RATE_TOLERANCE_DEG), None)
        if ok is None:     # none follows the span: none follows the whole timeline either
            return msg + translate("Metamaterial", "; no speed down to {0:g}x follows it: slow the motion "
                                   "down").format(self.SPEEDS[-1])
        if span < duration_s:
            return msg + translate("Metamaterial", "; {0:g}x follows its first {1:g} s (Connect compares the whole "
                                   "timeline)").format(ok, span)
        return msg + translate("Metamaterial", "; {0:g}x follows it").format(ok)

    def follow_span_note(self, duration_s, speed, span_s):
        """The panel's line when ``follow_problem(..., span_s=span_s)`` found nothing in a timeline longer than
        ``span_s``: the rest was not compared (None when the whole timeline was)."""
        if span_s >= duration_s:
            return None
        return translate("Metamaterial", "note: at {0:g}x the link's frames follow the first {1:g} s of the {2:g} s "
                         "timeline; the rest is compared at Connect only (it takes seconds): Disconnect and Connect "
                         "to compare all of it").format(speed, span_s, duration_s)

    def connect(self, port, scene):
        """Open ``port`` (``loop://`` = dry run), hand-shake, ARM and start streaming. Raises on failure
        (nothing left open)."""
        from metamaterial_wb.hardware import Link, Streamer, channel_map
        link = None
        try:
            link = Link.open(port, dry_run=port.startswith("loop://"))
            streamer = Streamer(link, channel_map(scene))
            streamer.prepare()
            streamer.on_error = self._failed
            streamer.start(self.source)
        except Exception:
            if link is not None:
                try:
                    link.close()
                except Exception:  # noqa: BLE001
                    pass
            raise
        self.link, self.streamer, self.error = link, streamer, None
        return streamer

    def _failed(self, message):       # called from the streaming thread
        self.error = message

    def take_error(self):
        err, self.error = self.error, None
        return err

    def disconnect(self):
        """Stop streaming (the firmware's watchdog holds, then parks the servos); returns the stats."""
        stats = None
        if self.streamer is not None:
            try:
                stats = self.streamer.stop(disarm=False)
            except Exception:  # noqa: BLE001
                pass
        if self.link is not None:
            try:
                self.link.close()
            except Exception:  # noqa: BLE001
                pass
        self.streamer = self.link = None
        return stats
