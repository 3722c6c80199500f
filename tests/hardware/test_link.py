"""The pyserial link: dry run over loop://, and a scripted fake device on a real pseudo-terminal
(handshake after a boot banner, retries, NAK reasons, events arriving in the same read as a reply)."""
import os
import time

import pytest

serial = pytest.importorskip("serial")

from metamaterial_wb.hardware import protocol as P  # noqa: E402
from metamaterial_wb.hardware.link import Link, LinkError  # noqa: E402
from ptydevice import PtyDevice, device_fixture  # noqa: E402


class FakeDevice(PtyDevice):
    """Answers servolink requests on the master side of a pty. ``drop``: {type: how many to ignore};
    ``nak``: {type: (code, detail)}; ``event_before_ack``: send an EVENT in the same write as each ACK."""

    def __init__(self, drop=None, nak=None, event_before_ack=False, major=P.PROTO_MAJOR, n_channels=8,
                 after_angles=None, lose_angles=(), garble_angles=(), clamp_angles=()):
        super().__init__()
        self.drop = dict(drop or {})
        self.nak = nak or {}
        self.event_before_ack = event_before_ack
        self.major = major
        self.n_channels = n_channels
        self.after_angles = after_angles  # (n, bytes): written once after the n-th SET_ANGLES reply
        self.received = []
        self.lose_angles = set(lose_angles)      # SET_ANGLES frames (1-based) that never arrive
        self.garble_angles = set(garble_angles)  # SET_ANGLES frames that arrive damaged: NAK CRC with seq 0xFF
        self.clamp_angles = set(clamp_angles)    # SET_ANGLES frames ACKed with every channel's clamp bit set
        os.write(self.master, P.build_frame(P.HELLO_ACK, 0, self.hello()))  # boot banner, already waiting

    def hello(self):
        return bytes([self.major, 0, 1, 0, 0, self.n_channels, 100, 0xF4, 0x01, 3, 0x28, 0, 0, 0, 0])

    def answer(self, pkt):
        self.received.append(pkt)
        if self.drop.get(pkt.type, 0) > 0:
            self.drop[pkt.type] -= 1
            return None
        n_angles = sum(p.type == P.SET_ANGLES for p in self.received)
        if pkt.type == P.SET_ANGLES and n_angles in self.lose_angles:
            return None
        if pkt.type == P.SET_ANGLES and n_angles in self.garble_angles:
            return P.build_frame(P.NAK, P.SEQ_NONE, bytes([P.E_CRC, 0]))
        if pkt.type in self.nak:
            out = P.build_frame(P.NAK, pkt.seq, bytes(self.nak[pkt.type]))
        elif pkt.type == P.HELLO:
            out = P.build_frame(P.HELLO_ACK, pkt.seq, self.hello())
        elif pkt.type == P.SET_ANGLES and n_angles in self.clamp_angles:
            first, count = pkt.payload[0], pkt.payload[1]
            mask = ((1 << count) - 1) << first
            out = P.build_frame(P.ACK, pkt.seq, bytes([pkt.type, P.ST_ARMED, mask & 0xFF, mask >> 8, count]))
        else:
            out = P.build_frame(P.ACK, pkt.seq, bytes([pkt.type, P.ST_ARMED, 0, 0, 1]))
            if self.event_before_ack:
                out = P.build_frame(P.EVENT, 0, bytes([P.EV_HOLD, P.ST_HOLD])) + out
        if self.after_angles and pkt.type == P.SET_ANGLES and n_angles == self.after_angles[0]:
            out += self.after_angles[1]
        return out


device = device_fixture(FakeDevice)


def test_handshake_skips_boot_banner_and_retries(device):
    dev = device(drop={P.HELLO: 2})
    with Link.open(dev.port) as link:
        t0 = time.perf_counter()
        info = link.handshake(interval_s=0.1)
        assert info.n_channels == 8 and info.proto_major == 1
        assert time.perf_counter() - t0 >= 0.2  # two HELLOs went unanswered
        hellos = [p for p in dev.received if p.type == P.HELLO]
        assert len(hellos) == 3 and len({p.seq for p in hellos}) == 3


def test_handshake_refuses_other_major_and_too_few_channels(device):
    dev = device(major=2)
    with Link.open(dev.port) as link, pytest.raises(LinkError, match="protocol 2"):
        link.handshake(total_s=1.0)
    dev2 = device(n_channels=2)
    with Link.open(dev2.port) as link, pytest.raises(LinkError, match="drives 2 channels"):
        link.handshake(total_s=1.0, min_channels=4)


