"""tools/lane-mounts.sh (the mount helper of run-lane.sh and lane-root.sh): every mount it made is gone after
a normal exit, after SIGTERM and after SIGINT of a script that uses it the way run-lane.sh does."""
import os
import shutil
import signal
import subprocess
import time

import pytest

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
HELPER = os.path.join(REPO, "tools", "lane-mounts.sh")

SCRIPT = r"""
set -euo pipefail
. "{helper}"
trap lane_unmount_all EXIT
trap 'lane_unmount_all; exit 130' INT
trap 'lane_unmount_all; exit 143' TERM
lane_mount_proc "{root}"
lane_bind "{root}" "{src}" /work
lane_bind "{root}" "{src}" /work/inner
echo mounted > "{root}/ready"
{tail}
"""


def mounts_below(root):
    out = subprocess.run(["findmnt", "-rn", "-o", "TARGET"], capture_output=True, text=True).stdout.split()
    return [m for m in out if m == root or m.startswith(root + "/")]


@pytest.fixture
def root(tmp_path):
    if os.geteuid() != 0:
        pytest.skip("mounting needs root")
    missing = [t for t in ("mount", "umount", "findmnt") if shutil.which(t) is None]
    if missing:
        pytest.skip(f"{', '.join(missing)} not installed (Debian package: mount / util-linux)")
    r = tmp_path / "root"
    r.mkdir()
    (tmp_path / "src").mkdir()
    probe = subprocess.run(["mount", "--bind", str(tmp_path / "src"), str(r)], capture_output=True)
    if probe.returncode != 0:
        pytest.skip(f"bind mounts are not allowed here: {probe.stderr.decode().strip()}")
    subprocess.run(["umount", str(r)], check=True)
    yield r
    for m in reversed(mounts_below(str(r))):
        subprocess.run(["umount", "-l", m])


def run(root, tail, sig=None):
    src = root.parent / "src"
    script = SCRIPT.format(helper=HELPER, root=root, src=src, tail=tail)
    # a shell that starts us in the background leaves SIGINT ignored, and bash cannot trap a signal ignored at
    # its start: give the script the default disposition, as an interactive run-lane.sh has
    p = subprocess.Popen(["bash", "-c", script], preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    if sig is not None:
        deadline = time.time() + 20
        while not (root / "ready").exists():
            assert time.time() < deadline, "the script never mounted"
            time.sleep(0.05)
        assert len(mounts_below(str(root))) == 3
        p.send_signal(sig)
    return p.wait(timeout=30)


def test_normal_exit_unmounts_everything(root):
    assert run(root, "true") == 0
    assert mounts_below(str(root)) == []


@pytest.mark.parametrize("sig, rc", [(signal.SIGTERM, 143), (signal.SIGINT, 130)])
def test_a_signal_unmounts_everything(root, sig, rc):
    # bash runs a trap only between commands: the script waits in a loop of short sleeps as run-lane.sh
    # waits for its child
    assert run(root, "while true; do sleep 0.1; done", sig) == rc
    assert mounts_below(str(root)) == []
