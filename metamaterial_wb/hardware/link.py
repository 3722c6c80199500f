"""pyserial link to the servolink firmware: open, handshake, requests with retries, fire-and-forget frames.

    link = Link.open("/dev/ttyUSB0")        # or "loop://" with dry_run=True, or a simulator pty
    info = link.handshake()                  # HELLO until HELLO_ACK (expects the DTR reset of an Uno/Nano)
    link.configure(channels); link.arm()
    seq = link.send(protocol.SET_ANGLES, payload)   # latest wins: never retried
    reply = link.wait_reply(seq, 0.02)

``pyserial`` is imported lazily so that the workbench loads without it. Nothing here imports FreeCAD.
Dry run: over ``loop://`` every frame comes back unchanged; the link decodes its own frame and counts it
as acknowledged, so the whole path (encoding, framing, pacing) runs without hardware.
"""
from __future__ import annotations

import struct
import sys
import threading
import time

from metamaterial_wb.core.errors import MetamaterialError

from . import protocol as P


READ_TIMEOUT_S = 0.002  # the serial port's read timeout: the longest a poll blocks in one read


def pyserial_help():
    """How to install pyserial, which streaming needs (the Addon Manager cannot: it is not on its allow-list)."""
    v = "%d.%d" % sys.version_info[:2]
    return ("streaming to hardware needs pyserial, which is not installed for the Python FreeCAD runs on "
            f"(Python {v}). Debian / Ubuntu: sudo apt install python3-serial; elsewhere: pip install pyserial "
            "for that Python (FreeCAD's Addon Manager cannot install it: pyserial is not on its dependency "
            "allow-list). Then restart FreeCAD.")


def pyserial_available():
    try:
        import serial  # noqa: F401
        return True
    except ImportError:
        return False


class LinkError(MetamaterialError):
    """The device did not answer, refused a request, or speaks another protocol version."""


