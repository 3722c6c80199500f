"""``stream`` to a board that stops answering part-way (frozen, unplugged on its TX side, crashed without a
reset): the stream stops after a run of unanswered frames longer than the link's bound (Streamer.silence_limit_s:
the link watchdog plus a reply timeout, at least the 3 tries of 250 ms a request gets), the report is marked failed
with the error and the command exits 2, as ``--mode osc`` does when its PINGs go unanswered. A stream that ran to
its end but exits 1 (frames lost beyond ``--max-lost``) says why in its report too. Through the CLI's own code over
the dry run's loop://, whose echo stands for the board's answers: frames not written are never answered."""
import json
import os

import pytest

pytest.importorskip("serial")

from metamaterial_wb.hardware import link as link_mod  # noqa: E402
from metamaterial_wb.hardware import protocol as P  # noqa: E402
from metamaterial_wb.hardware.streamer import Streamer  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
FISH = os.path.join(ROOT, "examples", "fish.json")


def _silence(monkeypatch, first, last=None):
    """From the ``first``-th SET_ANGLES frame on (0-based; up to ``last``, exclusive, None: for good) nothing the
    host sends reaches the board: loop:// echoes nothing, so no frame and no keep-alive PING is answered."""
    orig = link_mod.Link.send
    seen = {"frames": 0, "dropped": 0}

    def send(self, ptype, payload=b"", seq=None):
        if ptype == P.SET_ANGLES:
            seen["frames"] += 1
        n = seen["frames"] - 1
        if n >= first and (last is None or n < last) and ptype in (P.SET_ANGLES, P.PING):
            seen["dropped"] += ptype == P.SET_ANGLES
            return self.next_seq() if seq is None else seq   # sent into the void
        return orig(self, ptype, payload, seq)
    monkeypatch.setattr(link_mod.Link, "send", send)
    return seen


def _main(*args):
    from metamaterial_wb.cli import main
    try:
        return main(["stream", FISH, "--dry-run", *map(str, args)])
    except SystemExit as exc:
        return exc.code


def _report(path):
    with open(path, encoding="utf-8") as f:
        return json.load(f)


def test_board_that_stops_answering_fails_the_stream(tmp_path, monkeypatch, capsys):
    rep = tmp_path / "stats.json"
    seen = _silence(monkeypatch, 20)
    rc = _main("--seconds", "20", "--report", rep)
    err = capsys.readouterr().err
    assert rc == 2, err
    assert "stopped answering" in err and "no reply to the last" in err, err
    s = _report(rep)
    assert s["failed"] is True and "stopped answering" in s["error"], s["error"]
    # the first 20 frames were answered, none after: the stream stopped long before its 20 s (1000 frames)
    assert s["acked"] == 20 and s["naked"] == 0
    assert s["lost"] == s["frames"] - 20 == seen["dropped"] > 0
    assert s["frames"] < 1000 and s["last_t"] < 20 - 1
    assert str(rep) in err and "marked failed" in err


def test_silence_limit_follows_the_link_watchdog():
    # the bound: the link watchdog + the reply timeout, never below the 3 tries of 250 ms a request gets
    assert Streamer.silence_limit_s(500, 0.1) == 0.75
    assert Streamer.silence_limit_s(2000, 0.1) == 2.1
    assert Streamer.silence_limit_s(50, 0.1) == 0.75


def test_a_short_gap_is_counted_not_fatal_and_exit_1_is_in_the_report(tmp_path, monkeypatch, capsys):
    rep = tmp_path / "stats.json"
    seen = _silence(monkeypatch, 10, 13)   # 3 frames (60 ms) unanswered, then the board answers again
    rc = _main("--seconds", "1", "--report", rep)
    err = capsys.readouterr().err
    assert rc == 1, err
    assert "error: 3 frames lost (--max-lost 0)" in err, err
    s = _report(rep)
    assert s["ticks"] + s["skipped"] == 50 and s["lost"] == 3   # the stream ran to its end (a busy host may skip)
    assert s["failed"] is True and "3 frames lost (--max-lost 0)" in s["error"], s
    # within --max-lost: exit 0 and a report not marked failed
    seen["frames"] = 0
    assert _main("--seconds", "1", "--max-lost", 3, "--report", rep) == 0
    s = _report(rep)
    assert s["lost"] == 3 and s["failed"] is False and s["error"] == ""
