"""Issue 18: the linear 3-D frame of the curved sleeve ring (``core/sleeve/frame3d.py``). Its element against
beam theory's closed forms, its flat ring against the 2-D beam model it is built from, the flat limit of a
large ring, and its curvature knock-down against the curved CalculiX solid's stored runs."""
import json
import os

import numpy as np
import pytest

from metamaterial_wb.core.sleeve.cell import CellGeometry
from metamaterial_wb.core.sleeve.frame3d import RingFrame, element_stiffness, torsion_constant
from metamaterial_wb.core.sleeve.model import SleeveModel

RESULTS = os.path.join(os.path.dirname(__file__), "..", "..", "benchmarks", "results")


def test_element_is_a_cantilever_of_beam_theory_in_every_direction():
    """One element clamped at node 1: tip load along 1, 2, 3 and a twisting moment give P l / EA, P l^3 / (3 EI3),
    P l^3 / (3 EI2) and T l / GJ, and the tip rotations P l^2 / (2 EI) with the right signs."""
    l, EA, EI2, EI3, GJ = 2.0, 5.0, 0.7, 0.3, 0.11
    K = element_stiffness(l, EA, EI2, EI3, GJ)
    assert np.allclose(K, K.T)
    u = np.linalg.solve(K[6:, 6:], np.eye(6))                    # tip displacements for unit tip loads
    assert u[0, 0] == pytest.approx(l / EA)
    assert u[1, 1] == pytest.approx(l ** 3 / (3 * EI3)) and u[5, 1] == pytest.approx(l ** 2 / (2 * EI3))
    assert u[2, 2] == pytest.approx(l ** 3 / (3 * EI2)) and u[4, 2] == pytest.approx(-l ** 2 / (2 * EI2))
    assert u[3, 3] == pytest.approx(l / GJ)
    rigid = np.zeros(12)
    rigid[[2, 8]] = 1.0                                          # a rigid translation and a rigid rotation
    assert np.allclose(K @ rigid, 0)
    rot = np.zeros(12)
    rot[[5, 11]], rot[7] = 1.0, l                                # about 3: node 2 moves by l along 2
    assert np.allclose(K @ rot, 0)


def test_torsion_constant_of_a_square_and_of_a_thin_strip():
    assert torsion_constant(1.0, 1.0) == pytest.approx(0.1406, rel=2e-3)       # Roark: 0.1406 a^4
    assert torsion_constant(1.0, 100.0) == pytest.approx(100 / 3 * (1 - 0.63 / 100), rel=1e-3)


def test_flat_frame_is_the_beam_models_linear_flat_ring():
    """Lying in a plane, the out-of-plane motion decouples and the frame is the 2-D model's ring: the same
    stiffness as the model's force over a tiny rise, for both root extensions, with the pillars clamped at their
    bars' faces as the model's are. The pillars' roots in the bars (``bar_root``, the default) bend through the
    wall only: flat they change nothing but by their in-plane stiffness, the links' (1e3 times the pillar's)."""
    g = CellGeometry()
    for n, e in ((4, 0.0), (6, 0.63)):
        p = SleeveModel([g], [[0] * n], 24, curvature=False, root_extension=e).trace(np.array([0.0, 1e-6]))
        assert RingFrame(g, n, curved=False, root_extension=e, bar_root=0.0).axial_stiffness() == pytest.approx(
            p.F[1] / p.d[1], rel=1e-6)
        assert RingFrame(g, n, curved=False, root_extension=e).axial_stiffness() == pytest.approx(
            p.F[1] / p.d[1], rel=1e-3)


