"""The CalculiX rung when ccx misbehaves, without running the real solver: fake ``ccx`` executables on the PATH
that exit 0 but leave a ``.dat`` that is garbage or not UTF-8, or that fail outright.

Every solver must then raise :class:`ccx.FEError` naming its job and the table it missed (no KeyError or
UnicodeDecodeError traceback); ``bench fidelity --fe`` must still write its report with an "FE rung failed" note and
render every FE study it holds (not only the hinge's); ``sleeve --fe-check`` must still write the beam model's
outputs with the failure in its notes.
"""
import json
import os
import stat
import subprocess
import sys

import pytest

from metamaterial_wb.fe import ccx

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
STORED = os.path.join(REPO, "benchmarks", "results", "fe-study.json")

# the fake solvers: called as ``ccx -i JOB`` in the job's folder (so "$2" is the job's name)
FAKES = {"garbage": "printf 'garbage\\000\\001 not a dat file\\n' > \"$2.dat\"\necho 'Job finished'\nexit 0\n",
         "binary": "printf '\\377\\376 binary \\351\\n' > \"$2.dat\"\nexit 0\n",
         "empty": ": > \"$2.dat\"\nexit 0\n",
         "fail": "echo ' *ERROR in fake: simulated failure'\nexit 1\n"}


def fake_ccx(tmp_path, kind):
    """A folder holding a fake ``ccx`` of the given kind (``FAKES``)."""
    d = tmp_path / f"fakebin_{kind}"
    d.mkdir(exist_ok=True)
    exe = d / "ccx"
    exe.write_text("#!/bin/sh\n" + FAKES[kind])
    exe.chmod(exe.stat().st_mode | stat.S_IXUSR | stat.S_IXGRP | stat.S_IXOTH)
    return str(d)


def _env(fakebin):
    return dict(os.environ, PATH=fakebin + os.pathsep + os.environ.get("PATH", ""))


def test_a_non_utf8_dat_is_read_not_a_decode_error(tmp_path, monkeypatch):
    monkeypatch.setenv("PATH", fake_ccx(tmp_path, "binary") + os.pathsep + os.environ.get("PATH", ""))
    tables, info = ccx.run("*HEADING\nfake\n", "job", 30)
    assert tables == {} and info["wall_s"] >= 0


def test_table_names_the_job_and_the_missing_table():
    with pytest.raises(ccx.FEError, match=r"job 'hinge_K'.*displacements.*NREF"):
        ccx.table({}, ("displacements", "NREF"), "hinge_K")
    rows = [(1.0, {7: [0.0]})]
    assert ccx.table({("forces", "TOP"): rows}, ("forces", "TOP"), "x", nodes=[7]) == rows


def _solvers():
    from metamaterial_wb.core.sleeve.cell import CellGeometry
    from metamaterial_wb.fe import hinge, patch, sleeve2d, sleeve3d
    s, g = hinge.HingeSpec(), CellGeometry()
    return [("hinge_K", lambda: hinge.stiffness(s, 0.8, 30)),
            ("hinge_bend", lambda: hinge.bending_curve(s, 0.8, 10.0, 2, timeout_s=30)),
            ("patch", lambda: patch.solve_patch(patch.patch_scene(0.05), 0.5, 2, 2, timeout_s=30)),
            ("sleeve_cell", lambda: sleeve2d.solve_cell(g, 1, increments=4, timeout_s=30)),
            ("sleeve_ring", lambda: sleeve2d.solve_ring(g, 4, 1, increments=4, timeout_s=30)),
            ("sleeve_ring3d", lambda: sleeve3d.solve_ring3d(g, 4, 1, 1, increments=2, timeout_s=30))]


@pytest.mark.parametrize("kind", ["garbage", "binary", "empty"])
def test_every_solver_reports_an_unreadable_dat_as_an_fe_error(tmp_path, monkeypatch, kind):
    monkeypatch.setenv("PATH", fake_ccx(tmp_path, kind) + os.pathsep + os.environ.get("PATH", ""))
    for job, solve in _solvers():
        with pytest.raises(ccx.FEError, match=rf"job '{job}'.* table"):
            solve()


