"""Animate's playback clock (a part of :class:`~metamaterial_wb.gui.panels.animate.AnimatePanel`).

The clock follows wall time: each timer tick shows the frame of *now* (anchor time + elapsed wall time x speed),
so a frame that costs more than its slot makes the next ones skip ahead (frames are dropped, time is not).
:meth:`PlaybackClock.clock` is read by the stream controller from its own thread: it reads plain attributes only
(the anchor tuple, replaced whole under ``_clock_lock``, and the copies ``_playing`` / ``_duration`` / ``_loop``
the widgets' signals keep), never a widget. The panel provides the widgets (``timeline``, ``speed``,
``duration``, ``play_btn``, ``timer``, labels), the solver, the trajectory and the stream.
The real-time factor shown is the timeline time played per wall second (1.00 = real time, 2.00 at speed 2), the
loop's wraps unwrapped; a start, a scrub or a speed change begins a new measurement (a pause is not counted).
"""
import math
import time

from metamaterial_wb.core.errors import MetamaterialError
from metamaterial_wb.gui.i18n import translate


class PlaybackClock:
    """Show the frame of a time, play / pause / scrub / loop / speed, and the achieved rate (a mixin of the
    Animate panel)."""

    def show_time(self, t):
        if self.check_target():       # deleted (Ctrl+Z, Delete): nothing drawn, playback stopped
            return
        t0 = time.perf_counter()
        self.t = t
        vals = self.values_at(t)
        try:
            if self.trajectory is not None:
                frame = self.trajectory.frame(self.solver, min(t, self.trajectory.duration))
            else:
                frame = self.solver.frame(values=vals)
        except MetamaterialError as exc:
            self.show_error(str(exc))
            self.pause()
            return
        try:
            self.preview_frame(self.obj, self.solver, frame)
        except (ReferenceError, RuntimeError) as exc:
            if self.lost_on(exc):
                return
            raise
        self.frames += 1
        self.last_values = vals
        dur = self.duration.value()
        self.timeline.blockSignals(True)
        self.timeline.setValue(int(round(1000 * min(t, dur) / dur)))
        self.timeline.blockSignals(False)
        self.time_label.setText(translate("Metamaterial", "t = {0:.2f} s").format(t))
        self.shown_values = {a.name: float(vals[a.name]) for a in self.scene.actuators}
        # one entry per motor: its name, the servo angle sent, its value
        self.values_label.setText("  ".join(translate("Metamaterial", "{0} {1} ({2:+.2f})").format(
            n, self.angles.text(n, v), v) for n, v in self.shown_values.items()))
        err = self.stream.take_error()
        if err:
            self.show_error(translate("Metamaterial", "streaming stopped: {0}").format(err))
            self.connect_btn.setChecked(False)
        # the panel's own frame timer (values, solve, preview written, labels; the render follows)
        self.frame_ms = 1000 * (time.perf_counter() - t0)
        self.frame_times.append(self.frame_ms)
        del self.frame_times[:-1000]
        self.stats.setText(translate("Metamaterial", "frame {0}: {1:.1f} ms (no recompute)").format(self.frames, self.frame_ms))

    def step(self, n=1):
        """Advance ``n`` frames of ``dt`` (scripted playback, independent of wall time)."""
        for _ in range(n):
            self.show_time(self._wrap(self.t + self.dt * self.speed.value()))
        self._reanchor()

    def _wrap(self, t):
        dur = self._duration
        if t > dur:
            if self._loop:
                t = math.fmod(t, dur)
            else:
                t = dur
                self.pause()
        return t

    def _reanchor(self):
        """Anchor the clock at the frame shown (start, scrub, scripted steps); GUI thread."""
        speed = self.speed.value()
        with self._clock_lock:
            self.anchor = (time.perf_counter(), self.t, speed)
        self._restart_rate()

    def _restart_rate(self):
        """A new rate window: a start (Play, Resume), a scrub or a speed change is not time played at one speed,
        so the factor is measured afresh from the next frame."""
        self.rate_window = []
        self.played_before_anchor = 0.0     # timeline time played (wraps unwrapped) up to the anchor, this window

    def _speed_changed(self, *_):
        """Re-anchor at the clock's time now, reckoned at the old speed (the streaming thread has already sent
        values of times ahead of the last frame drawn: anchoring there would send it back)."""
        speed = self.speed.value()
        with self._clock_lock:
            now = time.perf_counter()
            t = self._clock_at(now, self.anchor) if self._playing and self.anchor is not None else self.t
            self.anchor = (now, t, speed)
        self._restart_rate()
        self._warn_follow()

    def _warn_follow(self):
        """While streaming: say so when the link's frames can no longer follow the motion (a faster speed, an
        edited profile); Connect refuses such a state (``StreamController.follow_problem``). Per edit only the first
        ``FOLLOW_SPAN_S`` of the timeline is compared (Connect compares all of it); a longer timeline is said so."""
        if not self.stream.connected or self.preview_scene is None:
            return
        dur, speed, span = self.duration.value(), self.speed.value(), self.stream.FOLLOW_SPAN_S
        try:
            problem = self.stream.follow_problem(self.preview_scene, dur, speed, span_s=span)
        except MetamaterialError as exc:
            problem = str(exc)
        if problem:
            text = translate("Metamaterial", "warning: {0}").format(problem)
        else:
            text = self.stream.follow_span_note(dur, speed, span) or ""
        if text:
            if text != self.error.text():
                self.show_error(text)
        elif self.error.text() and self.error.text() == getattr(self, "_follow_said", None):
            self.clear_error()              # its own earlier warning or note no longer holds (another stays)
        self._follow_said = text

    def _duration_changed(self, *_):
        self._duration = self.duration.value()
        self._warn_follow()                 # a longer timeline while streaming: its first span compared, said

    def _loop_toggled(self, on):
        self._loop = bool(on)
        self._warn_follow()                 # while streaming: a jump where the timeline now wraps, said

    def _clock_at(self, now, anchor):
        wall0, t0, speed = anchor
        t = t0 + (now - wall0) * speed
        dur = self._duration
        if t > dur:
            t = math.fmod(t, dur) if self._loop else dur
        return t

    def clock(self, now=None):
        """The animation time at wall time ``now`` (default: now); the paused time when not playing.
        Thread-safe (the stream calls it from its thread): reads plain attributes, no widget."""
        if not self._playing:
            return self.t
        with self._clock_lock:     # the anchor and the time it is read at belong together (a speed change
            anchor = self.anchor   # between the two would put the sample before the new anchor's start)
            if now is None:
                now = time.perf_counter()
        if anchor is None:
            return self.t
        return self._clock_at(now, anchor)

    def tick(self):
        """Timer: show the frame of the wall-clock time (frames that did not fit are skipped)."""
        if self.check_target():
            return
        now = time.perf_counter()
        if self.anchor is None:
            self._reanchor()
        anchor = self.anchor
        wall0, t0, speed = anchor
        raw = t0 + (now - wall0) * speed
        wrapped = raw > self._duration and self._loop
        t = self._wrap(raw)
        # timeline time played since the rate window began: a wrap's whole run counted, the end of an unlooped
        # timeline where it stops (nothing negative when the length was cut below the anchor's time)
        played = self.played_before_anchor + (raw - t0 if wrapped else max(0.0, t - t0))
        if wrapped:
            with self._clock_lock:
                if self.anchor is anchor:
                    self.anchor = (now, t, speed)   # keep the clock exact across the wrap
                    self.played_before_anchor = played
        self.show_time(t)
        self._rate(now, played)

    def _rate(self, now, played):
        """The achieved frame rate and the real-time factor: timeline seconds played per wall second (wraps of
        the loop unwrapped) over the last 2 s of frames since the last start / scrub / speed change."""
        w = self.rate_window
        w.append((now, played))
        while len(w) > 2 and now - w[0][0] > 2.0:
            w.pop(0)
        if len(w) >= 2 and now > w[0][0]:
            span = now - w[0][0]
            fps = (len(w) - 1) / span
            rtf = (w[-1][1] - w[0][1]) / span
            self.achieved_fps, self.real_time_factor = fps, rtf
            self.rate_label.setText(translate("Metamaterial", "{0:.1f} frames/s achieved (target {1:.0f}); real-time factor {2:.2f}").format(fps, 1.0 / self.dt, rtf))

    def play(self):
        self.play_btn.setChecked(True)

    def pause(self):
        self.play_btn.setChecked(False)

    def _play_toggled(self, on):
        if on:
            self.play_btn.setText(translate("Metamaterial", "Pause"))
            self._reanchor()
            self._playing = True
            self.timer.start()
        else:
            self.play_btn.setText(translate("Metamaterial", "Play"))
            self._stop_timer()

    def _stop_timer(self):
        self._playing = False
        self.timer.stop()

    def _scrub(self, v):
        self.show_time(v / 1000.0 * self.duration.value())
        self._reanchor()
