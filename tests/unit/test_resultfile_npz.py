"""``read_result`` on the JSON half of a ``solve --npz`` result: it returned zero nodes and no arrays (audit C).
It now reads the ``.npz`` file the JSON names, from beside it, and says so when that file is missing."""
import json
import os
import shutil
import subprocess
import sys

import numpy as np
import pytest

from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.core.resultfile import read_result

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
WORM = os.path.join(ROOT, "examples", "worm.json")


@pytest.fixture(scope="module")
def pair(tmp_path_factory):
    d = tmp_path_factory.mktemp("npz")
    r = subprocess.run([sys.executable, "-m", "metamaterial_wb", "solve", WORM, "--out", str(d / "a.json"), "--npz"],
                       capture_output=True, text=True, cwd=ROOT, env=dict(os.environ, PYTHONPATH=ROOT), timeout=300)
    assert r.returncode == 0, r.stderr
    return d


def test_the_json_half_reads_the_arrays_beside_it(pair):
    meta, a = read_result(pair / "a.json")
    _, b = read_result(pair / "a.npz")
    assert a["ij"].shape == (18, 2) and a["D"].shape == (18,) and a["rotation"].shape == (18, 3, 3)
    assert sorted(a) == sorted(b)
    for k in b:
        np.testing.assert_array_equal(a[k], b[k])
    assert meta["format"] == "metamaterial-result" and meta["arrays"]["file"] == "a.npz"


def test_the_arrays_are_found_beside_the_json_from_another_working_folder(pair, tmp_path, monkeypatch):
    shutil.copy(pair / "a.json", tmp_path / "a.json")
    shutil.copy(pair / "a.npz", tmp_path / "a.npz")
    monkeypatch.chdir(pair.parent)
    _, a = read_result(str(tmp_path / "a.json"))
    assert a["ij"].shape == (18, 2)


def test_a_missing_arrays_file_is_an_error_naming_it(pair, tmp_path):
    shutil.copy(pair / "a.json", tmp_path / "a.json")
    with pytest.raises(SceneError) as e:
        read_result(tmp_path / "a.json")
    assert str(tmp_path / "a.npz") in str(e.value) and "missing" in str(e.value)


def test_an_arrays_name_with_a_folder_is_refused(pair, tmp_path):
    doc = json.loads((pair / "a.json").read_text(encoding="utf-8"))
    doc["arrays"]["file"] = "../a.npz"
    (tmp_path / "a.json").write_text(json.dumps(doc), encoding="utf-8")
    with pytest.raises(SceneError, match=r"arrays\.file: '\.\./a\.npz'"):
        read_result(tmp_path / "a.json")


def test_arrays_of_another_result_are_refused(pair, tmp_path):
    doc = json.loads((pair / "a.json").read_text(encoding="utf-8"))
    doc["arrays"]["keys"] = doc["arrays"]["keys"] + ["extra_field"]
    (tmp_path / "a.json").write_text(json.dumps(doc), encoding="utf-8")
    shutil.copy(pair / "a.npz", tmp_path / "a.npz")
    with pytest.raises(SceneError, match="extra_field"):
        read_result(tmp_path / "a.json")
