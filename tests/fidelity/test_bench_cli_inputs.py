"""``bench fidelity``'s inputs and outputs: bad --from-json / --fe-json files and empty selections are refused
with one line naming the option (exit 2, nothing written); outputs that collide with each other or with an
input are refused before any work; the FE study with not-reached (NaN) figures is written by --fe-json-out as
strict JSON and reads back to the same report; the report credits the command and the measurement it shows."""
import json
import os
import time

import pytest

from metamaterial_wb.cli import main

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
STORED_FE = os.path.join(REPO, "benchmarks", "results", "fe-study.json")


def bench(capsys, *argv):
    """``(exit code, stdout, stderr)`` of ``bench fidelity argv``, run in this process."""
    capsys.readouterr()
    rc = main(["bench", "fidelity", "--quiet", *map(str, argv)])
    out, err = capsys.readouterr()
    return rc, out, err


@pytest.fixture(scope="module")
def raw(tmp_path_factory):
    """One small real run (chain, amplitude 0.05): its report and its raw-figures JSON."""
    d = tmp_path_factory.mktemp("raw")
    rc = main(["bench", "fidelity", "--quiet", "--scenes", "chain", "--amplitudes", "0.05", "--repeats", "1",
               "--out", str(d / "b1.md"), "--img", str(d / "b1.png"), "--json", str(d / "b1.json")])
    assert rc == 0
    return d


def refused(rc, err, flag, *files):
    assert rc == 2, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"error: {flag}:"), err
    assert "Traceback" not in err
    for f in files:
        assert not os.path.exists(f), f


# ---------------------------------------------------------------------------------------------------------
# 1. bad input files and empty selections
# ---------------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("content, words", [
    ("[1, 2]", "a list"),
    ('{"results": [{"foo": 1}]}', "results[0] has no 'key'"),
    ('{"results": [{"key": "chain", "rows": []}]}', "no 'amplitude'"),
    ('{"results": [{"key": "chain", "amplitude": 0.05, "rows": [1]}]}', "results[0].rows"),
    ('{"results": 5}', "'results' is a number (5)"),
    ('{"results": []}', "holds no results"),
])
def test_malformed_from_json_is_refused(tmp_path, capsys, content, words):
    src = tmp_path / "in.json"
    src.write_text(content, encoding="utf-8")
    rc, _, err = bench(capsys, "--from-json", src, "--out", tmp_path / "r.md", "--img", tmp_path / "r.png")
    refused(rc, err, "--from-json", tmp_path / "r.md", tmp_path / "r.png")
    assert words in err and "in.json" in err


@pytest.mark.parametrize("flag, value, held", [("--amplitudes", "0.5", "0.05"), ("--scenes", "grid10", "chain")])
def test_selection_not_in_from_json_is_refused(raw, tmp_path, capsys, flag, value, held):
    rc, _, err = bench(capsys, "--from-json", raw / "b1.json", flag, value, "--out", tmp_path / "r.md",
                       "--img", tmp_path / "r.png")
    refused(rc, err, flag, tmp_path / "r.md", tmp_path / "r.png")
    assert value in err and f"holds {held}" in err


@pytest.mark.parametrize("flag, value", [("--scenes", ","), ("--scenes", ""), ("--amplitudes", ""),
                                         ("--amplitudes", " , ")])
def test_option_naming_nothing_is_refused(tmp_path, capsys, flag, value):
    """Before the fix ``--scenes ,`` crashed and ``--amplitudes ""`` silently ran the default amplitudes."""
    t0 = time.perf_counter()
    rc, _, err = bench(capsys, flag, value, "--out", tmp_path / "r.md", "--img", tmp_path / "r.png")
    refused(rc, err, flag, tmp_path / "r.md", tmp_path / "r.png")
    assert "names no" in err and time.perf_counter() - t0 < 5.0      # refused before any model ran


