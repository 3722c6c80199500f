"""Sheet geometry against closed forms of the parameters: counts, volumes, bounding boxes, validity.

Every expected number below is computed here from the parameters (docs/fabrication.md), not taken
from the builder.
"""
import math

import pytest

from fabhelpers import make_scene

C, LH, W, TH = 20.0, 2.0, 0.8, 7.0          # scene defaults: cell, hinge length / width / thickness
S = C - LH                                   # plate side
NECK, DEPTH, MARGIN = 1.0, 2.0, 1.2          # anchor defaults
R_S, LIP, LIP_H, INSET = 1.6, 0.5, 1.5, 3.5  # socket defaults


def socket_vol(T=TH):
    return math.pi * (R_S ** 2 * (T - 2 * LIP_H) + 2 * (R_S + LIP) ** 2 * LIP_H)


def hinge_vol(tilt_deg=0.0, t=TH, gap=LH):
    wn = W / math.cos(math.radians(tilt_deg))
    wa = wn + MARGIN
    u1 = gap / 2 + NECK
    return (2 * u1 * wn + 2 * DEPTH * wa) * t


def anchor_vol(tilt_deg=0.0, t=TH):
    wn = W / math.cos(math.radians(tilt_deg))
    return (DEPTH * (wn + MARGIN) + NECK * wn) * t


def expected_node_volume(topo, ij, tilts, stubs):
    """Plate - sockets - one anchor pocket per attached hinge (+ rigid stubs around short hinges)."""
    i, j = ij
    v = S * S * TH - 4 * socket_vol()
    for name in (f"H{i},{j}", f"H{i},{j - 1}", f"V{i},{j}", f"V{i - 1},{j}"):
        if name in topo.joint_index:
            v -= anchor_vol(tilts.get(name, 0.0))
            if name in stubs:
                half = (LH - stubs[name]) / 2
                wn = W / math.cos(math.radians(tilts.get(name, 0.0)))
                v += half * (wn + MARGIN + 0.8) * TH - half * wn * TH    # stub: anchor + two nozzle widths
    return v


def test_chain_counts_and_names(chain_result):
    r = chain_result
    assert r.count("node") == 2 * 4 and r.count("hinge") == 1 * 4 + 3 * 2
    names = {q.name for q in r.parts}
    assert {"node_0_0", "node_1_3", "hinge_H0_2", "hinge_V0_3"} <= names
    assert all(q.material == "PLA" and q.extruder == 1 for q in r.parts if q.role == "node")
    assert all(q.material == "TPU" and q.extruder == 2 for q in r.parts if q.role == "hinge")


def test_chain_volumes(chain_result):
    r = chain_result
    topo = r.scene.topology
    for q in r.parts:
        vol = r.placed_shape(q).Volume
        if q.role == "hinge":
            assert vol == pytest.approx(hinge_vol(), rel=1e-9)
        else:
            ij = tuple(int(x) for x in q.info["node"][1:].split(","))
            assert vol == pytest.approx(expected_node_volume(topo, ij, {}, {}), rel=1e-9), q.name


def test_chain_bounding_boxes(chain_result, fc):
    r = chain_result
    bb = fc.BoundBox()
    for q in r.parts:
        bb.add(r.placed_shape(q).BoundBox)
    assert (bb.XMin, bb.XMax) == pytest.approx((-S / 2, 3 * C + S / 2))
    assert (bb.YMin, bb.YMax) == pytest.approx((-C - S / 2, S / 2))
    assert (bb.ZMin, bb.ZMax) == pytest.approx((0.0, TH))
    n = r.placed_shape(r.by_name("node_1_2")).BoundBox
    assert (n.XMin, n.XMax, n.YMin, n.YMax) == pytest.approx((2 * C - S / 2, 2 * C + S / 2, -C - S / 2, -C + S / 2))
    # H0,1 (i+j odd): bottom corners of N0,1 / N0,2, flush with the bottom edge line y = -S/2
    h = r.placed_shape(r.by_name("hinge_H0_1")).BoundBox
    span = LH + 2 * (NECK + DEPTH)
    assert (h.XMin, h.XMax) == pytest.approx((1.5 * C - span / 2, 1.5 * C + span / 2))
    assert (h.YMin, h.YMax) == pytest.approx((-S / 2, -S / 2 + W + MARGIN))
    # V0,0 (even): right corners of N0,0 / N1,0, flush with x = +S/2
    v = r.placed_shape(r.by_name("hinge_V0_0")).BoundBox
    assert (v.XMin, v.XMax) == pytest.approx((S / 2 - W - MARGIN, S / 2))
    assert (v.YMin, v.YMax) == pytest.approx((-C / 2 - span / 2, -C / 2 + span / 2))


