"""``stream SCENE.json --port PORT [--seconds S] [--dry-run] [--map NAME=CH,...] [--channels FILE] ...``

Streams the scene's actuator motion profiles to the servolink firmware (firmware/, docs/firmware.md) at
50 Hz: handshake, channel configuration, watchdog timing, ARM, then every 20 ms (a tick) one SET_ANGLES frame
per run of adjacent channels with each actuated joint's simulated rotation (hardware/joint_angle.py;
``servo.scale_deg`` for a linear ``value * scale`` instead). Before the port is opened the motion is checked:
the limits, the servos' reach, and whether the frames at ``--rate`` follow it (``--rate-tolerance``; with
``--mode osc`` whether the on-board sine, which a servo gets as a pulse every 20 ms, does).
``--dry-run`` runs everything over pyserial's ``loop://`` without hardware (refused with ``--port``: a dry run
never drives a board).

Ctrl+C (or SIGTERM / SIGHUP) while streaming ends the stream at its next tick, as its end would: ``--disarm``
disarms, else the firmware's watchdog holds, parks, releases. The summary line and ``--report`` then say
``interrupted`` with the duration and counts of what ran, and the exit status is 130 (128 + the signal's number).
A second signal stops at once, writing nothing.

``--report`` is written as the stream runs (hardware/report.py): each tick's angles go to a temporary file beside
it, the statistics after them, and a rename at the end makes the report appear whole; memory does not grow with
``--seconds``. A stream that fails part-way (a link error, a timeout, the board no longer answering for
Streamer.silence_limit_s, a watchdog trip, a second signal) still
gets its report, marked ``"failed": true`` with the ``error`` and what ran up to it (``frames``, ``ticks``,
``last_t``, ``duration_s`` and the ``frames_sent`` so far; ``--mode osc``: the ``pings``), and exits as it failed
(2; 130 for a second Ctrl+C). A failure before anything was sent (no frame, or the oscillators not started) and a
full disk (which stops the stream) leave no report, no temporary and no folder made for it; an earlier file at
the path stays as it was. A stream that ran to its end but exits 1 (frames lost beyond ``--max-lost``, refused,
clamped by the firmware) says so in its report too: ``"failed": true`` with the reason as ``error``.
"""
import json
import sys

NAME = "stream"
HELP = "stream a scene's motion to servo firmware over a serial port (servolink v1, 50 Hz)"


def add_arguments(p):
    from metamaterial_wb.cli import integer, number

    p.add_argument("scene", help="scene file (JSON, docs/scene-format.md)")
    p.add_argument("--port", help="serial port (/dev/ttyUSB0, /dev/ttyACM0, an emulator pty) or a pyserial URL")
    p.add_argument("--seconds", type=number, default=10.0, help="how long to stream (default 10 s)")
    p.add_argument("--dry-run", action="store_true",
                   help="no hardware: stream over pyserial's loop:// (not with --port)")
    p.add_argument("--mode", choices=("stream", "osc"), default="stream",
                   help="stream: send a frame every 1/rate s (any profile); osc: send sine profiles once and let "
                        "the firmware generate them (no host timing jitter), keeping the link alive with PINGs")
    p.add_argument("--baud", type=integer, default=115200,
                   help="baud rate, 1200..4000000 (default 115200, what the firmware speaks)")
    p.add_argument("--rate", type=number, default=None,
                   help="ticks per second, each sending one SET_ANGLES frame per run of adjacent channels (default "
                        "50, allowed 1..100); a rate whose frames cannot follow the motion is refused "
                        "(--rate-tolerance); not with --mode osc")
    p.add_argument("--rate-tolerance", type=number, default=None, metavar="DEG",
                   help="how far (deg) the servos, moving linearly from frame to frame, may stray from the motion "
                        "sampled at 1 kHz before --rate is refused (default 3, allowed (0, 180]; 180 lets any rate "
                        "through); with --mode osc the same for the on-board sine, which the servo gets every 20 ms")
    p.add_argument("--map", default="", metavar="NAME=CH,...",
                   help="actuator -> channel, e.g. head=0,tail=3 (default: the scene's servo.channel, else order)")
    p.add_argument("--channels", metavar="FILE",
                   help="JSON {actuator: {channel, scale_deg, invert, trim_deg, limits_deg, min_us, max_us, "
                        "park_deg, max_slew_dps}} (docs/firmware.md)")
    p.add_argument("--clamp", action="store_true",
                   help="clamp angles to the channel limits instead of refusing a motion that leaves them (counted "
                        "per actuator in the summary; a servo angle, +-angle + trim_deg, past +-90 deg is still "
                        "refused); not with --mode osc")
    p.add_argument("--watchdog-ms", type=integer, default=500,
                   help="host silence before the firmware holds (default 500)")
    p.add_argument("--park-after-ms", type=integer, default=500, help="hold time before parking (default 500)")
    p.add_argument("--release-after-ms", type=integer, default=5000,
                   help="time parked before the pulses stop (default 5000)")
    p.add_argument("--disarm", action="store_true", help="stop the pulses at the end (servos go limp)")
    p.add_argument("--max-lost", type=integer, default=None, metavar="N",
                   help="frames that may go without an answer (lost = sent - acked - NAKed over the whole stream) "
                        "before the command fails with exit 1 (default 0); not with --mode osc")
    p.add_argument("--report", metavar="FILE",
                   help="write the statistics as JSON, with the angle sent per frame and channel (frames_sent; "
                        "wanted_deg: the motion's angle where the host clamped it), written as the stream runs "
                        "and renamed into place at its end")


