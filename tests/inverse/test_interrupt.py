"""Ctrl-C of ``inverse --workers N``: a terminal sends SIGINT to the whole process group (the CLI and its
pool's workers); pressed twice it must still end the CLI promptly (exit 130) and leave no worker behind."""
import json
import os
import signal
import subprocess
import sys
import time

import pytest

from inverse_helpers import planted_result, scene_with
from metamaterial_wb.core.scene import Scene

pytestmark = pytest.mark.skipif(not os.path.isdir("/proc") or os.name != "posix", reason="needs Linux /proc")


def session_pids(sid):
    """Pids of the processes whose session is ``sid`` (the CLI's own session, see start_new_session)."""
    out = []
    for name in os.listdir("/proc"):
        if not name.isdigit():
            continue
        try:
            with open(f"/proc/{name}/stat") as f:
                stat = f.read()
        except OSError:
            continue
        fields = stat[stat.rindex(")") + 2:].split()      # after "pid (comm) "
        if fields[0] != "Z" and int(fields[3]) == sid:     # state, ppid, pgrp, session
            out.append(int(name))
    return out


@pytest.fixture(scope="module")
def inputs(tmp_path_factory):
    d = tmp_path_factory.mktemp("interrupt")
    s = scene_with(Scene.grid(12, 12), [("H1,1", 0.6), ("V2,3", 0.5)])
    (d / "t.json").write_text(json.dumps(planted_result(s)))
    bare = s.to_dict()
    bare["actuators"] = []
    (d / "s.json").write_text(json.dumps(bare))
    return d


def start_cli(d, out):
    from metamaterial_wb import REPO_DIR
    env = dict(os.environ, PYTHONPATH=REPO_DIR)
    cmd = [sys.executable, "-m", "metamaterial_wb", "inverse", str(d / "s.json"), "--target", str(d / "t.json"),
           "--servos", "4", "--out", str(d / out), "--evaluate", "quadratic", "--no-picture", "--fab-checks", "off",
           "--screen", "0", "--workers", "2"]
    # its own session and group, SIGINT at its default (as in an interactive terminal)
    return subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env,
                            start_new_session=True, preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))


def wait_for_workers(p, n=2, timeout=60):
    deadline = time.time() + timeout
    while time.time() < deadline:
        assert p.poll() is None, "the CLI ended before its pool started: " + p.stderr.read()[-2000:]
        if len(session_pids(p.pid)) >= 1 + n:
            return
        time.sleep(0.1)
    pytest.fail("the pool's workers never started")


def finish(p, timeout):
    t0 = time.time()
    try:
        _, err = p.communicate(timeout=timeout)
        return p.returncode, err, time.time() - t0
    except subprocess.TimeoutExpired:
        os.killpg(p.pid, signal.SIGKILL)
        p.communicate()
        pytest.fail(f"the CLI was still running {timeout} s after the interrupt")


def assert_no_leftovers(sid):
    deadline = time.time() + 5
    while session_pids(sid) and time.time() < deadline:
        time.sleep(0.1)
    left = session_pids(sid)
    for pid in left:
        try:
            os.kill(pid, signal.SIGKILL)
        except OSError:
            pass
    assert left == [], f"processes left behind: {left}"


@pytest.mark.parametrize("presses", [1, 2])
def test_ctrl_c_of_a_pool_run_ends_it_and_its_workers(inputs, presses):
    p = start_cli(inputs, f"out{presses}")
    wait_for_workers(p)
    time.sleep(4.0)                              # the workers are started and busy in the search now
    assert p.poll() is None, "the search ended before the interrupt; make it longer"
    for k in range(presses):
        if k:
            time.sleep(0.3)
        os.killpg(p.pid, signal.SIGINT)
    code, err, took = finish(p, 10)
    assert code == 130, err[-3000:]
    assert "interrupted" in err
    assert "Traceback" not in err, err[-3000:]
    assert_no_leftovers(p.pid)