def test_request_retries_then_raises_on_silence_and_names_nak(device):
    dev = device(drop={P.CONFIG_LINK: 2}, nak={P.ARM: (P.E_RANGE, 3)})
    with Link.open(dev.port) as link:
        link.handshake()
        link.configure_watchdog(200, 100, 1000)  # answered on the third try
        assert sum(p.type == P.CONFIG_LINK for p in dev.received) == 3
        with pytest.raises(LinkError, match="NAK RANGE"):
            link.arm()
    dev2 = device(drop={P.PING: 99})
    with Link.open(dev2.port) as link:
        link.handshake()
        with pytest.raises(LinkError, match="no reply to PING after 2 tries"):
            link.request(P.PING, retries=2, timeout=0.05)


def test_event_in_same_read_as_reply_is_kept(device):
    dev = device(event_before_ack=True)
    with Link.open(dev.port) as link:
        link.handshake()
        seen = []
        link.on_event = seen.append
        for _ in range(5):
            seq = link.send(P.PING)
            r = link.wait_reply(seq, 0.5)
            assert r is not None and r.kind == "ACK" and r.seq == seq
        assert len(seen) == 5 and all(e.code == P.EV_HOLD for e in seen)
        assert link.resets_seen == 0  # the boot banner was discarded by the handshake's input flush


def test_unsolicited_hello_ack_counts_as_reset(device):
    dev = device()
    with Link.open(dev.port) as link:
        link.handshake()
        os.write(dev.master, P.build_frame(P.HELLO_ACK, 0, dev.hello()))
        link.poll(0.2)
        assert link.resets_seen == 1


def test_dry_run_over_loop_decodes_its_own_frames():
    with Link.open("loop://", dry_run=True) as link:
        info = link.handshake()
        assert info.n_channels == 8
        seq = link.send(P.SET_ANGLES, P.set_angles_payload(0, [100, -200, 300]))
        r = link.wait_reply(seq, 0.2)
        assert r.kind == "ACK" and r.request == P.SET_ANGLES and r.data[2] == 3
        # a corrupted frame written to the loop is not acknowledged
        bad = bytearray(P.build_frame(P.SET_ANGLES, 77, P.set_angles_payload(0, [1])))
        bad[1] ^= 0x40  # the type byte (byte 0 is a COBS code)
        link.write_raw(bytes(bad))
        assert link.wait_reply(77, 0.05) is None
        assert link.reader.errors == ["CRC"]


def test_open_bad_port_is_a_clean_error():
    with pytest.raises(LinkError, match="cannot open"):
        Link.open("/dev/does-not-exist-servolink")


def _streamer(link):
    from metamaterial_wb.hardware import Streamer
    from metamaterial_wb.hardware.mapping import ChannelConfig
    # catch_up: a loaded machine sends late frames late instead of skipping them, so the counts are exact
    return Streamer(link, [ChannelConfig("a", 0), ChannelConfig("b", 1)], catch_up=True)


def test_streamer_reconfigures_after_a_board_reset(device):
    dev = device()
    dev.after_angles = (10, P.build_frame(P.HELLO_ACK, 0, dev.hello()))  # the board reboots mid-stream
    with Link.open(dev.port) as link:
        st = _streamer(link)
        st.prepare()
        stats = st.run(lambda t: {"a": 0.1, "b": -0.1}, 0.5)
    assert stats.resets == 1 and stats.lost == 0 and stats.acked == stats.frames == 25
    types = [p.type for p in dev.received]
    assert types.count(P.CONFIG_CH) == 4 and types.count(P.CONFIG_LINK) == 2 and types.count(P.ARM) == 2
    # the second ARM comes after the 10th frame, before the 11th
    angles_before_rearm = types[:[i for i, t in enumerate(types) if t == P.ARM][1]].count(P.SET_ANGLES)
    assert angles_before_rearm == 10


def test_streamer_stops_with_a_message_when_the_watchdog_trips(device):
    dev = device()
    dev.after_angles = (5, P.build_frame(P.EVENT, 0, bytes([P.EV_HOLD, P.ST_HOLD, 0xE8, 0x03, 0, 0])))
    with Link.open(dev.port) as link:
        st = _streamer(link)
        st.prepare()
        with pytest.raises(LinkError, match=r"watchdog tripped \(HOLD at 1000 ms\)"):
            st.run(lambda t: {"a": 0.0, "b": 0.0}, 1.0)
        assert st.stats.frames < 10


