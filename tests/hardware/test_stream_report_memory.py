"""``stream --report FILE`` for long runs (session 34): the report held every frame in memory until the end and
then wrote one JSON (a day at 50 Hz: hundreds of MB held, all lost to a crash). Now the frames go to the report
as they are sent, through a temporary file renamed at the end (Ctrl+C: written and marked ``interrupted``; a
second signal or an error after frames went out: written and marked ``failed`` (tests/hardware/
test_stream_partial_report.py); a full disk: no report, no temporary left), and memory does not grow with the run.

The CLI runs in this process over loop:// (--dry-run) with a virtual clock in hardware/streamer.py (each reading
a fraction of a tick later), so a long stream takes seconds, not hours; the memory is Python's own count
(tracemalloc) from the stream's start to the command's end."""
import errno
import json
import os
import time
import tracemalloc

import pytest

pytest.importorskip("serial")

from clihelpers import REPO  # noqa: E402

from metamaterial_wb import cli as CLI  # noqa: E402
from metamaterial_wb.hardware import streamer as S  # noqa: E402
from metamaterial_wb.hardware.link import Link  # noqa: E402

FISH = os.path.join(REPO, "examples", "fish.json")
RATE = 50.0


class _VirtualTime:
    """Stands in for the ``time`` module in hardware/streamer.py: ``perf_counter`` advances an eighth of a tick a
    reading, so the pacing loop runs at full speed and sends every tick (none skipped); the rest is the real one."""

    def __init__(self, rate):
        self.now = 1000.0
        self.step = 1.0 / rate / 8

    def perf_counter(self):
        self.now += self.step
        return self.now

    def __getattr__(self, name):
        return getattr(time, name)


@pytest.fixture
def fast(monkeypatch):
    """Streams run on the virtual clock; the link never waits for bytes (loop:// echoes every frame at once)."""
    monkeypatch.setattr(S, "time", _VirtualTime(RATE))
    real_poll = Link.poll
    monkeypatch.setattr(Link, "poll", lambda self, timeout=0.0: real_poll(self, 0.0))
    return monkeypatch


def _stream(tmp_path, seconds, name="r.json", *extra):
    rep = tmp_path / name
    rc = CLI.main(["stream", FISH, "--dry-run", "--seconds", str(seconds), "--report", str(rep), *extra])
    return rc, rep


def _stream_peak(monkeypatch, tmp_path, seconds):
    """(exit status, report path, bytes allocated at the peak above those live when the stream started)."""
    real_run = S.Streamer.run
    base = []

    def run(self, *a, **k):
        tracemalloc.reset_peak()
        base.append(tracemalloc.get_traced_memory()[0])
        return real_run(self, *a, **k)

    monkeypatch.setattr(S.Streamer, "run", run)
    tracemalloc.start()
    try:
        rc, rep = _stream(tmp_path, seconds, f"r{seconds}.json")
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert len(base) == 1
    return rc, rep, peak - base[0]


def test_memory_while_streaming_does_not_grow_with_the_run_length(fast, tmp_path, capsys):
    short, long_ = 10, 100  # s: 500 and 5 000 ticks
    rc, rep_s, peak_s = _stream_peak(fast, tmp_path, short)
    assert rc == 0, capsys.readouterr().err
    rc, rep_l, peak_l = _stream_peak(fast, tmp_path, long_)
    assert rc == 0, capsys.readouterr().err
    # a bounded stream: ten times the frames, about the same memory (it held every frame: about 10x). The slack
    # is what a text file's write buffer holds at a time (up to 8 kB of pending lines, wherever the run ends)
    assert peak_l < 1.5 * peak_s + 64 * 1024, (peak_s, peak_l)
    # and the report still lists every frame, a valid JSON with its format
    for rep, seconds in ((rep_s, short), (rep_l, long_)):
        d = json.loads(rep.read_text(encoding="utf-8"))
        assert d["format"] == "metamaterial-stream-report" and d["version"] == 1
        assert d["ticks"] == d["frames"] == d["acked"] == len(d["frames_sent"]) == int(seconds * RATE)
        assert [f["t"] for f in d["frames_sent"][:3]] == [0.0, 0.02, 0.04]
        assert d["frames_sent"][-1]["t"] == pytest.approx(seconds - 1 / RATE)
        assert set(d["frames_sent"][-1]["angles_deg"]) == {"0", "1"} and d["interrupted"] is None
        assert d["rtt_ms_median"] is not None and d["rtt_ms_max"] >= d["rtt_ms_p99"] >= d["rtt_ms_median"] > 0
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted([f"r{short}.json", f"r{long_}.json"])  # no temporary


