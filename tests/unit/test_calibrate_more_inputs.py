"""More inputs of ``calibrate`` (docs/calibration.md, section 2), from an audit:

* a test piece whose joints set ``k1`` / ``k2`` directly is refused before the fit, naming the joints and why (the
  fit computes k1 / k2 from the hinge sizes; the pinned values were silently ignored);
* the thickness note names the table it compares with (``--table FILE`` or the shipped table) and quotes that
  table's reference thickness;
* typed numbers are read strictly (no ``1_0``, no non-ASCII digits, no inf / nan, no subnormals): the angle cells
  of ANGLES.csv (the error names the file, the row and the column), the node names' digits, and the items of
  ``--lengths`` / ``--widths`` (the error names the flag and the item).
"""
import json
import os
import sys

import pytest

from metamaterial_wb.core import calibrate as C
from metamaterial_wb.core.calibration import _DEFAULT_PATH
from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.core.scene import Scene

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from test_calibrate_cli_inputs import cli, one_line_error, synthetic_angles, write_piece  # noqa: E402


def shipped():
    with open(_DEFAULT_PATH, encoding="utf-8") as f:
        return json.load(f)


def with_joints(scene, joints):
    d = json.loads(scene.to_json())
    d["joints"] = d.get("joints", []) + joints
    return Scene.from_dict(d)


# ---- 1: joints that pin k1 / k2 ---------------------------------------------------------------------------------
PINNED = [
    ([{"joint": "H2,2", "k1": 0.5}], ["H2,2 (k1 0.5)"]),
    ([{"joint": "V1,1", "k2": 3.0}, {"joint": "H0,0", "k1": 0.7, "k2": 2.0}], ["H0,0 (k1 0.7, k2 2)", "V1,1 (k2 3)"]),
]


@pytest.mark.parametrize("joints, shown", PINNED, ids=["one-k1", "k2-and-both"])
def test_a_piece_whose_joints_pin_k1_or_k2_is_refused_by_the_cli(tmp_path, joints, shown):
    sc = with_joints(C.test_piece(2.0), joints)
    pj, pc = write_piece(tmp_path, sc, synthetic_angles(sc, 0.9))
    out = tmp_path / "t.json"
    r = cli("measured", pj, pc, "--out", out)
    one_line_error(r, "joints")
    for s in shown:
        assert s in r.stderr, r.stderr
    assert "hinge sizes" in r.stderr and "remove" in r.stderr, r.stderr
    assert r.stdout == "" and not out.exists()


def test_a_piece_whose_joints_pin_k1_is_refused_by_the_library():
    sc = with_joints(C.test_piece(2.0, right_width_mm=1.6), [{"joint": "H1,1", "k1": 0.6}])
    deg = synthetic_angles(sc, 0.9, k2_ratio=6.0)
    import numpy as np
    with pytest.raises(SceneError) as e:
        C.fit_measured(sc, np.arange(sc.topology.n_nodes), np.radians(deg))
    assert e.value.field == "joints" and "H1,1 (k1 0.6)" in e.value.message


def test_size_overrides_alone_are_still_fitted(tmp_path):
    """Joints that only set sizes (the two-width piece) are fitted as before: the check is about k1 / k2."""
    sc = C.test_piece(2.0, right_width_mm=1.6)
    pj, pc = write_piece(tmp_path, sc, synthetic_angles(sc, 0.9, k2_ratio=6.0))
    r = cli("measured", pj, pc)
    assert r.returncode == 0, r.stderr
    assert r.stdout.startswith("k1 = 0.9"), r.stdout


# ---- 2: the thickness note quotes the table used -----------------------------------------------------------------
def test_the_thickness_note_quotes_the_table_given_with_table(tmp_path):
    sc = C.test_piece(2.0, thickness_mm=5.0)
    pj, pc = write_piece(tmp_path, sc, synthetic_angles(sc, 0.9))
    t = shipped()
    t["k2_thickness_reference_mm"] = 6.0
    table = tmp_path / "t6.json"
    table.write_text(json.dumps(t), encoding="utf-8")
    out = tmp_path / "o.json"
    r = cli("measured", pj, pc, "--table", table, "--out", out)
    assert r.returncode == 0, r.stderr
    note = [ln for ln in r.stdout.splitlines() if ln.startswith("note:")]
    assert len(note) == 1, r.stdout
    assert "reference thickness 6 mm (--table " in note[0] and str(table) in note[0], note
    assert "7 mm" not in note[0] and "shipped" not in note[0], note
    # a table whose reference is the piece's thickness: no note
    t["k2_thickness_reference_mm"] = 5.0
    table.write_text(json.dumps(t), encoding="utf-8")
    out.unlink()
    r = cli("measured", pj, pc, "--table", table, "--out", out)
    assert r.returncode == 0 and "note:" not in r.stdout, (r.stdout, r.stderr)