def test_pillars_run_through_their_bars_to_the_clamped_and_the_plates_faces():
    """``bar_root=1``: every pillar ends on a bar's outer face (the bottom ring's at z = 0, the top one's at the
    sleeve's height; stacked rings meet there), through an element of the pillar's section through the wall that
    is rigid in the wall's plane and along; ``bar_root=0`` ties them at the bars' inner faces. Each step in
    between softens the curved ring, not the flat one; out of range it is refused."""
    g = CellGeometry()
    for rows in ([[0] * 4], [[0] * 4, [0] * 4]):
        rf, r0 = RingFrame(g, pattern=rows), RingFrame(g, pattern=rows, bar_root=0.0)
        assert rf.bar_root == 1.0 and r0.bar_root == 0.0
        z = {p: sorted({round(float(rf.P[i, 2]) * g.L, 9) for i, q in rf.ties if q == p}) for p in range(len(rows) + 1)}
        assert z == {p: [pytest.approx(p * g.height)] for p in range(len(rows) + 1)}
        z0 = sorted({round(float(r0.P[i, 2]) * g.L, 9) for i, q in r0.ties if q == 0})
        assert z0 == [pytest.approx(0.5 * g.c)]                          # the central pillars' feet on the bar
        roots = [e for e, (i, j) in enumerate(rf.conn) if i in {t for t, _ in rf.ties} or j in {t for t, _ in rf.ties}]
        assert len(roots) == 2 * 4 * len(rows)                        # one per pillar end in a bar
        pillar = np.argmax(rf.EI2 * (rf.GJ < 0.99 * rf.GJ.max()))    # the widest element bending through the wall
        for e in roots:
            assert rf.EI2[e] == pytest.approx(rf.EI2[pillar]) and rf.GJ[e] == pytest.approx(rf.GJ[pillar])
            assert rf.l0[e] * g.L == pytest.approx(0.5 * g.c)
            assert rf.EI3[e] == pytest.approx(1e3 * r0.EI3[pillar]) and rf.EA[e] == pytest.approx(1e3 * r0.EA[pillar])
    k = [RingFrame(g, 4, plane="stress", root_extension=0.63, bar_root=b).axial_stiffness() for b in (0, 0.5, 1)]
    assert k[0] > k[1] > k[2] > 0.6 * k[0]
    flat = [RingFrame(g, 4, curved=False, bar_root=b).axial_stiffness() for b in (0, 1)]
    assert flat[1] == pytest.approx(flat[0], rel=1e-3)
    for bad in (-0.1, 1.5):
        with pytest.raises(ValueError, match=f"bar_root: {bad}; allowed: 0"):
            RingFrame(g, 4, bar_root=bad)


def test_a_large_ring_is_flat_and_a_small_one_is_knocked_down():
    """Curvature vanishes as the ring grows: curved / flat -> 1 (256 cells within 0.2 %), and it falls
    monotonically as the ring shrinks."""
    g = CellGeometry()
    ratios = [RingFrame(g, n).axial_stiffness() / RingFrame(g, n, curved=False).axial_stiffness()
              for n in (4, 8, 16, 64, 256)]
    assert np.all(np.diff(ratios) > 0)
    assert ratios[-1] == pytest.approx(1.0, abs=2e-3) and ratios[0] < 0.35


def test_curved_stiffness_matches_the_curved_solid_where_the_spring_model_does_not():
    """Against the stored CalculiX runs (curved 3-D rings of 4-12 cells, mesh r = 1, whose initial stiffness is
    7 % above the four-cell ring's finest meshes): the frame in plane stress with the calibrated root extension and
    the pillars bending on through their bars is within 15 % of the solid's curved stiffness at every size; with
    the pillars clamped at the bars' faces it is more than 14 % above at every size (as the solid is when its bars
    are held at their radius); the beam model's curvature springs are more than 40 % off in the knock-down."""
    cells = json.load(open(os.path.join(RESULTS, "fe-ring3d-comparison.json")))["cells"]
    g = CellGeometry()
    assert sorted(map(int, cells)) == [4, 6, 8, 12]
    for n, row in cells.items():
        fe = row["fe_curved"] / row["fe_flat"]
        frame = RingFrame(g, int(n), plane="stress", root_extension=0.63).axial_stiffness()
        clamped = RingFrame(g, int(n), plane="stress", root_extension=0.63, bar_root=0.0).axial_stiffness()
        assert abs(frame / row["fe_curved"] - 1) < 0.15, (n, frame, row["fe_curved"])
        assert clamped / row["fe_curved"] - 1 > 0.14, (n, clamped, row["fe_curved"])
        assert row["model_curved"] / row["model_flat"] / fe - 1 > 0.40


