"""Issue 19, loader / CLI / output paths / resource guards: each named defect, one test.

Every hostile input either loads or fails with exit status 2 and one ``error:`` line that names the
field; nothing is written; nothing allocates beyond the size budget.
"""
import json
import os
import signal
import subprocess
import sys
import time

import pytest

from metamaterial_wb.cli import main
from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.core.scene import Scene

PY = sys.executable
REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BASE = {"format": "metamaterial-scene", "version": 1, "layout": {"grid": [2, 3]},
        "actuators": [{"name": "m1", "joint": "V0,0", "value": 0.5}]}


def scene_text(**kw):
    d = json.loads(json.dumps(BASE))
    d.update(kw)
    return json.dumps(d)


def cli(argv, capsys):
    """Run the CLI in-process: (exit status, stderr)."""
    try:
        rc = main(argv)
    except SystemExit as exc:  # argparse
        rc = exc.code
    return rc, capsys.readouterr().err


def solve_text(tmp_path, capsys, text, mode="w"):
    src = tmp_path / "in.json"
    if isinstance(text, bytes):
        src.write_bytes(text)
    else:
        src.write_text(text)
    out = tmp_path / "out.json"
    rc, err = cli(["solve", str(src), "--out", str(out)], capsys)
    assert not out.exists()
    assert sorted(os.listdir(tmp_path)) == ["in.json"], os.listdir(tmp_path)
    return rc, err


def one_error(err):
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert len(lines) == 1 and lines[0].startswith("error: "), err
    assert "Traceback" not in err
    return lines[0]


# ---------------------------------------------------------------------------------------------
# numbers, nesting, encoding, file kinds
# ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize("raw,field,words", [
    ("1e309", "cell_size_mm", "not a finite number"),
    ("1" + "0" * 400, "cell_size_mm", "too large"),
    ("7" * 5000, "cell_size_mm", "5000 digits"),
    ("NaN", "cell_size_mm", "not a finite number"),
    ("-Infinity", "cell_size_mm", "not a finite number"),
])
def test_huge_and_nonfinite_numbers_name_the_field(tmp_path, capsys, raw, field, words):
    text = scene_text(cell_size_mm="@@").replace('"@@"', raw)
    rc, err = solve_text(tmp_path, capsys, text)
    line = one_error(err)
    assert rc == 2 and f"error: {field}:" in line and words in line, line


@pytest.mark.parametrize("depth", [40, 900, 100000])
def test_deep_nesting_is_refused(tmp_path, capsys, depth):
    text = scene_text(extra_key="@@").replace('"@@"', "[" * depth + "]" * depth)
    rc, err = solve_text(tmp_path, capsys, text)
    assert rc == 2 and "too deeply nested" in one_error(err)


def test_non_utf8_file_is_refused(tmp_path, capsys):
    rc, err = solve_text(tmp_path, capsys, scene_text(name="@@").replace("@@", "caf\u00e9").encode("latin-1"))
    line = one_error(err)
    assert rc == 2 and "not UTF-8" in line and "0xe9" in line


def test_not_json_says_so(tmp_path, capsys):
    rc, err = solve_text(tmp_path, capsys, b"\x00\x01binary")
    assert rc == 2 and "not a JSON file" in one_error(err)


@pytest.mark.parametrize("kind,words", [("dir", "is a directory"), ("loop", "symlink loop"),
                                        ("fifo", "not a regular file (a FIFO)"), ("under", "is a file, not a folder")])
def test_special_files_as_input(tmp_path, capsys, kind, words):
    p = tmp_path / "in.json"
    if kind == "dir":
        p.mkdir()
    elif kind == "loop":
        os.symlink(p, p)
    elif kind == "fifo":
        os.mkfifo(p)                     # reading it would block for ever
    else:
        (tmp_path / "f").write_text("x")
        p = tmp_path / "f" / "in.json"
    t = time.perf_counter()
    rc, err = cli(["solve", str(p), "--out", str(tmp_path / "o.json")], capsys)
    assert rc == 2 and words in one_error(err) and time.perf_counter() - t < 10


def test_wrong_module_type_names_the_field(tmp_path, capsys):
    text = scene_text(modules=[{"type": {}, "joint": "V0,0"}])
    for cmd, out in (("solve", "o.json"), ("design", "c.json")):
        src = tmp_path / "in.json"
        src.write_text(text)
        rc, err = cli([cmd, str(src), "--out", str(tmp_path / out)], capsys)
        assert rc == 2 and "modules[0].type" in one_error(err)