class Link:
    def __init__(self, ser, dry_run=False, name=""):
        self.ser = ser
        self.dry_run = dry_run
        self.name = name or getattr(ser, "port", "") or "serial"
        self.reader = P.FrameReader()
        self._seq = 0
        self._lock = threading.RLock()       # writers
        self._read_lock = threading.Lock()   # readers, and every read-modify of ``pending``
        self.pending = {}   # seq -> Reply received but not yet claimed (take it with take_reply / take_replies)
        self.events = []    # (time, Reply) for EVENT packets and unsolicited HELLO_ACKs
        self.on_event = None
        self.info = None
        self.watchdog_ms = None  # the link watchdog configured (CONFIG_LINK), else the device's (HELLO_ACK)
        self.resets_seen = 0
        self.rx_errors = 0
        self.unreadable_naks = 0   # NAKs with seq 0xFF: the device could not decode a frame (CRC, COBS, ...)
        self.unreadable_reasons = {}

    # -------------------------------------------------------------------------------------------
    @classmethod
    def open(cls, port, baud=115200, dry_run=False):
        """Open ``port`` (a device, an emulator pty or a pyserial URL). ``dry_run``: no hardware, over ``loop://``
        (``port`` empty, or a ``loop://`` URL); a dry run on any other port is refused (LinkError): the link would
        drive that board while answering for it itself."""
        if dry_run and port and not str(port).startswith("loop://"):
            raise LinkError(f"port {port}: a dry run streams over pyserial's loop:// and never drives a port; open "
                            f"{port} without dry run, or leave the port out (or give loop://) for a dry run")
        try:
            import serial
        except ImportError:
            raise LinkError(pyserial_help()) from None
        url = "loop://" if dry_run and not port else port
        try:
            ser = serial.serial_for_url(url, baudrate=baud, timeout=READ_TIMEOUT_S, write_timeout=1.0)
        except (serial.SerialException, ValueError) as exc:
            raise LinkError(f"port {url}: cannot open ({exc})") from None
        return cls(ser, dry_run=dry_run, name=url)

    def close(self):
        try:
            self.ser.close()
        except Exception:
            pass

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    # -------------------------------------------------------------------------------------------
    def next_seq(self):
        """1..254 (0 is the boot HELLO_ACK, 255 marks NAKs of undecodable frames)."""
        with self._lock:
            self._seq = self._seq + 1 if self._seq < 254 else 1
            return self._seq

    def write_raw(self, data: bytes):
        with self._lock:  # writers from several threads never interleave their frames
            self.ser.write(data)

    def send(self, ptype, payload=b"", seq=None):
        seq = self.next_seq() if seq is None else seq
        self.write_raw(P.build_frame(ptype, seq, payload))
        return seq

    def _handle(self, pkt, now):
        """File one packet (called by poll, under ``_read_lock``); returns the seq of the reply it stored in
        ``pending``, or None (an event, an unparsable reply)."""
        if self.dry_run and pkt.type < 0x7F:  # our own request, echoed by loop://
            data = b""
            if pkt.type in (P.SET_ANGLES, P.SET_PULSES) and len(pkt.payload) >= 2:
                data = b"\x00\x00" + bytes([pkt.payload[1]])
            if pkt.type == P.HELLO:
                self.pending[pkt.seq] = P.Reply("HELLO_ACK", pkt.seq, data=bytes(
                    [P.PROTO_MAJOR, P.PROTO_MINOR, 0, 0, 0, 8, 100, 0xF4, 0x01, 0x03, 0, 0, 0, 0, 0]))
                return pkt.seq
            self.pending[pkt.seq] = P.Reply("ACK", pkt.seq, request=pkt.type, state=P.ST_ARMED, data=data)
            return pkt.seq
        try:
            r = P.parse_reply(pkt)
        except P.ProtocolError:
            self.rx_errors += 1
            return None
        if r.kind == "EVENT" or (r.kind == "HELLO_ACK" and r.seq == 0):
            if r.kind == "HELLO_ACK":
                self.resets_seen += 1
            self.events.append((now, r))
            if self.on_event:
                self.on_event(r)
            return None
        r.time = now
        if r.kind == "NAK" and r.seq == P.SEQ_NONE:  # the answer to no request in particular: counted (streams)
            self.unreadable_naks += 1
            self.unreadable_reasons[r.reason] = self.unreadable_reasons.get(r.reason, 0) + 1
        self.pending[r.seq] = r
        return r.seq

    def poll(self, timeout=0.0):
        """Read what has arrived (waiting up to ``timeout`` s for the first byte); returns new replies' seqs.
        Waits in the serial port's own blocking read (select), so a reply is seen as soon as it arrives."""
        end = time.perf_counter() + timeout
        got = []
        while True:
            # one reader at a time (the streaming thread and e.g. a GUI ping); replies land in self.pending,
            # where every thread looks for its own seq (taking it under the same lock: take_reply)
            if self._read_lock.acquire(timeout=max(0.0, min(end - time.perf_counter(), 0.01))):
                try:
                    n = self.ser.in_waiting
                    if n:
                        data = self.ser.read(n)
                    elif timeout > 0:
                        data = self.ser.read(1)  # blocks for at most READ_TIMEOUT_S
                    else:
                        data = b""
                    if data:
                        now = time.perf_counter()
                        for pkt in self.reader.feed(data):
                            seq = self._handle(pkt, now)
                            if seq is not None:
                                got.append(seq)
                        self.rx_errors = len(self.reader.errors)
                finally:
                    self._read_lock.release()
                if got:
                    return got
            if time.perf_counter() >= end:
                return got

    def take_reply(self, seq):
        """The reply with this seq, removed from ``pending``; None if it has not arrived. Thread-safe: another
        thread's poll() may be filing replies meanwhile."""
        with self._read_lock:
            return self.pending.pop(seq, None)

    def take_replies(self, seqs):
        """``{seq: reply}`` of those of ``seqs`` that have arrived, removed from ``pending`` (thread-safe)."""
        with self._read_lock:
            return {s: self.pending.pop(s) for s in list(seqs) if s in self.pending}

    def clear_replies(self):
        """Drop every reply not claimed yet (thread-safe)."""
        with self._read_lock:
            self.pending.clear()

    def wait_reply(self, seq, timeout):
        """The reply (ACK / NAK / HELLO_ACK) with this seq, or None after ``timeout`` seconds."""
        end = time.perf_counter() + timeout
        while True:
            r = self.take_reply(seq)
            if r is not None:
                return r
            left = end - time.perf_counter()
            if left <= 0:
                return None
            self.poll(min(left, 0.005))

    def request(self, ptype, payload=b"", retries=3, timeout=0.25, expect_ack=True):
        """Send a stateful request and wait for its reply, retrying on silence (the requests are idempotent).
        Raises LinkError on a NAK (naming the reason) or when every try stays unanswered."""
        for _ in range(retries):
            seq = self.send(ptype, payload)
            r = self.wait_reply(seq, timeout)
            if r is None:
                continue
            if r.kind == "NAK" and expect_ack:
                raise LinkError(f"{self.name}: {P.TYPE_NAMES.get(ptype, hex(ptype))} refused: NAK {r.reason} "
                                f"(detail {r.detail})")
            return r
        raise LinkError(f"{self.name}: no reply to {P.TYPE_NAMES.get(ptype, hex(ptype))} after {retries} tries "
                        f"of {timeout * 1000:.0f} ms")

    # -------------------------------------------------------------------------------------------
    def handshake(self, total_s=4.0, interval_s=0.25, min_channels=1):
        """HELLO every ``interval_s`` until a HELLO_ACK answers (a board resets when the port opens, and its
        bootloader needs up to ~2 s). Checks the protocol major version and the channel count."""
        try:
            self.ser.reset_input_buffer()
        except Exception:
            pass
        t_start, resets_before = time.perf_counter(), self.resets_seen
        self.write_raw(b"\x00")  # end any partial frame in the device's receiver
        end = time.perf_counter() + total_s
        while time.perf_counter() < end:
            seq = self.send(P.HELLO, P.hello_payload())
            r = self.wait_reply(seq, interval_s)
            if r is None:
                continue
            if r.kind == "NAK":
                if r.code == P.E_VERSION:
                    raise LinkError(f"{self.name}: the firmware speaks servolink {r.detail}.x, this host "
                                    f"{P.PROTO_MAJOR}.{P.PROTO_MINOR}; update the firmware (firmware/README in docs/firmware.md)")
                continue
            try:
                info = P.parse_hello_ack(r.data)
            except P.ProtocolError as exc:
                raise LinkError(f"{self.name}: malformed answer to HELLO ({exc}): is the servolink firmware "
                                f"flashed, and the baud rate 115200?") from None
            if info.proto_major != P.PROTO_MAJOR:
                raise LinkError(f"{self.name}: protocol {info.proto_major}.{info.proto_minor}, expected "
                                f"{P.PROTO_MAJOR}.x")
            if info.n_channels < min_channels:
                raise LinkError(f"{self.name}: the firmware drives {info.n_channels} channels; the scene "
                                f"needs {min_channels}")
            self.info = info
            if self.watchdog_ms is None:
                self.watchdog_ms = info.watchdog_ms
            # a boot banner (HELLO_ACK seq 0) that arrived during the handshake is the reset we expected
            self.events = [(t, e) for t, e in self.events if not (e.kind == "HELLO_ACK" and t >= t_start)]
            self.resets_seen = resets_before
            # replies still queued answer frames from before the handshake (e.g. a NAK for HELLO bytes that
            # reached a booting board only in part): they would be taken for answers to later requests
            self.clear_replies()
            return info
        raise LinkError(f"{self.name}: no HELLO_ACK within {total_s:g} s (is the servolink firmware flashed, "
                        f"and the baud rate 115200?)")

    def configure(self, channels):
        for c in channels:
            self.request(P.CONFIG_CH, c.config_payload())

    def configure_watchdog(self, watchdog_ms=500, park_after_ms=500, release_after_ms=5000):
        self.request(P.CONFIG_LINK, P.config_link_payload(watchdog_ms, park_after_ms, release_after_ms))
        self.watchdog_ms = watchdog_ms

    def arm(self):
        return self.request(P.ARM)

    def disarm(self):
        return self.request(P.DISARM)

    def ping(self):
        r = self.request(P.PING)
        out = self._parse(P.parse_ping, r.data) if not self.dry_run else {}
        out["state"] = r.state
        return out

    def get_state(self):
        r = self.request(P.GET_STATE)
        out = self._parse(P.parse_state, r.data) if not self.dry_run else {"pulse_us": []}
        out["state"] = r.state
        return out

    def _parse(self, parse, data):
        """A reply's data decoded; a malformed one is a LinkError naming the port (never a struct.error)."""
        try:
            return parse(data)
        except (P.ProtocolError, struct.error, IndexError) as exc:
            raise LinkError(f"{self.name}: malformed reply: {exc}") from None