def run(args):
    from metamaterial_wb.core.errors import MetamaterialError, SceneError, check_integer, check_number
    from metamaterial_wb.core.scene import Scene
    from metamaterial_wb.hardware import Link, Streamer, channel_map, check_motion, parse_map
    from metamaterial_wb.hardware.report import StreamReport
    from metamaterial_wb.hardware.mapping import load_channel_file

    from metamaterial_wb.core.fileio import check_output
    if args.report is not None:
        check_output(args.report, "file", "--report", inputs=[("scene", args.scene), ("--channels file",
                                                                                      args.channels)])
    if not args.port and not args.dry_run:
        raise SceneError("--port", "a serial port is required (or --dry-run to stream over loop://)")
    if args.port and args.dry_run:  # a dry run never drives hardware: it would have streamed to PORT
        raise SceneError("--dry-run", f"not used with --port ({args.port}): a dry run streams over pyserial's "
                                      f"loop:// and never opens a port; leave out --port for a dry run, or "
                                      f"--dry-run to stream to {args.port}")
    if args.mode == "osc":  # the firmware generates the motion: no frames, no rate, nothing to clamp or lose
        for flag, given, why in (("--clamp", args.clamp, "the on-board oscillators are refused, never clamped, "
                                                         "when they leave a channel's limits"),
                                 ("--rate", args.rate is not None, "the firmware generates the motion"),
                                 ("--max-lost", args.max_lost is not None, "no frames are streamed")):
            if given:
                raise SceneError(flag, f"not used with --mode osc ({why}); leave it out, or use --mode stream")
    if args.rate is None:
        args.rate = 50.0
    if args.max_lost is None:
        args.max_lost = 0
    check_number("--seconds", args.seconds, 0.0, 86400.0, "s", low_open=True)
    check_number("--rate", args.rate, 1.0, 100.0, "Hz")
    if args.rate_tolerance is not None:
        check_number("--rate-tolerance", args.rate_tolerance, 0, 180, "deg", low_open=True)
    check_integer("--baud", args.baud, 1200, 4_000_000, "bits/s, 8N1; the firmware speaks 115200")
    check_number("--watchdog-ms", args.watchdog_ms, 50, 10000, "ms")
    check_number("--park-after-ms", args.park_after_ms, 0, 60000, "ms")
    check_number("--release-after-ms", args.release_after_ms, 0, 60000, "ms")
    check_number("--max-lost", args.max_lost, 0, 10**9, "frames")
    scene = Scene.load(args.scene)
    overrides = load_channel_file(args.channels) if args.channels else None
    channels = channel_map(scene, parse_map(args.map), overrides, overrides_from=args.channels)
    if args.mode == "osc":
        from metamaterial_wb.hardware.onboard import osc_params
        # refuse a scene the generator cannot run, or the chip cannot render, before opening the port
        osc_params(scene, channels, tolerance_deg=args.rate_tolerance)
    else:  # the limits (unless --clamp) and, on the angles as sent, the servo's reach (+-angle + trim) and
        # whether the frames at --rate follow the motion (within --rate-tolerance)
        check_motion(scene, channels, args.seconds, args.rate, clamp=args.clamp,
                     rate_tolerance_deg=args.rate_tolerance)
    if args.mode == "stream":
        _check_bandwidth(args.baud, args.rate, channels)

    # --report (streamed): the frames go to a temporary file beside it as they are sent, the statistics after them,
    # then the rename; memory does not grow with --seconds (hardware/report.py). Not a frame of a stream that never ran.
    report = StreamReport(args.report, channels) if args.report and args.mode == "stream" else None
    link = Link.open("loop://" if args.dry_run else args.port, baud=args.baud, dry_run=args.dry_run)
    intr = streamer = None
    try:
        if report is not None:
            report.open()
        streamer = Streamer(link, channels, rate_hz=args.rate, clamp=args.clamp)
        streamer.prepare(args.watchdog_ms, args.park_after_ms, args.release_after_ms)
        intr = _Interrupt(streamer.stop).install()  # from here a signal ends the stream as its end would
        info = link.info
        print(f"{link.name}: servolink {info.proto_major}.{info.proto_minor}, firmware "
              f"{'.'.join(map(str, info.fw_version))}, {info.n_channels} channels"
              f"{' (dry run)' if args.dry_run else ''}; "
              + ("on-board oscillators " if args.mode == "osc" else "streaming ")
              + ", ".join(f"{c.name}->ch{c.channel}" for c in channels)
              + f" for {args.seconds:g} s" + ("" if args.mode == "osc" else f" at {args.rate:g} Hz"),
              file=sys.stderr)
        if args.mode == "osc":
            return _run_osc(args, scene, channels, link, intr)
        if report is not None:  # --report lists what each channel was told, per frame (and wanted, if clamped)
            streamer.on_frame = report.frame
            streamer.on_clamp = report.clamp
            report.on_error = lambda exc: streamer.stop()  # a full disk: the report cannot be had; stop
        try:
            stats = streamer.run(scene, args.seconds)
        finally:
            intr.restore()  # a signal from here on: KeyboardInterrupt at once, the report marked failed
        if args.disarm:  # on Ctrl+C too: the servos end as at the stream's end
            link.disarm()
    except BaseException as exc:
        if report is not None:  # frames sent: the report of what ran, marked failed; none sent: nothing written
            stats = streamer.stats if streamer is not None else None
            if stats is None or not stats.frames or report.error is not None:
                report.discard()
            else:
                s = _summary(stats, link, args, channels, intr, exc)
                _written(lambda: report.finish(s), args.report,
                         f"{s['ticks']} ticks ({s['frames']} frames, motion time {s['last_t']:g} s) in "
                         f"{s['duration_s']:.2f} s")
        raise
    finally:
        if intr is not None:
            intr.restore()
        link.close()
    if report is not None and report.error is not None:
        print(f"stream stopped after {stats.ticks} ticks ({stats.duration_s:.2f} s): --report could not be written",
              file=sys.stderr)
        raise report.error
    s = _summary(stats, link, args, channels, intr)
    # what the stream found wrong once it ran (exit 1): on stderr after the summary line, and in the report
    problems = [] if stats.error or intr.signum is not None else _problems(s, args.max_lost)
    if stats.error:
        s.update(_failure(MetamaterialError(f"stream stopped: {stats.error}")))
    elif problems:
        s.update(failed=True, error="; ".join(problems))
    if report is not None:
        report.finish(s)  # after frames_sent_columns and frames_sent; the rename makes the report appear whole
    rtt = (f"round trip median {s['rtt_ms_median']:.2f} ms, p99 {s['rtt_ms_p99']:.2f} ms, max {s['rtt_ms_max']:.2f} ms"
           if s["rtt_ms_median"] is not None else "no replies")
    per_tick = (f" ({s['frames_per_tick']} a tick: one per run of adjacent channels)" if s["frames_per_tick"] > 1
                else "")
    print(("" if intr.signum is None else f"interrupted ({intr.name}): ") +
          f"{s['ticks']} ticks in {s['duration_s']:.2f} s ({s['rate_hz']:.1f} Hz), {s['frames']} frames{per_tick}: "
          f"{s['acked']} acked, "
          f"{s['naked']} NAKed{' ' + json.dumps(s['nak_reasons']) if s['nak_reasons'] else ''}, {s['lost']} lost, "
          f"{s['skipped']} skipped; {s['nak_unreadable']} unreadable-frame NAKs"
          f"{' ' + json.dumps(s['unreadable_reasons']) if s['unreadable_reasons'] else ''}; {rtt}; "
          f"{s['clamped_frames']} frames clamped (host {s['host_clamped_frames']}{_per_actuator(s, 'host')}; "
          f"firmware {s['firmware_clamped_frames']}{_per_actuator(s, 'firmware')})")
    if stats.error:
        raise MetamaterialError(f"stream stopped: {stats.error}")
    intr.raise_if_signalled()  # exit 130 (Ctrl+C) / 128 + the signal, the report written and marked
    for p in problems:
        print(f"error: {p}", file=sys.stderr)
    return 1 if problems else 0