def test_nan_in_a_kept_section_is_refused_and_design_does_not_crash(tmp_path, capsys):
    text = scene_text(axes=[{"direction": "vertical", "line": 1, "fold_deg": 10}],
                      dynamics={"friction": "@@"}).replace('"@@"', "NaN")
    src = tmp_path / "in.json"
    src.write_text(text)
    rc, err = cli(["design", str(src), "--out", str(tmp_path / "c.json")], capsys)
    assert rc == 2 and "dynamics.friction" in one_error(err)


def test_accepted_scenes_save_again():
    """Every accepted scene of the hostile corpus can be written and read back unchanged."""
    sys.path.insert(0, os.path.dirname(__file__))
    import hostile_corpus as hc

    n = 0
    for c in hc.cases():
        if c.kind != "scene" or c.out is not None or c.id.startswith("scene-special"):
            continue
        d = os.path.join("/tmp", f"rt-{os.getpid()}")
        os.makedirs(d, exist_ok=True)
        try:
            path = c.make(d)
            try:
                s = Scene.load(path)
            except SceneError:
                continue
            text = s.to_json()
            again = Scene.from_json(text)
            assert again.to_dict() == s.to_dict(), c.id
            n += 1
        finally:
            import shutil
            shutil.rmtree(d, ignore_errors=True)
    assert n >= 10


# ---------------------------------------------------------------------------------------------
# size budget and numeric guards
# ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize("layout,field,limit", [
    ({"chain": 10 ** 7}, "layout.chain", "1000000"),
    ({"rows": ["#" * 10 ** 7]}, "layout.rows", "16000000"),
    ({"cells": [[0, 0], [0, 1], [60000, 60000], [60000, 60001]]}, "layout", "16000000"),
    ({"cells": [[0, 10 ** 18], [0, 10 ** 18 + 1]]}, "layout.cells[0]", "4000000"),
    ({"grid": [2000, 2000]}, "layout.grid", "1000000"),   # the old documented maximum: ~36 GB, lowered
    ({"grid": [1001, 1000]}, "layout.grid", "1000000"),
])
def test_size_budget_before_allocation(tmp_path, capsys, layout, field, limit):
    t = time.perf_counter()
    rc, err = solve_text(tmp_path, capsys, scene_text(layout=layout, actuators=[]))
    line = one_error(err)
    assert rc == 2 and f"error: {field}" in line and limit in line, line
    assert time.perf_counter() - t < 20


def test_documented_maximum_loads_quickly():
    """1000 x 1000 cells is the documented maximum (solve measured: 9.1 GB, docs/scene-format.md)."""
    t = time.perf_counter()
    s = Scene.grid(1000, 1000)
    assert s.topology.n_nodes == 1001 * 1001 and time.perf_counter() - t < 30
    s2 = Scene.from_dict({"format": "metamaterial-scene", "version": 1, "layout": {"chain": 1_000_000}})
    assert len(s2.topology.cell_array) == 1_000_000


@pytest.mark.parametrize("k2", [1e308, 9e307, 1e10, 5e-320, 1e-12])
def test_k2_out_of_range_names_k2(tmp_path, capsys, k2):
    rc, err = solve_text(tmp_path, capsys, scene_text(joints=[{"joint": "H0,1", "k2": k2}]))
    line = one_error(err)
    assert rc == 2 and "k2" in line and "NaN" not in line, line


def test_quadratic_model_refuses_unknown_options(tmp_path, capsys):
    src = tmp_path / "in.json"
    src.write_text(scene_text())
    rc, err = cli(["solve", str(src), "--out", str(tmp_path / "o.json"), "--option", "tol=1e-3"], capsys)
    assert rc == 2 and "--option tol" in one_error(err)
    assert not (tmp_path / "o.json").exists()


def test_simulate_tiny_dt_refused_with_the_limit(tmp_path, capsys):
    src = tmp_path / "in.json"
    src.write_text(scene_text())
    t = time.perf_counter()
    rc, err = cli(["simulate", str(src), "--seconds", "1", "--dt", "1e-9", "--out", str(tmp_path / "sim")], capsys)
    line = one_error(err)
    assert rc == 2 and "--dt" in line and "20000000" in line, line
    assert time.perf_counter() - t < 10 and not (tmp_path / "sim").exists()


