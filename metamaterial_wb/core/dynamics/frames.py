"""When ``Simulator.run`` records a frame (integrators.py): frames are states the integrator reaches, so they lie on
its step grid. Frame k stands for the instant ``k * record_dt`` and is the state at the time step nearest that
instant (within half a step; ties to the earlier step), so the spacing is as even as the step allows: a whole
number of steps per frame gives exactly even frames, otherwise consecutive frames are ``floor`` or ``ceil`` of
``record_dt / dt`` steps apart. The final state (t = the run's end) is always a frame.

A frame interval shorter than the step (more than one frame per step) cannot be honoured: the command line
refuses ``--fps`` above 1 / ``--dt`` (or 1 / the scene's ``dt_s``) before any work; where the step is only known
during the run (the automatic step, a fallback to another integrator), every step is a frame from there on and
``report()`` says so (``every_step_from_s``, ``note``).
"""
from __future__ import annotations

SNAPPING = ("each frame is the state at the time step nearest its instant k / fps (within half a step); the final "
            "state at the end of the run is always a frame")


class FrameClock:
    """The record instants ``k * record_dt`` (k = 0, 1, ...) of one run.

    Parameters
    ----------
    record_dt : float
        Frame interval (s), > 0.
    """

    def __init__(self, record_dt):
        self.record_dt = float(record_dt)
        self.k = 0                   # the next instant to record: k * record_dt
        self.frames = 0
        self.max_offset = 0.0        # largest |frame time - its instant| (s)
        self.every_step = None       # (t, step) where a step first stood for more than one instant

    def instant(self):
        """The next instant to record (s): a multiple of ``record_dt`` (no sum of intervals drifting)."""
        return self.k * self.record_dt

    def rec_at(self, h, eps):
        """The earliest step end that is the nearest step of the next instant, for a step ``h``."""
        return self.instant() - 0.5 * h - eps

    def due(self, t, h, eps):
        """Whether the state at ``t`` is the frame of the next instant (the next step, ``h`` on, is farther)."""
        return t >= self.rec_at(h, eps)

    def recorded(self, t, h, eps):
        """The state at ``t`` was recorded as a frame: every instant whose nearest step it is (one when the frame
        interval is at least the step ``h``) is done."""
        n = 0
        while self.instant() <= t + 0.5 * h + eps:
            self.max_offset = max(self.max_offset, abs(t - self.instant()))
            self.k += 1
            n += 1
            if self.record_dt <= 0:  # no interval (a run of no length asked for 7 frames): every step is a frame
                break
        if n > 1 and self.every_step is None:
            self.every_step = (t, h)
        self.frames += 1

    def report(self):
        """What was recorded, for the summary and the trajectory (``recording``)."""
        out = {"fps": 1.0 / self.record_dt if self.record_dt > 0 else None, "frame_interval_s": self.record_dt, "frames": self.frames,
               "max_offset_s": self.max_offset, "snapping": SNAPPING}
        if self.every_step is not None:
            t, h = self.every_step
            out["every_step_from_s"] = t
            out["note"] = (f"{1.0 / self.record_dt:g} frames/s is more than one frame per time step ({h:g} s): "
                           f"from t = {t:g} s every step is a frame ({1.0 / h:g} frames/s)")
        return out