def test_nonlinear_paragraph_reports_each_mesh_against_the_solid():
    from metamaterial_wb.bench.fe_frame3d import nonlinear_markdown
    d = np.linspace(0, 0.7, 141)
    F = 1e-3 * np.where(d < 0.5, 1.2 * np.sin(np.pi * d / 0.28), 5 * (d - 0.5))   # one peak 1.2e-3 at d/L 0.14
    nl = {"12": {"d": d.tolist(), "F": F.tolist(), "seconds": 60.0, "iterations": 400}}
    fe = {"p1_ext": (0.143, 1.0e-3, 0.03e-3, 0.002), "valley_ext": (0.46, 0.38e-3, 0.03e-3, 0.005)}
    planar = {"d": d.tolist(), "F": (2.1 * F).tolist()}
    text = nonlinear_markdown(nl, fe, planar)
    assert "12 elements per beam half: 1 peak, 1 valley" in text and "P1 1.200 at d/L 0.140" in text
    assert "P1 1.000 +- 0.030, valley 0.380 +- 0.030 at d/L 0.460" in text and "P1 is +20 % off the solid's" in text
    assert "calibrated ring is +152 % off" in text
    assert "times faster" not in text                                  # no baselines stored: no speed claim
    nl["12"].update(derivatives_seconds=0.01, reference_derivatives_seconds=0.13, planar_seconds=2.0)
    assert ("(60 s, 400 Newton and chord iterations; one gradient and Hessian in 10 ms, 13.0 times faster than "
            "differencing each element's whole energy, the path 30.0 times the planar model's 2.0 s)"
            ) in nonlinear_markdown(nl, fe, planar)


def test_plate_study_is_current_and_its_paragraph_quotes_it():
    """The stored runs with the solid's free plate (``bench_sleeve_frame3d.py --plate``): the eight-cell ring's
    untilted run recomputed gives the same force and tilt pair, whose zero (the tilt bifurcation) the paragraph
    quotes, beside the solid's stall and its probes' extrapolated zero."""
    import json
    import os
    from metamaterial_wb.bench import fe_frame3d_plate as fp
    res = os.path.join(os.path.dirname(__file__), "..", "..", "benchmarks", "results")
    stored = json.load(open(os.path.join(res, "frame3d.json")))["plate"]
    comp = json.load(open(os.path.join(res, "fe-ring3d-comparison.json")))
    fresh = fp.plate_study(runs={"8": fp.RUNS["8"]})["8"]
    assert np.allclose(fresh["F"], stored["8"]["F"], rtol=1e-6, atol=1e-12)
    # soft eigenvalues (5e-6) of a differenced Hessian whose entries reach 1e4: 2e-11 apart between numpy 1.24 and 2.4
    assert np.allclose(fresh["tilt_pair"], stored["8"]["tilt_pair"], rtol=1e-4, atol=1e-9)
    z = fp.zero_crossings(stored["8"]["d"], stored["8"]["tilt_pair"])
    assert len(z) == 1 and z[0][1] == "down" and 0.07 < z[0][0] < 0.12       # near the solid's 0.091
    text = fp.markdown(stored, comp)
    assert f"reaches zero at d/L {z[0][0]:.3f}" in text and "reaching zero at d/L 0.091" in text
    assert "stall at d/L 0.077" in text
    sn = fp.snapping(stored["8_bias1e-05"])
    assert sn["units"] == 8 and 0 < sn["valley"][1] < 8
    assert f"{sn['valley'][1]} of 8 at the first valley (d/L {sn['valley'][0]:.3f})" in text


def test_zero_crossings_by_linear_interpolation():
    from metamaterial_wb.bench.fe_frame3d_plate import zero_crossings
    assert zero_crossings([0, 1, 2, 3], [2.0, 1.0, -1.0, 1.0]) == [(1.5, "down"), (2.5, "up")]
    assert zero_crossings([0, 1], [1.0, 2.0]) == []


def test_sequence_table_quotes_the_stored_cycles():
    """The sequencing table (``bench_sleeve_frame3d.py --sequence``): every stored frame cycle and the beam
    model's sequence appear as stored, with the seed's sequence beside them."""
    import json
    import os
    from metamaterial_wb.bench import fe_frame3d_plate as fp
    res = os.path.join(os.path.dirname(__file__), "..", "..", "benchmarks", "results")
    st = json.load(open(os.path.join(res, "frame3d.json")))["sequence"]
    text = fp.sequence_markdown(st)
    assert "| [0, 1] \\| [0, 1] (asymmetric), leaning the other way |" in text            # the seed's combination 2
    for key, r in st.items():
        m = r["model"]
        assert f"{m['loading']} \\| {m['unloading']}" in text
        for n_el, f in r["frame"].items():
            assert f"{n_el}: {f['loading']} \\| {f['unloading']}" in text
    assert st["1"]["frame"]["12"]["loading"] == [0, 1] and st["1"]["frame"]["12"]["symmetric"]   # the seed's