# ---------------------------------------------------------------------------------------------
# output paths, temporaries, signals, atomic sets
# ---------------------------------------------------------------------------------------------
def _bad_outputs(tmp):
    (tmp / "f").write_text("x")
    (tmp / "d").mkdir()
    os.mkfifo(tmp / "p")
    return [("", "empty path"), ("/proc/self/x.json", "kernel file system"),
            (str(tmp / ("x" * 300)), "at most 255"), (str(tmp / "f" / "o"), "not a folder"),
            (str(tmp / "p"), "FIFO"), ("a\x00b", "NUL")]


@pytest.mark.parametrize("cmd", ["solve", "design", "render", "simulate", "build", "sleeve", "stream"])
def test_bad_output_paths_refused_before_work(tmp_path, capsys, cmd):
    # the input does not even exist: the output path is checked first
    for out, words in _bad_outputs(tmp_path) + ([(str(tmp_path / "d"), "directory")]
                                                if cmd in ("solve", "design", "render") else []):
        if cmd == "stream":
            argv = ["stream", "nowhere.json", "--dry-run", "--report", out]
        else:
            argv = [cmd, "nowhere.json", "--out", out] + (["--seconds", "1"] if cmd == "simulate" else [])
        rc, err = cli(argv, capsys)
        line = one_error(err)
        assert rc == 2 and words in line and "nowhere.json" not in line, (cmd, out, line)
    assert sorted(os.listdir(tmp_path)) == ["d", "f", "p"]


