"""servolink v1 codec (host side): COBS framing, CRC-16/MCRF4XX, packets and message payloads.

The normative description is ``firmware/PROTOCOL.md``; the byte-exact test vectors shared with the
firmware's C tests are in ``firmware/test_vectors/protocol.json``. Pure Python, no pyserial, no FreeCAD.
"""
from __future__ import annotations

import struct
from dataclasses import dataclass

from metamaterial_wb.core.errors import MetamaterialError

PROTO_MAJOR = 1
PROTO_MINOR = 1
MAX_PACKET = 64
MAX_PAYLOAD = MAX_PACKET - 4
MAX_ENCODED = MAX_PACKET + 2
SEQ_NONE = 0xFF

# message types
HELLO, PING, ARM, DISARM, GET_STATE = 0x01, 0x02, 0x03, 0x04, 0x05
SET_ANGLES, SET_PULSES = 0x10, 0x11
CONFIG_CH, CONFIG_LINK = 0x20, 0x21
OSC_SET, SET_MODE = 0x30, 0x31
GAIT_SET, GAIT_CONTACTS = 0x40, 0x41
NAK, ACK, HELLO_ACK, EVENT = 0x7F, 0x80, 0x81, 0x82

TYPE_NAMES = {HELLO: "HELLO", PING: "PING", ARM: "ARM", DISARM: "DISARM", GET_STATE: "GET_STATE",
              SET_ANGLES: "SET_ANGLES", SET_PULSES: "SET_PULSES", CONFIG_CH: "CONFIG_CH",
              CONFIG_LINK: "CONFIG_LINK", OSC_SET: "OSC_SET", SET_MODE: "SET_MODE", GAIT_SET: "GAIT_SET",
              GAIT_CONTACTS: "GAIT_CONTACTS", NAK: "NAK", ACK: "ACK", HELLO_ACK: "HELLO_ACK", EVENT: "EVENT"}

# NAK reasons
E_CRC, E_COBS, E_SHORT, E_TOO_LONG, E_TYPE, E_LEN, E_CHANNEL, E_NOT_ARMED, E_VERSION, E_RANGE, E_MODE = range(1, 12)
NAK_NAMES = {E_CRC: "CRC", E_COBS: "COBS", E_SHORT: "SHORT", E_TOO_LONG: "TOO_LONG", E_TYPE: "TYPE",
             E_LEN: "LEN", E_CHANNEL: "CHANNEL", E_NOT_ARMED: "NOT_ARMED", E_VERSION: "VERSION",
             E_RANGE: "RANGE", E_MODE: "MODE"}

# link states, modes, events
ST_DISARMED, ST_ARMED, ST_HOLD, ST_PARK, ST_RELEASED = range(5)
STATE_NAMES = {ST_DISARMED: "DISARMED", ST_ARMED: "ARMED", ST_HOLD: "HOLD", ST_PARK: "PARK",
               ST_RELEASED: "RELEASED"}
MODE_STREAM, MODE_OSC, MODE_GAIT = 0, 1, 2
EV_HOLD, EV_PARK, EV_RELEASE, EV_SERVO_FAULT = 0xE1, 0xE2, 0xE3, 0xE4
EVENT_NAMES = {EV_HOLD: "HOLD", EV_PARK: "PARK", EV_RELEASE: "RELEASE", EV_SERVO_FAULT: "SERVO_FAULT"}
SERVO_FAULT_HELP = ("the servo driver did not take the pulse widths (PCA9685 back end: no answer on I2C; check its "
                    "wiring to A4/A5, its power and its address 0x40): the servos are not where they were told")
CAP_OSC, CAP_GAIT, CAP_PCA9685, CAP_CONTACT_PINS = 0x01, 0x02, 0x04, 0x08
GAIT_CLOSED, GAIT_PINS = 0x01, 0x02


class ProtocolError(MetamaterialError):
    """A frame or payload that does not follow servolink v1 (a MetamaterialError: the CLI reports it in one line,
    exit 2)."""


# ------------------------------------------------------------------------------------------------
# CRC and COBS
# ------------------------------------------------------------------------------------------------
def crc16(data: bytes, crc: int = 0xFFFF) -> int:
    """CRC-16/MCRF4XX (init 0xFFFF, reflected poly 0x8408, no final xor); crc16(b"123456789") == 0x6F91."""
    for b in data:
        crc ^= b
        for _ in range(8):
            crc = (crc >> 1) ^ 0x8408 if crc & 1 else crc >> 1
    return crc


def cobs_encode(data: bytes) -> bytes:
    """Consistent Overhead Byte Stuffing (no delimiter appended)."""
    out = bytearray([0])
    code_pos, code = 0, 1
    for i, b in enumerate(data):
        if b == 0:
            out[code_pos] = code
            code_pos, code = len(out), 1
            out.append(0)
        else:
            out.append(b)
            code += 1
            if code == 0xFF and i + 1 < len(data):
                out[code_pos] = code
                code_pos, code = len(out), 1
                out.append(0)
    out[code_pos] = code
    return bytes(out)


