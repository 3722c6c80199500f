"""``bench fidelity --fe-json-out`` wrote its FE study without a format marker, unlike every other JSON report
(``"format": "metamaterial-..."``, session 33): read as a scene it was "not a scene" without saying what it is,
and ``--fe-json`` took any JSON object whose keys rendered, also another document carrying its own marker. Now
the file carries ``"format": "metamaterial-fe-study", "version": 1``; ``--fe-json`` reads it back, refuses another
format naming it (and another version), and still reads a file written before the marker (the stored study),
silently, as scenes and targets without "format" are read. Fast: the raw figures are test_bench_cli_flags's small
file and the FE study the stored one (no model, no CalculiX runs)."""
import json
import os
import sys

import pytest

from clihelpers import one_line_error, run_cli


sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from test_bench_cli_flags import RAW, STORED_FE, bench  # noqa: E402


@pytest.fixture
def raw(tmp_path):
    """A one-scene run's raw figures (every invocation passes --from-json: no model runs)."""
    p = tmp_path / "run.json"
    p.write_text(json.dumps(RAW), encoding="utf-8")
    return p


def stored():
    with open(STORED_FE, encoding="utf-8") as fh:
        return json.load(fh)           # NaN figures as NaN (the stored file holds them as literals)


def refused(rc, err, *files):
    assert rc == 2, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: --fe-json:"), err
    for f in files:
        assert not os.path.exists(f), f


def test_fe_json_out_carries_the_marker_and_reads_back(raw, tmp_path, capsys):
    fj = tmp_path / "fe.json"
    rc, _, err = bench(capsys, "--fe", "--fe-parts", "hinge", "--fe-json", STORED_FE, "--fe-json-out", fj,
                       "--from-json", raw, "--out", tmp_path / "a.md", "--img", tmp_path / "a.png")
    assert rc == 0, err
    data = json.loads(fj.read_text(encoding="utf-8"))
    assert (data["format"], data["version"]) == ("metamaterial-fe-study", 1), list(data)[:3]
    assert list(data)[:2] == ["format", "version"]
    rc, _, err = bench(capsys, "--fe-json", fj, "--from-json", raw, "--out", tmp_path / "b.md",
                       "--img", tmp_path / "b.png")
    assert rc == 0 and err == "", err
    a, b = ((tmp_path / n).read_text(encoding="utf-8") for n in ("a.md", "b.md"))
    assert "## FE top rung" in b
    # the FE section is the same: the marker is not taken for a figure of the study
    assert b[b.index("## FE top rung"):].split("FE figures read from")[0] == \
        a[a.index("## FE top rung"):].split("FE figures read from")[0]


def test_the_written_study_read_as_a_scene_says_what_it_is(raw, tmp_path, capsys):
    fj = tmp_path / "fe.json"
    rc, _, err = bench(capsys, "--fe", "--fe-parts", "hinge", "--fe-json", STORED_FE, "--fe-json-out", fj,
                       "--from-json", raw, "--out", tmp_path / "a.md", "--img", tmp_path / "a.png")
    assert rc == 0, err
    r = run_cli("solve", fj, "--out", tmp_path / "r.json")
    one_line_error(r, "format")
    assert "'metamaterial-fe-study' is not a scene (it is a bench --fe-json-out FE study)" in r.stderr, r.stderr


@pytest.mark.parametrize("fmt, named", [("metamaterial-fidelity", "a bench fidelity file"),
                                        ("metamaterial-result", "a result of solve"),
                                        ("metamaterial-scene", "a scene"), ("my-own-format", None)])
@pytest.mark.parametrize("fe", [[], ["--fe", "--fe-parts", "hinge"]], ids=["read", "fe-run"])
def test_another_format_is_refused_naming_it(raw, tmp_path, capsys, fmt, named, fe):
    """The study's own figures with another document's marker: it was read as an FE study (exit 0)."""
    src = tmp_path / "other.json"
    src.write_text(json.dumps({"format": fmt, "version": 1, **stored()}), encoding="utf-8")
    rc, _, err = bench(capsys, *fe, "--fe-json", src, "--from-json", raw, "--out", tmp_path / "r.md",
                       "--img", tmp_path / "r.png")
    refused(rc, err, tmp_path / "r.md", tmp_path / "r.png")
    assert f"other.json': its format is {fmt!r}" in err, err
    assert (f"({named}), not an FE study" if named else f"{fmt!r}, not an FE study") in err, err
    assert "expected 'metamaterial-fe-study' (a file written by --fe-json-out)" in err, err


@pytest.mark.parametrize("version", [2, "1", 1.0, True, None])
def test_another_version_is_refused(raw, tmp_path, capsys, version):
    src = tmp_path / "v.json"
    marked = {"format": "metamaterial-fe-study", **stored()}
    if version is not None:
        marked["version"] = version
    src.write_text(json.dumps(marked), encoding="utf-8")
    rc, _, err = bench(capsys, "--fe-json", src, "--from-json", raw, "--out", tmp_path / "r.md",
                       "--img", tmp_path / "r.png")
    refused(rc, err, tmp_path / "r.md", tmp_path / "r.png")
    assert f"version {version!r} of 'metamaterial-fe-study' is not supported" in err, err


def test_a_study_written_before_the_marker_still_reads(raw, tmp_path, capsys):
    assert "format" not in stored()                        # the stored study predates the marker
    rc, _, err = bench(capsys, "--fe-json", STORED_FE, "--from-json", raw, "--out", tmp_path / "r.md",
                       "--img", tmp_path / "r.png")
    assert rc == 0 and err == "", err
    assert "## FE top rung" in (tmp_path / "r.md").read_text(encoding="utf-8")
