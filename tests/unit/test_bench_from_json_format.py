"""``bench fidelity --from-json`` did not look at its file's format marker (session 33): an FE study written by
``--fe-json-out`` (``"format": "metamaterial-fe-study"``) failed only with "an object without 'results'", a scene
the same way, and another document carrying a 'results' list was read as raw figures. Now the marker is checked
as ``--fe-json`` checks its own: another format is refused naming it and the one expected
(``'metamaterial-fidelity'``, a file written by ``--json``), another version too; a file without "format" is read
as it is. Fast: the small raw figures of test_bench_cli_flags, no model runs."""
import json
import os
import sys

import pytest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from test_bench_cli_flags import RAW, bench, outs  # noqa: E402


def _file(tmp_path, doc, name="in.json"):
    p = tmp_path / name
    p.write_text(json.dumps(doc), encoding="utf-8")
    return p


def _refused(rc, err, tmp_path):
    lines = err.strip().splitlines()
    assert rc == 2 and len(lines) == 1 and lines[0].startswith("error: --from-json: "), err
    assert not (tmp_path / "r.md").exists() and not (tmp_path / "r.png").exists()
    return lines[0]


@pytest.mark.parametrize("fmt, named", [("metamaterial-fe-study", "a bench --fe-json-out FE study"),
                                        ("metamaterial-scene", "a scene"),
                                        ("metamaterial-result", "a result of solve"), ("my-own-format", None)])
@pytest.mark.parametrize("with_results", [False, True], ids=["its-own-keys", "with-results"])
def test_another_format_is_refused_naming_it(tmp_path, capsys, fmt, named, with_results):
    body = {k: v for k, v in RAW.items() if k not in ("format", "version")} if with_results else {"patch": []}
    src = _file(tmp_path, {"format": fmt, "version": 1, **body})
    line = _refused(*bench(capsys, "--from-json", src, *outs(tmp_path))[::2], tmp_path)
    assert f"in.json': its format is {fmt!r}" in line, line
    assert (f"({named}), not raw figures" if named else f"{fmt!r}, not raw figures") in line, line
    assert "expected 'metamaterial-fidelity' (a file written by --json)" in line, line


@pytest.mark.parametrize("version", [2, "1", 1.0, True, None])
def test_another_version_is_refused(tmp_path, capsys, version):
    doc = dict(RAW)
    if version is None:
        del doc["version"]
    else:
        doc["version"] = version
    line = _refused(*bench(capsys, "--from-json", _file(tmp_path, doc), *outs(tmp_path))[::2], tmp_path)
    assert f"version {version!r} of 'metamaterial-fidelity' is not supported" in line, line


def test_the_marked_file_and_one_without_a_marker_render(tmp_path, capsys):
    for doc in (RAW, {k: v for k, v in RAW.items() if k not in ("format", "version")}):
        rc, _, err = bench(capsys, "--from-json", _file(tmp_path, doc), *outs(tmp_path))
        assert rc == 0, err
        assert "Measured 2001-02-03" in (tmp_path / "r.md").read_text(encoding="utf-8")
        os.remove(tmp_path / "r.md")
