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
    # without --fe the stored CalculiX study (benchmarks/results/fe-study.json) is rendered, not dropped: the
    # README's command regenerates docs/fidelity.md without losing its FE rung
    for heading in ("## FE top rung: one hinge in CalculiX", "### Hinge stiffness", "### 3 x 3 patch",
                    "### Sleeve cell and ring: the beam model against CalculiX"):
        assert heading in text, heading
    assert "FE figures read from `fe-study.json` (a stored `--fe` run; `--fe` runs CalculiX again)." in text
    # the reference is the nonlinear model converged in the number of hinge elements: its error falls as the
    # hinges are refined, the 8-element level sits at the reference's own uncertainty
    assert "Reference convergence in the number of elements per hinge" in text

    def err(prefix):
        rows = [ln for ln in text.splitlines() if ln.startswith(prefix)]
        return [float(ln.split("|")[3].split("+-")[0]) for ln in rows]

    one = err("| nonlinear (R2), tol 1e-8")
    two, four, eight = (err(f"| nonlinear (R2), {n} elements per hinge, tol 1e-11") for n in (2, 4, 8))
    assert len(one) == len(two) == len(four) == len(eight) == 2
    for a, b, c, d in zip(one, two, four, eight):
        assert a > b > c > d


def test_bench_rejects_unknown_scene(tmp_path):
    r = subprocess.run([sys.executable, "-m", "metamaterial_wb", "bench", "fidelity", "--out", str(tmp_path / "f.md"),
                        "--scenes", "donut"], cwd=REPO, capture_output=True, text=True)
    assert r.returncode == 2 and "donut" in r.stderr and not (tmp_path / "f.md").exists()


def test_bench_without_stored_fe_study_says_how_to_get_it(tmp_path):
    """``--fe-json`` naming a file that is not there, without ``--fe``: a clear error, nothing written."""
    r = subprocess.run([sys.executable, "-m", "metamaterial_wb", "bench", "fidelity", "--out", str(tmp_path / "f.md"),
                        "--fe-json", str(tmp_path / "none.json"), "--scenes", "chain"], cwd=REPO, capture_output=True,
                       text=True)
    assert r.returncode == 2 and "none.json" in r.stderr and "--fe-json" in r.stderr
    assert not (tmp_path / "f.md").exists()
