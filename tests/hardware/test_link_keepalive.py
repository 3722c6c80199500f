"""The link watchdog against slow frame rates and the keep-alive, and malformed device replies, with a scripted
fake device on a pseudo-terminal (no emulator needed).

* A slow --rate is legitimate: the streamer sends PINGs between frames so the device never goes longer than
  ``watchdog_ms / 3`` without hearing from the host (firmware/PROTOCOL.md section 6).
* A watchdog trip (EVENT) is noticed while waiting between frames / keep-alive PINGs, not only at the next
  frame or after the whole ``--seconds``.
* A device that answers with a malformed reply gives a one-line error (exit 2), never a traceback."""
import os
import subprocess
import sys
import time

import pytest

pytest.importorskip("serial")

from metamaterial_wb.core.errors import MetamaterialError  # noqa: E402
from metamaterial_wb.hardware import Link, Streamer  # noqa: E402
from metamaterial_wb.hardware import protocol as P  # noqa: E402
from metamaterial_wb.hardware.link import LinkError  # noqa: E402
from metamaterial_wb.hardware.mapping import ChannelConfig  # noqa: E402
from metamaterial_wb.hardware import onboard  # noqa: E402
from metamaterial_wb.hardware.onboard import OscParams, run_oscillators  # noqa: E402
from ptydevice import PtyDevice, device_fixture  # noqa: E402

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
FISH = os.path.join(REPO, "examples", "fish.json")
HELLO = bytes([1, 0, 1, 0, 0, 8, 100, 0xF4, 0x01, 3, 0x28, 0, 0, 0, 0])


class Device(PtyDevice):
    """Answers every request with an ACK (HELLO with a HELLO_ACK), recording (time, packet).
    ``replies``: {type: payload of the reply} overriding the default; ``event_after``: (type, n, delay_s) sends
    an EVENT HOLD ``delay_s`` after the n-th request of that type."""

    poll_s = 0.005

    def __init__(self, replies=None, event_after=None):
        super().__init__()
        self.replies = replies or {}
        self.event_after = event_after
        self.received = []
        self._event_at = None

    def tick(self):
        if self._event_at is not None and time.perf_counter() >= self._event_at:
            self._event_at = None
            os.write(self.master, P.build_frame(P.EVENT, 0, bytes([P.EV_HOLD, P.ST_HOLD, 0, 0, 0, 0])))

    def answer(self, pkt):
        self.received.append((time.perf_counter(), pkt))
        if pkt.type in self.replies:
            kind, payload = self.replies[pkt.type]
            out = P.build_frame(kind, pkt.seq, payload)
        elif pkt.type == P.HELLO:
            out = P.build_frame(P.HELLO_ACK, pkt.seq, HELLO)
        elif pkt.type == P.SET_ANGLES:
            out = P.build_frame(P.ACK, pkt.seq, bytes([pkt.type, P.ST_ARMED, 0, 0, pkt.payload[1]]))
        else:
            out = P.build_frame(P.ACK, pkt.seq, bytes([pkt.type, P.ST_ARMED]))
        if self.event_after and pkt.type == self.event_after[0]:
            if sum(p.type == pkt.type for _, p in self.received) == self.event_after[1]:
                self._event_at = time.perf_counter() + self.event_after[2]
        return out


device = device_fixture(Device)


def _gaps(dev, after_type=P.ARM):
    """Largest silence (s) between two frames the device received after the first ``after_type``."""
    t = [t for t, p in dev.received]
    k = next(i for i, (_, p) in enumerate(dev.received) if p.type == after_type)
    return max(b - a for a, b in zip(t[k:], t[k + 1:]))


def _watch_polls(link):
    """Record every ``link.poll``: (timeout asked, whether an EVENT had already been filed in ``link.events``)."""
    polls, poll, n0 = [], link.poll, len(link.events)

    def watched(timeout=0.0):
        polls.append((timeout, any(e.kind == "EVENT" for _, e in link.events[n0:])))
        return poll(timeout)
    link.poll = watched
    return polls


