"""Every benchmark script answers ``--help`` with its usage and runs nothing.

``bench_fidelity.py`` read ``sys.argv`` by hand: ``--help`` (like any unknown flag) ran the whole ladder for
half a minute and rewrote its section of docs/benchmarks.md.
"""
import glob
import os
import subprocess
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SCRIPTS = sorted(glob.glob(os.path.join(ROOT, "benchmarks", "bench_*.py")))


def test_there_are_scripts():
    assert len(SCRIPTS) >= 15


@pytest.mark.parametrize("path", SCRIPTS, ids=[os.path.basename(p) for p in SCRIPTS])
def test_help_prints_usage_and_writes_nothing(path, tmp_path):
    docs = os.path.join(ROOT, "docs", "benchmarks.md")
    before = os.stat(docs).st_mtime_ns
    r = subprocess.run([sys.executable, path, "--help"], capture_output=True, text=True, timeout=60, cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert "usage:" in r.stdout
    assert os.stat(docs).st_mtime_ns == before
    bad = subprocess.run([sys.executable, path, "--no-such-flag"], capture_output=True, text=True, timeout=60,
                         cwd=tmp_path)
    assert bad.returncode == 2 and "error:" in bad.stderr   # argparse: unrecognized, or a missing sub-command
    assert os.stat(docs).st_mtime_ns == before
