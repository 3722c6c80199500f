"""Issue 19: the hostile corpus (tests/unit/hostile_corpus.py, > 900 malformed scenes, sleeve specs,
special files and bad output paths) through every command: 0 tracebacks, 0 hangs, 0 stray files.

The corpus runs in-process (``cli.main(argv)``) inside one subprocess with a 3 GB address-space limit
and a per-command alarm; a sample also runs as real ``python3 -m metamaterial_wb`` processes.
"""
import json
import os
import resource
import subprocess
import sys

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)
import hostile_corpus as hc  # noqa: E402

LIMIT = 3 * 2 ** 30


def _limit():
    resource.setrlimit(resource.RLIMIT_AS, (LIMIT, LIMIT))


def test_corpus_is_big_and_varied():
    cases = hc.cases()
    kinds = {c.kind for c in cases}
    assert len(cases) >= 300 and kinds == {"scene", "sleeve"}
    ids = " ".join(c.id for c in cases)
    for word in ("nan", "inf", "int5000", "deep", "uni", "truncated", "latin1", "special-fifo", "special-loop",
                 "out-proc", "out-empty", "chain-1e7", "cells-far"):
        assert word in ids, word


def test_whole_corpus_in_process_under_limits():
    r = subprocess.run([sys.executable, os.path.join(HERE, "hostile_corpus.py"), "--limit-mb", str(LIMIT >> 20),
                        "--timeout", "30"], capture_output=True, text=True, timeout=1500, cwd=REPO)
    lines = [json.loads(ln) for ln in r.stdout.splitlines() if ln.startswith("{")]
    assert lines, r.stdout[-2000:] + r.stderr[-2000:]
    summary = lines[-1]
    failing = [ln for ln in lines if "problems" in ln]
    assert summary["cases"] >= 300
    assert summary["failing"] == 0 and r.returncode == 0, json.dumps(failing[:20], indent=1)


SAMPLE = ["scene-cell_size_mm-int5000", "scene-modules.0.type-obj", "scene-deep-list", "scene-latin1",
          "scene-special-fifo", "scene-cells-far", "sleeve-L_mm-e309", "out-proc-solve", "out-empty-sleeve",
          "out-fifo-render"]


@pytest.mark.parametrize("cid", SAMPLE)
def test_sample_as_real_processes(tmp_path, cid):
    case = next(c for c in hc.cases() if c.id == cid)
    cmd = case.commands[0]
    indir, outdir, cwd = (tmp_path / n for n in ("in", "out", "cwd"))
    for d in (indir, outdir, cwd):
        d.mkdir()
    (tmp_path / "angles.csv").write_text("node,angle_deg\nN0,1,1.0\n")
    inp = case.make(str(indir))
    out = case.out(str(outdir))[0] if case.out else None
    before = sorted(os.listdir(outdir))
    argv = hc.argv_for(cmd, inp, str(outdir), out)
    r = subprocess.run([sys.executable, "-m", "metamaterial_wb", *argv], cwd=str(cwd), capture_output=True, text=True,
                       timeout=120, preexec_fn=_limit, env=dict(os.environ, PYTHONPATH=REPO))
    assert r.returncode == 2, (r.returncode, r.stderr[-1500:])
    lines = [ln for ln in r.stderr.splitlines() if ln.strip()]
    assert len(lines) == 1 and lines[0].startswith("error: ") and "Traceback" not in r.stderr, r.stderr[-1500:]
    assert os.listdir(cwd) == [] and sorted(os.listdir(outdir)) == before, os.listdir(outdir)
