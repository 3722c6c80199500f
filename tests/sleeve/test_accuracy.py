"""Issue 18: every sleeve summary carries the beam model's measured error against the CalculiX solid
(``core/sleeve/accuracy.py``). The ratios it quotes are the stored results' (so they cannot drift from what
docs/sleeves.md shows), and a sleeve the ratios were not measured for is told so instead of given a number."""
import json
import os

import pytest

from metamaterial_wb.core.sleeve import accuracy as acc
from metamaterial_wb.core.sleeve.cell import CellGeometry
from metamaterial_wb.core.sleeve.model import ROOT_EXTENSION_FE

RESULTS = os.path.join(os.path.dirname(__file__), "..", "..", "benchmarks", "results")


def _load(name):
    with open(os.path.join(RESULTS, name)) as f:
        return json.load(f)


def _ratio(model, model_err, fe, fe_err):
    r = model / fe
    return r, r * ((model_err / model) ** 2 + (fe_err / fe) ** 2) ** 0.5


def test_quoted_ratios_are_the_stored_results():
    study = _load("fe-study.json")
    cal = study["sleeve_calibration"]
    fe_pv, fe_err = cal["fe_cell"]["pv"], cal["fe_cell"]["err"]
    for flavour, key in (("documented", "uncalibrated"), ("calibrated", "calibrated")):
        m = cal["models"][key]
        for name, i in (("CELL_PEAK", 1), ("CELL_VALLEY", 3)):
            r, e = _ratio(m["cell_pv"][i], m["cell_err"][i], fe_pv[i], fe_err[i])
            assert getattr(acc, name)[flavour] == pytest.approx((r, e), abs=2e-3), (name, flavour)
        r, e = _ratio(m["ring_p1"][1], m["ring_p1_err"][1], cal["fe_ring"]["pv"][1], cal["fe_ring"]["err"][1])
        assert acc.FLAT_RING_P1[flavour][0] == pytest.approx(r, abs=2e-3)
        assert acc.FLAT_RING_P1[flavour][1] == pytest.approx(e, abs=3e-3)
    cur = study["sleeve_curved"]
    p1, p1_err = cur["p1_fe"]
    for flavour, key in (("documented", "p1_model"), ("calibrated", "p1_model_calibrated")):
        assert acc.CURVED_RING_P1[flavour][0] == pytest.approx(cur[key] / p1, abs=2e-3)
        assert acc.CURVED_RING_P1[flavour][1] == pytest.approx(cur[key] / p1 * p1_err / p1, abs=2e-3)
    # the ring's initial stiffness: against the solid extrapolated over its meshes r = 1, 2, 3, with that error
    from metamaterial_wb.bench.fe_frame3d import solid_extrapolated
    cells = _load("fe-ring3d-comparison.json")["cells"]
    for flavour, key in (("documented", "model_curved_documented"), ("calibrated", "model_curved")):
        quoted = acc.CURVED_RING_STIFFNESS[flavour]
        assert sorted(quoted) == sorted(int(n) for n in cells)
        for n, row in cells.items():
            fe, err, _ = solid_extrapolated(row)["curved"]
            assert quoted[int(n)][0] == pytest.approx(row[key] / fe, abs=6e-3), (flavour, n)
            assert quoted[int(n)][1] == pytest.approx(row[key] / fe * err / fe, abs=6e-3), (flavour, n)
    assert acc.CALIBRATED_ROOT_EXTENSION == ROOT_EXTENSION_FE
    assert acc.SEED_CELL == {k: getattr(CellGeometry(), k) for k in acc.SEED_CELL}


