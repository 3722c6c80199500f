"""``solve --fields`` and ``solve --npz`` (issue 18, item 6): the binary result holds exactly the JSON
result's numbers, field selection leaves the rest out, bad input writes nothing."""
import json

import numpy as np
import pytest

from metamaterial_wb import example_path
from metamaterial_wb.cli import main
from metamaterial_wb.core.resultfile import read_result


def _solve(tmp_path, name, *extra):
    out = tmp_path / name
    assert main(["solve", example_path("fish"), "--out", str(out), *extra]) == 0
    return out


def test_npz_holds_the_json_results_numbers(tmp_path):
    ref = json.loads(_solve(tmp_path, "ref.json").read_text())
    out = _solve(tmp_path, "bin.json", "--npz")
    small = json.loads(out.read_text())
    assert "nodes" not in small and "joints" not in small
    assert small["arrays"]["file"] == "bin.npz" and small["fields"] == ["D", "poses", "joints"]
    meta, a = read_result(tmp_path / "bin.npz")
    assert meta["format"] == "metamaterial-result-npz" and meta["scene"] == ref["scene"]
    with np.load(tmp_path / "bin.npz", allow_pickle=False) as z:      # plain numpy, no pickles
        assert z["D"].shape == (len(ref["nodes"]),)
    nodes = ref["nodes"]
    assert a["ij"].tolist() == [[n["i"], n["j"]] for n in nodes]
    assert np.array_equal(a["D"], [n["D"] for n in nodes])
    assert np.array_equal(a["position_mm"], [n["position_mm"] for n in nodes])
    assert np.array_equal(a["rotation"], [n["rotation"] for n in nodes])
    assert np.array_equal(a["rotation_deg"], [n["rotation_deg"] for n in nodes])
    js = ref["joints"]
    assert a["joint_names"].tolist() == [j["name"] for j in js]
    assert np.array_equal(a["joint_fold_deg"], [j["fold_deg"] for j in js])
    assert np.array_equal(a["joint_tilt_deg"], [j["tilt_deg"] for j in js])
    names = [n["name"] for n in nodes]
    assert [[names[p], names[q]] for p, q in a["joint_nodes"]] == [j["nodes"] for j in js]
    # the JSON reader gives the same arrays
    _, b = read_result(tmp_path / "ref.json")
    for k in a:
        assert np.array_equal(a[k], b[k]), k


def test_fields_select_what_is_written(tmp_path):
    res = json.loads(_solve(tmp_path, "d.json", "--fields", "D").read_text())
    assert res["fields"] == ["D"] and "joints" not in res
    assert set(res["nodes"][0]) == {"i", "j", "name", "D"}
    res = json.loads(_solve(tmp_path, "p.json", "--fields", "poses,joints").read_text())
    assert set(res["nodes"][0]) == {"i", "j", "name", "rotation_deg", "position_mm", "rotation"}
    assert len(res["joints"]) > 0
    _solve(tmp_path, "j.json", "--fields", "joints", "--npz")
    _, a = read_result(tmp_path / "j.npz")
    assert "D" not in a and "position_mm" not in a and "joint_fold_deg" in a


@pytest.mark.parametrize("fields", ["D,stress", "", "D,,poses"])
def test_bad_fields_exit_2_and_write_nothing(tmp_path, capsys, fields):
    out = tmp_path / "never.json"
    assert main(["solve", example_path("fish"), "--out", str(out), "--fields", fields, "--npz"]) == 2
    assert "--fields" in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []


def test_npz_gets_the_same_permissions_as_the_json(tmp_path):
    """The .npz beside the JSON is readable as the JSON is (0666 less the umask), not 0600 as a bare mkstemp file,
    and no temporary file is left behind."""
    import os
    import stat
    old = os.umask(0o022)
    try:
        out = _solve(tmp_path, "perm.json", "--npz")
    finally:
        os.umask(old)
    mode = {p.name: stat.S_IMODE(p.stat().st_mode) for p in tmp_path.iterdir()}
    assert mode == {"perm.json": 0o644, "perm.npz": 0o644}, mode
    assert out.exists()
