"""Inputs of ``calibrate measured`` and of the calibration table (docs/calibration.md, section 2).

* Every entry of a calibration table is a real number (a JSON ``true`` or a quoted ``"0.9"`` is not taken as a
  number), finite and in its range (lengths and widths > 0); ``source`` is text or absent. A bad entry is refused
  before any fit, naming the table file, the field with its index and the value, and nothing is written.
* A measured test piece has one hinge length and one hinge thickness on every joint (k1 is filed under one length);
  a piece with several is refused naming the values and joints, before any fit.
"""
import copy
import json
import os
import sys

import numpy as np
import pytest

from metamaterial_wb.core import calibrate as C
from metamaterial_wb.core.calibration import _DEFAULT_PATH, Calibration
from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.core.scene import Scene

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from test_calibrate_cli_inputs import cli, one_line_error, synthetic_angles, write_piece  # noqa: E402


def shipped():
    with open(_DEFAULT_PATH, encoding="utf-8") as f:
        return json.load(f)


@pytest.fixture
def piece(tmp_path):
    sc = C.test_piece(2.0)
    return write_piece(tmp_path, sc, synthetic_angles(sc, 0.9))


# (path into the table, value, field named in the error, value shown)
BAD_ENTRIES = [
    (("k1_vs_length", "k1", 0), True, "k1_vs_length.k1[0]", "True"),
    (("k1_vs_length", "k1", 0), "0.9", "k1_vs_length.k1[0]", "'0.9'"),
    (("k1_vs_length", "k1", 2), None, "k1_vs_length.k1[2]", "None"),
    (("k1_vs_length", "k1", 1), 1.5, "k1_vs_length.k1[1]", "1.5"),
    (("k1_vs_length", "length_mm", 0), 0, "k1_vs_length.length_mm[0]", "0"),
    (("k1_vs_length", "length_mm", 0), -0.25, "k1_vs_length.length_mm[0]", "-0.25"),
    (("k1_vs_length", "length_mm", 3), False, "k1_vs_length.length_mm[3]", "False"),
    (("k2_vs_width", "width_mm", 0), 0, "k2_vs_width.width_mm[0]", "0"),
    (("k2_vs_width", "width_mm", 2), "0.6", "k2_vs_width.width_mm[2]", "'0.6'"),
    (("k2_vs_width", "factor", 3), True, "k2_vs_width.factor[3]", "True"),
    (("k2_vs_width", "factor", 0), [0.01], "k2_vs_width.factor[0]", "[0.01]"),
    (("k2_thickness_reference_mm",), True, "k2_thickness_reference_mm", "True"),
    (("k2_thickness_reference_mm",), "7", "k2_thickness_reference_mm", "'7'"),
    (("source",), None, "source", "None"),
    (("source",), 5, "source", "5"),
]
IDS = [f"{'.'.join(map(str, p))}={v!r}" for p, v, _, _ in BAD_ENTRIES]


def with_entry(table, path, value):
    t = copy.deepcopy(table)
    node = t
    for k in path[:-1]:
        node = node[k]
    node[path[-1]] = value
    return t


# ---- 1: every table entry is checked, naming the file, the field and the value ---------------------------------
@pytest.mark.parametrize("path, value, field, shown", BAD_ENTRIES, ids=IDS)
def test_load_refuses_a_bad_entry_naming_file_field_and_value(tmp_path, path, value, field, shown):
    p = tmp_path / "my-table.json"
    p.write_text(json.dumps(with_entry(shipped(), path, value)), encoding="utf-8")
    with pytest.raises(SceneError) as e:
        Calibration.load(str(p))
    msg = str(e.value)
    assert f"calibration.{field}" in msg and shown in msg and "my-table.json" in msg, msg


@pytest.mark.parametrize("path, value, field, shown", BAD_ENTRIES, ids=IDS)
def test_measured_refuses_a_bad_table_entry_before_the_fit(tmp_path, piece, path, value, field, shown):
    pj, pc = piece
    table = tmp_path / "bad-table.json"
    table.write_text(json.dumps(with_entry(shipped(), path, value)), encoding="utf-8")
    out = tmp_path / "out.json"
    r = cli("measured", pj, pc, "--table", table, "--out", out)
    one_line_error(r, "--table")
    assert "bad-table.json" in r.stderr and f"calibration.{field}" in r.stderr and shown in r.stderr, r.stderr
    assert r.stdout == "" and not out.exists()         # no fit printed, nothing written