def _problems(s, max_lost):
    """What makes a stream that ran to its end exit 1 (one line each; the report's ``error``, joined by '; ')."""
    out = []
    if s["lost"] > max_lost or s["naked"]:
        out.append(f"{s['lost']} frames lost (--max-lost {max_lost}) and {s['naked']} refused out of {s['frames']}")
    if s["firmware_clamped_frames"]:  # the host checked every angle sent: the board should have clamped none
        out.append(f"the firmware clamped {s['firmware_clamped_frames']} frames ({_per_actuator(s, 'firmware')[2:]}) "
                   f"that the host had checked against the channel limits and the servo range: the servos did not go "
                   f"where they were told; is the board configured by another program, or running other firmware?")
    return out


def _summary(stats, link, args, channels, intr, exc=None):
    """The statistics of the report and the summary line; ``exc``: the failure that ended the stream part-way."""
    s = stats.summary()
    s["port"] = link.name
    s["dry_run"] = bool(args.dry_run)
    s["channels"] = [c.to_dict() for c in channels]
    # "SIGINT" (Ctrl+C) / "SIGTERM" / "SIGHUP" when a signal ended the stream early
    s["interrupted"] = None if intr is None else intr.name
    s.update(_failure(exc))
    return s


def _failure(exc):
    """{"failed", "error"} of a report: ``exc`` (None: the stream ran to its end) as one line."""
    if exc is None:
        return {"failed": False, "error": ""}
    if isinstance(exc, KeyboardInterrupt):  # a second signal (or one while no handler was installed)
        import signal
        name = signal.Signals(getattr(exc, "signum", signal.SIGINT)).name
        why = f"KeyboardInterrupt: stopped at once by {name}"
    else:
        why = " ".join((str(exc) or type(exc).__name__).split())
    return {"failed": True, "error": why}


