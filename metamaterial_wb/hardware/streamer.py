"""50 Hz streaming of a scene's motion to the servolink firmware, in its own thread.

    from metamaterial_wb.hardware import Link, Streamer, channel_map
    link = Link.open("/dev/ttyUSB0")
    streamer = Streamer(link, channel_map(scene))
    streamer.start(scene)            # or start(callable t -> {actuator name: value in [-1, 1]})
    ...
    stats = streamer.stop()          # StreamStats: sent, acked, naked, lost, round-trip times, clamps

Each tick (every 1 / rate s) sends one SET_ANGLES frame per run of adjacent channels (channels 2 and 5: two
frames a tick); the stats count ticks and frames apart, and their rate is ticks per second. Frames carry
absolute angles: the latest wins, a lost frame is never retransmitted (the next one, 20 ms later, supersedes
it). Deadlines are absolute (``next += period``), so the rate does not drift; a tick that would be more than
one period late is skipped and counted (``catch_up=True`` sends it late instead). Whether the rate can follow a
scene's motion is checked before streaming (mapping.check_motion / check_rate; the CLI does, this class does
not). A board that stops answering (no ACK or NAK of a frame, no reply to a keep-alive PING) for longer than
``silence_limit_s`` (the link watchdog + the reply timeout, at least the 0.75 s a request waits) ends the stream
with a LinkError: by then a board that no longer hears the host holds its servos (and parks them after
``park_after_ms``), so streaming on blind would only count lost frames. The GUI calls ``start``/``stop`` from
its thread; the sending happens here, never in the Qt event loop.
"""
from __future__ import annotations

import threading
import time
from dataclasses import dataclass, field

from metamaterial_wb.core.errors import MetamaterialError

from . import protocol as P
from .link import LinkError
from .mapping import check_servo_reach, runs
from .onboard import count_rtt, keepalive_interval, link_watchdog_ms, raise_on_trip, rtt_summary

# how long Link.request waits for a reply before it gives up: 3 tries of 250 ms (the floor of silence_limit_s)
REQUEST_WAIT_S = 3 * 0.25


@dataclass
class StreamStats:
    ticks: int = 0            # deadlines at which the frames went out (rate_hz = ticks / duration_s)
    frames: int = 0           # SET_ANGLES frames sent: one per run of adjacent channels a tick
    frames_per_tick: int = 1  # the channel runs (mapping.runs): channels 2 and 5 take two frames a tick
    acked: int = 0            # answered with an ACK carrying the frame's seq
    naked: int = 0            # answered with a NAK carrying the frame's seq (read, refused)
    lost: int = 0             # frames - acked - naked over the whole stream: no answer of their own
    nak_unreadable: int = 0   # NAKs with seq 0xFF during the stream: the device could not decode a frame
    rx_errors: int = 0        # replies the host could not decode
    skipped: int = 0          # ticks missed by more than one period (not sent)
    keepalive_pings: int = 0  # PINGs sent between slow frames to feed the link watchdog (not frames)
    resets: int = 0           # board reboots seen (re-configured and re-armed)
    clamped_frames: int = 0   # frames clamped by the host (--clamp) or the firmware (ACK clamp mask), each once
    host_clamped_frames: int = 0      # frames in which the host clamped an angle to its channel's limits
    firmware_clamped_frames: int = 0  # ACKs whose clamp mask was not zero
    clamped_by_actuator: dict = field(default_factory=dict)  # {name: {"host": frames, "firmware": frames}}
    nak_reasons: dict = field(default_factory=dict)
    unreadable_reasons: dict = field(default_factory=dict)
    # round-trip times: {ms, onboard.rtt_key-rounded: ACKs}, so a day's stream keeps a bounded table, not a list per
    # frame (the --mode osc keep-alive PINGs are counted the same way: onboard.run_oscillators)
    rtt_counts: dict = field(default_factory=dict)
    duration_s: float = 0.0
    last_t: float = None      # motion time of the last frame sent (s)
    events: list = field(default_factory=list)
    error: str = ""

    def add_rtt(self, ms):
        count_rtt(self.rtt_counts, ms)

    def summary(self):
        return {"ticks": self.ticks, "frames": self.frames, "frames_per_tick": self.frames_per_tick,
                "acked": self.acked, "naked": self.naked, "lost": self.lost,
                "nak_unreadable": self.nak_unreadable, "unreadable_reasons": self.unreadable_reasons,
                "rx_errors": self.rx_errors,
                "skipped": self.skipped, "keepalive_pings": self.keepalive_pings, "resets": self.resets,
                "clamped_frames": self.clamped_frames, "host_clamped_frames": self.host_clamped_frames,
                "firmware_clamped_frames": self.firmware_clamped_frames,
                "clamped_by_actuator": {k: dict(v) for k, v in self.clamped_by_actuator.items()},
                "nak_reasons": self.nak_reasons,
                "duration_s": round(self.duration_s, 4), "last_t": self.last_t,
                # ticks per second (the --rate achieved), not frames: a tick sends a frame per channel run
                "rate_hz": round(self.ticks / self.duration_s, 3) if self.duration_s > 0 else 0.0,
                **rtt_summary(self.rtt_counts),   # rtt_ms_median, rtt_ms_p99, rtt_ms_max
                "events": self.events, "error": self.error}


