"""Issue 19: a STEP export killed with SIGKILL leaves its ``.mmwb-<pid>-*.step`` temporary behind (the
process gets no chance to clean up); the next STEP export removes it (its writer no longer runs), keeps a
live writer's, and leaves no temporary of its own."""
import os
import signal
import subprocess
import sys
import time

import pytest

pytest.importorskip("FreeCAD")

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
HEAD = f"""import os, sys, time
sys.path.append("/usr/lib/freecad-python3/lib")
sys.path.insert(0, {REPO!r})
from metamaterial_wb.geometry.fc import freecad
App, Part = freecad()
from metamaterial_wb.export.step import write_step
bodies = [("cube", Part.makeBox(1, 2, 3), "#ff0000")]
"""
# the first export stops inside FreeCAD's STEP writer (a slow export), after the temporary exists
SLOW = HEAD + """import Import
real = Import.export
def slow(objs, path):
    real(objs, path)
    open(os.path.join(sys.argv[1], "ready"), "w").close()
    time.sleep(120)
Import.export = slow
write_step(os.path.join(sys.argv[1], "a.step"), bodies)
"""
NEXT = HEAD + """write_step(os.path.join(sys.argv[1], "b.step"), bodies)
"""


def _temps(d):
    return sorted(n for n in os.listdir(d) if n.startswith(".mmwb-"))


def test_step_kill9_temporary_swept_by_the_next_export(tmp_path):
    tmpdir = tmp_path / "tmp"
    tmpdir.mkdir()
    out = tmp_path / "out"
    out.mkdir()
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    env["TMPDIR"] = str(tmpdir)
    p = subprocess.Popen([sys.executable, "-c", SLOW, str(out)], env=env)
    try:
        t0 = time.time()
        while not (out / "ready").exists():
            assert p.poll() is None and time.time() - t0 < 120, "the slow export never reached the writer"
            time.sleep(0.05)
        left = _temps(tmpdir)
        assert left, "the export wrote no temporary"
        p.send_signal(signal.SIGKILL)
        p.wait(timeout=30)
    finally:
        if p.poll() is None:
            p.kill()
    assert _temps(tmpdir) == left                         # SIGKILL: nothing could clean up
    live = f".mmwb-{os.getpid()}-keep.step"               # a writer that still runs keeps its file
    (tmpdir / live).write_text("partial")
    r = subprocess.run([sys.executable, "-c", NEXT, str(out)], env=env, capture_output=True, text=True,
                       timeout=300)
    assert r.returncode == 0, r.stdout + r.stderr
    assert (out / "b.step").stat().st_size > 1000 and not (out / "a.step").exists()
    assert _temps(tmpdir) == [live]


INSTANCED = HEAD + """from metamaterial_wb.export.step import write_step_instanced
write_step_instanced(os.path.join(sys.argv[1], "c.step"), {"k": bodies[0][1]},
                     [("cube_a", "k", App.Placement()), ("cube_b", "k", App.Placement(App.Vector(5, 0, 0), App.Rotation()))],
                     colours={"k": "#ff0000"})
"""


def test_the_instanced_writer_that_build_uses_sweeps_and_cleans_too(tmp_path):
    """``build`` writes its sheet with the instanced writer: it shares the temporary handling (pid-named,
    stale ones swept, its own removed)."""
    tmpdir = tmp_path / "tmp"
    tmpdir.mkdir()
    out = tmp_path / "out"
    out.mkdir()
    dead = subprocess.Popen([sys.executable, "-c", "pass"])
    dead.wait()
    stale = f".mmwb-{dead.pid}-killed.step"                # a writer that no longer runs
    (tmpdir / stale).write_text("partial")
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    env["TMPDIR"] = str(tmpdir)
    r = subprocess.run([sys.executable, "-c", INSTANCED, str(out)], env=env, capture_output=True, text=True,
                       timeout=300)
    assert r.returncode == 0, r.stdout + r.stderr
    text = (out / "c.step").read_text(errors="replace")
    assert "cube_a" in text and "cube_b" in text
    assert _temps(tmpdir) == []
