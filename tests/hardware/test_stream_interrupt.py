"""Ctrl+C (SIGINT) and SIGTERM during ``stream``: the stream ends at its next tick as its end would (``--disarm``
disarms, else nothing more is sent and the firmware's watchdog holds, parks, releases), the exit status is 130
(128 + the signal), and ``--report`` is written whole and marked ``interrupted`` with what really ran (it said
the full ``--seconds`` with exit 0). Through the real CLI against a scripted device on a pty (tests/ptydevice.py);
the signal is sent once the device has seen the stream start, never after a fixed time."""
import json
import os
import signal
import subprocess
import sys
import time

import pytest

pytest.importorskip("serial")

from metamaterial_wb.hardware import protocol as P  # noqa: E402
from ptydevice import PtyDevice, device_fixture  # noqa: E402

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
FISH = os.path.join(REPO, "examples", "fish.json")
HELLO = bytes([1, 0, 1, 0, 0, 8, 100, 0xF4, 0x01, 3, 0x28, 0, 0, 0, 0])
SECONDS = "120"  # far longer than the test waits: only the signal can end the stream


class Device(PtyDevice):
    """ACKs every request (HELLO with a HELLO_ACK), recording the packet types in order."""

    poll_s = 0.005

    def __init__(self):
        super().__init__()
        self.types = []

    def answer(self, pkt):
        self.types.append(pkt.type)
        if pkt.type == P.HELLO:
            return P.build_frame(P.HELLO_ACK, pkt.seq, HELLO)
        if pkt.type == P.SET_ANGLES:
            return P.build_frame(P.ACK, pkt.seq, bytes([pkt.type, P.ST_ARMED, 0, 0, pkt.payload[1]]))
        if pkt.type == P.SET_MODE:
            return P.build_frame(P.ACK, pkt.seq, bytes([pkt.type, P.ST_ARMED, 0, 0, 0, 0]))
        return P.build_frame(P.ACK, pkt.seq, bytes([pkt.type, P.ST_ARMED]))


device = device_fixture(Device)


def _interrupt(dev, started, *args, sig=signal.SIGINT):
    """Run ``stream FISH --port dev ARGS``, send ``sig`` once ``started(dev.types)`` holds; (rc, stdout, stderr)."""
    argv = [sys.executable, "-m", "metamaterial_wb", "stream", FISH, "--port", dev.port, "--seconds", SECONDS,
            *map(str, args)]
    # SIGINT as in a terminal: a job started in the background by a script (a CI lane) inherits it ignored
    p = subprocess.Popen(argv, cwd=REPO, stdout=subprocess.PIPE, stderr=subprocess.PIPE, encoding="utf-8",
                         env=dict(os.environ, PYTHONPATH=REPO, PYTHONUTF8="1"),
                         preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    try:
        first = p.stderr.readline()  # the handshake line: printed once the board is armed
        assert "servolink" in first, first + p.stderr.read()
        wait_until = time.monotonic() + 60  # a limit for a broken run, not a timing assertion
        while not started(list(dev.types)):
            assert p.poll() is None and time.monotonic() < wait_until, (dev.types, p.stderr.read())
            time.sleep(0.01)
        p.send_signal(sig)
        out, err = p.communicate(timeout=60)
    finally:
        if p.poll() is None:
            p.kill()
            p.wait()
    return p.returncode, out, first + err


def _frames(n):
    return lambda types: types.count(P.SET_ANGLES) >= n


def _pings_after_osc(types):
    return P.SET_MODE in types and types[types.index(P.SET_MODE):].count(P.PING) >= 2


def test_ctrl_c_streaming_exits_130_with_a_complete_report_marked_interrupted_and_disarms(device, tmp_path):
    dev = device()
    rep = tmp_path / "stats.json"
    rc, out, err = _interrupt(dev, _frames(5), "--disarm", "--report", rep)
    assert rc == 130, (out, err)
    assert "Traceback" not in err and err.rstrip().endswith("interrupted"), err
    assert out.startswith("interrupted (SIGINT): "), out
    s = json.loads(rep.read_text(encoding="utf-8"))
    assert s["interrupted"] == "SIGINT"
    sent = dev.types.count(P.SET_ANGLES)
    assert s["frames"] == s["ticks"] == len(s["frames_sent"]) == sent >= 5  # what really ran, every frame listed
    assert s["acked"] == sent and s["lost"] == 0
    assert 0 < s["duration_s"] < float(SECONDS)
    assert f"{s['ticks']} ticks in " in out
    # the servos end as at a normal end with --disarm: DISARM after the last frame, nothing streamed after it
    assert P.DISARM in dev.types
    assert dev.types.index(P.DISARM) > len(dev.types) - 1 - dev.types[::-1].index(P.SET_ANGLES)


def test_ctrl_c_without_disarm_sends_nothing_more_and_no_report_is_asked(device, tmp_path):
    dev = device()
    rc, out, err = _interrupt(dev, _frames(3))
    assert rc == 130, (out, err)
    assert out.startswith("interrupted (SIGINT): "), out
    assert P.DISARM not in dev.types  # as at a normal end without --disarm: the firmware's watchdog parks
    assert list(tmp_path.iterdir()) == []


def test_sigterm_streaming_exits_143_and_marks_the_report(device, tmp_path):
    dev = device()
    rep = tmp_path / "stats.json"
    rc, out, err = _interrupt(dev, _frames(3), "--report", rep, sig=signal.SIGTERM)
    assert rc == 128 + signal.SIGTERM, (out, err)
    s = json.loads(rep.read_text(encoding="utf-8"))
    assert s["interrupted"] == "SIGTERM" and s["frames"] == dev.types.count(P.SET_ANGLES)
    assert [p.name for p in tmp_path.iterdir()] == ["stats.json"]  # no temporary file left


def test_ctrl_c_in_osc_mode_says_how_long_it_ran_not_seconds(device, tmp_path):
    dev = device()
    rep = tmp_path / "osc.json"
    rc, out, err = _interrupt(dev, _pings_after_osc, "--mode", "osc", "--disarm", "--report", rep)
    assert rc == 130, (out, err)
    assert f"ran {SECONDS} s" not in out and "interrupted (SIGINT)" in out, out
    s = json.loads(rep.read_text(encoding="utf-8"))
    assert s["interrupted"] == "SIGINT" and s["seconds"] == float(SECONDS)
    assert 0 < s["duration_s"] < float(SECONDS)
    after = dev.types[dev.types.index(P.SET_MODE):]
    assert s["pings"] == after.count(P.PING) >= 2  # the keep-alive PINGs that really went out
    assert after[-1] == P.DISARM  # --disarm, as at a normal end


def test_a_full_run_is_not_marked_interrupted(tmp_path):
    from clihelpers import run_cli
    for mode in ("stream", "osc"):
        rep = tmp_path / f"{mode}.json"
        r = run_cli("stream", FISH, "--dry-run", "--mode", mode, "--seconds", "0.3", "--report", rep)
        assert r.returncode == 0, r.stderr
        s = json.loads(rep.read_text(encoding="utf-8"))
        assert s["interrupted"] is None and "interrupted" not in r.stdout
