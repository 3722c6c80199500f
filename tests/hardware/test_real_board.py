"""Hardware in the loop: the same protocol checks against a real board running the servolink firmware.

Skipped unless ``SERVOLINK_PORT`` names its serial port (e.g. ``SERVOLINK_PORT=/dev/ttyUSB0``); CI has no
board and runs the same checks against the firmware in simavr (tests/firmware/test_emulator.py), which can
also measure the pins. Disconnect the servos' power or expect them to move (small angles, then parked)."""
import json
import os
import time

import pytest

PORT = os.environ.get("SERVOLINK_PORT")
pytestmark = pytest.mark.skipif(not PORT, reason="no real board: set SERVOLINK_PORT=/dev/ttyUSB0 to run")

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


@pytest.fixture
def link():
    pytest.importorskip("serial")
    from metamaterial_wb.hardware import Link
    lk = Link.open(PORT)
    lk.handshake(total_s=6.0)  # opening the port resets an Uno / Nano: the bootloader runs first
    yield lk
    lk.disarm()
    lk.close()


def test_board_answers_every_exchange_vector(link):
    from metamaterial_wb.hardware import protocol as P
    vec = json.load(open(os.path.join(REPO, "firmware", "test_vectors", "protocol.json")))
    for e in vec["exchanges"]:
        (link.arm if e["armed"] else link.disarm)()
        link.write_raw(bytes.fromhex(e["raw_hex"]) if "raw_hex" in e else
                       P.build_frame(e["type"], e["seq"], bytes.fromhex(e["payload_hex"])))
        want = e["reply"]
        r = link.wait_reply(want["seq"], 0.5)
        assert r is not None, e["name"]
        # the reply's kind always, its code and detail where the vector gives them (an ACK has no code)
        assert r.kind == {P.NAK: "NAK", P.ACK: "ACK", P.HELLO_ACK: "HELLO_ACK"}[want["type"]], (e["name"], r)
        if "code" in want:
            assert r.code == want["code"], (e["name"], r.reason)
        if "detail" in want:
            assert r.detail == want["detail"], e["name"]


def test_board_acknowledges_250_frames_at_50_hz(link):
    from metamaterial_wb.hardware import Streamer
    from metamaterial_wb.hardware.mapping import ChannelConfig
    st = Streamer(link, [ChannelConfig(f"c{k}", k, limits_deg=(-10.0, 10.0)) for k in range(8)])
    st.prepare(handshake=False)
    stats = st.run(lambda t: {f"c{k}": 0.05 for k in range(8)}, 5.0)
    assert stats.frames == stats.acked == 250 and stats.lost == 0, stats.summary()


def test_board_watchdog_timeline(link):
    from metamaterial_wb.hardware import protocol as P
    link.configure_watchdog(200, 300, 800)
    link.arm()
    last = link.ping()["uptime_ms"]
    seen = {}
    end = time.perf_counter() + 5
    while time.perf_counter() < end and len(seen) < 3:
        link.poll(0.01)
        seen.update({P.EVENT_NAMES[e.code]: e.time_ms for _, e in link.events if e.kind == "EVENT"})
    assert 200 < seen["HOLD"] - last <= 215
    assert seen["PARK"] - seen["HOLD"] == 300 and seen["RELEASE"] - seen["PARK"] == 800