def test_seed_cell_gets_the_measured_ratios_and_words():
    g = CellGeometry()
    a = acc.accuracy([g], 4, 0.0, True)
    assert a["measured_cell"] and a["model"] == "documented"
    assert a["ring_first_peak"] == acc.CURVED_RING_P1["documented"]
    assert a["ring_initial_stiffness"] == (4.31, 0.24)
    assert any("4.31 +- 0.24 times the curved solid's (extrapolated in its mesh)" in n for n in a["notes"])
    assert any("too high" in n for n in a["notes"]) and any("0.63" in n for n in a["notes"])
    c = acc.accuracy([g], 8, ROOT_EXTENSION_FE, True)
    assert c["model"] == "calibrated" and c["ring_initial_stiffness"] == (2.08, 0.10)
    assert c["ring_first_peak"] is None           # measured on four cells only: null, not missing (audit)
    # a ring size between the measured ones gets the measured neighbours in words, no number of its own
    b = acc.accuracy([g], 5, 0.0, True)
    assert b["ring_initial_stiffness"] is None and "not measured at 5 cells" in b["notes"][0]
    f = acc.accuracy([g], 4, 0.0, False)
    assert f["ring_first_peak"] == acc.FLAT_RING_P1["documented"] and "flat" in f["notes"][0]


@pytest.mark.parametrize("kw,why", [({"t": 1.2}, "not the seed's cell"), ({}, "root_extension 0.3")])
def test_other_sleeves_are_told_the_ratios_are_not_measured(kw, why):
    g = CellGeometry(**kw)
    a = acc.accuracy([g], 4, 0.3 if not kw else 0.0, True)
    assert a["cell_peak"] is None and a["ring_initial_stiffness"] is None
    assert why in a["notes"][0] and "not measured" in a["notes"][0]
    # the range it quotes for the seed's cell spans every measured ratio (the largest: the documented model's
    # four-cell ring stiffness against the extrapolated solid)
    quoted = [v[0] for t in (acc.CELL_PEAK, acc.CELL_VALLEY, acc.FLAT_RING_P1, acc.CURVED_RING_P1) for v in t.values()]
    quoted += [v[0] for t in acc.CURVED_RING_STIFFNESS.values() for v in t.values()]
    assert f"forces were {min(quoted):.1f}-{max(quoted):.1f} times the solid's" in a["notes"][0]
    assert max(quoted) == acc.CURVED_RING_STIFFNESS["documented"][4][0]


def test_the_frames_quoted_match_with_the_solid_is_the_stored_one_and_the_stored_frames_are_current():
    """``FRAME_STIFFNESS_OFF`` (quoted in every frame note) is the stored study's range, and the stored study is what
    the frame gives today (it is deterministic and fast: recomputed here)."""
    from metamaterial_wb.bench import fe_frame3d
    stored = _load("frame3d.json")
    x = fe_frame3d.summary(stored)["extrapolated"]
    assert acc.FRAME_STIFFNESS_OFF == tuple(round(v) for v in x["absolute"])
    assert acc.FRAME_STIFFNESS_REF_ERROR == round(x["error"][1])
    fresh = fe_frame3d.study(_load("fe-ring3d-comparison.json")["cells"], stored["root_extensions"], stored["n_el"])
    for n, row in stored["cells"].items():
        for k, v in row.items():
            if k.startswith("frame_") and k != "frame_s":
                assert fresh["cells"][n][k] == pytest.approx(v, rel=1e-6), (n, k)   # 2e-9 apart on numpy 2 (stiff links)


def test_the_nonlinear_frames_quoted_first_peak_errors_are_the_stored_ones():
    """``FRAME_NL_P1_OFF`` and ``PLANAR_P1_OFF`` (quoted in every nonlinear-frame note) are the stored study's first
    peaks against the curved solid's extrapolated one."""
    from metamaterial_wb.bench import fe_frame3d
    s = _load("frame3d.json")
    frame, planar = fe_frame3d.p1_off(s["nonlinear"], s["fe_family"], s["planar_calibrated"])
    assert (acc.FRAME_NL_P1_OFF, acc.PLANAR_P1_OFF) == (round(frame), round(planar))


def test_frame_nl_note_gives_newtons_millimetres_and_the_ratio():
    base = {"elements": 12, "seconds": 3.2}
    note = acc.frame_nl_note(0, 4, dict(base, P1=1.3e-3, P1_displacement=0.137, ratio=1.8, beam_model_plane="strain"),
                             28 * 18 ** 2, 18)
    assert note.startswith("nonlinear frame, uniform ring of type 0 (4 cells, 12 elements per beam half): first peak "
                           f"{1.3e-3 * 28 * 18 ** 2:.3g} N at {0.137 * 18:.3g} mm")
    assert "the beam model's first peak (plane strain) is 1.80 times it" in note and f"{acc.FRAME_NL_P1_OFF:+d} % off" in note
    assert "no first peak within the traced stroke" in acc.frame_nl_note(0, 4, dict(base, P1=None), 1, 1)
    assert "no first peak (no equilibrium" in acc.frame_nl_note(0, 4, dict(base, error="no equilibrium in 40"), 1, 1)