def check_servo_driver(link, settle_s=0.05):
    """After ARM the firmware writes the pulses to its servo driver (a failed write is retried every 20 ms): a PING
    ``settle_s`` later tells whether the last write failed (PING byte servo_fault). LinkError if so. PINGs keep the
    link watchdog fed meanwhile."""
    if link.dry_run:
        return
    step = keepalive_interval(link_watchdog_ms(link))
    end = time.perf_counter() + settle_s
    while True:
        time.sleep(max(0.0, min(step, end - time.perf_counter())))
        r = link.request(P.PING)
        if time.perf_counter() >= end:
            break
    if len(r.data) > 14 and r.data[14]:  # (firmware before the servo_fault byte: nothing to check)
        raise LinkError(f"{link.name}: PING reports a servo fault: {P.SERVO_FAULT_HELP}")


def wire_bytes_per_tick(channels):
    """Bytes on the wire per streamed tick: each channel run's SET_ANGLES frame and the firmware's ACK of it
    (request, state, clamp mask, count: 11 bytes), COBS and the delimiter included. At 8N1 a byte is 10 bits."""
    total = 0
    for first, cfgs in runs(channels):
        total += len(P.build_frame(P.SET_ANGLES, 1, P.set_angles_payload(first, [0] * len(cfgs))))
        total += len(P.build_frame(P.ACK, 1, bytes([P.SET_ANGLES, P.ST_ARMED, 0, 0, len(cfgs)])))
    return total


def source_function(source):
    """A Scene (its actuators' motion profiles) or a callable ``t -> {name: value}``."""
    if callable(source):
        return source
    if hasattr(source, "actuators"):
        from metamaterial_wb.core.motion import scene_values_at

        return lambda t: scene_values_at(source, t)
    raise MetamaterialError(f"stream source: expected a scene or a function of time, got {type(source).__name__}")


