"""The emulated board frozen part-way (SIGSTOP to simavr: the chip neither answers nor hears) while the CLI streams
the fish to it: the stream stops after Streamer.silence_limit_s of unanswered frames, exits 2 and leaves its report
marked failed (before: it streamed blind for the whole --seconds and exited 1 with a report saying it went fine)."""
import json
import os
import signal
import subprocess
import sys
import time

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def test_cli_stream_fails_when_the_board_stops_answering(sim, tmp_path):
    rep = tmp_path / "stream.json"
    p = subprocess.Popen([sys.executable, "-m", "metamaterial_wb", "stream",
                          os.path.join(REPO, "examples", "fish.json"), "--port", sim.port, "--seconds", "8",
                          "--report", str(rep)],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, encoding="utf-8", cwd=REPO,
                         env=dict(os.environ, PYTHONPATH=REPO))
    try:
        first = p.stderr.readline()  # the handshake line, printed just before the first frame
        assert "streaming" in first, first
        time.sleep(0.5)
        os.kill(sim.proc.pid, signal.SIGSTOP)
        out, err = p.communicate(timeout=60)
    finally:
        os.kill(sim.proc.pid, signal.SIGCONT)
        if p.poll() is None:
            p.kill()
            p.wait()
    assert p.returncode == 2, out + err
    assert "the board stopped answering" in err, err
    with open(rep, encoding="utf-8") as f:
        d = json.load(f)
    assert d["failed"] is True and "stopped answering" in d["error"]
    assert d["acked"] > 0 and d["lost"] > 0 and d["acked"] + d["lost"] == d["frames"]
    # stopped long before the end of its 8 s (400 frames): the frames after the freeze are the run it gave up after
    assert d["last_t"] < 8 - 1 and d["frames"] < 400
