"""servolink v1 host codec against the vectors shared with the firmware's C tests
(firmware/test_vectors/protocol.json), plus the stream reader's resynchronisation."""
import json
import os
import random
import struct

import pytest

from metamaterial_wb.hardware import protocol as P

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
VEC = json.load(open(os.path.join(REPO, "firmware", "test_vectors", "protocol.json")))


def test_crc_check_values():
    for v in VEC["crc16"]:
        assert P.crc16(bytes.fromhex(v["data_hex"])) == v["crc"]


def test_crc_matches_bitwise_polynomial_division():
    """Independent reference: CRC-16/MCRF4XX as the reflected (LSB-first) long division by x^16+x^12+x^5+1."""
    def ref(data):
        reg = 0xFFFF
        for byte in data:
            for bit in range(8):
                inbit = (byte >> bit) & 1
                top = (reg & 1) ^ inbit
                reg >>= 1
                if top:
                    reg ^= 0x8408
        return reg
    rnd = random.Random(1)
    for n in range(0, 70, 7):
        data = bytes(rnd.randrange(256) for _ in range(n))
        assert P.crc16(data) == ref(data)


@pytest.mark.parametrize("v", VEC["cobs"], ids=lambda v: v["name"])
def test_cobs_vectors(v):
    data, enc = bytes.fromhex(v["data_hex"]), bytes.fromhex(v["enc_hex"])
    assert P.cobs_encode(data) == enc
    assert P.cobs_decode(enc) == data


def test_cobs_round_trip_random_and_no_zero_inside():
    rnd = random.Random(7)
    for n in list(range(0, 600, 37)) + [253, 254, 255, 508, 509]:
        data = bytes(rnd.choice([0, 0, 1, 255, rnd.randrange(256)]) for _ in range(n))
        enc = P.cobs_encode(data)
        assert 0 not in enc
        assert len(enc) <= n + n // 254 + 1
        assert P.cobs_decode(enc) == data


@pytest.mark.parametrize("v", VEC["cobs_invalid"], ids=lambda v: v["name"])
def test_cobs_invalid(v):
    with pytest.raises(P.ProtocolError):
        P.cobs_decode(bytes.fromhex(v["enc_hex"]))


@pytest.mark.parametrize("v", VEC["frames"], ids=lambda v: v["name"])
def test_golden_frames(v):
    frame = P.build_frame(v["type"], v["seq"], bytes.fromhex(v["payload_hex"]))
    assert frame.hex() == v["frame_hex"]
    pkt = P.parse_frame(frame[:-1])
    assert (pkt.type, pkt.seq, pkt.payload.hex()) == (v["type"], v["seq"], v["payload_hex"])


def test_malformed_exchanges_give_the_documented_reason():
    """The raw malformed frames of the shared exchange vectors are rejected by the host decoder with the
    same reason that the firmware NAKs them with (NAK code -> name)."""
    raw = [e for e in VEC["exchanges"] if "raw_hex" in e]
    assert len(raw) >= 4
    for e in raw:
        r = P.FrameReader()
        assert r.feed(bytes.fromhex(e["raw_hex"])) == []
        assert r.errors == [P.NAK_NAMES[e["reply"]["code"]]], e["name"]


def test_reader_keeps_leftovers_and_resyncs():
    a = P.build_frame(P.ACK, 5, b"\x10\x01\x00\x00\x02")
    b = P.build_frame(P.NAK, 6, b"\x08\x00")
    c = P.build_frame(P.EVENT, 0, b"\xe1\x02")
    # two pieces of junk, each ended by a delimiter, then three frames
    stream = b"\x03\x22\x33\x00" + b"\x11\x22\x00" + a + b + c
    rd = P.FrameReader()
    got = []
    for i in range(0, len(stream), 5):  # in awkward chunks
        got += rd.feed(stream[i:i + 5])
    assert [(p.type, p.seq) for p in got] == [(P.ACK, 5), (P.NAK, 6), (P.EVENT, 0)]
    assert rd.errors == ["SHORT", "COBS"]  # 2 decoded bytes < 4; a block code (0x11) running past the end
    # a flipped bit anywhere in a frame never yields a wrong packet
    for pos in range(len(a) - 1):
        for bit in range(8):
            bad = bytearray(a)
            bad[pos] ^= 1 << bit
            for p in P.FrameReader().feed(bytes(bad)):
                assert (p.type, p.seq, p.payload) == (P.ACK, 5, b"\x10\x01\x00\x00\x02")


def test_payload_layouts():
    """Byte layouts as written in PROTOCOL.md, unpacked independently with struct."""
    assert P.set_angles_payload(2, [9000, -9000]) == bytes([2, 2]) + struct.pack("<hh", 9000, -9000)
    cfg = P.config_ch_payload(3, 600, 2400, -150, True, -4500, 4000, 1000, 120)
    assert len(cfg) == 16
    assert struct.unpack("<BHHhBhhhH", cfg) == (3, 600, 2400, -150, 1, -4500, 4000, 1000, 120)
    assert P.config_link_payload(500, 500, 5000) == bytes.fromhex("f401f4018813")
    assert len(P.gait_set_payload(8, 1, 1)) == 9
    assert P.pack_mask([1, 0, 0, 1, 1, 1, 1, 1, 1]) == bytes([0xF9, 0x01])
    assert P.unpack_mask(bytes([0xF9, 0x01]), 9) == [1, 0, 0, 1, 1, 1, 1, 1, 1]
    with pytest.raises(P.ProtocolError):
        P.build_frame(P.SET_ANGLES, 1, bytes(61))
