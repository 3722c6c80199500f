"""``bench fidelity``: one command writes the report and the work-precision plot (reduced run here)."""
import os
import subprocess
import sys

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def test_bench_fidelity_writes_report_and_plot(tmp_path):
    md = tmp_path / "docs" / "fidelity.md"
    png = tmp_path / "docs" / "img" / "wp.png"
    r = subprocess.run([sys.executable, "-m", "metamaterial_wb", "bench", "fidelity", "--out", str(md), "--img", str(png),
                        "--scenes", "chain,bending", "--amplitudes", "0.05", "--repeats", "1", "--quiet"],
                       cwd=REPO, capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    text = md.read_text()
    assert "](img/wp.png)" in text
    for label in ("quadratic (R0)", "linear lattice (R1)", "nonlinear (R2), tol 1e-2", "RMS dD", "max pos. err"):
        assert label in text
    assert text.count("| chain | 0.05 |") == 1 and text.count("| bending | 0.05 |") == 1
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    # the reference agrees with itself: the tightest nonlinear row has (near) zero error
    rows = [ln for ln in text.splitlines() if ln.startswith("| nonlinear (R2), tol 1e-8")]
    assert rows and all(float(ln.split("|")[3]) < 1e-6 for ln in rows)


def test_bench_rejects_unknown_scene(tmp_path):
    r = subprocess.run([sys.executable, "-m", "metamaterial_wb", "bench", "fidelity", "--out", str(tmp_path / "f.md"),
                        "--scenes", "donut"], cwd=REPO, capture_output=True, text=True)
    assert r.returncode == 2 and "donut" in r.stderr and not (tmp_path / "f.md").exists()