def test_an_absent_source_is_fine_and_the_update_appends_to_nothing(tmp_path, piece):
    pj, pc = piece
    t = shipped()
    del t["source"]
    Calibration(t)
    table = tmp_path / "no-source.json"
    table.write_text(json.dumps(t), encoding="utf-8")
    out = tmp_path / "out.json"
    r = cli("measured", pj, pc, "--table", table, "--out", out)
    assert r.returncode == 0, r.stderr
    written = json.loads(out.read_text(encoding="utf-8"))
    assert written["source"].startswith("Updated from measured angles")
    assert all(type(v) is float for v in written["k1_vs_length"]["k1"])


def test_the_shipped_table_and_a_written_update_load():
    cal = Calibration.load()
    assert cal.t_ref == 7.0 and cal.k1(2.0) == shipped()["k1_vs_length"]["k1"][3]
    t = C.update_table(shipped(), 2.5, 0.95, 0.9, 1.3)
    Calibration(t)
    with pytest.raises(SceneError, match=r"calibration\.k1_vs_length\.k1\[0\]: expected a number, got True"):
        Calibration(with_entry(shipped(), ("k1_vs_length", "k1", 0), True))


@pytest.mark.parametrize("table, field", [
    ([1, 2], "calibration"),
    ({"k1_vs_length": {"length_mm": "1,2", "k1": [0.9, 0.8]}, "k2_vs_width": {"width_mm": [0.8], "factor": [1]}},
     "calibration.k1_vs_length.length_mm"),
    ({"k1_vs_length": {"length_mm": [1, 2], "k1": [0.9, 0.8]}, "k2_vs_width": [0.8]}, "calibration.k2_vs_width"),
], ids=["not-an-object", "a-string-for-a-list", "a-list-for-an-object"])
def test_a_table_of_the_wrong_shape_is_refused_naming_where(table, field):
    with pytest.raises(SceneError) as e:
        Calibration(table)
    assert e.value.field == field, str(e.value)


# ---- 2: one hinge length and one thickness per measured piece --------------------------------------------------
def mixed_piece(key, value):
    d = json.loads(C.test_piece(2.0).to_json())
    d["joints"] = [{"joint": f"H{r},{c}", key: value} for r in range(6) for c in range(3, 5)]
    return Scene.from_dict(d)


@pytest.mark.parametrize("key, value, base, shown", [("length_mm", 6.0, 2.0, "hinge lengths"),
                                                     ("thickness_mm", 3.0, 7.0, "hinge thicknesses")])
def test_fit_measured_refuses_several_lengths_or_thicknesses(key, value, base, shown):
    sc = mixed_piece(key, value)
    deg = synthetic_angles(sc, 0.9)
    idx = np.arange(sc.topology.n_nodes)
    with pytest.raises(SceneError) as e:
        C.fit_measured(sc, idx, np.radians(deg))
    msg = str(e.value)
    assert e.value.field == "joints" and shown in msg, msg
    assert f"{value:g} mm" in msg and f"{base:g} mm" in msg, msg               # the values
    assert "H0,3" in msg, msg                                                   # a joint with the odd size


def test_measured_cli_refuses_several_lengths_and_writes_nothing(tmp_path):
    sc = mixed_piece("length_mm", 6.0)
    pj, pc = write_piece(tmp_path, sc, synthetic_angles(sc, 0.9))
    out = tmp_path / "out.json"
    r = cli("measured", pj, pc, "--out", out)
    one_line_error(r, "joints")
    assert "6 mm" in r.stderr and "2 mm" in r.stderr and "H0,3" in r.stderr
    assert r.stdout == "" and not out.exists()


def test_a_piece_of_another_thickness_is_fitted_with_a_note(tmp_path):
    sc = C.test_piece(2.0, thickness_mm=3.0)
    pj, pc = write_piece(tmp_path, sc, synthetic_angles(sc, 0.9))
    r = cli("measured", pj, pc)
    assert r.returncode == 0, r.stderr
    assert "k1 = 0.900000" in r.stdout
    assert "note: the piece's hinge thickness 3 mm differs from the table's reference thickness 7 mm" in r.stdout


def test_k1_is_filed_under_the_joints_length_not_an_unused_default():
    d = json.loads(C.test_piece(2.0).to_json())
    sc0 = Scene.from_dict(d)
    d["joints"] = [{"joint": n, "length_mm": 3.0} for n in sc0.topology.joint_names]   # every joint: 3 mm
    sc = Scene.from_dict(d)
    deg = synthetic_angles(sc, 0.9)
    fit = C.fit_measured(sc, np.arange(sc.topology.n_nodes), np.radians(deg))
    assert fit["length_mm"] == 3.0 and fit["thickness_mm"] == 7.0 and abs(fit["k1"] - 0.9) < 1e-4