def test_sensitivity_sentence_quotes_each_change_and_its_rate():
    from metamaterial_wb.bench.fe_frame3d import sensitivity_sentence
    text = sensitivity_sentence({"base": 1.3e-3, "EI2_pillars": -0.066, "GJ_all": -0.0226})
    assert "EI2 of the pillars x0.8: -6.6 % (0.33 per unit)" in text
    assert "GJ of every element x0.5: -2.3 % (0.05 per unit)" in text
    assert "EA of" not in text


def test_solid_hysterons_are_read_off_the_stored_rises_by_the_models_rule():
    """``solid_snapped`` turns a solid run's beam-end rises into snapped pillars (the mean of a pillar's two halves
    beyond h), and ``snapping`` counts them at the first valley, where half the ring has snapped and whether the
    snapped ones are neighbours; a run that ends before its valley says so instead of counting at its start."""
    from metamaterial_wb.bench import fe_frame3d_plate as fp
    h = 0.4
    d = np.linspace(0, 0.4, 9)
    F = np.array([0, 3, 4, 3, 2, 1, 1.5, 2.5, 3.0])                  # a peak at 0.1, the valley at d = 0.25
    rises = np.zeros((9, 6))                                          # three pillars: halves (0, 1), (2, 3), (4, 5)
    rises[4:, 0:2] = 1.5 * h                                          # pillar 0 from d = 0.2
    rises[5:, 2] = 1.9 * h                                            # pillar 1's halves: mean 1.05 h from 0.25
    rises[5:, 3] = 0.2 * h
    rises[7:, 4:6] = 0.9 * h                                          # pillar 2 never (0.9 h)
    pre = "x_"
    row = {pre + "p1_rises": rises.tolist(), pre + "p1_units": [0, 0, 1, 1, 2, 2], pre + "p1_snap_height": h,
           pre + "p1_curve": {"d": d.tolist(), "F": F.tolist()}}
    run = fp.solid_snapped(row, pre)
    assert np.asarray(run["snapped"]).sum(axis=1).tolist() == [0, 0, 0, 0, 1, 2, 2, 2, 2]
    sn = fp.snapping(run)
    assert sn["valley"][1] == 2 and abs(sn["valley"][0] - 0.25) < 0.05
    assert sn["half"] == pytest.approx(0.25) and sn["contiguous"] and sn["units"] == 3
    assert fp.snapping_words(sn).startswith("2 of 3 at the first valley (d/L 0.2")
    early = fp.snapping(dict(run, d=d[:4].tolist(), F=F[:4].tolist(), snapped=run["snapped"][:4]))
    assert early["valley"] is None and early["end"] == (pytest.approx(0.15), 0)
    assert "0 of 3 at d/L 0.150, the run's end, before any valley" in fp.snapping_words(early)
    assert fp.solid_snapped({}, pre) is None


def test_the_frames_pillars_in_their_bars_are_what_the_solid_says_was_missing():
    """The stored four-cell runs: the solid's first peak rises by more than 10 % when its bars are held at their
    radius (the frame's old clamp at the bars' faces); the frame with its pillars bending on through the bars
    (the default) peaks within 5 % of the solid's extrapolated P1, clamped at the faces more than 10 % above; the
    paragraph quotes these."""
    from metamaterial_wb.bench import fe_frame3d
    s = json.load(open(os.path.join(RESULTS, "frame3d.json")))
    raw = json.load(open(os.path.join(RESULTS, "fe-ring3d.json")))
    held = {k: v["p1"] for k, v in raw["p1_held"].items()}
    held["free"] = raw["cells"]["4"]["fe_curved_p1"]
    assert held["bars"] / held["free"] > 1.10 and held["fixed"] > held["pillars"] > held["bars"]
    sens = s["p1_sensitivity"]
    p1_ext = s["fe_family"]["p1_ext"][1]
    assert abs(sens["base"] / p1_ext - 1) < 0.05 and sens["bar_root"] == 1.0
    assert sens["base"] * (1 + sens["bar_root_0"]) / p1_ext - 1 > 0.10
    text = fe_frame3d.bar_root_markdown(sens, held, s["fe_family"])
    assert f"from {1e3 * held['free']:.3f}e-3 to {1e3 * held['bars']:.3f}e-3" in text
    assert f"at {1e3 * sens['base']:.3f}e-3, {100 * (sens['base'] / p1_ext - 1):+.1f} % off the solid's" in text