def _bench(tmp_path, *extra, env=None):
    md, png = tmp_path / "f.md", tmp_path / "img" / "wp.png"
    r = subprocess.run([sys.executable, "-m", "metamaterial_wb", "bench", "fidelity", "--out", str(md),
                        "--img", str(png), "--scenes", "chain", "--amplitudes", "0.05", "--repeats", "1", "--quiet",
                        *extra], cwd=REPO, env=env, capture_output=True, text=True, timeout=300)
    return r, md


def test_bench_fe_with_a_broken_ccx_still_writes_the_report(tmp_path):
    r, md = _bench(tmp_path, "--fe", "--fe-parts", "hinge", env=_env(fake_ccx(tmp_path, "binary")))
    assert r.returncode == 0, r.stderr
    assert "Traceback" not in r.stderr
    text = md.read_text()
    assert "FE rung failed: " in text and "'hinge_K'" in text
    assert "| chain | 0.05 |" in text


def _stored_parts(tmp_path, *keys):
    with open(STORED) as f:
        full = json.load(f)
    path = tmp_path / "part.json"
    path.write_text(json.dumps({k: full[k] for k in keys if k in full}))
    return str(path)


def test_bench_fe_renders_the_patch_study_alone(tmp_path):
    """``--fe-parts patch``: the patch study (here read back from a file, so nothing runs) is in the report."""
    r, md = _bench(tmp_path, "--fe", "--fe-parts", "patch", "--fe-json", _stored_parts(tmp_path, "patch"))
    assert r.returncode == 0, r.stderr
    text = md.read_text()
    assert "### 3 x 3 patch, two actuated joints: every model against CalculiX" in text
    assert "Amplitude 0.05: FE uncertainty" in text


def test_bench_fe_renders_the_sleeve_study_alone(tmp_path):
    sleeves = tmp_path / "sleeves.md"
    sleeves.write_text("# Sleeves\n\n## Sequencing\n")
    r, md = _bench(tmp_path, "--fe", "--fe-parts", "sleeve", "--sleeves-out", str(sleeves),
                   "--sleeves-img", str(tmp_path / "img" / "sl.png"),
                   "--fe-json", _stored_parts(tmp_path, "sleeve", "sleeve_calibration", "sleeve_curved"))
    assert r.returncode == 0, r.stderr
    assert "### Sleeve cell and ring: the beam model against CalculiX" in md.read_text()


@pytest.mark.parametrize("parts", [",", "", " , "])
def test_bench_refuses_an_empty_fe_parts(tmp_path, parts):
    r, md = _bench(tmp_path, "--fe", "--fe-parts", parts)
    assert r.returncode == 2
    assert "--fe-parts" in r.stderr and "hinge, patch, sleeve" in r.stderr
    assert not md.exists()


SEED = {"format": "metamaterial-sleeve", "version": 1, "L_mm": 18, "c_mm": 4, "delta_mm": 0.5, "T_mm": 1.8,
        "shear_modulus_MPa": 1, "cell_types": [{"t_mm": 1.0, "h_mm": 7.5}], "ring": [0, 0, 0, 0],
        "model": {"elements_cell": 6, "steps": 60}}


@pytest.mark.parametrize("kind", ["fail", "garbage"])
def test_sleeve_fe_check_failure_keeps_the_beam_model_outputs(tmp_path, kind):
    """A failing check (here a fake ccx) costs the check, not the analysis: the summary is written with the failure
    in its accuracy notes and ``fe_check``, one warning line on stderr, exit 0 (docs/sleeves.md)."""
    spec = tmp_path / "spec.json"
    spec.write_text(json.dumps(SEED))
    out = tmp_path / "out"
    r = subprocess.run([sys.executable, "-m", "metamaterial_wb", "sleeve", str(spec), "--out", str(out), "--quiet",
                        "--no-plots", "--fe-check", "stiffness"], cwd=REPO, capture_output=True, text=True,
                       timeout=600, env=_env(fake_ccx(tmp_path, kind)))
    assert r.returncode == 0, r.stderr
    assert "Traceback" not in r.stderr
    warn = [ln for ln in r.stderr.splitlines() if ln.startswith("warning: ")]
    assert len(warn) == 1 and "fe check failed" in warn[0] and "sleeve_ring3d" in warn[0]
    s = json.loads((out / "summary.json").read_text())
    assert s["ring"]["peaks"] and s["accuracy"]["fe_check"]["failed"].startswith("ccx ")
    assert any(n.startswith("fe check failed") for n in s["accuracy"]["notes"])