class Streamer:
    def __init__(self, link, channels, rate_hz=50.0, clamp=False, reply_timeout_s=0.1, catch_up=False):
        if not 1.0 <= rate_hz <= 100.0:
            raise MetamaterialError(f"rate {rate_hz} Hz is outside the allowed range [1, 100] Hz")
        self.link = link
        self.channels = list(channels)
        self.rate_hz = float(rate_hz)
        self.clamp = clamp
        self.reply_timeout_s = reply_timeout_s
        self.catch_up = catch_up  # True: after a stall send the missed frames back to back instead of skipping
        self.stats = StreamStats()
        self.on_frame = None   # callback(t, {name: angle_deg}) after each frame (from the streaming thread)
        self.on_clamp = None   # callback(t, {name: wanted angle_deg}) for a frame whose angles the host clamped
        self.on_error = None   # callback(message) when the stream stops on an error
        self._thread = None
        self._stop = threading.Event()
        # seq -> (send time, whether the host clamped it) of the frames not answered yet (a seq is reused after
        # 254 frames)
        self._outstanding = {}
        self._pings = set()  # seqs of keep-alive PINGs not answered yet (their replies are only discarded)
        self._unreadable_heard = 0  # the link's unreadable_naks when last looked at (each new one: the board answers)
        self._link_timing = (500, 500, 5000)
        self._events_seen = 0
        self._silent_since = None  # when the first frame sent since the board's last answer went out (None: answered)
        self._unanswered = 0       # frames sent since the board's last answer

    @staticmethod
    def silence_limit_s(watchdog_ms, reply_timeout_s):
        """How long the board may leave every frame and PING unanswered before the stream fails: its link watchdog
        (by then a board that does not hear the host holds the servos, then parks them) plus the reply timeout,
        and never less than a request's 3 tries of 250 ms (Link.request), so that a stream is not stricter than a
        handshake or a CONFIG."""
        return round(max(REQUEST_WAIT_S, (watchdog_ms or 500) / 1000.0 + reply_timeout_s), 6)

    # ------------------------------------------------------------------------------------------
    def prepare(self, watchdog_ms=500, park_after_ms=500, release_after_ms=5000, handshake=True):
        """Handshake (if not done), send the channel configuration and the watchdog timing, ARM."""
        self._link_timing = (watchdog_ms, park_after_ms, release_after_ms)
        if handshake and self.link.info is None:
            self.link.handshake(min_channels=max(c.channel for c in self.channels) + 1)
        self.link.configure(self.channels)
        self.link.configure_watchdog(watchdog_ms, park_after_ms, release_after_ms)
        self.link.arm()
        check_servo_driver(self.link)

    def frame_payloads(self, values):
        """``{name: value}`` -> [(payload, {name: angle sent}, {name: wanted angle})] for the channel runs; the
        angle sent is the whole centidegrees of the frame (cdeg / 100 deg), the wanted one the motion's.

        An angle outside its channel's limits is refused, or with ``clamp`` clamped (the third item holds the
        wanted angle of every clamped channel, empty if none); a servo angle (+-angle + trim) outside [-90, 90]
        deg is refused in both cases (mapping.check_servo_reach)."""
        out = []
        for first, cfgs in runs(self.channels):
            cdeg, angles, wanted = [], {}, {}
            for c in cfgs:
                v = float(values.get(c.name, 0.0))
                a = c.angle_deg(v)
                lo, hi = c.limits_deg
                if not c.within_limits(a):
                    if not self.clamp:
                        raise MetamaterialError(f"actuator {c.name!r}: {a:.2f} deg (value {v:.4f}) is outside channel "
                                                f"{c.channel}'s limits [{lo:g}, {hi:g}] deg")
                    wanted[c.name] = a
                    a = min(max(a, lo), hi)
                check_servo_reach(c, a, f"actuator {c.name!r} (value {v:.4f})")
                cd = int(round(a * 100))   # the wire carries whole centidegrees: report what was sent
                cdeg.append(cd)
                angles[c.name] = cd / 100  # an int / 100: never -0.0
            out.append((P.set_angles_payload(first, cdeg), angles, wanted))
        return out

    def _collect(self, timeout):
        self.link.poll(timeout)
        if self.link.unreadable_naks != self._unreadable_heard:  # a NAK of a frame it could not read: it answers
            self._unreadable_heard = self.link.unreadable_naks
            self._answered()
        # taken under the link's read lock: another thread (e.g. a GUI ping) may be polling meanwhile
        for seq in self.link.take_replies(self._pings):
            self._pings.discard(seq)
            self._answered()
        for seq, r in self.link.take_replies(self._outstanding).items():  # also replies read by another thread
            sent, host_clamped = self._outstanding.pop(seq)
            self._answered()
            if r.kind == "ACK":
                self.stats.acked += 1
                self.stats.add_rtt((getattr(r, "time", time.perf_counter()) - sent) * 1000.0)
                if r.clamp_mask:
                    self.stats.firmware_clamped_frames += 1
                    self.stats.clamped_frames += 0 if host_clamped else 1
                    for c in self.channels:
                        if r.clamp_mask >> c.channel & 1:
                            self._count_clamp(c.name, "firmware")
            else:
                self.stats.naked += 1
                self.stats.nak_reasons[r.reason] = self.stats.nak_reasons.get(r.reason, 0) + 1

    def _answered(self):
        self._silent_since, self._unanswered = None, 0

    def _check_silence(self, limit_s):
        """LinkError when nothing the host sent has been answered for longer than ``limit_s`` (silence_limit_s)."""
        if self._silent_since is None:
            return
        silent = time.perf_counter() - self._silent_since
        if silent > limit_s:
            raise LinkError(f"{self.link.name}: the board stopped answering: no reply to the last {self._unanswered} "
                            f"frames in {silent:.2f} s (allowed: {limit_s:g} s, the link watchdog "
                            f"{self._link_timing[0]} ms + the reply timeout {self.reply_timeout_s * 1000:.0f} ms, at "
                            f"least {REQUEST_WAIT_S * 1000:.0f} ms); a board that does not hear the host holds its "
                            f"servos, then parks them; check the cable and the board's power, then connect again")

    def _count_clamp(self, name, by):
        self.stats.clamped_by_actuator.setdefault(name, {"host": 0, "firmware": 0})[by] += 1

    def _check_events(self, n_events):
        """Raise LinkError on an EVENT from the device (checked between frames too, not only per frame)."""
        self._events_seen = raise_on_trip(self.link, n_events + self._events_seen, "while streaming") - n_events

    def run(self, source, duration_s=None, t0=0.0):
        """Stream in the calling thread until ``duration_s`` (None: until stop()). Returns the stats.

        Between frames further apart than the keep-alive interval (``min(0.1 s, watchdog_ms / 3)``, e.g. at a
        slow rate) a PING keeps the link watchdog fed (PROTOCOL.md section 6); a watchdog EVENT stops the stream
        as soon as it arrives."""
        fn = source_function(source)
        period = 1.0 / self.rate_hz
        keepalive_s = keepalive_interval(self._link_timing[0])
        self._pings = set()
        self.stats = StreamStats(clamped_by_actuator={c.name: {"host": 0, "firmware": 0} for c in self.channels},
                                 frames_per_tick=len(runs(self.channels)))
        self._outstanding = {}
        self._unreadable_heard = self.link.unreadable_naks
        self._answered()
        silence_s = self.silence_limit_s(self._link_timing[0], self.reply_timeout_s)
        n_events = len(self.link.events)
        self._events_seen = 0
        unreadable0, reasons0 = self.link.unreadable_naks, dict(self.link.unreadable_reasons)
        rx_errors0 = self.link.rx_errors
        start = time.perf_counter()
        deadline = start
        last_tx = start
        k = 0
        try:
            resets = self.link.resets_seen
            while not self._stop.is_set():
                if self.link.resets_seen != resets:  # the board rebooted (brown-out, cable): set it up again
                    resets = self.link.resets_seen
                    self.stats.resets += 1
                    self._outstanding.clear()
                    self.prepare(*self._link_timing, handshake=False)
                    self._answered()  # (it answered the re-configuration)
                self._check_events(n_events)
                t = t0 + k * period
                if duration_s is not None and k * period >= duration_s - 1e-9:
                    break
                for payload, angles, wanted in self.frame_payloads(fn(t)):
                    seq = self.link.send(P.SET_ANGLES, payload)
                    last_tx = time.perf_counter()
                    self._pings.discard(seq)  # a seq reused (wrap) by a frame is the frame's now
                    # a seq still outstanding 254 frames later was lost: it stays counted (lost = frames -
                    # acked - naked), only its entry is replaced
                    self._outstanding[seq] = (time.perf_counter(), bool(wanted))
                    if self._silent_since is None:
                        self._silent_since = last_tx
                    self._unanswered += 1
                    self.stats.frames += 1
                    self.stats.last_t = t
                    if wanted:  # the host clamped (--clamp): counted here, the firmware's clamps from the ACKs
                        self.stats.host_clamped_frames += 1
                        self.stats.clamped_frames += 1
                        for name in wanted:
                            self._count_clamp(name, "host")
                        if self.on_clamp:
                            self.on_clamp(t, wanted)
                    if self.on_frame:
                        self.on_frame(t, angles)
                self.stats.ticks += 1
                deadline += period
                k += 1
                # collect replies until the next deadline; keep the link alive between slow frames
                while True:
                    now = time.perf_counter()
                    left = deadline - now
                    if left <= 0 or self._stop.is_set():
                        break
                    if now - last_tx >= keepalive_s and left > 0.002:
                        ping = self.link.send(P.PING)
                        self._outstanding.pop(ping, None)  # (a seq reused by the PING: that frame stays lost)
                        self._pings.add(ping)
                        self.stats.keepalive_pings += 1
                        last_tx = now
                    self._collect(min(left, 0.005, max(0.0, last_tx + keepalive_s - now)))
                    self._check_events(n_events)
                    self._check_silence(silence_s)
                # also when the loop above had no time left (a host slower than the period): read what waits first,
                # so replies sitting unread are not taken for a silent board
                self._collect(0)
                self._check_events(n_events)
                self._check_silence(silence_s)
                late = time.perf_counter() - deadline
                if late > period and not self.catch_up:  # fell behind: skip the missed deadlines, keep the time base
                    missed = int(late // period)
                    self.stats.skipped += missed
                    deadline += missed * period
                    k += missed
            end = time.perf_counter() + self.reply_timeout_s
            while self._outstanding and time.perf_counter() < end:
                self._collect(0.005)
        except (LinkError, MetamaterialError) as exc:
            self.stats.error = str(exc)
            if self.on_error:
                self.on_error(str(exc))
            if self._thread is None:
                raise
        except Exception as exc:  # serial errors (unplugged cable) end the stream with a message
            self.stats.error = f"{type(exc).__name__}: {exc}"
            if self.on_error:
                self.on_error(self.stats.error)
            if self._thread is None:
                raise LinkError(f"{self.link.name}: {self.stats.error}") from None
        finally:
            self.stats.duration_s = time.perf_counter() - start
            self.stats.lost = self.stats.frames - self.stats.acked - self.stats.naked
            self.stats.nak_unreadable = self.link.unreadable_naks - unreadable0
            self.stats.unreadable_reasons = {k: v - reasons0.get(k, 0) for k, v in self.link.unreadable_reasons.items()
                                             if v - reasons0.get(k, 0)}
            self.stats.rx_errors = self.link.rx_errors - rx_errors0
            self.stats.events = [P.EVENT_NAMES.get(r.code, hex(r.code)) if r.kind == "EVENT" else "RESET"
                                 for _, r in self.link.events[n_events:]]
        return self.stats

    # ------------------------------------------------------------------------------------------
    @property
    def running(self):
        return self._thread is not None and self._thread.is_alive()

    def start(self, source, duration_s=None, t0=0.0):
        """Start streaming ``source`` in a background thread (the link must be prepared: see prepare())."""
        if self.running:
            raise MetamaterialError("the streamer is already running; stop() it first")
        fn = source_function(source)
        self.frame_payloads(fn(t0))  # fail now, in the caller's thread, on a bad first frame
        self._stop.clear()
        self._thread = threading.Thread(target=self.run, args=(fn, duration_s, t0), name="servolink-stream",
                                        daemon=True)
        self._thread.start()

    def stop(self, disarm=False, timeout=2.0):
        """Stop the thread; ``disarm=True`` also stops the pulses (servos go limp); otherwise the firmware's
        watchdog holds, then parks, then releases the servos. Returns the stats."""
        self._stop.set()
        if self._thread is not None:
            self._thread.join(timeout)
            self._thread = None
        if disarm:
            try:
                self.link.disarm()
            except LinkError as exc:
                self.stats.error = self.stats.error or str(exc)
        return self.stats