def cobs_decode(data: bytes) -> bytes:
    out = bytearray()
    i, n = 0, len(data)
    while i < n:
        code = data[i]
        i += 1
        if code == 0:
            raise ProtocolError("COBS: zero byte inside a frame")
        if i + code - 1 > n:
            raise ProtocolError("COBS: block runs past the end of the frame")
        block = data[i:i + code - 1]
        if 0 in block:
            raise ProtocolError("COBS: zero byte inside a frame")
        out += block
        i += code - 1
        if code != 0xFF and i < n:
            out.append(0)
    return bytes(out)


# ------------------------------------------------------------------------------------------------
# packets
# ------------------------------------------------------------------------------------------------
@dataclass
class Packet:
    type: int
    seq: int
    payload: bytes = b""

    @property
    def name(self):
        return TYPE_NAMES.get(self.type, f"0x{self.type:02x}")


def build_frame(ptype: int, seq: int, payload: bytes = b"") -> bytes:
    """``COBS(type | seq | payload | crc16 LE) 0x00``."""
    if len(payload) > MAX_PAYLOAD:
        raise ProtocolError(f"payload of {len(payload)} bytes; at most {MAX_PAYLOAD}")
    raw = bytes([ptype & 0xFF, seq & 0xFF]) + bytes(payload)
    raw += struct.pack("<H", crc16(raw))
    return cobs_encode(raw) + b"\x00"


def parse_frame(encoded: bytes) -> Packet:
    """Decode one frame (without its delimiter). Raises ProtocolError naming the NAK reason."""
    if len(encoded) > MAX_ENCODED:
        raise ProtocolError("TOO_LONG")
    try:
        raw = cobs_decode(encoded)
    except ProtocolError:
        raise ProtocolError("COBS") from None
    if len(raw) < 4:
        raise ProtocolError("SHORT")
    if len(raw) > MAX_PACKET:
        raise ProtocolError("TOO_LONG")
    if struct.unpack("<H", raw[-2:])[0] != crc16(raw[:-2]):
        raise ProtocolError("CRC")
    return Packet(raw[0], raw[1], bytes(raw[2:-2]))


class FrameReader:
    """Accumulates bytes from a stream and returns the complete packets (keeps leftovers)."""

    def __init__(self):
        self.buf = bytearray()
        self.errors = []  # reasons of frames that did not decode
        self.overflow = False

    def feed(self, data: bytes):
        out = []
        for b in data:
            if b != 0:
                if len(self.buf) < 4 * MAX_ENCODED:
                    self.buf.append(b)
                else:
                    self.overflow = True
                continue
            frame, self.buf = bytes(self.buf), bytearray()
            if self.overflow:
                self.overflow = False
                self.errors.append("TOO_LONG")
                continue
            if not frame:
                continue
            try:
                out.append(parse_frame(frame))
            except ProtocolError as exc:
                self.errors.append(str(exc))
        return out


# ------------------------------------------------------------------------------------------------
# payload encoders (host -> MCU)
# ------------------------------------------------------------------------------------------------
def hello_payload(major=PROTO_MAJOR, minor=PROTO_MINOR, caps=0):
    return bytes([major, minor, caps])


def set_angles_payload(first_ch: int, cdeg):
    cdeg = [int(v) for v in cdeg]
    return struct.pack(f"<BB{len(cdeg)}h", first_ch, len(cdeg), *cdeg)


def set_pulses_payload(first_ch: int, us):
    us = [int(v) for v in us]
    return struct.pack(f"<BB{len(us)}H", first_ch, len(us), *us)


def config_ch_payload(ch, min_us, max_us, trim_cdeg, invert, lo_cdeg, hi_cdeg, park_cdeg, max_slew_dps):
    return struct.pack("<BHHhBhhhH", ch, min_us, max_us, trim_cdeg, 1 if invert else 0, lo_cdeg, hi_cdeg,
                       park_cdeg, max_slew_dps)


def config_link_payload(watchdog_ms, park_after_ms, release_after_ms):
    return struct.pack("<HHH", watchdog_ms, park_after_ms, release_after_ms)


GAIN_ONE = 16384  # Q14 joint gain of OSC_SET


def osc_set_payload(ch, amp_cdeg, offset_cdeg, period_ms, phase_cdeg, gain_pos=None, gain_neg=None):
    """9 bytes, or 13 with the joint gains (Q14): angle = v * (v >= 0 ? gain_pos : gain_neg) / 16384."""
    p = struct.pack("<BhhHH", ch, amp_cdeg, offset_cdeg, period_ms, phase_cdeg % 36000)
    if gain_pos is None and gain_neg is None:
        return p
    return p + struct.pack("<hh", gain_pos, gain_neg)


