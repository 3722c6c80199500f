"""``calibrate``'s inputs are checked before any work and a fit the data do not determine is never written
(docs/calibration.md): sizes checked up front naming the flag, non-finite fits refused, fits on their search bound
refused, the k2 ratio labelled and normalised by the piece's own base width, flags that do not apply refused, an
output equal to an input refused, a bad --table named as such."""
import json
import os

import numpy as np
import pytest

from metamaterial_wb.core import calibrate as C
from metamaterial_wb.core.calibration import Calibration
from metamaterial_wb.core.errors import MetamaterialError, SceneError
from metamaterial_wb.core.lattice.geometry import LatticeGeometry
from metamaterial_wb.core.solver import QuadraticModel, scene_groups
from clihelpers import one_line_error, run_cli  # noqa: F401 (one_line_error: shared with other test files)

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def cli(*args):
    return run_cli("calibrate", *args)


def synthetic_angles(scene, k1, k2_ratio=1.0):
    """Node angles (deg) of the quadratic model with known k1 and k2(other width) / k2(base width)."""
    topo = scene.topology
    base_w = scene.hinge["width_mm"]
    k2 = np.array([1.0 if scene.joint_hinge(n)["width_mm"] == base_w else k2_ratio for n in topo.joint_names])
    m = QuadraticModel(topo.n_nodes, topo.joint_pairs, np.full(topo.n_joints, k1), k2, scene_groups(scene))
    D = m.solve([it.value for _, it in scene.fixed_items()])
    return np.degrees(LatticeGeometry(scene).phi_from_D(D))


def write_piece(tmp_path, scene, deg):
    pj = tmp_path / "piece.json"
    pj.write_text(scene.to_json())
    pc = tmp_path / "angles.csv"
    pc.write_text("node,angle_deg\n" + "".join(f"\"N{i},{j}\",{deg[k]:.12f}\n"
                                               for k, (i, j) in enumerate(scene.topology.nodes)))
    return pj, pc


@pytest.fixture
def piece(tmp_path):
    sc = C.test_piece(2.0)
    return write_piece(tmp_path, sc, synthetic_angles(sc, 0.9))


# ---- 1: sizes -------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("flag, text, shown", [
    ("--lengths", "1e-9", "1e-09"), ("--lengths", "1e-300", "1e-300"), ("--lengths", "2,nan", "nan"),
    ("--lengths", "2,inf", "inf"), ("--lengths", "2,30", "30.0"), ("--lengths", "2,10", "10.0"),
    ("--widths", "0.8,50", "50.0"), ("--widths", "0.01,0.8", "0.01"), ("--widths", "0.8,4.6", "4.6"),
])
def test_model_sizes_are_checked_before_any_fit(tmp_path, flag, text, shown):
    out = tmp_path / "t.json"
    other = ("--widths", "0.8") if flag == "--lengths" else ("--lengths", "2")
    r = cli("model", flag, text, *other, "--out", out)
    one_line_error(r, flag)
    assert shown in r.stderr and "allowed range" in r.stderr, r.stderr
    assert "k1: hinge length" not in r.stderr and "k2: hinge width" not in r.stderr      # no fit started
    assert not out.exists() and r.stdout == ""


@pytest.mark.filterwarnings("ignore:invalid value encountered:RuntimeWarning")   # the lattice model's own D scale
def test_a_non_finite_fit_is_refused_naming_the_size():
    with pytest.raises(MetamaterialError, match=r"hinge length 1e-09 mm.*not finite"):
        C.fit_length(1e-9)


def test_model_sizes_checked_by_the_library_too():
    with pytest.raises(SceneError, match=r"^lengths: 30.0 mm is outside"):
        C.fit_table_to_model([2.0, 30.0], [0.8])


# ---- 2: fit on its search bound ---------------------------------------------------------------------------------
@pytest.mark.parametrize("rows, bound", [
    (('"N0,0",0', '"N0,1",0', '"N0,2",0'), "0"),
    (('"N0,0",90', '"N0,1",-90', '"N0,2",90', '"N1,0",-90'), "1"),
], ids=["all-zero", "plus-minus-90"])
def test_k1_on_its_search_bound_is_refused(tmp_path, piece, rows, bound):
    pj, _ = piece
    bad = tmp_path / "z.csv"
    bad.write_text("node,angle_deg\n" + "\n".join(rows) + "\n")
    out = tmp_path / "t.json"
    r = cli("measured", pj, bad, "--out", out)
    one_line_error(r, "k1")
    assert f"search bound {bound}" in r.stderr and "RMS residual" in r.stderr, r.stderr
    assert not out.exists()


@pytest.mark.parametrize("ratio, words", [
    (1e7, "search bound 10000 of [0.0001, 10000]"),            # on the search bound: not determined
    # a 1.6 mm hinge fitted as half as stiff as the 0.8 mm one would sit below the 1.2 mm factor: not written
    (0.5, "at width 1.6 mm does not lie between its neighbours"),
], ids=["on-its-bound", "breaks-the-tables-order"])
def test_a_k2_ratio_that_cannot_enter_the_table_is_refused(tmp_path, ratio, words):
    sc = C.test_piece(2.0, right_width_mm=1.6)
    pj, pc = write_piece(tmp_path, sc, synthetic_angles(sc, 0.9, k2_ratio=ratio))
    out = tmp_path / "t.json"
    r = cli("measured", pj, pc, "--out", out)
    one_line_error(r, "k2 ratio")
    assert words in r.stderr and not out.exists(), r.stderr


