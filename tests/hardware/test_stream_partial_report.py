"""``stream --report FILE`` that fails part-way (the link lost, a timeout, a watchdog trip, a second Ctrl+C) still
leaves a report: marked ``"failed": true`` with the error, and the frames sent up to the failure (``frames``,
``last_t``, ``duration_s``, ``frames_sent``); the command still fails (exit 2 / 130). A failure before anything was
sent (no frame, the oscillators not started) writes no report and leaves no folder the report would have needed.
Through the CLI's own code (``metamaterial_wb.cli.main``) over the dry run's loop://, the link made to fail after N
frames / PINGs."""
import json
import math
import os

import pytest

from metamaterial_wb.hardware import link as link_mod
from metamaterial_wb.hardware import protocol as P

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
FISH = os.path.join(ROOT, "examples", "fish.json")


def _fail_after(monkeypatch, ptype, n, exc, method="send", after=None):
    """Make Link.<method> raise ``exc`` at the (n + 1)-th ``ptype`` packet (counted from the first ``after``)."""
    orig = getattr(link_mod.Link, method)
    seen = {"n": 0, "armed": after is None}

    def wrapped(self, t, *args, **kwargs):
        if t == after:
            seen["armed"] = True
        if t == ptype and seen["armed"]:
            if seen["n"] >= n:
                raise exc
            seen["n"] += 1
        return orig(self, t, *args, **kwargs)
    monkeypatch.setattr(link_mod.Link, method, wrapped)
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


def _check_frames(s, n):
    assert s["frames"] == n
    assert len(s["frames_sent"]) == math.ceil(n / s["frames_per_tick"])  # every frame sent, a partial tick too
    assert s["last_t"] == s["frames_sent"][-1]["t"] > 0
    assert s["duration_s"] > 0


def test_link_error_after_frames_leaves_a_report_marked_failed(tmp_path, monkeypatch, capsys):
    rep = tmp_path / "out" / "stats.json"
    _fail_after(monkeypatch, P.SET_ANGLES, 7, link_mod.LinkError("loop://: board went away"))
    rc = _main("--seconds", "30", "--report", rep)
    err = capsys.readouterr().err
    assert rc == 2 and "board went away" in err, err
    s = _report(rep)
    assert s["format"] == "metamaterial-stream-report" and s["failed"] is True
    assert "board went away" in s["error"]
    _check_frames(s, 7)
    assert s["interrupted"] is None
    assert str(rep) in err and "failed" in err  # the user is told the report is there, and what it says
    assert os.listdir(rep.parent) == ["stats.json"]  # no temporary left


def test_second_ctrl_c_leaves_a_report_marked_failed(tmp_path, monkeypatch, capsys):
    rep = tmp_path / "stats.json"
    _fail_after(monkeypatch, P.SET_ANGLES, 5, KeyboardInterrupt())
    rc = _main("--seconds", "30", "--report", rep)
    assert rc == 130
    s = _report(rep)
    assert s["failed"] is True and "KeyboardInterrupt" in s["error"]
    _check_frames(s, 5)
    assert os.listdir(tmp_path) == ["stats.json"]


def test_a_full_run_is_not_marked_failed(tmp_path):
    rep = tmp_path / "stats.json"
    assert _main("--seconds", "0.1", "--report", rep) == 0
    s = _report(rep)
    assert s["failed"] is False and s["error"] == ""


def test_failure_before_the_first_frame_writes_nothing(tmp_path, monkeypatch, capsys):
    rep = tmp_path / "new" / "a" / "stats.json"
    _fail_after(monkeypatch, P.SET_ANGLES, 0, link_mod.LinkError("loop://: board went away"))
    assert _main("--seconds", "30", "--report", rep) == 2
    assert "board went away" in capsys.readouterr().err
    assert os.listdir(tmp_path) == []  # no report, no temporary, no folder made for it


def test_failure_before_the_first_frame_keeps_an_earlier_report(tmp_path, monkeypatch, capsys):
    rep = tmp_path / "stats.json"
    rep.write_text('{"old": 1}', encoding="utf-8")
    _fail_after(monkeypatch, P.ARM, 0, link_mod.LinkError("loop://: ARM refused"), method="request")
    assert _main("--seconds", "30", "--report", rep) == 2
    assert rep.read_text(encoding="utf-8") == '{"old": 1}' and os.listdir(tmp_path) == ["stats.json"]


def test_osc_failing_after_pings_leaves_a_report_marked_failed(tmp_path, monkeypatch, capsys):
    rep = tmp_path / "osc.json"
    _fail_after(monkeypatch, P.PING, 3, link_mod.LinkError("loop://: no reply to PING after 3 tries of 250 ms"),
                method="request", after=P.SET_MODE)
    rc = _main("--mode", "osc", "--seconds", "600", "--report", rep)
    err = capsys.readouterr().err
    assert rc == 2 and "no reply to PING" in err, err
    s = _report(rep)
    assert s["mode"] == "osc" and s["failed"] is True and "no reply to PING" in s["error"]
    assert s["pings"] == 3 and 0 < s["duration_s"] < 600
    assert s["ping_rtt_ms_median"] is not None
    assert os.listdir(tmp_path) == ["osc.json"]


@pytest.mark.parametrize("ptype", [P.OSC_SET, P.SET_MODE])
def test_osc_failing_before_the_oscillators_start_writes_nothing(tmp_path, monkeypatch, capsys, ptype):
    rep = tmp_path / "new" / "osc.json"
    _fail_after(monkeypatch, ptype, 0, link_mod.LinkError("loop://: refused"), method="request")
    assert _main("--mode", "osc", "--seconds", "600", "--report", rep) == 2
    assert os.listdir(tmp_path) == []