def test_eight_cell_solid_and_frame_snap_the_same_pillars_on_the_leaning_branch():
    """The stored eight-cell solid run under the hundred-fold bias (its beam ends printed at every increment) and
    the frame's run with the same bias, ramped over the same rise (the solid run's step end): both snap three
    edge pillars, neighbours, by their first valley, each within 0.01 d/L of the other's; the paragraph quotes
    both counts."""
    from metamaterial_wb.bench import fe_frame3d_plate as fp
    row = json.load(open(os.path.join(RESULTS, "fe-ring3d.json")))["cells"]["8"]
    stored = json.load(open(os.path.join(RESULTS, "frame3d.json")))["plate"]
    assert fp.RUNS["8_bias0.001"][4] == pytest.approx(row["c3d20_bias0.001_p1_d_reached"])
    runs = {"solid": fp.solid_snapped(row), "frame": stored["8_bias0.001"]}
    first = {}
    for key, run in runs.items():
        sn = fp.snapping(run)
        assert sn["valley"][1] == 3 and sn["contiguous"] and sn["units"] == 8, key
        S, d = np.asarray(run["snapped"], bool), np.asarray(run["d"])
        first[key] = [float(d[np.argmax(S.sum(axis=1) >= k)]) for k in (1, 2, 3)]
    assert np.allclose(first["solid"], first["frame"], atol=0.01), first
    text = fp.markdown(stored, json.load(open(os.path.join(RESULTS, "fe-ring3d-comparison.json"))))
    assert "the solid's, read off its beams' ends by the same rule" in text
    assert text.count("3 of 8 at the first valley") >= 2


def test_eight_cell_snapping_count_is_the_same_on_every_beam_mesh():
    """Issue 18 asks that the snapping count converge with the mesh: the frame's eight-cell leaning runs (both
    biases) on 6, 12 and 24 elements per beam half snap 3 of 8 pillars, neighbours, by their first valley, which
    lies within 0.01 d/L on every mesh; the paragraph says so, and says otherwise when a mesh's count differs."""
    import copy
    from metamaterial_wb.bench import fe_frame3d_plate as fp
    s = json.load(open(os.path.join(RESULTS, "frame3d.json")))
    meshes, pl = s["plate_meshes"], s["plate"]
    assert sorted(meshes, key=int) == ["6", "24"] and pl["8"]["elements"] == 12
    for key in fp.MESH_RUNS:
        sn = [fp.snapping(pl[key])] + [meshes[n][key]["snapping"] for n in ("6", "24")]
        assert [x["valley"][1] for x in sn] == [3, 3, 3] and all(x["contiguous"] for x in sn), key
        assert np.ptp([x["valley"][0] for x in sn]) < 0.01, key
    words = fp.count_words(pl, meshes)
    assert words.startswith("On 6, 12, 24 elements per beam half the count is the same: with the default bias 3, 3, 3 "
                            "of 8 at the first valley")
    assert words in open(os.path.join(RESULTS, "..", "..", "docs", "sleeves.md")).read()
    other = copy.deepcopy(meshes)
    other["24"]["8_bias0.001"]["snapping"]["valley"][1] = 4
    assert "the count is not the same" in fp.count_words(pl, other) and "3, 3, 4 of 8" in fp.count_words(pl, other)


def test_walker_on_the_frame_is_mesh_converged_and_documented():
    """The walker of examples/walker.json on the frame's cycle: stored on 6, 12 and 24 elements per beam half, its
    loop, stroke, lift and step change by under 1 % from 12 to 24; the paragraph says so and is in the docs; the
    stored 12-element figures are what the ``sleeve`` command's summary gives now (``walker.frame3d_nl``)."""
    from metamaterial_wb.bench import fe_frame3d_plate as fp
    w = json.load(open(os.path.join(RESULTS, "frame3d.json")))["walker"]
    assert sorted(k for k in w if k != "model") == ["12", "24", "6"]
    assert all(abs(w["24"][k] / w["12"][k] - 1) < 0.01 for k in fp.WALKER_KEYS)
    text = fp.walker_markdown(w)
    assert "From 12 to 24 elements per beam half the frame's figures change by at most 0.4 %" in text
    assert text in open(os.path.join(RESULTS, "..", "..", "docs", "sleeves.md")).read()
    now = fp.walker_study(meshes=(12,))
    for k in fp.WALKER_KEYS:
        assert now["12"][k] == pytest.approx(w["12"][k], rel=1e-6), k
        assert now["model"][k] == pytest.approx(w["model"][k], rel=1e-6), k