@pytest.mark.parametrize("content, words", [("[1, 2]", "a JSON list, expected an object"),
                                            ('{"stiffness": null}', "incomplete or malformed")])
def test_malformed_fe_json_is_refused(raw, tmp_path, capsys, content, words):
    src = tmp_path / "fe.json"
    src.write_text(content, encoding="utf-8")
    for fe in ([], ["--fe", "--fe-parts", "hinge"]):
        rc, _, err = bench(capsys, *fe, "--fe-json", src, "--from-json", raw / "b1.json", "--out", tmp_path / "r.md",
                           "--img", tmp_path / "r.png")
        refused(rc, err, "--fe-json", tmp_path / "r.md", tmp_path / "r.png")
        assert words in err and "fe.json" in err


# ---------------------------------------------------------------------------------------------------------
# 2. --fe-json-out with the stored study (NaN figures of the sleeve ring)
# ---------------------------------------------------------------------------------------------------------
def _strict(text):
    def no_constant(c):
        raise ValueError(f"non-standard JSON constant {c}")
    return json.loads(text, parse_constant=no_constant)


def test_fe_json_out_writes_strict_json_that_renders_the_same_report(raw, tmp_path, capsys):
    copy = tmp_path / "fj-copy.json"
    rc, out, err = bench(capsys, "--fe", "--fe-parts", "hinge", "--fe-json", STORED_FE, "--fe-json-out", copy,
                         "--from-json", raw / "b1.json", "--out", tmp_path / "a.md", "--img", tmp_path / "a.png")
    assert rc == 0, err
    first = (tmp_path / "a.md").read_text(encoding="utf-8")
    assert "### Sleeve cell and ring" in first and (tmp_path / "a.png").stat().st_size > 1000
    data = _strict(copy.read_text(encoding="utf-8"))            # no NaN literal: strict JSON
    stored = json.load(open(STORED_FE, encoding="utf-8"))
    pv = stored["sleeve"]["ring"]["fe"][0]["pv"]
    assert pv[2] != pv[2]                                        # the stored study does hold NaN there
    assert data["sleeve"]["ring"]["fe"][0]["pv"][2] is None
    assert ["sleeve", "ring", "fe", 0, "pv", 2] in data["nan_paths"]
    assert data["sleeve_calibration"]["trace"]["info"]["stopped"] is None   # a genuine null stays one
    assert "nan_paths" not in stored
    # read back: the same report (but for the file named in the command), and the same plot
    rc, _, err = bench(capsys, "--fe", "--fe-parts", "hinge", "--fe-json", copy, "--from-json", raw / "b1.json",
                       "--out", tmp_path / "b.md", "--img", tmp_path / "b.png")
    assert rc == 0, err
    second = (tmp_path / "b.md").read_text(encoding="utf-8")
    assert second.replace(str(copy), STORED_FE).replace("fj-copy.json", "fe-study.json").replace("b.png", "a.png") \
        == first
    assert (tmp_path / "b.png").read_bytes() == (tmp_path / "a.png").read_bytes()


def test_fe_json_out_is_checked_before_any_work(raw, tmp_path, capsys):
    (tmp_path / "adir").mkdir()
    rc, _, err = bench(capsys, "--fe", "--fe-parts", "hinge", "--fe-json", STORED_FE, "--fe-json-out",
                       tmp_path / "adir", "--from-json", raw / "b1.json", "--out", tmp_path / "r.md",
                       "--img", tmp_path / "r.png")
    refused(rc, err, "--fe-json-out", tmp_path / "r.md", tmp_path / "r.png")