def test_the_thickness_note_names_the_shipped_table_without_table(tmp_path):
    sc = C.test_piece(2.0, thickness_mm=5.0)
    pj, pc = write_piece(tmp_path, sc, synthetic_angles(sc, 0.9))
    r = cli("measured", pj, pc)
    assert r.returncode == 0, r.stderr
    note = [ln for ln in r.stdout.splitlines() if ln.startswith("note:")]
    assert len(note) == 1 and "reference thickness 7 mm (the shipped table, " in note[0], r.stdout


# ---- 3: typed numbers ---------------------------------------------------------------------------------------------
BAD_ANGLES = [("1_0", "is not a number"), ("\u0663", "is not a number"), ("\uff13", "is not a number"),
              ("inf", "is not a number"), ("nan", "is not a number"), ("1e999", "beyond the largest"),
              ("1e-310", "subnormal")]


@pytest.mark.parametrize("cell, words", BAD_ANGLES, ids=["underscore", "arabic-indic", "full-width", "inf", "nan",
                                                          "overflow", "subnormal"])
@pytest.mark.parametrize("form", ["quoted", "three-columns"])
def test_an_angle_cell_is_read_strictly_naming_file_row_and_column(tmp_path, cell, words, form):
    sc = C.test_piece(2.0)
    p = tmp_path / "bad.csv"
    node = '"N0,1"' if form == "quoted" else "N0,1"
    p.write_text(f"node,angle_deg\n\"N0,0\",1.0\n{node},{cell}\n\"N1,0\",2.0\n", encoding="utf-8")
    with pytest.raises(SceneError) as e:
        C.read_angles_csv(str(p), sc)
    col = 2 if form == "quoted" else 3
    assert e.value.field == f"{p}:3 column {col} (angle_deg)", e.value.field
    assert repr(cell) in e.value.message and words in e.value.message, e.value.message


def test_an_angle_cell_is_read_strictly_by_the_cli(tmp_path):
    sc = C.test_piece(2.0)
    pj, pc = write_piece(tmp_path, sc, synthetic_angles(sc, 0.9))
    lines = pc.read_text(encoding="utf-8").splitlines()
    node = lines[4].split(",")[:2]
    lines[4] = ",".join(node + ["1_0"])
    pc.write_text("\n".join(lines) + "\n", encoding="utf-8")
    out = tmp_path / "t.json"
    r = cli("measured", pj, pc, "--out", out)
    one_line_error(r, f"{pc}:5 column 2 (angle_deg)")
    assert "'1_0'" in r.stderr and r.stdout == "" and not out.exists()


def test_good_angle_cells_are_still_read(tmp_path):
    sc = C.test_piece(2.0)
    p = tmp_path / "ok.csv"
    p.write_text("node,angle_deg\n\"N0,0\", 1.5\nN0,1,-2e-1\n\"N1,0\",+.5\n\"N1,1\",0\n", encoding="utf-8")
    idx, ang = C.read_angles_csv(str(p), sc)
    assert list(ang) == pytest.approx([0.02617993877991494, -0.003490658503988659, 0.008726646259971648, 0.0])


@pytest.mark.parametrize("name", ["N\u0663,1", "N0,\uff11"], ids=["arabic-indic", "full-width"])
def test_a_node_name_with_non_ascii_digits_is_refused(tmp_path, name):
    sc = C.test_piece(2.0)
    p = tmp_path / "bad.csv"
    p.write_text(f"node,angle_deg\n\"N0,0\",1.0\n\"{name}\",2.0\n", encoding="utf-8")
    with pytest.raises(SceneError) as e:
        C.read_angles_csv(str(p), sc)
    assert e.value.field == f"{p}:3" and "is not a node name" in e.value.message, str(e.value)


@pytest.mark.parametrize("flag, text, item, shown, words", [
    ("--lengths", "2,1_0", 2, "1_0", "is not a number"),
    ("--lengths", "\u0662\u0660", 1, "\u0662\u0660", "is not a number"),      # Arabic-Indic 20
    ("--lengths", "2,1e-310", 2, "1e-310", "subnormal"),
    ("--lengths", "2,1e999", 2, "1e999", "beyond the largest"),
    ("--widths", "0.8,\uff13\uff10", 2, "\uff13\uff10", "is not a number"),  # full-width 30
], ids=["underscore", "arabic-indic", "subnormal", "overflow", "full-width"])
def test_size_items_are_read_strictly_naming_the_flag_and_the_item(tmp_path, flag, text, item, shown, words):
    out = tmp_path / "t.json"
    other = ("--widths", "0.8") if flag == "--lengths" else ("--lengths", "2")
    r = cli("model", flag, text, *other, "--out", out)
    one_line_error(r, flag)
    assert f"item {item}" in r.stderr and repr(shown) in r.stderr and words in r.stderr, r.stderr
    assert "allowed range" in r.stderr, r.stderr
    assert "k1: hinge length" not in r.stderr and not out.exists() and r.stdout == ""
