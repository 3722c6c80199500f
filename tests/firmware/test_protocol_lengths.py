"""Exact payload lengths on the real firmware (simavr): a request with a payload it does not take is NAKed LEN
(detail = the expected length) and changes nothing; the firmware's flash / RAM figures quoted in the docs are the
ones avr-size measures for the build under test. (The LEN vectors themselves: firmware/test_vectors/protocol.json,
run by test_emulator.py and the C host tests.)"""
import os
import re

from metamaterial_wb.hardware import protocol as P

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def ask(link, ptype, payload):
    seq = link.send(ptype, payload)
    r = link.wait_reply(seq, 0.5)
    assert r is not None, (ptype, payload)
    return r


def test_junk_payloads_change_nothing(link):
    r = ask(link, P.ARM, b"\x01\x02\x03")
    assert (r.kind, r.reason, r.detail) == ("NAK", "LEN", 0)
    assert link.get_state()["state"] == P.ST_DISARMED  # not armed by a malformed ARM
    link.arm()
    r = ask(link, P.DISARM, b"\x05")
    assert (r.kind, r.reason, r.detail) == ("NAK", "LEN", 0)
    assert link.get_state()["state"] == P.ST_ARMED
    r = ask(link, P.PING, b"\xaa" * 10)
    assert (r.kind, r.reason, r.detail) == ("NAK", "LEN", 0)
    for payload, detail in ((b"\x01", 3), (b"", 3), (b"\x01\x00\x00\x00", 3)):
        r = ask(link, P.HELLO, payload)
        assert (r.kind, r.reason, r.detail) == ("NAK", "LEN", detail), payload
    r = ask(link, P.HELLO, b"\x02")  # another major: VERSION whatever the length
    assert (r.kind, r.reason, r.detail) == ("NAK", "VERSION", 1)
    for payload, detail in ((b"\x00\x00", 4), (b"\x00\xc8", 255), (b"\x00\x1d", 60)):
        r = ask(link, P.SET_ANGLES, payload)
        assert (r.kind, r.reason, r.detail) == ("NAK", "LEN", detail), payload
    assert link.ping()["state"] == P.ST_ARMED


def _measured(fw_build):
    m = re.search(r"servolink flash=(\d+)/\d+ ram=(\d+)/\d+", fw_build["size_line"])
    assert m, fw_build["size_line"]
    return int(m.group(1)), int(m.group(2))


def test_docs_quote_the_measured_flash_and_ram(fw_build):
    flash, ram = _measured(fw_build)
    bench = open(os.path.join(REPO, "docs", "benchmarks.md"), encoding="utf-8").read()
    m = re.search(r"Firmware: ([\d.]+) KB flash, (\d+) B RAM", bench)
    assert m and float(m.group(1)) == round(flash / 1000, 1) and int(m.group(2)) == ram, (m and m.group(0), flash, ram)
    fwmd = " ".join(open(os.path.join(REPO, "docs", "firmware.md"), encoding="utf-8").read().split())
    m = re.search(r"Today: about ([\d.]+) KB of flash and (\d+) bytes of RAM", fwmd)
    assert m and float(m.group(1)) == round(flash / 1000, 1) and int(m.group(2)) == ram, (m and m.group(0), flash, ram)