def _hook_frames(monkeypatch, at_frame):
    """Call ``at_frame(n)`` after the n-th frame the streamer sends (n from 1)."""
    real = Link.send
    count = [0]

    def send(self, ptype, payload=b"", seq=None):
        out = real(self, ptype, payload, seq)
        from metamaterial_wb.hardware import protocol as P
        if ptype == P.SET_ANGLES:
            count[0] += 1
            at_frame(count[0])
        return out

    monkeypatch.setattr(Link, "send", send)
    return count


def test_the_frames_go_to_a_temporary_beside_the_report_while_streaming(fast, tmp_path):
    seen = []

    def look(n):
        if n in (2500, 7500):
            tmp = [p for p in tmp_path.iterdir() if p.name.startswith(f".tmp-{os.getpid()}-")]
            seen.append((n, (tmp_path / "r.json").exists(), len(tmp), tmp[0].stat().st_size if tmp else 0))

    _hook_frames(fast, look)
    rc, rep = _stream(tmp_path, 150)
    assert rc == 0
    # the report is not there until the stream ends; its temporary grows with the frames written
    assert [(n, there, k) for n, there, k, _ in seen] == [(2500, False, 1), (7500, False, 1)], seen
    assert seen[1][3] > 2 * seen[0][3] > 0  # (a write buffer of 64 kB: about 1 200 ticks)
    assert len(json.loads(rep.read_text(encoding="utf-8"))["frames_sent"]) == 7500
    assert [p.name for p in tmp_path.iterdir()] == ["r.json"]


def test_ctrl_c_writes_the_frames_sent_and_marks_the_report(fast, tmp_path, capsys):
    import signal

    def ctrl_c(n):
        if n == 300:
            os.kill(os.getpid(), signal.SIGINT)  # the stream's handler: the stream ends at its next tick

    count = _hook_frames(fast, ctrl_c)
    # Ctrl+C as in a terminal (a job a script starts in the background inherits SIGINT ignored)
    old = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        rc, rep = _stream(tmp_path, 1000)
    finally:
        signal.signal(signal.SIGINT, old)
    assert rc == 130
    d = json.loads(rep.read_text(encoding="utf-8"))
    assert d["interrupted"] == "SIGINT" and d["format"] == "metamaterial-stream-report"
    assert d["frames"] == len(d["frames_sent"]) == count[0] >= 300
    assert count[0] < 1000 * RATE
    assert [p.name for p in tmp_path.iterdir()] == ["r.json"]


def test_a_second_signal_mid_stream_writes_the_frames_sent_marked_failed_and_no_temporary(fast, tmp_path, capsys):
    rep = tmp_path / "r.json"
    rep.write_text("old\n", encoding="utf-8")

    def second_signal(n):
        if n == 500:
            raise KeyboardInterrupt  # as the second Ctrl+C does: stop at once

    _hook_frames(fast, second_signal)
    assert CLI.main(["stream", FISH, "--dry-run", "--seconds", "100", "--report", str(rep)]) == 130
    d = json.loads(rep.read_text(encoding="utf-8"))  # the old report replaced by the one of what ran, whole
    assert d["failed"] is True and "KeyboardInterrupt" in d["error"]
    # the 500th frame raised inside Link.send, before the streamer counted it: 499 frames sent and listed
    assert d["frames"] == len(d["frames_sent"]) == 499
    assert [p.name for p in tmp_path.iterdir()] == ["r.json"]


class _FullFile:
    """A text file whose writes fail as on a full disk once ``budget`` characters went in (OSError without a name)."""

    def __init__(self, f, budget):
        self._f = f
        self._left = budget

    def write(self, data):
        self._left -= len(data)
        if self._left < 0:
            raise OSError(errno.ENOSPC, "No space left on device")
        return self._f.write(data)

    def __getattr__(self, name):
        return getattr(self._f, name)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self._f.close()
        return False


def test_a_full_disk_mid_stream_stops_it_names_the_report_and_leaves_nothing(fast, tmp_path, capsys):
    real = os.fdopen
    fast.setattr(os, "fdopen", lambda fd, *a, **k: _FullFile(real(fd, *a, **k), 50_000))
    count = _hook_frames(fast, lambda n: None)
    rc, rep = _stream(tmp_path, 100)
    err = capsys.readouterr().err
    assert rc == 2, err
    assert f"{rep}: No space left on device" in err and "free space" in err, err
    assert count[0] < 2500  # stopped soon after the disk filled, not after 100 s of frames
    assert list(tmp_path.iterdir()) == []