def test_sleeve_out_empty_writes_nothing_in_cwd(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    rc, err = cli(["sleeve", os.path.join(REPO, "examples", "sleeve.json"), "--out", ""], capsys)
    assert rc == 2 and "--out" in one_error(err) and os.listdir(tmp_path) == []


def test_kill9_leftovers_are_swept_at_the_next_run(tmp_path, capsys):
    dead = subprocess.Popen([PY, "-c", "pass"])
    dead.wait()
    stale = [f".tmp-{dead.pid}-abc-r.json", f".build-{dead.pid}-xyz", f".tmp-simulate-{dead.pid}-q"]
    alive = f".tmp-{os.getpid()}-keep"
    out = tmp_path / "o"
    out.mkdir()
    for n in stale[:1] + [alive]:
        (out / n).write_text("partial")
    for n in stale[1:]:
        (out / n).mkdir()
        (out / n / "part.step").write_text("x" * 1000)
    src = tmp_path / "in.json"
    src.write_text(scene_text())
    rc, err = cli(["solve", str(src), "--out", str(out / "r.json")], capsys)
    assert rc == 0, err
    assert sorted(os.listdir(out)) == sorted([alive, "r.json"])


def test_sigterm_removes_the_temporary_folder(tmp_path):
    """The CLI's handler turns SIGTERM into an exception, so OutputSet's cleanup runs."""
    code = f"""
import os, sys, time
sys.path.insert(0, {REPO!r})
from metamaterial_wb.cli import _install_signals
from metamaterial_wb.core.fileio import OutputSet
_install_signals()
with OutputSet({str(tmp_path / 'out')!r}, "tmp-simulate") as tmp:
    open(os.path.join(tmp, "trajectory.json"), "w").write("x" * 100000)
    open({str(tmp_path / 'ready')!r}, "w").close()
    time.sleep(60)
"""
    p = subprocess.Popen([PY, "-c", code])
    t0 = time.time()
    while not (tmp_path / "ready").exists():
        assert time.time() - t0 < 60 and p.poll() is None
        time.sleep(0.05)
    p.send_signal(signal.SIGTERM)
    p.wait(timeout=30)
    assert not (tmp_path / "out").exists()          # the temporary folder, and the --out folder the run created


def test_output_set_moves_all_or_nothing(tmp_path, monkeypatch):
    from metamaterial_wb.core import fileio

    out = tmp_path / "out"
    out.mkdir()
    (out / "a.json").write_text("old a")
    (out / "b.json").write_text("old b")
    real = os.replace
    calls = {"n": 0}

    def flaky(src, dst):
        calls["n"] += 1
        if str(dst).endswith("b.json") and str(src).endswith(os.path.join("", "b.json")) and ".old" not in str(dst) \
                and ".old" not in str(src):
            raise OSError(28, "No space left on device")
        return real(src, dst)

    monkeypatch.setattr(fileio.os, "replace", flaky)
    with pytest.raises(OSError):
        with fileio.OutputSet(str(out)) as tmp:
            (tmp_path / "x").write_text("")
            open(os.path.join(tmp, "a.json"), "w").write("new a")
            open(os.path.join(tmp, "b.json"), "w").write("new b")
    monkeypatch.setattr(fileio.os, "replace", real)
    assert sorted(os.listdir(out)) == ["a.json", "b.json"]
    assert (out / "a.json").read_text() == "old a" and (out / "b.json").read_text() == "old b"


# ---------------------------------------------------------------------------------------------
# BLAS threads (issue 14): importing the CLI must not make every command single-threaded
# ---------------------------------------------------------------------------------------------
def test_cli_import_keeps_blas_threads():
    env = {k: v for k, v in os.environ.items() if not k.endswith("_NUM_THREADS")}
    probe = ("import sys; sys.path.insert(0, %r); {pre}"
             "from metamaterial_wb.core.threads import blas_thread_counts; print(max(blas_thread_counts() or [0]))"
             % REPO)
    base = subprocess.run([PY, "-c", probe.format(pre="")], env=env, capture_output=True, text=True, timeout=120)
    after = subprocess.run([PY, "-c", probe.format(pre="import metamaterial_wb.cli as c; c.build_parser(); ")],
                           env=env, capture_output=True, text=True, timeout=120)
    n0, n1 = int(base.stdout.split()[-1]), int(after.stdout.split()[-1])
    if n0 <= 1:
        pytest.skip("one BLAS thread by default on this machine (or no OpenBLAS): nothing to compare")
    assert n1 == n0, (n0, n1)


def test_sleeve_runs_blas_single_threaded_and_restores():
    from metamaterial_wb.core.threads import blas_thread_counts, blas_threads

    before = blas_thread_counts()
    if not before:
        pytest.skip("no OpenBLAS loaded")
    with blas_threads(1):
        assert set(blas_thread_counts()) == {1}
    assert blas_thread_counts() == before


def test_read_only_folder_refused(tmp_path, capsys, monkeypatch):
    """As root a chmod 555 folder stays writable, so the refusal is exercised through os.access."""
    from metamaterial_wb.core import fileio

    real = os.access
    monkeypatch.setattr(fileio.os, "access", lambda p, mode: False if str(p) == str(tmp_path) else real(p, mode))
    src = tmp_path / "in.json"
    src.write_text(scene_text())
    rc, err = cli(["solve", str(src), "--out", str(tmp_path / "r.json")], capsys)
    assert rc == 2 and "is not writable" in one_error(err)
    assert sorted(os.listdir(tmp_path)) == ["in.json"]


def test_channel_file_hostile(tmp_path, capsys):
    src = tmp_path / "in.json"
    src.write_text(scene_text())
    os.mkfifo(tmp_path / "ch.json")
    rc, err = cli(["stream", str(src), "--dry-run", "--seconds", "0.05", "--channels", str(tmp_path / "ch.json")],
                  capsys)
    assert rc == 2 and "--channels" in one_error(err) and "FIFO" in err


@pytest.mark.parametrize("k2", [9e307, 1e200, 5e-320, 1e-200])
def test_solver_refuses_k2_that_overflows_or_is_subnormal(k2):
    from metamaterial_wb.core.solver import check_stiffness

    with pytest.raises(SceneError, match=r"joint H0,0\.k2"):
        check_stiffness([0.5, 0.5], [1.0, k2][::-1], ["H0,0", "V0,0"])
    check_stiffness([0.5], [1e12], ["H0,0"])      # scale invariance: large but normal k2 is fine


def test_path_objects_load_like_strings(tmp_path):
    """pathlib.Path was accepted before the hardened reader; it still is (only non-paths are refused)."""
    import pathlib

    import metamaterial_wb
    from metamaterial_wb.core.errors import SceneError
    from metamaterial_wb.core.scene import Scene
    src = pathlib.Path(metamaterial_wb.example_path("fish"))
    assert Scene.load(src).to_dict() == Scene.load(str(src)).to_dict()
    with pytest.raises(SceneError, match="no file name"):
        Scene.load(12)
