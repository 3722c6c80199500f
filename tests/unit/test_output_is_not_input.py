"""An output path that is one of the command's inputs is refused before any work (it was overwritten: the scene
replaced by a PNG, a result or a stream report, exit 0). The same file through a symbolic link counts too."""
import os
import shutil
import subprocess
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
FISH = os.path.join(ROOT, "examples", "fish.json")


def cli(*args):
    return subprocess.run([sys.executable, "-m", "metamaterial_wb", *args], capture_output=True, text=True, cwd=ROOT,
                          timeout=300, env=dict(os.environ, PYTHONPATH=ROOT))


@pytest.mark.parametrize("args, option", [
    (("render", "{scene}", "--out", "{scene}"), "--out"),
    (("solve", "{scene}", "--out", "{link}"), "--out"),
    (("stream", "{scene}", "--dry-run", "--seconds", "0.1", "--report", "{scene}"), "--report"),
    (("design", "{scene}", "--out", "{tmp}/d.json", "--report", "{scene}"), "--report"),
], ids=["render", "solve-through-a-link", "stream-report", "design-report"])
def test_output_equal_to_the_input_is_refused(tmp_path, args, option):
    scene = tmp_path / "fish.json"
    shutil.copy(FISH, scene)
    link = tmp_path / "link.json"
    os.symlink(scene, link)
    before = scene.read_bytes()
    r = cli(*[a.format(scene=scene, link=link, tmp=tmp_path) for a in args])
    assert r.returncode == 2, (r.stdout, r.stderr)
    assert f"{option}: " in r.stderr and "is the scene this command reads" in r.stderr
    assert "it would be overwritten" in r.stderr
    assert r.stderr.strip().count("\n") == 0
    assert scene.read_bytes() == before
    assert not (tmp_path / "d.json").exists()


def test_stream_channels_file_is_an_input_too(tmp_path):
    ch = tmp_path / "c.json"
    ch.write_text("{}")
    r = cli("stream", FISH, "--dry-run", "--seconds", "0.1", "--channels", str(ch), "--report", str(ch))
    assert r.returncode == 2 and "--report: " in r.stderr and "is the --channels file" in r.stderr
    assert ch.read_text() == "{}"


@pytest.mark.parametrize("baud", ["7", "0", "-115200", "5000000"])
def test_stream_baud_is_checked(baud):
    r = cli("stream", FISH, "--dry-run", "--seconds", "0.1", "--baud", baud)
    assert r.returncode == 2 and r.stderr.startswith("error: --baud: ") and "1200..4000000" in r.stderr, r.stderr


def test_stream_baud_too_slow_for_the_rate():
    r = cli("stream", FISH, "--dry-run", "--seconds", "0.1", "--baud", "2400", "--rate", "50")
    assert r.returncode == 2 and "--baud: " in r.stderr and "--rate 50" in r.stderr, r.stderr
    r = cli("stream", FISH, "--dry-run", "--seconds", "0.1", "--baud", "57600")
    assert r.returncode == 0, r.stderr


def test_wire_bytes_match_the_measured_frame_and_ack():
    """8 channels in one run: a 24-byte SET_ANGLES frame and an 11-byte ACK (docs/benchmarks.md, the emulator's
    wire floor); two runs cost two frames and two ACKs."""
    from metamaterial_wb.hardware.mapping import ChannelConfig
    from metamaterial_wb.hardware.streamer import wire_bytes_per_tick
    eight = [ChannelConfig(name=f"m{i}", channel=i) for i in range(8)]
    assert wire_bytes_per_tick(eight) == 24 + 11
    two_runs = [ChannelConfig(name="a", channel=0), ChannelConfig(name="b", channel=5)]
    assert wire_bytes_per_tick(two_runs) == 2 * (10 + 11)


@pytest.mark.parametrize("args, message", [
    (("--out", "{tmp}/r.svg"), r"--out: .*r\.svg: render writes a PNG picture; give a name ending in \.png"),
    (("--out", "{tmp}/r.png", "--view", "1e300,0"), r"--view: .*elevation 1e\+300 is outside the allowed range "
                                                    r"\[-90, 90\]"),
    (("--out", "{tmp}/r.png", "--view", "30,400"), r"--view: .*azimuth 400(\.0)? is outside the allowed range "
                                                   r"\[-360, 360\]"),
])
def test_render_refuses_a_picture_it_cannot_make(tmp_path, args, message):
    import re
    r = cli("render", FISH, *[a.format(tmp=tmp_path) for a in args])
    assert r.returncode == 2 and re.search(message, r.stderr), r.stderr
    assert list(tmp_path.iterdir()) == []


def test_render_help_shows_how_to_give_a_negative_elevation():
    r = cli("render", "--help")
    assert "--view=-10,30" in " ".join(r.stdout.split())