def _written(write, path, ran):
    """Write the report of a stream that failed part-way (``write()``) and say so; a report that cannot be
    written is said too, never raised (the stream's own failure is what the command exits with)."""
    try:
        write()
    except Exception as exc:  # (the temporary is removed by the writer)
        print(f"stream failed after {ran}; --report {path} could not be written: {exc}", file=sys.stderr)
    else:
        print(f"stream failed after {ran}; --report {path} written, marked failed", file=sys.stderr)


def _per_actuator(s, by):
    """': tail 28, head 3' for the actuators that ``by`` ("host" / "firmware") clamped, else ''."""
    counts = [f"{name} {n[by]}" for name, n in s["clamped_by_actuator"].items() if n[by]]
    return ": " + ", ".join(counts) if counts else ""


def _check_bandwidth(baud, rate, channels):
    """The frames and their ACKs must fit the line: 10 bits per byte at 8N1, with a quarter to spare."""
    from metamaterial_wb.core.errors import SceneError
    from metamaterial_wb.hardware.streamer import wire_bytes_per_tick
    need = wire_bytes_per_tick(channels) * 10 * rate * 1.25
    if baud < need:
        raise SceneError("--baud", f"{baud} bits/s is too slow for --rate {rate:g}: each tick's frames and ACKs "
                                   f"take {wire_bytes_per_tick(channels)} bytes, so at least {need:.0f} bits/s are "
                                   f"needed (the firmware speaks 115200)")


