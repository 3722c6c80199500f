"""Issue 18: the curved FE ring's report (``bench/fe_ring3d.py``) reads the stored runs right: the stability
probes' modes are told apart by the plate's turn, the unstable stretch of the path is bracketed by the probes,
and the path's force is extrapolated in the element size (a known h^2 error is removed exactly)."""
import json

import numpy as np
import pytest

from metamaterial_wb.bench import fe_ring3d as rep
from metamaterial_wb.bench import fe_ring3d_corner as corner


def _probe(d, eig, rot, size, density=1e-10):
    return {"d": d, "eigenvalues": eig, "plate_rotation": rot, "plate_rotation_size": size, "density": density,
            "stable": min(eig) > 0}


def test_modes_are_tilt_twist_or_a_wall_mode_with_the_plate_still():
    pr = _probe(0.3, [-2e6, 7e5, 7e5, 2e6], [[0.9, 0.4, 0], [0.3, 0.95, 0.01], [-0.95, 0.3, 0], [0, 0, 1]],
                [2.7, 110.0, 109.0, 90.0])
    lam, kind = rep.classify_modes(pr)
    assert kind.tolist() == ["still", "tilt", "tilt", "twist"]
    assert lam[0] == pytest.approx(-2e-4)                        # omega^2 rho: independent of the density chosen
    pr9 = dict(pr, eigenvalues=[v / 10 for v in pr["eigenvalues"]], density=1e-9)
    assert np.allclose(rep.classify_modes(pr9)[0], lam)


def test_unstable_stretch_is_bracketed_by_the_probes():
    ok = _probe(0, [1.0], [[1, 0, 0]], [1.0])
    bad = dict(ok, eigenvalues=[-1.0], stable=False)
    st = {f"r2@{d:.3f}": dict(ok if s else bad, d=d) for d, s in
          ((0.14, True), (0.26, True), (0.30, False), (0.35, False), (0.45, True))}
    st["r3@0.300"] = dict(bad, d=0.3)
    st["r2@0.200"] = {"d": 0.2, "stable": None}                  # a probe whose solve stopped: no eigenvalues
    assert rep.unstable_range({"stability": st}) == (0.26, 0.30, 0.35, 0.45)
    assert rep.unstable_range({"stability": {"r2@0.140": dict(ok, d=0.14)}}) is None
    st.pop("r2@0.450")
    assert rep.unstable_range({"stability": st}) == (0.26, 0.30, 0.35, None)


def test_path_force_is_extrapolated_in_the_element_size():
    d = np.linspace(0, 0.7, 71)
    exact = np.sin(3 * d) * 1e-3

    def path(r):                                                  # a discretisation error c h^2, h = 1 / r
        return {"d": d.tolist(), "F": (exact * (1 + 0.05 / r ** 2)).tolist()}
    c = {"p1_r2": path(2), "p1_r3": path(3), "trace": dict(path(1), tilt_deg=[0.0] * len(d))}
    pc = rep.path_convergence(c)
    assert pc["meshes"] == ["r1", "r2", "r3"]
    for dd, vals, ext, err, n in pc["rows"]:
        assert n == 3
        assert ext == pytest.approx(np.sin(3 * dd) * 1e-3, rel=1e-6)
    assert pc["p1_ext"][1] == pytest.approx(1e-3, rel=1e-3)       # the peak of sin(3 d): 1e-3 at pi / 6
    assert pc["p1_ext"][0] == pytest.approx(np.pi / 6, abs=0.01)


def test_corner_paths_are_reported_past_the_reduced_mesh_stop():
    d = np.linspace(0, 0.7, 71)
    F = 1e-3 * (np.sin(2 * np.pi * d / 0.45) * 0.5 + 0.6)              # two peaks, a valley between
    info = {"increments": 70, "d_reached": 0.7, "wall_s": 600.0, "full_elements": 144, "full_near": 1.5}
    full = {"d": d.tolist(), "F": F.tolist(), "tilt_deg": [0.1] * len(d), "info": info,
            "extrema": [("peak", 0.1125, 1.1e-3), ("valley", 0.3375, 0.1e-3), ("peak", 0.5625, 1.1e-3)]}
    k = d <= 0.468
    red = {"d": d[k].tolist(), "F": (F[k] * 0.99).tolist()}
    c = {"p1_r2": red, "p1_r2_full1.5": full, "p1_r2_inc280": red,
         "p1_r3_full1.5low": dict(full, info=dict(info, full_elements=433, full_low=True))}
    assert corner.corner_keys(c) == [("p1_r2_full1.5", "r2", "_full1.5"), ("p1_r3_full1.5low", "r3", "_full1.5low")]
    text = "\n".join(corner.corner_markdown(c))
    assert "(r = 2, 144 bricks within 1.5 mm" in text and "to d/L 0.700" in text and "(the whole range)" in text
    assert "2 peaks, 1 valley" in text and "+1.0 %" in text and "its stop at d/L 0.460" in text
    assert "(r = 3, 433 bricks within 1.5 mm of the beam's re-entrant corners and of the edge pillar's side" in text
    assert corner.corner_markdown({"p1_r2": red}) == []


