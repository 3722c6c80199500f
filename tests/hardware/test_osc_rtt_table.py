"""``stream --mode osc`` keeps its keep-alive round trips as the streamed mode does: a bounded count table
(streamer.StreamStats.rtt_counts, keyed by rtt_key), not a list growing by a float per PING (a day's run: ~1 M
floats), and reports median / p99 / max computed the same way. A fake link answers the PINGs; a fake clock gives
each PING a round trip of its own (nanosecond detail, so a list would hold every one apart)."""
import json
import os
import statistics

from metamaterial_wb.hardware import onboard
from metamaterial_wb.hardware import protocol as P
from metamaterial_wb.hardware.onboard import OscParams, run_oscillators
from metamaterial_wb.hardware.streamer import StreamStats

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


class _Clock:
    def __init__(self):
        self.now = 1000.0

    def perf_counter(self):
        return self.now

    @staticmethod
    def sleep(s):
        pass


class _Reply:
    def __init__(self, data=b""):
        self.data = data
        self.kind = "ACK"


class FakeLink:
    """Answers every request; a PING takes 1..3 ms on the fake clock, a different value each time."""

    name = "fake"
    dry_run = False
    watchdog_ms = 500

    def __init__(self, clock):
        self.clock = clock
        self.events = []
        self.rtts = []

    def request(self, ptype, payload=b""):
        if ptype == P.PING:
            ms = 1.0 + (len(self.rtts) * 7919 % 2_000_003) / 1_000_001.5  # in [1, 3) ms, all distinct
            self.rtts.append(ms)
            self.clock.now += ms / 1000.0
        return _Reply(bytes([0x10, 0x27, 0, 0]) if ptype == P.SET_MODE else b"")

    def poll(self, timeout=0.0):
        self.clock.now += timeout


def _run(monkeypatch, pings):
    clock = _Clock()
    monkeypatch.setattr(onboard, "time", clock)
    link = FakeLink(clock)
    res = run_oscillators(link, [OscParams("a", 0, 1000, 0, 1000, 0)], 1e9, keepalive_s=0.0,
                          stop=lambda: len(link.rtts) >= pings)
    return link, res


def test_osc_keeps_a_bounded_round_trip_table_not_a_list(monkeypatch):
    sizes = {}
    for pings in (5_000, 40_000):
        link, res = _run(monkeypatch, pings)
        assert res["pings"] == pings == len(link.rtts)
        table = res["rtt_counts"]
        assert sum(table.values()) == pings  # every round trip counted ...
        assert not any(isinstance(v, list) for v in res.values())  # ... and none kept one by one
        sizes[pings] = len(table)
        # median / p99 / max as the streamed mode computes them, from the table; the list's within the key rounding
        want = StreamStats(rtt_counts=dict(table)).summary()
        for k in ("rtt_ms_median", "rtt_ms_p99", "rtt_ms_max"):
            assert res[k] == want[k], k
        r = sorted(link.rtts)
        assert abs(res["rtt_ms_median"] - statistics.median(r)) <= 0.0011
        assert abs(res["rtt_ms_p99"] - r[min(len(r) - 1, int(0.99 * len(r)))]) <= 0.0011
        assert abs(res["rtt_ms_max"] - r[-1]) <= 0.0011
    # 1..3 ms to the microsecond: at most 2001 entries however many PINGs (8x the PINGs, not 8x the table)
    assert sizes[40_000] <= 2001 and sizes[40_000] < 40_000 / 10, sizes


def test_osc_report_states_median_p99_max(tmp_path):
    from clihelpers import run_cli
    rep = tmp_path / "osc.json"
    r = run_cli("stream", os.path.join(REPO, "examples", "fish.json"), "--dry-run", "--mode", "osc",
                "--seconds", "0.3", "--report", rep)
    assert r.returncode == 0, r.stderr
    s = json.loads(rep.read_text(encoding="utf-8"))
    assert s["pings"] >= 1
    assert s["ping_rtt_ms_max"] >= s["ping_rtt_ms_p99"] >= s["ping_rtt_ms_median"] >= 0
    assert not any(isinstance(v, list) and k.startswith(("rtt", "ping")) for k, v in s.items())
    assert "round trip median" in r.stdout and " p99 " in r.stdout and " max " in r.stdout
