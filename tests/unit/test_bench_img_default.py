"""``bench fidelity --out rep.md`` (no ``--img``) wrote its plot to ``docs/img/fidelity-work-precision.png``
relative to the working folder, whatever ``--out`` said (session 35 audit): in an empty folder it made
``./docs/img/``, run from the checkout it overwrote the tracked docs picture; ``--help`` gave no default. The
same for ``--sleeves-img`` when ``--sleeves-out`` is given. And ``--img out/f.txt`` wrote a PNG under a .txt
name, where ``render`` insists on .png.

Now: with ``--out`` and without ``--img`` the plot goes beside the report, ``<out stem>-work-precision.png``
(with ``--sleeves-out`` and without ``--sleeves-img``: ``<sleeves-out stem>-fe-check.png``); without ``--out``
the documented defaults stay (docs/img/...), and ``--help`` shows them; an image name not ending in .png is
refused naming the flag, nothing written. Fast: the figures come from test_bench_cli_flags's small --json file
(and the stored FE study), except one run of the smallest scene as the audit ran it."""
import json
import os
import re
import sys

from clihelpers import REPO, one_line_error, run_cli

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from test_bench_cli_flags import RAW, STORED_FE  # noqa: E402

DOCS_PNG = os.path.join(REPO, "docs", "img", "fidelity-work-precision.png")
DOCS_SLEEVE_PNG = os.path.join(REPO, "docs", "img", "sleeve-fe-check.png")


def _stamp(p):
    return os.stat(p).st_mtime_ns if os.path.exists(p) else None


def _raw(tmp_path):
    p = tmp_path / "run.json"
    p.write_text(json.dumps(RAW), encoding="utf-8")
    return p


def test_help_shows_the_image_defaults():
    r = run_cli("bench", "--help")
    assert r.returncode == 0, r.stderr
    text = re.sub(r"-\s+", "-", " ".join(r.stdout.split()))      # argparse wraps lines after a hyphen
    assert "<out stem>-work-precision.png" in text and "docs/img/fidelity-work-precision.png" in text
    assert "<sleeves-out stem>-fe-check.png" in text and "docs/img/sleeve-fe-check.png" in text


def test_the_plot_goes_beside_out(tmp_path):
    """The audit's command (one chain scene, one timing run): the plot beside the report, linked from it; the
    docs picture untouched, no docs/ folder made in the working folder."""
    before = _stamp(DOCS_PNG)
    out = tmp_path / "rep.md"
    r = run_cli("bench", "fidelity", "--out", out, "--scenes", "chain", "--amplitudes", "0.05", "--repeats", "1",
                "--quiet")
    assert r.returncode == 0, r.stderr
    png = tmp_path / "rep-work-precision.png"
    assert png.read_bytes()[:4] == b"\x89PNG"
    assert "](rep-work-precision.png)" in out.read_text(encoding="utf-8")
    assert str(png) in r.stdout
    assert _stamp(DOCS_PNG) == before
    assert sorted(os.listdir(tmp_path)) == ["rep-work-precision.png", "rep.md"]


def test_the_sleeve_plot_goes_beside_sleeves_out(tmp_path):
    before = _stamp(DOCS_SLEEVE_PNG), _stamp(DOCS_PNG)
    doc = tmp_path / "s.md"
    doc.write_text("# Sleeves\n\n## Sequencing\n", encoding="utf-8")
    r = run_cli("bench", "fidelity", "--from-json", _raw(tmp_path), "--fe", "--fe-parts", "sleeve", "--fe-json",
                STORED_FE, "--sleeves-out", doc, "--out", tmp_path / "r.md", "--quiet")
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "s-fe-check.png").read_bytes()[:4] == b"\x89PNG"
    assert "](s-fe-check.png)" in doc.read_text(encoding="utf-8")
    assert (tmp_path / "r-work-precision.png").exists()
    assert (_stamp(DOCS_SLEEVE_PNG), _stamp(DOCS_PNG)) == before


def test_an_image_name_not_ending_in_png_is_refused(tmp_path):
    raw = _raw(tmp_path)
    r = run_cli("bench", "fidelity", "--from-json", raw, "--out", tmp_path / "r.md", "--img", tmp_path / "f.txt",
                "--quiet")
    one_line_error(r, "--img")
    assert "f.txt" in r.stderr and ".png" in r.stderr
    doc = tmp_path / "s.md"
    doc.write_text("# Sleeves\n", encoding="utf-8")
    r = run_cli("bench", "fidelity", "--from-json", raw, "--fe", "--fe-parts", "sleeve", "--fe-json", STORED_FE,
                "--sleeves-out", doc, "--sleeves-img", tmp_path / "s.jpg", "--out", tmp_path / "r.md",
                "--img", tmp_path / "r.png", "--quiet")
    one_line_error(r, "--sleeves-img")
    assert "s.jpg" in r.stderr
    assert sorted(os.listdir(tmp_path)) == ["run.json", "s.md"]       # nothing written
    assert doc.read_text(encoding="utf-8") == "# Sleeves\n"