# ---------------------------------------------------------------------------------------------------------
# 3. outputs that collide with each other or with an input
# ---------------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("extra, flag, other", [
    (["--img", "{d}/s.md"], "--img", "--out"),
    (["--img", "{d}/s.png", "--json", "{d}/s.md"], "--json", "--out"),
    (["--img", "{d}/s.png", "--json", "{d}/sub/../s.png"], "--json", "--img"),
    (["--img", "{d}/s.png", "--fe", "--fe-parts", "hinge", "--fe-json", STORED_FE, "--fe-json-out", "{d}/s.png"],
     "--fe-json-out", "--img"),
])
def test_outputs_naming_the_same_file_are_refused(raw, tmp_path, capsys, extra, flag, other):
    (tmp_path / "sub").mkdir()
    args = [a.replace("{d}", str(tmp_path)) for a in extra]
    rc, _, err = bench(capsys, "--from-json", raw / "b1.json", "--out", tmp_path / "s.md", *args)
    refused(rc, err, flag, tmp_path / "s.md", tmp_path / "s.png")
    assert f"also the {other} file" in err


def test_output_that_is_the_input_is_refused(raw, tmp_path, capsys):
    src = tmp_path / "b2.json"
    src.write_bytes((raw / "b1.json").read_bytes())
    before = src.read_bytes()
    rc, _, err = bench(capsys, "--from-json", src, "--out", src, "--img", tmp_path / "r.png")
    refused(rc, err, "--out", tmp_path / "r.png")
    assert "--from-json file this command reads" in err and src.read_bytes() == before
    rc, _, err = bench(capsys, "--from-json", raw / "b1.json", "--fe-json", src, "--out", tmp_path / "r.md",
                       "--img", tmp_path / "r.png", "--json", src)
    refused(rc, err, "--json", tmp_path / "r.md", tmp_path / "r.png")
    assert "--fe-json file this command reads" in err and src.read_bytes() == before


# ---------------------------------------------------------------------------------------------------------
# 4. the command and the measurement the report credits
# ---------------------------------------------------------------------------------------------------------
def test_report_credits_the_command_and_the_recorded_measurement(raw, tmp_path, capsys):
    text = (raw / "b1.md").read_text(encoding="utf-8")
    assert "Generated by `python3 -m metamaterial_wb bench fidelity --repeats 1 --scenes chain --amplitudes 0.05`" \
        in text
    data = json.load(open(raw / "b1.json", encoding="utf-8"))
    m = data["measured"]
    assert m["date"] == time.strftime("%Y-%m-%d", time.gmtime()) and m["cores"] == os.cpu_count()
    assert m["repeats"] == 1 and "--scenes chain" in m["command"]
    # rendered from the JSON: its recorded date and machine, not today's and this one's
    m.update(date="2001-02-03", cores=64, python="3.9.1", arch="aarch64", load_average=1.0)
    src = tmp_path / "old-run.json"
    src.write_text(json.dumps(data), encoding="utf-8")
    rc, _, err = bench(capsys, "--from-json", src, "--scenes", "chain", "--out", tmp_path / "r.md",
                       "--img", tmp_path / "r.png")
    assert rc == 0, err
    text = (tmp_path / "r.md").read_text(encoding="utf-8")
    assert f"Generated by `python3 -m metamaterial_wb bench fidelity --from-json {src} --scenes chain`" in text
    assert "Measured 2001-02-03 on 64 cores, Python 3.9.1 (aarch64)" in text
    assert "Figures read from `old-run.json` (measured by `python3 -m metamaterial_wb bench fidelity --repeats 1" \
        in text
    assert time.strftime("%Y-%m-%d", time.gmtime()) not in text and "best of 1 run," in text
    # an older file without the record: said so, nothing invented
    del data["measured"]
    src.write_text(json.dumps(data), encoding="utf-8")
    rc, _, err = bench(capsys, "--from-json", src, "--out", tmp_path / "r.md", "--img", tmp_path / "r.png")
    assert rc == 0, err
    text = (tmp_path / "r.md").read_text(encoding="utf-8")
    assert "Measured: date and machine not recorded (figures read from `old-run.json`" in text
    assert time.strftime("%Y-%m-%d", time.gmtime()) not in text and f"{os.cpu_count()} cores" not in text
    assert "best of several runs (how many was not recorded)" in text