def test_corner_family_converges_past_the_peak_and_its_valley_is_extrapolated():
    """The corner-integrated paths on r = 1, 2, 3 with a known h^2 error: the force at fixed d, P1 and the valley
    come back exact; a mesh that stopped early drops out of the rows it did not reach."""
    d = np.linspace(0, 0.7, 701)
    exact = 1e-3 * (np.sin(2 * np.pi * d / 0.6) + 4 * d ** 2)        # one peak, one valley, then stiffening

    def path(r, stop=0.7):
        k = d <= stop + 1e-12
        info = {"increments": 70, "d_reached": float(d[k][-1]), "wall_s": 60.0, "full_near": 1.5, "full_low": True,
                "full_elements": 50 * r}
        return {"d": d[k].tolist(), "F": (exact[k] * (1 + 0.04 / r ** 2)).tolist(), "info": info,
                "extrema": [("peak", 0.14, 1e-3), ("valley", 0.45, 0.4e-3)], "tilt_deg": [0.0] * int(k.sum())}
    c = {"p1_r1" + corner.FAMILY: path(1, 0.63), "p1_r2" + corner.FAMILY: path(2), "p1_r3" + corner.FAMILY: path(3)}
    pc = corner.family_convergence(c)
    assert pc["meshes"] == ["r1", "r2", "r3"]
    rows = {round(r_[0], 2): r_ for r_ in pc["rows"]}
    for dd in (0.10, 0.30, 0.60):
        assert rows[dd][4] == 3 and rows[dd][2] == pytest.approx(np.interp(dd, d, exact), rel=1e-5)
    assert rows[0.70][1][0] is None and rows[0.70][4] == 2           # r = 1 stopped at 0.63
    i = np.flatnonzero((np.diff(np.sign(np.diff(exact)))) > 0)[0] + 1  # the exact valley
    assert pc["valley_ext"][1] == pytest.approx(exact[i], rel=1e-3)
    assert pc["valley_ext"][0] == pytest.approx(d[i], abs=2e-3)
    text = "\n".join(corner.family_markdown(c))
    assert "on three meshes" in text and "--p1-full-near 1.5 --p1-full-low" in text
    assert "| 0.70 | - |" in text and "(2 meshes)" in text and "r = 1: 1 peak, 1 valley to d/L 0.630" in text
    assert corner.family_markdown({"p1_r2" + corner.FAMILY: path(2)}) == []


def test_probe_on_the_corner_integrated_path_is_named_apart():
    d = np.linspace(0, 0.7, 71)

    def path(r):
        return {"d": d.tolist(), "F": (np.sin(3 * d) * 1e-3 * (1 + 0.05 / r ** 2)).tolist()}
    pr = dict(_probe(0.6, [3e6, 5e6, 5e6], [[0, 0, 1], [1, 0, 0], [0, 1, 0]], [90.0, 100.0, 100.0]), mesh="r2",
              full_near=1.5)
    c = {"p1_r2": path(2), "p1_r3": path(3), "trace": dict(path(1), tilt_deg=[0.0] * len(d)),
         "stability": {"r2_full1.5@0.600": pr}}
    text = "\n".join(rep.path_markdown(c))
    assert "r = 2 with the beam's corner bricks C3D20 (1.5 mm) at d/L 0.600: tilt" in text and "- stable" in text
    assert rep.unstable_range(c) is None                           # not read as a probe of the reduced r = 2 path