def test_frame_sequence_note_sets_the_frames_sequence_beside_the_models():
    fs = {"loading": [0, 1], "unloading": [1, 0], "symmetric": True, "lean_reverses": False, "elements": 12,
          "seconds": 27.0, "max_tilt_loading_deg": 3.1, "max_tilt_unloading_deg": 4.4, "agrees_with_model": False}
    seq = {"loading": [1, 0], "unloading": [1, 0], "symmetric": False, "frame3d_nl": fs}
    note = acc.frame_sequence_note(seq)
    assert "loading [0, 1], unloading [1, 0] (symmetric)" in note and "the same way" in note
    assert "the beam model's: loading [1, 0], unloading [1, 0] (asymmetric) - they differ" in note
    assert acc.frame_sequence_note({"frame3d_nl": {"error": "no equilibrium"}}).endswith("none (no equilibrium)")


def test_frame_note_names_the_type_the_ratio_and_the_measured_match():
    note = acc.frame_note(1, 6, {"ratio": 2.345, "seconds": 0.05})
    assert note.startswith("curvature, uniform ring of type 1 (6 cells): the beam model's initial stiffness is 2.35 "
                           "times that of a linear 3-D frame")
    assert f"{acc.FRAME_STIFFNESS_OFF[0]:+.0f} to {acc.FRAME_STIFFNESS_OFF[1]:+.0f} % off the curved solid's" in note


def test_the_solids_snapping_orders_quoted_are_the_stored_runs():
    """``SOLID_ORDERS`` is the stored solid runs' (``fe-ring3d.json``, ``combinations``): the seed's combinations'
    cell types to 1e-3 mm, both combinations' differences extrapolated over three meshes (+- their errors, to
    0.01 %), and the two-hysteron orders on them."""
    from metamaterial_wb.bench import fe_ring3d_combinations as fc
    from metamaterial_wb.bench.fe_frame3d_plate import combination_cells
    solid = _load("fe-ring3d.json")["combinations"]
    assert len(acc.SOLID_ORDERS) == 2
    for key, rec in (("2", acc.SOLID_ORDERS[((1.098, 7.092), (1.098, 7.488))]),
                     ("1", acc.SOLID_ORDERS[((0.99, 6.696), (1.17, 6.696))])):
        types = next(t for t, r in acc.SOLID_ORDERS.items() if r is rec)
        assert [v for g in combination_cells(key) for v in (g.t, g.h)] == pytest.approx(
            [v for th in types for v in th], abs=1e-3)
        ex = fc.extrapolated(solid[key])["differences"]
        assert rec["P1"] == pytest.approx(ex["P1"], abs=0.01) and rec["valley"] == pytest.approx(ex["valley"], abs=0.01)
        assert rec["mesh"] == "extrapolated over three meshes"
        for mesh, rows in solid[key].items():
            order = fc.solid_rule(rows)
            assert (order["loading"], order["unloading"]) == (rec["loading"], rec["unloading"]), (key, mesh)
        # the mixed ring [0, 0, 1, 1] itself as one solid (``mixed_cycles``): its own order and lean on every mesh
        # (static; and each other variant stored: by implicit dynamics, without the bias moment)
        runs = _load("fe-ring3d.json")["mixed_cycles"][key]
        for mesh, run in runs.items():
            for variant in fc.CYCLE_KEYS.values():
                if variant not in run:
                    continue
                seq = fc.cycle_sequence(run[variant])
                assert {k: rec["mixed"][k] for k in ("loading", "unloading", "lean_reverses")} == {
                    "loading": seq["loading"], "unloading": seq["unloading"],
                    "lean_reverses": seq["lean_reverses"]}, (mesh, variant)
        dyn = [m[1:] for m in sorted(runs) if "cycle_dynamic" in runs[m]]
        stat = [m[1:] for m in sorted(runs) if "cycle" in runs[m]]
        assert rec["mixed"]["mesh"] == (f"r = {fc.listed(stat)}, static and by implicit dynamics" if dyn == stat else
                                        f"r = {fc.listed(stat)} static, r = {fc.listed(dyn)} by implicit dynamics"
                                        if dyn else "r = " + fc.listed(stat))
        # the two types as two stacked rings in one solid (``stacked_solid``): the order its run gives
        from metamaterial_wb.bench import fe_ring3d_stack as fs
        stacks = _load("fe-ring3d.json")["stacked_solid"][key]
        assert rec["stacked"]["mesh"] == "r = " + fc.listed([m[1:] for m in sorted(stacks)])
        for mesh, run in stacks.items():
            seq = fs.stack_sequence(run)
            assert [seq["loading"], seq["unloading"]] == [rec["stacked"]["loading"], rec["stacked"]["unloading"]]
            assert rec["stacked"].get("damped", False) == bool(run.get("damping")), (key, mesh)


