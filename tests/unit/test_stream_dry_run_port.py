"""``stream --dry-run --port P`` drove the board on P: the CLI and ``Link.open`` opened P whenever a port was given,
streamed the whole motion to it (the emulated pins carried it), printed "(dry run)", wrote ``"dry_run": true``
and skipped the servo-driver check that a real stream makes. A dry run never drives hardware: the combination is
refused (the CLI names both flags, ``Link.open`` the port), while a dry run over ``loop://`` (no port, or the
Animate panel's ``loop://`` port) still runs. The same on the emulated chip: tests/firmware/test_emulator_osc_render.py."""
import json
import os

import pytest

pytest.importorskip("serial")

from clihelpers import one_line_error, run_cli  # noqa: E402

from metamaterial_wb.hardware.link import Link, LinkError  # noqa: E402

FISH = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))), "examples",
                    "fish.json")


@pytest.fixture
def board():
    """A pseudo-terminal: (the port a host would open, the board's end to read what reached it)."""
    master, slave = os.openpty()
    os.set_blocking(master, False)
    yield os.ttyname(slave), master
    os.close(master)
    os.close(slave)


def _received(fd):
    try:
        return os.read(fd, 65536)
    except BlockingIOError:
        return b""


def test_cli_refuses_dry_run_with_a_port_and_sends_nothing(board, tmp_path):
    port, fd = board
    rep = tmp_path / "r.json"
    r = run_cli("stream", FISH, "--dry-run", "--port", port, "--seconds", "0.5", "--report", rep, timeout=60)
    one_line_error(r, "--dry-run")   # before: the stream went to the port (or waited for its handshake there)
    assert "--port" in r.stderr and port in r.stderr and "loop://" in r.stderr, r.stderr
    assert _received(fd) == b""      # not one byte reached the board
    assert not rep.exists()


def test_cli_dry_run_without_a_port_still_streams_over_loop(tmp_path):
    rep = tmp_path / "r.json"
    r = run_cli("stream", FISH, "--dry-run", "--seconds", "0.2", "--report", rep, timeout=60)
    assert r.returncode == 0, r.stderr
    assert r.stderr.startswith("loop://:") and "(dry run)" in r.stderr, r.stderr
    d = json.loads(rep.read_text(encoding="utf-8"))
    assert d["dry_run"] is True and d["port"] == "loop://" and d["frames"] == d["acked"] > 0


def test_link_open_refuses_a_dry_run_on_a_real_port(board):
    port, fd = board
    with pytest.raises(LinkError, match=rf"port {port}: a dry run streams over pyserial's loop:// and never drives"):
        Link.open(port, dry_run=True)
    assert _received(fd) == b""


@pytest.mark.parametrize("port", ["loop://", "", None])
def test_link_open_dry_run_over_loop_still_works(port):
    """The Animate panel's Connect passes ``loop://`` with dry_run=True; scripts pass no port."""
    with Link.open(port, dry_run=True) as link:
        assert link.name == "loop://" and link.dry_run
        info = link.handshake()
        assert info.n_channels == 8
