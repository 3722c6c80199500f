"""The PCA9685 firmware with no chip on the I2C bus (harness without --pca9685): the failed writes are reported
(PING servo_fault / servo_faults, EVENT SERVO_FAULT), and ``stream`` fails with one line instead of reporting a
stream whose servos never moved."""
import os
import subprocess
import sys

import simrun

from metamaterial_wb.hardware import Link

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def test_missing_pca9685_is_reported(fw_build, tmp_path):
    paths = dict(fw_build, elf=fw_build["elf_pca9685"])  # the PCA9685 build on a bus with nothing on it
    with simrun.SimAVR(paths, log_dir=str(tmp_path)) as sim:
        r = subprocess.run([sys.executable, "-m", "metamaterial_wb", "stream", os.path.join(REPO, "examples", "fish.json"),
                            "--port", sim.port, "--seconds", "1"], capture_output=True, text=True, cwd=REPO, timeout=60)
        assert r.returncode == 2, r.stdout + r.stderr
        assert "Traceback" not in r.stderr and r.stderr.strip().count("\n") == 0, r.stderr
        assert "servo fault" in r.stderr and "PCA9685" in r.stderr, r.stderr
        with Link.open(sim.port) as link:
            link.handshake()
            st = link.ping()
            assert st["servo_fault"] and st["servo_faults"] >= 1, st


def test_present_pca9685_reports_no_fault(fw_build, tmp_path):
    with simrun.SimAVR(fw_build, log_dir=str(tmp_path), pca9685=True) as sim, Link.open(sim.port) as link:
        link.handshake()
        link.arm()
        st = link.ping()
        assert not st["servo_fault"] and st["servo_faults"] == 0, st


def test_the_device_says_protocol_1_1_which_has_the_servo_fault_bytes(link):
    """The PING reply's servo_fault bytes and EVENT SERVO_FAULT came with protocol 1.1 (PROTOCOL.md): the device
    and the host both say 1.1, and the 1.1 PING reply is 16 bytes."""
    from metamaterial_wb.hardware import protocol as P
    info = link.handshake()
    assert (info.proto_major, info.proto_minor) == (P.PROTO_MAJOR, P.PROTO_MINOR) == (1, 1)
    assert len(link.request(P.PING).data) == 16
    with open(os.path.join(REPO, "firmware", "PROTOCOL.md"), encoding="utf-8") as f:
        assert "Version 1.1." in f.read()