def _bench_script():
    import importlib.util
    import os
    path = os.path.join(os.path.dirname(__file__), "..", "..", "benchmarks", "bench_sleeve_ring3d.py")
    spec = importlib.util.spec_from_file_location("bench_sleeve_ring3d", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_all_bricks_full_is_a_family_of_its_own_and_refuses_a_corner_zone(capsys):
    """``--p1-element C3D20`` runs are stored as ``p1_<mesh>_C3D20``, named as every brick fully integrated, and
    reported on three meshes; a corner zone with it is refused before any solve (it would mean nothing)."""
    d = np.linspace(0, 0.7, 71)

    def path(r, stop=0.7, ex=(("peak", 0.14, 1.2e-3), ("valley", 0.44, 0.45e-3))):
        k = d <= stop + 1e-12
        info = {"increments": 70, "d_reached": float(d[k][-1]), "wall_s": 600.0, "full_near": 0.0,
                "full_low": False, "full_elements": 0, "element": "C3D20", "elements": 264 * r * r}
        return {"d": d[k].tolist(), "F": (1e-3 * np.sin(3 * d[k]) * (1 + 0.04 / r ** 2)).tolist(), "info": info,
                "extrema": list(ex), "tilt_deg": [0.0] * int(k.sum())}
    c = {"p1_r1_C3D20": path(1), "p1_r2_C3D20": path(2),
         "p1_r3_C3D20": dict(path(3, 0.15, ()), info=dict(path(3, 0.15)["info"], note="(A note.)"))}
    assert [k for k, _, _ in corner.corner_keys(c)] == ["p1_r1_C3D20", "p1_r2_C3D20", "p1_r3_C3D20"]
    text = "\n".join(corner.corner_markdown(c))
    assert "(r = 3, all 2376 bricks fully integrated, C3D20)." in text and "the rest C3D20R" not in text
    assert "0 peaks, 0 valleys; the force" in text and "(A note.)" in text
    fam = "\n".join(corner.family_markdown(c, "_C3D20"))
    assert "every brick, `--p1-element C3D20`" in fam and "--p1-full-near" not in fam
    bench = _bench_script()
    with pytest.raises(SystemExit) as e:
        bench.main(["--p1-mesh", "r2", "--p1-element", "C3D20", "--p1-full-near", "1.5", "--no-write"])
    assert e.value.code == 2
    assert "--p1-full-near (mm) picks some of them, so it must be 0 with it, not 1.5" in capsys.readouterr().err


def test_ring_size_run_with_every_brick_full_is_reported_beside_the_reduced_stall():
    row = {"radius_mm": 28.0, "fe_flat": 0.1, "fe_curved": 0.05, "model_flat": 0.12, "model_curved": 0.11,
           "model_curved_documented": 0.15, "fe_curved_p1": None, "fe_curved_p1_d": None, "p1_wall_s": 800.0,
           "p1_d_reached": 0.08, "p1_stopped": "stalled", "model_curved_p1": 4.8e-3,
           "c3d20_fe_curved_p1": 3.2e-3, "c3d20_fe_curved_p1_d": 0.125, "c3d20_p1_wall_s": 600.0,
           "c3d20_p1_d_reached": 0.17, "c3d20_p1_stopped": "", "c3d20_p1_tilt_deg_max": 0.21}
    text = "\n".join(rep.cells_markdown({"cells": {"8": row}}))
    assert "8 cells: no first peak - the static run stopped at d/L 0.080" in text
    assert ("8 cells with every brick fully integrated (`--cells-p1 8 --cells-p1-element C3D20`, the same mesh): "
            "P1 3.200 at d/L 0.125, the run reaching d/L 0.170 in 10.0 min, the plate tilting by at most 0.21 deg; "
            "the calibrated beam model's P1 is 1.50 times it.") in text


def test_a_ccx_exit_is_told_by_its_error_line_or_by_the_stall_it_ended():
    """A stored stop reason in a few words: ccx's ``*ERROR`` line; for a bare exit code (``ccx.run`` keeps only the
    cut-off tail of ccx's output) the code, the increments' size and how flat the force had become (measured on the
    stored curve, not made up); a hand-written reason as it is."""
    from metamaterial_wb.bench.fe_ring3d_paths import stop_reason
    assert stop_reason("ccx failed (exit code 201):\n *ERROR: increment size smaller than minimum\n best") == \
        "*ERROR: increment size smaller than minimum"
    d = np.linspace(0, 0.07, 71)
    F = 1e-3 * (64 * d - 400 * d ** 2)                     # flattening: secant slope 64 - 400 (d1 + d2)
    why = stop_reason("ccx failed on job 'x' (exit code 201):\n largest co", {"d": d.tolist(), "F": F.tolist()})
    assert why.startswith("ccx gave up, exit code 201, its increments cut to 1.0e-03 d/L, the force flat at 2.520e-3")
    assert why.endswith("(its slope over the last 0.005 d/L 16 % of the initial one)")    # 10 / 63.6
    assert stop_reason("stalled there and stopped by hand") == "stalled there and stopped by hand"
    assert stop_reason("") == ""


def test_four_meshes_are_reported_as_four_and_extrapolated_from_the_last_three():
    """The fully integrated family with a fourth mesh: the table gets its column, the prose says four, and the
    extrapolation uses r = 2, 3, 4 (a known error in h removed exactly; r = 1 is off that trend and must not count)."""
    d = np.linspace(0, 0.7, 71)
    exact = 1e-3 * np.sin(3 * d)

    def path(r, off=0.0):
        info = {"increments": 70, "d_reached": 0.7, "wall_s": 600.0, "full_near": 0.0, "full_low": False,
                "full_elements": 0, "element": "C3D20", "elements": 264 * r * r}
        return {"d": d.tolist(), "F": (exact * (1 + 0.1 / r + off)).tolist(), "info": info,
                "extrema": [("peak", 0.52, 1e-3)], "tilt_deg": [0.0] * len(d)}
    c = {"p1_r1_C3D20": path(1, 0.3), "p1_r2_C3D20": path(2), "p1_r3_C3D20": path(3), "p1_r4_C3D20": path(4)}
    pc = corner.family_convergence(c, "_C3D20")
    assert pc["meshes"] == ["r1", "r2", "r3", "r4"]
    row = {round(r_[0], 2): r_ for r_ in pc["rows"]}[0.30]
    assert row[4] == 4 and row[2] == pytest.approx(np.interp(0.3, d, exact), rel=1e-6)
    text = "\n".join(corner.family_markdown(c, "_C3D20"))
    assert "on four meshes.**" in text and "| d/L | r = 1 | r = 2 | r = 3 | r = 4 | extrapolated |" in text
    assert "curved FE ring on four meshes](" in text and "three" not in text


def test_probes_of_other_rings_are_stored_apart_from_the_four_cell_path():
    """``--stability-cells``/``--stability-element`` probes get their own key, so the four-cell r = 2 table and its
    unstable stretch never read an eight-cell probe; the four-cell keys are unchanged."""
    bench = _bench_script()
    assert bench.probe_key("r2", 0.1) == "r2@0.100"
    assert bench.probe_key("r2", 0.6, full_near=1.5) == "r2_full1.5@0.600"
    k = bench.probe_key("layers2", 0.05, n_cells=8, element="C3D20")
    assert k == "layers2_cells8_C3D20@0.050"
    c = {"stability": {k: _probe(0.05, [-1e-6, 5e-6], [[1, 0, 0], [0, 0, 1]], [90.0, 80.0])}}
    assert rep.unstable_range(c, "layers2") is None and rep.unstable_range(c) is None


def test_an_eight_cell_rings_probes_are_its_own_and_say_where_its_tilt_stiffness_runs_out():
    """The eight-cell probes are reported with the ring-size runs, not among the four-cell path's "other meshes";
    the tilt pair's eigenvalue on a line through the last two probes gives the bifurcation (here exactly 0.08)."""
    rot = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]
    st = {f"layers2_cells8_C3D20@{d:.3f}": dict(_probe(d, [lam, lam, 2.4e6], rot, [100.0, 100.0, 90.0]),
                                                 mesh="layers2", n_cells=8, element="C3D20", d_reached=d)
          for d, lam in ((0.05, 3.0e6), (0.06, 2.0e6), (0.07, 1.0e6))}
    row = {"radius_mm": 28.0, "fe_flat": 0.1, "fe_curved": 0.05, "model_flat": 0.12, "model_curved": 0.11,
           "model_curved_documented": 0.15, "fe_curved_p1": None, "fe_curved_p1_d": None, "p1_wall_s": 800.0,
           "p1_d_reached": 0.08, "p1_stopped": "stalled"}
    text = "\n".join(rep.cells_markdown({"cells": {"8": row}, "stability": st}))
    assert "Stability of the 8-cell path (two bricks through the wall, every brick fully integrated;" in text
    assert "d/L 0.050: tilt 0.0003/0.0003, twist 0.00024; d/L 0.060: tilt 0.0002/0.0002" in text
    assert "falls from 0.0003 to 0.0001 (33 %); on the last two probes' line it would reach zero at d/L 0.080." in text
    assert "The static run with the same bricks" not in text             # no C3D20 run of this ring stored
    row.update(c3d20_p1_d_reached=0.0795, c3d20_fe_curved_p1=None, c3d20_p1_wall_s=900.0, c3d20_p1_stopped="",
               c3d20_p1_tilt_deg_max=0.3)
    text = "\n".join(rep.cells_markdown({"cells": {"8": row}, "stability": st}))
    assert "stopped at d/L 0.080: the tilt bifurcation is where the path ends." in text
    row.update(c3d20_p1_d_reached=0.07)
    text = "\n".join(rep.cells_markdown({"cells": {"8": row}, "stability": st}))
    assert ("stopped at d/L 0.070, where the last probe (d/L 0.070) finds all 3 lowest modes stable and the tilt pair "
            "at 0.0001: the stop is not a bifurcation these probes see.") in text
    d = np.linspace(0, 0.3, 31)
    c = {"p1_r2": {"d": d.tolist(), "F": (1e-3 * d).tolist()}, "p1_r3": {"d": d.tolist(), "F": (1e-3 * d).tolist()},
         "trace": {"d": d.tolist(), "F": (1e-3 * d).tolist(), "tilt_deg": [0.0] * len(d)}, "stability": st}
    assert "Probes on other meshes" not in "\n".join(rep.path_markdown(c))