def test_replies_queued_before_the_handshake_are_dropped():
    """A NAK for HELLO bytes that reached a booting board only in part (seq 255) must not be taken later
    as the answer to a malformed frame (seen under load in the emulator test)."""
    with Link.open("loop://", dry_run=True) as link:
        link.pending[255] = P.Reply("NAK", 255, code=P.E_CRC)
        link.handshake()
        assert 255 not in link.pending
        assert link.wait_reply(255, 0.05) is None


def test_lost_frames_are_counted_across_the_sequence_wrap(device):
    """Issue 19: 10 frames dropped early in a 400-frame stream (the seq wraps after 254) and 5 answered with NAKs for
    unreadable frames (seq 0xFF): lost = sent - acked - naked = 15, the 5 NAKs counted. Before the fix the report
    said "lost 0" (outstanding frames were forgotten when their seq was reused) and ignored the seq 0xFF NAKs."""
    dev = device(lose_angles=range(5, 15), garble_angles=(100, 200, 300, 301, 399))
    with Link.open(dev.port) as link:
        st = _streamer(link)
        st.rate_hz, st.reply_timeout_s = 100.0, 1.0
        st.prepare()
        stats = st.run(lambda t: {"a": 0.1, "b": -0.1}, 4.0)
    assert stats.frames == 400, stats.summary()
    assert stats.lost == 15 and stats.acked == 385 and stats.naked == 0, stats.summary()
    assert stats.nak_unreadable == 5 and stats.unreadable_reasons == {"CRC": 5}, stats.summary()


def test_cli_exits_1_when_frames_are_lost_beyond_max_lost(device, tmp_path):
    import json
    import subprocess
    import sys
    repo = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    fish = os.path.join(repo, "examples", "fish.json")
    for max_lost, rc in ((None, 1), (3, 0), (2, 1)):
        dev = device(lose_angles=(20, 40), garble_angles=(60,))
        rep = tmp_path / f"r{max_lost}.json"
        cmd = [sys.executable, "-m", "metamaterial_wb", "stream", fish, "--port", dev.port, "--seconds", "1.6",
               "--report", str(rep)] + ([] if max_lost is None else ["--max-lost", str(max_lost)])
        r = subprocess.run(cmd, capture_output=True, text=True, cwd=repo, timeout=60)
        assert r.returncode == rc, (max_lost, r.stdout, r.stderr)
        d = json.loads(rep.read_text())
        assert d["lost"] == 3 and d["nak_unreadable"] == 1 and d["frames"] == d["acked"] + 3, d
        if rc:
            assert "3 frames lost (--max-lost" in r.stderr


def test_missing_pyserial_says_how_to_install_it(monkeypatch):
    """pyserial is not on the Addon Manager's allow-list: the error tells the user how to get it (issue 13)."""
    import sys as _sys

    from metamaterial_wb.hardware import link as L
    monkeypatch.setitem(_sys.modules, "serial", None)      # import serial -> ImportError
    assert L.pyserial_available() is False
    with pytest.raises(L.LinkError) as exc:
        L.Link.open("/dev/ttyUSB0")
    msg = str(exc.value)
    assert "python3-serial" in msg and "pip install pyserial" in msg and "allow-list" in msg


def test_cli_exits_1_naming_the_firmware_clamps_of_a_checked_motion(device, tmp_path):
    """The host checks the whole motion against the channel limits and the servo range before streaming, so a
    clamp mask in an ACK means the board did not do what it was told: before, it was only a number at the end of
    the summary line, with exit status 0."""
    import json
    import subprocess
    import sys
    repo = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    fish = os.path.join(repo, "examples", "fish.json")
    dev = device(clamp_angles=(10, 11, 30))
    rep = tmp_path / "r.json"
    r = subprocess.run([sys.executable, "-m", "metamaterial_wb", "stream", fish, "--port", dev.port, "--seconds", "1",
                        "--report", str(rep)], capture_output=True, text=True, cwd=repo, timeout=60)
    assert r.returncode == 1, (r.stdout, r.stderr)
    assert "3 frames clamped (host 0; firmware 3: head 3, tail 3)" in r.stdout
    assert "error: the firmware clamped 3 frames (head 3, tail 3) that the host had checked" in r.stderr
    d = json.loads(rep.read_text())
    assert d["firmware_clamped_frames"] == 3 and d["host_clamped_frames"] == 0
    assert d["clamped_by_actuator"] == {"head": {"host": 0, "firmware": 3}, "tail": {"host": 0, "firmware": 3}}