def gait_set_payload(n_cells, n1, n2, closed=True, pins=False, first_cell=0, inflate_cdeg=4500, vent_cdeg=0):
    flags = (GAIT_CLOSED if closed else 0) | (GAIT_PINS if pins else 0)
    return struct.pack("<BBBBBhh", n_cells, n1, n2, flags, first_cell, inflate_cdeg, vent_cdeg)


def pack_mask(bits) -> bytes:
    """[1, 0, 1, ...] -> bytes, bit i of byte i // 8 = entry i."""
    bits = list(bits)
    out = bytearray((len(bits) + 7) // 8)
    for i, b in enumerate(bits):
        if b:
            out[i >> 3] |= 1 << (i & 7)
    return bytes(out)


def unpack_mask(data: bytes, n: int):
    return [(data[i >> 3] >> (i & 7)) & 1 for i in range(n)]


# ------------------------------------------------------------------------------------------------
# reply decoders (MCU -> host)
# ------------------------------------------------------------------------------------------------
@dataclass
class HelloAck:
    proto_major: int
    proto_minor: int
    fw_version: tuple
    n_channels: int
    max_rate_hz: int
    watchdog_ms: int
    caps: int
    board_id: int
    build_hash: int


def parse_hello_ack(payload: bytes) -> HelloAck:
    if len(payload) < 15:
        raise ProtocolError(f"HELLO_ACK of {len(payload)} bytes; expected 15")
    (pmaj, pmin, fmaj, fmin, fpat, nch, rate, wd, caps, board, bh) = struct.unpack("<BBBBBBBHBBI", payload[:15])
    return HelloAck(pmaj, pmin, (fmaj, fmin, fpat), nch, rate, wd, caps, board, bh)


@dataclass
class Reply:
    """An ACK, NAK or EVENT, decoded."""
    kind: str          # "ACK", "NAK", "EVENT", "HELLO_ACK"
    seq: int
    request: int = 0   # ACK: the request type
    state: int = 0     # ACK/EVENT: link state after the request
    code: int = 0      # NAK: reason; EVENT: event code
    detail: int = 0    # NAK: detail
    data: bytes = b""  # ACK: type-specific bytes after request and state

    @property
    def reason(self):
        return NAK_NAMES.get(self.code, str(self.code)) if self.kind == "NAK" else None

    @property
    def time_ms(self):
        """EVENT: the firmware's clock (ms since boot) when it happened."""
        return struct.unpack("<I", self.data[:4])[0] if self.kind == "EVENT" and len(self.data) >= 4 else None

    @property
    def clamp_mask(self):
        return struct.unpack("<H", self.data[:2])[0] if len(self.data) >= 2 else 0


def parse_reply(pkt: Packet) -> Reply:
    p = pkt.payload
    if pkt.type == ACK:
        if len(p) < 2:
            raise ProtocolError("ACK shorter than 2 bytes")
        return Reply("ACK", pkt.seq, request=p[0], state=p[1], data=bytes(p[2:]))
    if pkt.type == NAK:
        if len(p) < 2:
            raise ProtocolError("NAK shorter than 2 bytes")
        return Reply("NAK", pkt.seq, code=p[0], detail=p[1])
    if pkt.type == EVENT:
        if len(p) < 2:
            raise ProtocolError("EVENT shorter than 2 bytes")
        return Reply("EVENT", pkt.seq, code=p[0], state=p[1], data=bytes(p[2:]))
    if pkt.type == HELLO_ACK:
        return Reply("HELLO_ACK", pkt.seq, data=bytes(p))
    raise ProtocolError(f"unexpected packet type 0x{pkt.type:02x} from the device")


def parse_ping(data: bytes) -> dict:
    if len(data) < 14:
        raise ProtocolError(f"PING reply with {len(data)} data bytes; expected 14 (uptime_ms u32, 4 counters u16, "
                            f"wdt_trips u8, mode u8)")
    up, rx_ok, crc_err, fr_err, gaps, trips, mode = struct.unpack("<IHHHHBB", data[:14])
    return {"uptime_ms": up, "rx_ok": rx_ok, "crc_err": crc_err, "framing_err": fr_err, "seq_gaps": gaps,
            "wdt_trips": trips, "mode": mode, "servo_fault": bool(data[14]) if len(data) > 14 else False,
            "servo_faults": data[15] if len(data) > 15 else 0}


def parse_state(data: bytes) -> dict:
    if len(data) < 2:
        raise ProtocolError(f"GET_STATE reply with {len(data)} data bytes; expected at least 2 (mode u8, n u8)")
    mode, n = data[0], data[1]
    if len(data) < 2 + 2 * n:
        raise ProtocolError(f"GET_STATE reply with {len(data)} data bytes for {n} channels; expected {2 + 2 * n}")
    us = list(struct.unpack(f"<{n}H", data[2:2 + 2 * n]))
    return {"mode": mode, "n_channels": n, "pulse_us": us}