def test_a_ring_size_run_with_a_larger_tilt_bias_is_its_own_line_with_its_extrema_and_tilt():
    """``--cells-p1-bias`` runs are stored with their own prefix (the default run's fields untouched) and reported
    with the bias, the extrema and where the plate passes 1 degree."""
    bench = _bench_script()
    assert bench.cells_p1_prefix() == "" and bench.cells_p1_prefix("C3D20") == "c3d20_"
    pre = bench.cells_p1_prefix("C3D20", 1e-3)
    assert pre == "c3d20_bias0.001_"
    d = np.linspace(0, 0.2, 21)
    row = {"radius_mm": 28.0, "fe_flat": 0.1, "fe_curved": 0.05, "model_flat": 0.12, "model_curved": 0.11,
           "model_curved_documented": 0.15, "model_curved_p1": 4.8e-3}
    row.update({pre + k: v for k, v in {
        "fe_curved_p1": 3.0e-3, "fe_curved_p1_d": 0.09, "p1_wall_s": 1200.0, "p1_d_reached": 0.2, "p1_stopped": "",
        "p1_curve": {"d": d.tolist(), "F": (1e-3 * np.sin(np.pi * d / 0.18)).tolist()}, "p1_bias": 1e-3,
        "p1_tilt_deg": (30 * d).tolist(), "p1_tilt_deg_max": 6.0,
        "p1_extrema": [["peak", 0.09, 3.0e-3], ["valley", 0.18, 0.5e-3]]}.items()})
    text = "\n".join(rep.cells_markdown({"cells": {"8": row}}))
    assert ("8 cells with every brick fully integrated and a tilt bias 0.001 G L^2 (100 times the default) "
            "(`--cells-p1 8 --cells-p1-element C3D20 --cells-p1-bias 0.001`, the same mesh): P1 3.000 at d/L 0.090, "
            "the run reaching d/L 0.200 in 20.0 min; 1 peak, 1 valley, peak 3.000 at d/L 0.090, valley 0.500 at d/L "
            "0.180; the plate's tilt 6.0 deg at d/L 0.200, above 1 deg from d/L 0.040; the calibrated beam model's "
            "P1 is 1.60 times it.") in text


def test_a_ring_size_rerun_keeps_that_sizes_other_stored_runs(tmp_path, monkeypatch):
    """Re-running ``--cells 4`` (the coarse stiffness) replaces only its own fields of the four-cell row: the
    first-peak runs and the mesh study stored beside them stay (they took an hour of ccx); the other sizes stay."""
    mod = _bench_script()
    store = tmp_path / "fe-ring3d.json"
    monkeypatch.setattr(mod, "STORE", str(store))
    store.write_text(json.dumps({"cells": {"4": {"fe_flat": 1.0, "fe_curved_p1": 2.0, "c3d20_r2_fe_curved": 3.0},
                                           "8": {"fe_flat": 4.0}}}))
    mod._store_rows("cells", {"4": {"fe_flat": 5.0, "fe_curved": 6.0}})
    cells = json.loads(store.read_text())["cells"]
    assert cells["4"] == {"fe_flat": 5.0, "fe_curved_p1": 2.0, "c3d20_r2_fe_curved": 3.0, "fe_curved": 6.0}
    assert cells["8"] == {"fe_flat": 4.0}