def _run_osc(args, scene, channels, link, intr):
    """--mode osc: the firmware generates the sine profiles; the host only keeps the link alive."""
    import time

    from metamaterial_wb.core.fileio import write_json
    from metamaterial_wb.hardware.onboard import osc_params, rtt_summary, run_oscillators

    params = osc_params(scene, channels, tolerance_deg=args.rate_tolerance)
    for p in params:
        f = f"{1000.0 / p.period_ms:.4g} Hz" if p.period_ms else "constant"
        if not p.period_ms or not p.amp_cdeg:  # a constant channel: no sine to print
            wave = (f"{p.offset_cdeg / 100:g} deg (constant)" if p.gain_pos is None else
                    f"v = {p.offset_cdeg / 9000:g} (constant), joint angle {p.angle_range_deg[0]:.2f} deg")
        elif p.gain_pos is None:
            wave = f"{p.offset_cdeg / 100:g} + {p.amp_cdeg / 100:g} deg sin(2 pi {f} t + {p.phase_cdeg / 100:g} deg)"
        else:
            wave = (f"v = {p.offset_cdeg / 9000:g} + {p.amp_cdeg / 9000:g} sin(2 pi {f} t + {p.phase_cdeg / 100:g} "
                    f"deg), joint angle {p.angle_range_deg[0]:.2f}..{p.angle_range_deg[1]:.2f} deg")
        print(f"  {p.name} -> ch{p.channel}: {wave}" + (f", frequency off by {p.frequency_error:+.2%}"
                                                          if abs(p.frequency_error) > 1e-4 else ""), file=sys.stderr)
    def summary(duration, exc=None):
        # seconds: --seconds; duration_s: how long the host kept the link alive (shorter when interrupted or failed)
        # ping_rtt_ms_median / _p99 / _max: from the bounded table run_oscillators keeps (as the streamed mode's)
        return {"format": "metamaterial-stream-report", "version": 1,
                "mode": "osc", "port": link.name, "dry_run": bool(args.dry_run), "seconds": args.seconds,
                "duration_s": round(duration, 4), "interrupted": intr.name,
                "pings": res["pings"], "firmware_start_ms": res["t_start_ms"],
                **{"ping_" + k: v for k, v in rtt_summary(res["rtt_counts"]).items()}, **_failure(exc),
                "oscillators": [vars(p) for p in params], "channels": [c.to_dict() for c in channels]}

    res = {}
    t0 = time.perf_counter()
    try:
        try:  # a signal (Ctrl+C) ends the keep-alive loop at its next check, as its end would
            run_oscillators(link, params, args.seconds, stop=lambda: intr.signum is not None, result=res)
        finally:
            intr.restore()
        duration = time.perf_counter() - t0
        if args.disarm:  # on Ctrl+C too
            link.disarm()
    except BaseException as exc:  # the oscillators started: the report of what ran, marked failed
        if args.report and res.get("started"):
            s = summary(time.perf_counter() - t0, exc)
            _written(lambda: write_json(args.report, s), args.report,
                     f"{s['pings']} keep-alive pings in {s['duration_s']:.2f} s")
        raise
    s = summary(duration)
    if args.report:
        write_json(args.report, s)
    ran = (f"{args.seconds:g} s" if intr.signum is None else
           f"{duration:.2f} s of --seconds {args.seconds:g}, interrupted ({intr.name})")
    rtt = (f"round trip median {s['ping_rtt_ms_median']:.2f} ms, p99 {s['ping_rtt_ms_p99']:.2f} ms, max "
           f"{s['ping_rtt_ms_max']:.2f} ms" if s["ping_rtt_ms_median"] is not None else "no replies")
    print(f"on-board oscillators ran {ran}; {s['pings']} keep-alive pings, {rtt}")
    intr.raise_if_signalled()
    return 0


class _Interrupt:
    """Ctrl+C (SIGINT), SIGTERM and SIGHUP while streaming: the first calls ``stop()`` (the stream ends at its next
    tick, as at its end) and is remembered; a second one raises at once (KeyboardInterrupt: a report marked failed).
    ``raise_if_signalled()`` then exits as the CLI does for that signal (130 / 128 + its number). Only in the main
    thread (signal handlers); a signal the process ignores stays ignored."""

    def __init__(self, stop):
        self._stop = stop
        self._old = {}
        self.signum = None

    @property
    def name(self):
        import signal
        return None if self.signum is None else signal.Signals(self.signum).name

    def install(self):
        import signal
        import threading
        if threading.current_thread() is threading.main_thread():
            for sig in (signal.SIGINT, signal.SIGTERM, getattr(signal, "SIGHUP", None)):
                if sig is not None and signal.getsignal(sig) is not signal.SIG_IGN:
                    self._old[sig] = signal.signal(sig, self._handler)
        return self

    def restore(self):
        import signal
        old, self._old = self._old, {}
        for sig, h in old.items():
            signal.signal(sig, h)

    def _handler(self, signum, frame):
        if self.signum is not None:  # the second signal: stop waiting for the stream's end
            self.restore()
            self._raise(signum)
        self.signum = signum
        self._stop()

    def raise_if_signalled(self):
        if self.signum is not None:
            self._raise(self.signum)

    @staticmethod
    def _raise(signum):
        import signal
        if signum == signal.SIGINT:
            raise KeyboardInterrupt
        from metamaterial_wb.cli import _Signalled
        raise _Signalled(signum)