# ---- 3: k2 ratio label and normalisation ------------------------------------------------------------------------
@pytest.mark.parametrize("base, right, ratio", [(1.2, 0.8, 1 / 3), (0.8, 1.6, 6.0)], ids=["base-wider", "base-ref"])
def test_k2_ratio_label_and_table_follow_the_base_width(tmp_path, base, right, ratio):
    sc = C.test_piece(2.0, width_mm=base, right_width_mm=right)
    pj, pc = write_piece(tmp_path, sc, synthetic_angles(sc, 0.9, k2_ratio=ratio))
    out = tmp_path / "t.json"
    r = cli("measured", pj, pc, "--out", out)
    assert r.returncode == 0, r.stderr
    line = r.stdout.splitlines()[0]
    assert f"k2 ratio (width {right} / {base} mm) = " in line, line
    assert float(line.rsplit("=", 1)[1]) == pytest.approx(ratio, rel=5e-2)
    t = json.loads(out.read_text())
    w = t["k2_vs_width"]
    assert w["factor"][w["width_mm"].index(0.8)] == 1.0                 # the reference width keeps factor 1
    cal = Calibration(t)
    assert cal.k2(right, cal.t_ref) / cal.k2(base, cal.t_ref) == pytest.approx(ratio, rel=5e-2)


# ---- 4: flags that do not apply ---------------------------------------------------------------------------------
@pytest.mark.parametrize("extra, flag, other", [
    (("--lengths", "1"), "--lengths", "calibrate measured"),
    (("--widths", "0.8"), "--widths", "calibrate measured"),
    (("--table", "{table}"), "--table", "--out"),
], ids=["lengths", "widths", "table-without-out"])
def test_measured_refuses_flags_it_would_ignore(tmp_path, piece, extra, flag, other):
    pj, pc = piece
    table = tmp_path / "in.json"
    table.write_text(open(os.path.join(REPO, "metamaterial_wb", "core", "data", "calibration.json")).read())
    r = cli("measured", pj, pc, *[e.format(table=table) for e in extra])
    one_line_error(r, flag)
    assert other in r.stderr and r.stdout == ""


def test_model_refuses_table(tmp_path):
    r = cli("model", "--lengths", "2", "--widths", "0.8", "--table", tmp_path / "x.json")
    one_line_error(r, "--table")
    assert "calibrate measured" in r.stderr and r.stdout == ""


# ---- 5: output equal to an input -------------------------------------------------------------------------------
@pytest.mark.parametrize("target", ["angles", "piece", "table", "link-to-angles"])
def test_out_equal_to_an_input_is_refused(tmp_path, piece, target):
    pj, pc = piece
    table = tmp_path / "in.json"
    table.write_text(open(os.path.join(REPO, "metamaterial_wb", "core", "data", "calibration.json")).read())
    link = tmp_path / "link.csv"
    os.symlink(pc, link)
    out = {"angles": pc, "piece": pj, "table": table, "link-to-angles": link}[target]
    named = {"angles": pc, "piece": pj, "table": table, "link-to-angles": pc}[target]
    before = {p: p.read_bytes() for p in (pj, pc, table)}
    r = cli("measured", pj, pc, "--table", table, "--out", out)
    one_line_error(r, "--out")
    assert os.path.basename(str(named)) in r.stderr and r.stdout == "", r.stderr
    assert {p: p.read_bytes() for p in (pj, pc, table)} == before


# ---- 6: bad --table --------------------------------------------------------------------------------------------
@pytest.mark.parametrize("content", ['{"k1_vs_length": 3}', '{"k1_vs_length": {"length_mm": [1, 2], "k1": [0.9, 2]},'
                                     ' "k2_vs_width": {"width_mm": [0.8], "factor": [1]}}'], ids=["shape", "k1-range"])
def test_bad_table_names_the_flag_and_the_file(tmp_path, piece, content):
    pj, pc = piece
    table = tmp_path / "bad-table.json"
    table.write_text(content)
    out = tmp_path / "t.json"
    r = cli("measured", pj, pc, "--table", table, "--out", out)
    one_line_error(r, "--table")
    assert "bad-table.json" in r.stderr and r.stdout == "" and not out.exists()


def test_out_equal_to_the_default_table_is_refused(piece):
    pj, pc = piece
    shipped = os.path.join(REPO, "metamaterial_wb", "core", "data", "calibration.json")
    before = open(shipped, "rb").read()
    r = cli("measured", pj, pc, "--out", shipped)
    one_line_error(r, "--out")
    assert "shipped table" in r.stderr and open(shipped, "rb").read() == before


# ---- an audit of the scene format and calibrate (session 26) -------------------------------------------------
def test_an_empty_item_in_a_size_list_is_refused(tmp_path):
    """``--lengths 2,,3`` silently dropped the empty item."""
    r = cli("model", "--lengths", "2,,3", "--widths", "0.8", "--out", tmp_path / "t.json")
    one_line_error(r, "--lengths")
    assert "empty item" in r.stderr


def test_a_header_after_comment_lines_is_read_as_a_header(tmp_path):
    """A comment line before ``node,angle_deg`` made the header line 2, read as data ('node' is not a node name)."""
    sc = C.test_piece(2.0)
    _, pc = write_piece(tmp_path, sc, synthetic_angles(sc, 0.9))
    text = pc.read_text()
    pc.write_text("# measured 2026-12-06, caliper\n\n" + text)
    idx, ang = C.read_angles_csv(str(pc), sc)
    assert len(idx) == sc.topology.n_nodes
    pc.write_text("# a comment\n" + text.splitlines()[1] + "\n" + text)   # a header after data is still refused
    with pytest.raises(SceneError):
        C.read_angles_csv(str(pc), sc)


def test_set_twice_for_one_item_is_refused():
    from metamaterial_wb.cli.solve import parse_sets
    with pytest.raises(SceneError) as e:
        parse_sets(["m1=0.2", "m1=0.9"])
    assert e.value.field == "--set m1" and "twice" in str(e.value)
