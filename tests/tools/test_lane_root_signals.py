"""tools/lane-root.sh's mmdebstrap run (a stand-in mmdebstrap first on PATH, no network): a failed attempt is
retried once and then named (under ``set -e`` the wait on the failed attempt ended the script at once, exit 3, no
second attempt, no message); a TERM of the script ends the run it started (``timeout`` runs mmdebstrap in a
process group of its own, which a TERM of the script's group missed: it went on until its 1500 s limit)."""
import os
import signal
import subprocess
import time

import pytest

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
LANE_ROOT = os.path.join(REPO, "tools", "lane-root.sh")


def fake_mmdebstrap(tmp_path, body):
    bindir = tmp_path / "bin"
    bindir.mkdir()
    f = bindir / "mmdebstrap"
    f.write_text("#!/bin/sh\n" + body + "\n", encoding="utf-8")
    f.chmod(0o755)
    return dict(os.environ, PATH=f"{bindir}:{os.environ['PATH']}")


def test_a_failed_attempt_is_retried_then_named(tmp_path):
    env = fake_mmdebstrap(tmp_path, 'echo "stand-in mmdebstrap fails" >&2; exit 3')
    r = subprocess.run(["bash", LANE_ROOT, "trixie", str(tmp_path / "roots" / "trixie")], env=env,
                       capture_output=True, text=True, timeout=60)
    assert r.returncode == 1, (r.returncode, r.stderr)
    assert r.stderr.count("stand-in mmdebstrap fails") == 2, r.stderr          # attempts 1 and 2
    assert "could not make the trixie root" in r.stderr, r.stderr
    assert not (tmp_path / "roots" / "trixie").exists()


def _running(tag):
    """The pids whose command line is ``tag`` (read from /proc: the lane roots have no pgrep)."""
    want = tag.encode().replace(b" ", b"\0") + b"\0"
    pids = []
    for d in os.listdir("/proc"):
        if d.isdigit():
            try:
                with open(f"/proc/{d}/cmdline", "rb") as f:
                    if f.read() == want:
                        pids.append(int(d))
            except OSError:
                pass
    return pids


def test_a_term_ends_the_mmdebstrap_it_started(tmp_path):
    tag = f"{time.time_ns() % 10**6 + 1000}.25"           # a sleep this test alone starts
    env = fake_mmdebstrap(tmp_path, f"sleep {tag}")
    p = subprocess.Popen(["bash", LANE_ROOT, "trixie", str(tmp_path / "roots" / "trixie")], env=env,
                         stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                         preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    try:
        deadline = time.time() + 30
        while not _running(f"sleep {tag}") and time.time() < deadline:
            time.sleep(0.1)
        assert _running(f"sleep {tag}"), "the stand-in mmdebstrap did not start"
        p.send_signal(signal.SIGTERM)
        assert p.wait(timeout=60) == 143
        deadline = time.time() + 20
        while _running(f"sleep {tag}") and time.time() < deadline:
            time.sleep(0.1)
        left = _running(f"sleep {tag}")
        assert not left, f"mmdebstrap's run went on after the TERM of lane-root.sh: pids {left}"
    finally:
        for pid in _running(f"sleep {tag}"):
            os.kill(pid, signal.SIGKILL)
        if p.poll() is None:
            p.kill()