def test_solid_order_note_maps_the_types_and_sets_the_models_order_beside():
    """The note is given for the measured cell types only, in whichever order the sleeve lists them (the type
    indices follow the sleeve's), with the beam model's order beside it and whether they agree; a ring size other
    than the measured four is said; any other sleeve gets none."""
    from metamaterial_wb.bench.fe_frame3d_plate import combination_cells
    two = combination_cells("2")
    note = acc.solid_order_note(two, 4, {"loading": [1, 0], "unloading": [1, 0]})
    assert "type 1's first peak +1.76 +- 0.34 % and its valley -3.85 +- 0.10 % against type 0's" in note
    assert "loading [0, 1], unloading [0, 1] (asymmetric)" in note and "they differ" in note
    assert ("the mixed ring [0, 0, 1, 1] itself as one curved solid (r = 1, 2 and 3, static and by implicit "
            "dynamics) snaps loading [0, 1], unloading [1, 0] (symmetric), leaning the same way on both") in note
    assert "on the curved solid and on the 3-D frame the seed's mixed combination 2 is symmetric" in note
    assert ("two such rings stacked as one curved solid (r = 1 and 2, implicit dynamics with the rubber's damping) "
            "snap loading [0, 1], unloading [0, 1] (asymmetric), the rule's") in note
    assert "four cells around" not in note
    rev = acc.solid_order_note(two[::-1], 8, {"loading": [1, 0], "unloading": [1, 0]})
    assert "type 0's first peak +1.76 +- 0.34 %" in rev and "against type 1's" in rev
    assert "loading [1, 0], unloading [1, 0] (asymmetric)" in rev and "the same" in rev
    assert ("the mixed ring [1, 1, 0, 0] itself as one curved solid (r = 1, 2 and 3, static and by implicit "
            "dynamics) snaps loading [1, 0], unloading [0, 1]") in rev
    assert "(measured with four cells around, this sleeve has 8)" in rev
    one = acc.solid_order_note(combination_cells("1"), 4, {"loading": [0, 1], "unloading": [1, 0]})
    assert "first peak +22.32 +- 0.27 %" in one and "loading [0, 1], unloading [1, 0] (symmetric)" in one and "the same" in one
    assert ("two such rings stacked as one curved solid (r = 1 and 2, implicit dynamics) snap loading [0, 1], unloading "
            "[1, 0] (symmetric), the rule's") in one
    flip = acc.solid_order_note(combination_cells("1")[::-1], 4, {"loading": [1, 0], "unloading": [0, 1]})
    assert "stacked as one curved solid (r = 1 and 2, implicit dynamics) snap loading [1, 0], unloading [0, 1]" in flip
    assert acc.solid_order_note([two[0]], 4, {"loading": [0], "unloading": [0]}) is None
    assert acc.solid_order_note([CellGeometry(), two[1]], 4, {"loading": [0, 1], "unloading": [0, 1]}) is None
    other_L = [CellGeometry(L=20.0, t=g.t, h=g.h) for g in two]
    assert acc.solid_order_note(other_L, 4, {"loading": [0, 1], "unloading": [0, 1]}) is None