def test_grid_counts_volumes_tilts_and_stubs(grid_result):
    r = grid_result
    topo = r.scene.topology
    assert r.count("node") == 16 and r.count("hinge") == 24
    tilts = {"H1,1": 20.0, "V1,2": -15.0}
    stubs = {"H0,0": 1.2}
    for q in r.parts:
        vol = r.placed_shape(q).Volume
        if q.role == "hinge":
            # a shorter hinge still spans the gap; only its free length changes (the stubs are rigid)
            assert vol == pytest.approx(hinge_vol(tilts.get(q.info["joint"], 0.0)), rel=1e-9), q.name
        else:
            ij = tuple(int(x) for x in q.info["node"][1:].split(","))
            assert vol == pytest.approx(expected_node_volume(topo, ij, tilts, stubs), rel=1e-9), q.name
    # every node of a 4 x 4 node grid differs (corners, edges, parity, tilts); hinges repeat
    assert len([k for k in r.shapes if k[0] == "hinge"]) == 5     # untilted x 2 sides, 2 tilted, 1 short


def test_tilted_hinge_leans_towards_the_fold_vector(grid_result):
    """H1,1 has tilt +20 deg: its top face is shifted by T tan(20) towards f = u x z = -y."""
    r = grid_result
    shape = r.placed_shape(r.by_name("hinge_H1_1"))
    top = [f for f in shape.Faces if abs(f.CenterOfMass.z - TH) < 1e-9][0]
    bottom = [f for f in shape.Faces if abs(f.CenterOfMass.z) < 1e-9][0]
    shift = top.CenterOfMass.y - bottom.CenterOfMass.y
    assert shift == pytest.approx(-TH * math.tan(math.radians(20.0)), abs=1e-9)
    bb = shape.BoundBox
    wa = W / math.cos(math.radians(20)) + MARGIN
    # i+j = 2 even: top corners, the plate lies at y < -C + S/2; the lean stays inside the plate line
    assert bb.YMax == pytest.approx(-C + S / 2) and bb.YMax - bb.YMin == pytest.approx(wa + TH * math.tan(math.radians(20)))


def test_stub_shortens_the_free_hinge(grid_result):
    """H0,0 is 1.2 mm long in a 2 mm gap: each node grows a 0.4 mm rigid stub around the neck."""
    r = grid_result
    n = r.placed_shape(r.by_name("node_0_0")).BoundBox
    assert n.XMax == pytest.approx(S / 2 + (LH - 1.2) / 2)
    n1 = r.placed_shape(r.by_name("node_0_1")).BoundBox
    assert n1.XMin == pytest.approx(C - S / 2 - (LH - 1.2) / 2)


def test_all_solids_valid_and_overlap_only_at_anchors(chain_result, grid_result):
    from metamaterial_wb.geometry import validity
    for r in (chain_result, grid_result):
        assert validity.check_solids(r) == []
        assert validity.check_sheet(r) == []


def test_overlap_check_catches_a_missing_pocket(fc, chain_result):
    """Mutation: a node without the anchor pockets must be reported (the check can fail)."""
    from metamaterial_wb.geometry import validity
    from metamaterial_wb.geometry.parts import BuildResult
    import Part
    r = chain_result
    bad = BuildResult(r.scene, r.params)
    bad.shapes = dict(r.shapes)
    bad.parts = list(r.parts)
    key = r.by_name("node_0_1").key
    bad.shapes[key] = Part.makeBox(S, S, TH, fc.Vector(-S / 2, -S / 2, 0))
    problems = validity.check_sheet(bad)
    assert any("share" in p for p in problems)


