"""Figures quoted in firmware/PROTOCOL.md and docs/firmware.md are computed, not remembered: the link load of
each direction from the frame sizes of hardware/protocol.py, and the example error from the actual command."""
import json
import os
import re
import subprocess
import sys

import pytest

from metamaterial_wb.hardware import protocol as P

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def words(path):
    return " ".join(open(os.path.join(REPO, path), encoding="utf-8").read().split())


def test_protocol_md_states_the_link_load_of_each_direction():
    """Before: "at 50 Hz the link is 10 % busy each way"; the ACK direction is 4.8 %."""
    frame = len(P.build_frame(P.SET_ANGLES, 1, P.set_angles_payload(0, [0] * 8)))
    ack = len(P.build_frame(P.ACK, 1, bytes([P.SET_ANGLES, P.ST_ARMED, 0, 0, 8])))
    assert (frame, ack) == (24, 11)
    pct = [n * 10 * 50 / 115200 * 100 for n in (frame, ack)]
    text = words("firmware/PROTOCOL.md")
    section1 = text[text.index("## 1. Physical layer"):text.index("## 2. Framing")]
    assert "each way" not in section1
    assert f"host → device {pct[0]:.1f} %" in section1 and f"device → host {pct[1]:.1f} %" in section1, section1
    assert f"{frame} bytes on the wire ({frame * 10 / 115.2:.1f} ms)" in section1
    assert f"ACK {ack} bytes ({ack * 10 / 115.2:.2f} ms)" in section1


def test_firmware_md_quotes_the_real_limit_error(tmp_path):
    """Before: the quoted error said "reaches 81.0 deg at t = 0.000 s"; the command says 60.1 deg at 0.383 s. The
    limits come from the --channels file, which the error names (it used to blame the scene file)."""
    chans = tmp_path / "lim.json"
    chans.write_text(json.dumps({"tail": {"limits_deg": [-60, 60]}}), encoding="utf-8")
    pytest.importorskip("serial")
    r = subprocess.run([sys.executable, "-m", "metamaterial_wb", "stream", os.path.join(REPO, "examples", "fish.json"),
                        "--dry-run", "--channels", "lim.json"], capture_output=True, text=True, cwd=tmp_path,
                       timeout=60, env=dict(os.environ, PYTHONPATH=REPO))
    assert r.returncode == 2 and r.stderr.startswith("error: --channels lim.json tail.limits_deg"), r.stderr
    assert re.search(r"60\.1 deg at t = 0\.383 s", r.stderr)
    assert " ".join(r.stderr.split()) in words("docs/firmware.md")
