"""Progress lines on stderr for long builds and exports (throttled, never on stdout)."""
import sys
import time


class Progress:
    """``p = Progress("nodes", 441); p.step(); ...; p.done()`` prints at most every ``interval_s``."""

    def __init__(self, label, total, stream=None, interval_s=0.5, enabled=True):
        self.label = label
        self.total = int(total)
        self.count = 0
        self.stream = stream if stream is not None else sys.stderr
        self.interval_s = interval_s
        self.enabled = enabled
        self.t0 = time.perf_counter()
        self._last = self.t0

    def step(self, n=1):
        self.count += n
        if not self.enabled:
            return
        now = time.perf_counter()
        if now - self._last >= self.interval_s:
            self._last = now
            pct = 100.0 * self.count / self.total if self.total else 100.0
            print(f"build: {self.label} {self.count}/{self.total} ({pct:.0f}%)", file=self.stream, flush=True)

    def done(self, extra=""):
        if self.enabled:
            dt = time.perf_counter() - self.t0
            print(f"build: {self.label} {self.count}/{self.total} done in {dt:.2f} s{extra}", file=self.stream,
                  flush=True)


def note(message, enabled=True, stream=None):
    if enabled:
        print(f"build: {message}", file=stream if stream is not None else sys.stderr, flush=True)