def test_eight_cell_mesh_error_extrapolates_with_the_four_cell_familys_order():
    """``eight_cell_meshes``: eight-cell first peaks that fall from r = 1 to r = 2 as the four-cell ring's do
    (the same ratio) fall by the same per cent and extrapolate, with the four-cell family's observed order, to the
    four-cell extrapolation from the same two meshes scaled alike (1e-12); that order reproduces the four-cell
    family's four-mesh extrapolation within 1 %. Without both runs there is nothing to report."""
    import copy
    import json
    import os
    from metamaterial_wb.bench import fe_frame3d_plate as fp
    from metamaterial_wb.bench.fe_ring3d_corner import family_convergence
    res = os.path.join(os.path.dirname(__file__), "..", "..", "benchmarks", "results")
    comp = copy.deepcopy(json.load(open(os.path.join(res, "fe-ring3d-comparison.json"))))
    pc = family_convergence(comp, "_C3D20")
    p4 = [F for _, F in pc["p1"][:2]]
    row = comp["cells"]["8"]
    for key in [k for k in row if k.startswith(("c3d20_bias0.001_r1_", "c3d20_bias0.001_r2_", "c3d20_bias0.001_r3_"))]:
        del row[key]
    assert fp.eight_cell_meshes(comp) is None
    k = 2.4
    for m, F in zip(("r1", "r2"), p4):
        row.update({f"c3d20_bias0.001_{m}_fe_curved_p1": k * F, f"c3d20_bias0.001_{m}_fe_curved_p1_d": 0.06,
                    f"c3d20_bias0.001_{m}_p1_wall_s": 600.0})
    m8 = fp.eight_cell_meshes(comp)
    assert m8["fall"] == pytest.approx(m8["four_fall"], abs=1e-12)
    p = m8["order"]
    four_two = p4[1] + (p4[1] - p4[0]) * 0.5 ** p / (1 - 0.5 ** p)
    assert m8["ext"][0] == pytest.approx(k * four_two, rel=1e-12)
    assert four_two == pytest.approx(pc["p1_ext"][1], rel=0.01)
    words = fp.eight_cell_words(m8, 0.97 * m8["ext"][0])
    assert f"falls by {100 * m8['four_fall']:+.1f} %" in words and "the frame's leaning peak is -3 % off it" in words
    assert "A third mesh" not in words
    # a third eight-cell mesh (r = 3) scaled alike: its own observed order is the four-cell family's, and it
    # extrapolates to the four-cell ring's three-mesh value scaled alike
    from metamaterial_wb.core.extrapolation import richardson3
    p4_3 = [F for m, (_, F) in zip(pc["meshes"], pc["p1"]) if m in ("r1", "r2", "r3")]
    row.update({"c3d20_bias0.001_r3_fe_curved_p1": k * p4_3[2], "c3d20_bias0.001_r3_fe_curved_p1_d": 0.06,
                "c3d20_bias0.001_r3_p1_wall_s": 3000.0})
    m8 = fp.eight_cell_meshes(comp)
    e4, _, o4 = richardson3([1.0, 0.5, 1.0 / 3.0], p4_3)
    assert m8["own_order"] == pytest.approx(o4[0], rel=1e-9) and m8["own_ext"][0] == pytest.approx(k * e4[0], rel=1e-9)
    assert m8["fall3"] == pytest.approx(m8["four_fall3"], abs=1e-12)
    words = fp.eight_cell_words(m8, m8["own_ext"][0])
    assert "A third mesh, r = 3 (`--cells-p1-mesh r3`, 50 min)" in words and "the eight-cell ring's own observed order is" in words
    assert "the frame's leaning peak is +0 % off it" in words