def _stopped_at_once(polls):
    """The trip was noticed when the EVENT arrived, checked independently of the machine's speed: every wait for
    the device was a short poll (at most a quarter of the 0.2 s until the EVENT: a wait for the next frame or
    keep-alive in one blocking read, which an EVENT does not end, is refused) and at most a few polls followed the
    one that filed the EVENT (the trip is checked after every read, not at the next frame / keep-alive / end)."""
    assert polls, "no wait for the device was seen"
    assert max(t for t, _ in polls) <= 0.05, f"a blocking wait: timeouts up to {max(t for t, _ in polls):.3f} s"
    after = [t for t, seen in polls if seen]
    # a reply already awaited when the EVENT lands (a frame's ACK on a loaded machine) is still read: a few short
    # polls; checking the trip only at the next frame / keep-alive / end shows as 100+ (133 and 167 measured)
    assert len(after) <= 5, f"{len(after)} more waits for the device after the EVENT arrived"


def test_keepalive_interval_follows_the_watchdog():
    assert onboard.keepalive_interval(500) == pytest.approx(0.1)
    assert onboard.keepalive_interval(150) == pytest.approx(0.05)
    assert onboard.keepalive_interval(50) == pytest.approx(0.05 / 3)
    assert onboard.keepalive_interval(None) == pytest.approx(0.1)


@pytest.mark.parametrize("rate,watchdog_ms", [(1.0, 500), (2.0, 300)])
def test_slow_stream_pings_between_frames(device, rate, watchdog_ms):
    dev = device()
    with Link.open(dev.port) as link:
        st = Streamer(link, [ChannelConfig("a", 0)], rate_hz=rate)
        st.prepare(watchdog_ms=watchdog_ms)
        stats = st.run(lambda t: {"a": 0.1}, 2.0)
    assert stats.error == "" and stats.frames == int(2.0 * rate) and stats.lost == 0
    pings = [p for _, p in dev.received if p.type == P.PING]
    assert len(pings) >= 2.0 * 1000 / watchdog_ms * 2  # several per watchdog period
    # the device never waited longer than watchdog_ms / 3 (plus scheduling slack) for a frame
    assert _gaps(dev) < watchdog_ms / 3000 + 0.03, _gaps(dev)


def test_fast_stream_sends_no_pings(device):
    dev = device()
    with Link.open(dev.port) as link:
        st = Streamer(link, [ChannelConfig("a", 0)], rate_hz=50, catch_up=True)   # a loaded machine: late, not
        st.prepare(watchdog_ms=500)                                                # skipped
        stats = st.run(lambda t: {"a": 0.1}, 0.5)
    assert stats.frames == 25 and stats.lost == 0
    k = next(i for i, (_, p) in enumerate(dev.received) if p.type == P.SET_ANGLES)
    # (prepare's PING checks the servo driver) none on a quiet machine; a loaded one may stall a frame past the
    # 100 ms keep-alive once or twice
    assert len([p for _, p in dev.received[k:] if p.type == P.PING]) <= 2


def test_stream_stops_at_once_on_a_trip_between_slow_frames(device):
    """An EVENT arriving 0.2 s after the first frame at 1 Hz stops the stream then, not at the next frame."""
    dev = device(event_after=(P.SET_ANGLES, 1, 0.2))
    with Link.open(dev.port) as link:
        st = Streamer(link, [ChannelConfig("a", 0)], rate_hz=1.0)
        st.prepare(watchdog_ms=500)
        polls = _watch_polls(link)
        with pytest.raises(LinkError, match="watchdog tripped"):
            st.run(lambda t: {"a": 0.1}, 5.0)
    _stopped_at_once(polls)