def test_unique_shapes_built_once(fc, monkeypatch):
    from metamaterial_wb.geometry import build, sheet
    calls = {"node": 0, "hinge": 0}
    real_node, real_hinge = sheet.make_node, sheet.make_hinge

    def count_node(*a, **k):
        calls["node"] += 1
        return real_node(*a, **k)

    def count_hinge(*a, **k):
        calls["hinge"] += 1
        return real_hinge(*a, **k)

    monkeypatch.setattr(sheet, "make_node", count_node)
    monkeypatch.setattr(sheet, "make_hinge", count_hinge)
    r = build.build_scene(make_scene({"grid": [6, 6]}), progress=False)
    assert r.count("node") == 49 and r.count("hinge") == 84
    assert calls["node"] == len([k for k in r.shapes if k[0] == "node"]) <= 18
    # hinge prototypes: one per (spec, side) plus the pocket cutters inside the node variants
    assert len([k for k in r.shapes if k[0] == "hinge"]) == 2


def test_progress_goes_to_stderr(fc, capsys):
    from metamaterial_wb.geometry.build import build_scene
    build_scene(make_scene({"grid": [2, 2]}), progress=True)
    out, err = capsys.readouterr()
    assert out == "" and "build: sheet parts 21/21 done" in err


def test_hinge_thinner_than_the_sheet(fc):
    """A 5 mm hinge in an 8 mm sheet sits on the mid-plane in blind anchor pockets."""
    from metamaterial_wb.geometry import validity
    from metamaterial_wb.geometry.build import build_scene
    r = build_scene(make_scene({"chain": 1}, hinge={"length_mm": 2, "width_mm": 0.8, "thickness_mm": 5},
                               fabrication={"sheet_thickness_mm": 8.0}), progress=False)
    h = r.placed_shape(r.by_name("hinge_H0_0")).BoundBox
    assert (h.ZMin, h.ZMax) == pytest.approx((1.5, 6.5))
    n = r.placed_shape(r.by_name("node_0_0"))
    assert n.Volume == pytest.approx(S * S * 8.0 - 4 * socket_vol(8.0) - 2 * anchor_vol(t=5.0), rel=1e-9)
    assert validity.check_solids(r) == [] and validity.check_sheet(r) == []


def test_cli_check_flag(tmp_path):
    import json
    import os
    import subprocess
    import sys
    from fabhelpers import REPO
    sp = tmp_path / "s.json"
    sp.write_text(json.dumps({"format": "metamaterial-scene", "version": 1, "name": "two", "layout": {"chain": 2}}))
    r = subprocess.run([sys.executable, "-m", "metamaterial_wb", "build", str(sp), "--out", str(tmp_path / "o"),
                        "--check", "--3mf"], cwd=REPO, capture_output=True, encoding="utf-8", errors="replace", timeout=300)
    assert r.returncode == 0, r.stderr
    assert "checks passed" in r.stderr
    assert sorted(os.listdir(tmp_path / "o")) == ["manifest.json", "two_sheet.3mf", "two_sheet_components.3mf"]
    assert [os.path.basename(x) for x in r.stdout.split()] == ["two_sheet.3mf", "two_sheet_components.3mf",
                                                               "manifest.json"]
    m = json.load(open(tmp_path / "o" / "manifest.json"))
    assert m["checks"]["ran"] == ["solids", "sheet"] and m["checks"]["skipped"] == ["modules"]


def test_hinges_sit_on_the_kinematic_corners(chain_result):
    """The corner each hinge joins in core/kinematics.py (its own corner table) is the outer corner of the
    printed hinge's neck: on the plate edge line the hinge is flush with, at the plate face."""
    from metamaterial_wb.core import kinematics
    r = chain_result
    topo = r.scene.topology
    a, b, ra, rb, _ = kinematics._hinge_geometry(r.scene)
    centres = kinematics.flat_positions_mm(r.scene)
    for k, name in enumerate(topo.joint_names):
        kind, rest = name[0], name[1:]
        i, j = (int(x) for x in rest.split(","))
        bb = r.placed_shape(r.by_name(f"hinge_{kind}{i}_{j}")).BoundBox
        for node, off in ((a[k], ra[k]), (b[k], rb[k])):
            cx, cy = centres[node][0] + off[0], centres[node][1] + off[1]
            # inside the hinge's footprint, on its flush side
            assert bb.XMin - 1e-9 <= cx <= bb.XMax + 1e-9 and bb.YMin - 1e-9 <= cy <= bb.YMax + 1e-9, name
            if kind == "H":
                assert min(abs(cy - bb.YMin), abs(cy - bb.YMax)) < 1e-9, name
            else:
                assert min(abs(cx - bb.XMin), abs(cx - bb.XMax)) < 1e-9, name