def test_solid_stiffness_extrapolated_over_its_meshes_recovers_a_known_limit():
    """``solid_extrapolated``: stiffnesses that converge as k + a h^1.5 (h = 1 / r) extrapolate to k with order 1.5
    (1e-9), the curved over r = 1, 2, 3, the flat over r = 2, 4, 8 (and over r = 1, 2, 3 as its coarse check); a
    row missing a mesh gives None."""
    from metamaterial_wb.bench.fe_frame3d import FLAT_MESHES, SOLID_MESHES, solid_extrapolated
    assert FLAT_MESHES == ("r2", "r4", "r8")
    row = {}
    for m in SOLID_MESHES:
        h = 1.0 / int(m[1:])
        row.update({f"c3d20_{m}_fe_curved": 0.015 + 0.002 * h ** 1.5, f"c3d20_{m}_fe_curved_wall_s": 10.0 * int(m[1:])})
    for m in SOLID_MESHES + FLAT_MESHES:
        row[f"{m}_fe_flat"] = 0.058 - 0.001 * (1.0 / int(m[1:])) ** 1.5
    x = solid_extrapolated(row)
    assert x["curved"][0] == pytest.approx(0.015, rel=1e-9) and x["curved"][2] == pytest.approx(1.5, rel=1e-6)
    assert x["flat"][0] == pytest.approx(0.058, rel=1e-9) and x["seconds"] == [10.0, 20.0, 30.0]
    assert x["flat"][1] == pytest.approx(0.001 / 8 ** 1.5, rel=1e-6) and x["flat_coarse"][0] == pytest.approx(0.058)
    assert x["flat_meshes"] == [row[f"{m}_fe_flat"] for m in FLAT_MESHES]
    assert x["curved"][1] == pytest.approx(0.002 / 3 ** 1.5, rel=1e-6)      # the error: the finest mesh's distance
    for gone in ("r8_fe_flat", "r1_fe_flat"):
        assert solid_extrapolated({k: v for k, v in row.items() if k != gone}) is None
    assert x["curved_check"] is None                                       # no fourth curved mesh stored
    row["c3d20_r4_fe_curved"] = 0.015 + 0.002 * 0.25 ** 1.5
    check = solid_extrapolated(row)["curved_check"]                        # over r = 2, 3, 4
    assert check[0] == pytest.approx(0.015, rel=1e-9) and check[2] == pytest.approx(1.5, rel=1e-6)
    assert check[1] == pytest.approx(0.002 / 4 ** 1.5, rel=1e-6)


def test_the_frames_curved_stiffness_against_the_solid_extrapolated_in_its_mesh():
    """The stored ring-size runs on three meshes (``--cells-meshes``, the flat ring's ``--cells-flat``): the curved solid's stiffness falls with the
    mesh at every size and the table's coarse mesh lies 5-12 % above its extrapolation; the frame (plane stress,
    calibrated, pillars through their bars) is within 12 % of the extrapolated solid at every size, closer than the
    coarse solid's own excess at four cells; the generated paragraphs quote it."""
    from metamaterial_wb.bench import fe_frame3d, fe_ring3d
    comp = json.load(open(os.path.join(RESULTS, "fe-ring3d-comparison.json")))
    g = CellGeometry()
    for n, row in comp["cells"].items():
        x = fe_frame3d.solid_extrapolated(row)
        assert np.all(np.diff(x["curved_meshes"]) < 0) and np.all(np.diff(x["flat_meshes"]) < 0), n
        # the flat ring over r = 2, 4, 8 converges at the re-entrant corners' order (about 1.2, within 1 %); over
        # r = 1, 2, 3 it looked like order 0.56 and extrapolated 3-4 % too low: r = 1 is pre-asymptotic
        assert 1.0 < x["flat"][2] < 1.5 and x["flat"][1] < 0.01 * x["flat"][0], n
        assert x["flat_coarse"][2] < 0.7 and -0.05 < x["flat_coarse"][0] / x["flat"][0] - 1 < -0.02, n
        # a fourth curved mesh (r = 4): over r = 2, 3, 4 the curved reference lands inside its error over r = 1, 2, 3
        check = x["curved_check"]
        assert abs(check[0] - x["curved"][0]) <= x["curved"][1] and check[1] < x["curved"][1], n
        assert row["c3d20_r4_fe_curved"] < row["c3d20_r3_fe_curved"], n
        assert 0.05 < row["fe_curved"] / x["curved"][0] - 1 < 0.12, n
        frame = RingFrame(g, int(n), plane="stress", root_extension=0.63).axial_stiffness()
        assert abs(frame / x["curved"][0] - 1) < 0.12, (n, frame, x["curved"])
    s = fe_frame3d.study(comp["cells"], (0.0, 0.63))
    text = fe_frame3d.markdown(s)
    sm = fe_frame3d.summary(s)["extrapolated"]
    assert f"the frame's curved stiffness is {sm['absolute'][0]:+.0f} to {sm['absolute'][1]:+.0f} % off" in text
    assert "| 4 | 58.4 | 15.7 |" in text and "| 14.3 +- 0.8 | 0.94 |" in text
    assert f"]({fe_frame3d.IMG_STIFFNESS})" in text                       # the plot, committed beside the doc
    assert os.path.exists(os.path.join(RESULTS, "..", "..", "docs", fe_frame3d.IMG_STIFFNESS))
    rows = sorted(comp["cells"].items(), key=lambda kv: int(kv[0]))
    words = fe_ring3d.cells_meshes_markdown(rows)
    assert "4 cells: curved 16.9, 15.5, 15.1 -> 14.3 +- 0.8" in words and "A fourth curved mesh checks" in words
    # the docs carry the paragraph as the stored runs give it now (a stale regeneration had dropped two sentences)
    assert words in open(os.path.join(RESULTS, "..", "..", "docs", "sleeves.md")).read()