@pytest.mark.parametrize("watchdog_ms", [50, 100])
def test_oscillators_ping_faster_than_a_third_of_the_watchdog(device, watchdog_ms):
    dev = device(replies={P.SET_MODE: (P.ACK, bytes([P.SET_MODE, P.ST_ARMED, 0, 0, 0, 0]))})
    with Link.open(dev.port) as link:
        link.handshake()
        link.configure_watchdog(watchdog_ms, 500, 5000)
        link.arm()
        res = run_oscillators(link, [OscParams("a", 0, 1000, 0, 1000, 0)], 1.0)
    assert res["pings"] >= 1.0 / (watchdog_ms / 3000) * 0.7
    # a PING every watchdog_ms / 3 (the median: a loaded machine may stall one now and then, which no keep-alive
    # can prevent, so the longest silence is not asserted)
    t = [t for t, p in dev.received if p.type == P.PING]
    gaps = sorted(b - a for a, b in zip(t, t[1:]))
    assert gaps[len(gaps) // 2] < watchdog_ms / 3000 + 0.005, gaps


def test_oscillators_stop_at_once_on_a_trip(device):
    """A trip during on-board motion ends run_oscillators when the EVENT arrives, not after ``seconds``."""
    dev = device(event_after=(P.SET_MODE, 1, 0.2))
    with Link.open(dev.port) as link:
        link.handshake()
        polls = _watch_polls(link)
        with pytest.raises(LinkError, match="watchdog tripped"):
            run_oscillators(link, [OscParams("a", 0, 1000, 0, 1000, 0)], 5.0, keepalive_s=2.0)
    _stopped_at_once(polls)


# ------------------------------------------------------------------------------------------------
# malformed replies: one-line errors (MetamaterialError -> exit 2), never a traceback
# ------------------------------------------------------------------------------------------------
def test_protocol_errors_are_metamaterial_errors():
    assert issubclass(P.ProtocolError, MetamaterialError)
    with pytest.raises(P.ProtocolError, match="HELLO_ACK of 4 bytes"):
        P.parse_hello_ack(b"\x01\x00\x01\x00")
    with pytest.raises(P.ProtocolError, match="PING"):
        P.parse_ping(b"\x01\x02\x03")
    with pytest.raises(P.ProtocolError, match="GET_STATE"):
        P.parse_state(b"\x00")
    with pytest.raises(P.ProtocolError, match="GET_STATE"):
        P.parse_state(b"\x00\x08\xdc\x05")  # 8 channels announced, 1 width sent
    assert P.parse_state(b"\x00\x02\xdc\x05\x00\x00")["pulse_us"] == [1500, 0]


def test_short_hello_ack_is_a_link_error(device):
    dev = device(replies={P.HELLO: (P.HELLO_ACK, b"\x01\x00\x01\x00")})
    with Link.open(dev.port) as link, pytest.raises(LinkError, match="HELLO_ACK of 4 bytes"):
        link.handshake(total_s=1.0)


def test_short_ping_and_state_replies_are_link_errors(device):
    dev = device(replies={P.PING: (P.ACK, bytes([P.PING, 0, 1, 2])), P.GET_STATE: (P.ACK, bytes([P.GET_STATE, 0, 0]))})
    with Link.open(dev.port) as link:
        link.handshake()
        with pytest.raises(MetamaterialError, match="PING"):
            link.ping()
        with pytest.raises(MetamaterialError, match="GET_STATE"):
            link.get_state()


def test_cli_malformed_hello_ack_exits_2_with_one_line(device):
    dev = device(replies={P.HELLO: (P.HELLO_ACK, b"\x01\x00\x01\x00")})
    r = subprocess.run([sys.executable, "-m", "metamaterial_wb", "stream", FISH, "--port", dev.port, "--seconds", "1"],
                       capture_output=True, text=True, cwd=REPO, timeout=60)
    assert r.returncode == 2, r.stderr
    assert "Traceback" not in r.stderr and r.stderr.strip().count("\n") == 0, r.stderr
    assert r.stderr.startswith("error: ") and "HELLO_ACK of 4 bytes" in r.stderr and dev.port in r.stderr