def test_eight_cell_solid_on_three_meshes_converges_as_the_four_cell_family():
    """The stored eight-cell leaning runs on r = 1, 2, 3 (``--cells-p1-mesh``): the first peak falls at a shrinking
    rate, at the same place (d/L within 0.001), its own observed order within 0.15 of the four-cell family's, and
    the frame's leaning peak lies within the extrapolation's error of it; the paragraph quotes the third mesh."""
    from metamaterial_wb.bench import fe_frame3d_plate as fp
    comp = json.load(open(os.path.join(RESULTS, "fe-ring3d-comparison.json")))
    m8 = fp.eight_cell_meshes(comp)
    assert m8["r1"] > m8["r2"] > m8["r3"] and abs(m8["fall3"]) < abs(m8["fall"])
    row = comp["cells"]["8"]
    ds = [row[f"c3d20_bias0.001_{m}_fe_curved_p1_d"] for m in ("r1", "r2", "r3")]
    assert max(ds) - min(ds) < 0.001
    assert abs(m8["own_order"] - m8["order"]) < 0.15
    stored = json.load(open(os.path.join(RESULTS, "frame3d.json")))["plate"]
    f = fp.facts(stored, comp)
    frame_p1 = f["frame8_bias0.001"]["P1"][1]
    e, err = m8["own_ext"]
    assert abs(frame_p1 - e) < err
    text = fp.markdown(stored, comp)
    assert f"gives {1e3 * m8['r3']:.3f}e-3" in text and f"extrapolates to {1e3 * e:.2f} +- {1e3 * err:.2f}e-3" in text


def test_a_flat_top_hangs_every_pillar_from_the_tallest_cell():
    """The seed's mixed ring [0, 0, 1, 1] (combination 2: the types differ in h): by default each edge pillar hangs
    from the taller of its two cells' top bars, so the top plate's ties step; with ``flat_top`` (the curved solid's
    mixed ring) they all sit at the taller type's top. A uniform ring is the same either way."""
    from metamaterial_wb.bench.fe_ring3d_combinations import combination_cells
    a, b = combination_cells("2")

    def plate_heights(ring):
        return sorted({round(float(ring.P[i, 2]), 9) for i, p in ring.ties if p == 1})
    step, flat = (RingFrame([a, b], row=[0, 0, 1, 1], flat_top=f) for f in (False, True))
    assert len(plate_heights(step)) == 2 and len(plate_heights(flat)) == 1
    assert plate_heights(flat)[0] == pytest.approx(plate_heights(step)[1])
    assert plate_heights(step)[1] - plate_heights(step)[0] == pytest.approx((b.height - a.height) / a.L)   # in L
    u, uf = RingFrame(a), RingFrame(a, flat_top=True)
    assert np.array_equal(u.P, uf.P) and np.array_equal(u.conn, uf.conn)
