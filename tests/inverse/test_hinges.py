"""Hinge lengths per region (core/inverse/hinges.py): exact sensitivities, planted lengths recovered."""
import json
import os
import subprocess
import sys

import numpy as np
import pytest

from inverse_helpers import planted_result, scene_with
from metamaterial_wb import REPO_DIR
from metamaterial_wb.core.errors import MetamaterialError
from metamaterial_wb.core.inverse.fit import Problem, combined_errors
from metamaterial_wb.core.inverse.hinges import HingeRegions, parse_regions
from metamaterial_wb.core.inverse.targets import parse_target
from metamaterial_wb.core.scene import Scene

PLANTED_L = [2.5, 6.0]          # per region (the sheet's hinge length 8 mm sets the plate gap: stubs)
PLANTED_W = [0.8, 1.2]          # the first region's width is the reference (only k2 ratios act on D)


@pytest.fixture(scope="module")
def planted():
    s = scene_with(Scene.grid(6, 6, hinge={"length_mm": 8, "width_mm": 0.8, "thickness_mm": 7}),
                   [("H1,1", 0.6), ("V3,4", 0.7)])
    hr0 = HingeRegions(Problem(s, parse_target(s, {"nodes": planted_result(s)["nodes"]})), 1, 2)
    d = s.to_dict()
    names = s.topology.joint_names
    d["joints"] = [{"joint": names[k], "length_mm": L, "width_mm": w}
                   for L, w, js in zip(PLANTED_L, PLANTED_W, hr0.regions) for k in js]
    sp = Scene.from_dict(d)
    return s, sp, planted_result(sp)


def test_residual_jacobian_in_sizes_values_alignment_equals_finite_differences(planted):
    s, _sp, res = planted
    pb = Problem(s, parse_target(s, {"nodes": res["nodes"]}))
    hr = HingeRegions(pb, 1, 2)
    assert (hr.nL, hr.nW) == (2, 1)
    hr.fit(("H1,1", "V3,4"), max_nfev=1)
    rng = np.random.default_rng(4)
    x = np.concatenate([[3.5, 5.0, 1.1], [0.4, 0.5], rng.normal(0, 0.01, 6)])
    r, J = hr._fun(x)
    h = 1e-6
    for k in range(len(x)):
        e = np.zeros(len(x))
        e[k] = h
        fd = (hr._fun(x + e, jac=False)[0] - hr._fun(x - e, jac=False)[0]) / (2 * h)
        assert np.abs(fd - J[:, k]).max() < 1e-6 * max(1.0, np.abs(fd).max()), k


def test_size_sensitivities_of_the_response_equal_finite_differences(planted):
    s, _sp, res = planted
    hr = HingeRegions(Problem(s, parse_target(s, {"nodes": res["nodes"]})), 1, 2)
    L = np.array([3.5, 5.0, 1.1])                 # between the table's knots (piecewise linear laws)
    D0, G, dD0, dG = hr.response(("H1,1", "V3,4"), L)
    h = 1e-6
    for r in range(3):
        e = np.zeros(3)
        e[r] = h
        Gp = hr.response(("H1,1", "V3,4"), L + e)[1]
        Gm = hr.response(("H1,1", "V3,4"), L - e)[1]
        assert np.abs((Gp - Gm) / (2 * h) - dG[r]).max() < 1e-7 * max(1.0, np.abs(dG[r]).max())


def test_planted_lengths_and_values_recovered(planted):
    s, _sp, res = planted
    pb = Problem(s, parse_target(s, {"nodes": res["nodes"]}))
    plain = pb.fit(("H1,1", "V3,4"))
    assert combined_errors([f.parts for f in plain.frames])["max_mm"] > 1e-2   # lengths matter
    hr = HingeRegions(pb, 1, 2)
    fit, p = hr.fit(("H1,1", "V3,4"))
    assert combined_errors([f.parts for f in fit.frames])["max_mm"] < 1e-6
    assert np.allclose(p, PLANTED_L + PLANTED_W[1:], atol=1e-6)
    assert np.allclose(fit.values[0], [0.6, 0.7], atol=1e-6)
    ov = hr.overrides(p)
    assert len(ov) == s.topology.n_joints
    assert all(min(abs(v["length_mm"] - x) for x in PLANTED_L) < 1e-6 for v in ov.values())
    assert {round(v["width_mm"], 6) for v in ov.values() if "width_mm" in v} == {1.2}


def test_bounds_and_bad_regions(planted):
    s, _sp, res = planted
    hr = HingeRegions(Problem(s, parse_target(s, {"nodes": res["nodes"]})), 2, 2)
    for lo, hi in hr.bounds[:hr.nL]:
        assert lo == 0.25 and hi == 8.0            # the table's range, at most the plate gap (lh = 8 mm)
    for lo, hi in hr.bounds[hr.nL:]:
        assert lo == 0.2 and hi == 3.0             # the table's widths, at most (cell - L) / 4
    for bad in ("0x2", "two", "2x99"):
        with pytest.raises(MetamaterialError):
            parse_regions(bad)


def test_cli_hinges_writes_overrides(planted, tmp_path):
    s, _sp, res = planted
    (tmp_path / "t.json").write_text(json.dumps(res))
    (tmp_path / "s.json").write_text(s.to_json())
    p = subprocess.run([sys.executable, "-m", "metamaterial_wb", "inverse", str(tmp_path / "s.json"), "--target",
                        str(tmp_path / "t.json"), "--values-only", "--hinges", "--hinge-regions", "1x2",
                        "--out", str(tmp_path / "o"), "--evaluate", "quadratic", "--no-picture"],
                       capture_output=True, text=True, env=dict(os.environ, PYTHONPATH=REPO_DIR), timeout=600)
    assert p.returncode == 0, p.stderr
    rep = json.loads((tmp_path / "o" / "report.json").read_text())
    assert [h["length_mm"] for h in rep["hinges"] if "length_mm" in h] == pytest.approx(PLANTED_L, abs=1e-6)
    assert [h["width_mm"] for h in rep["hinges"] if "width_mm" in h] == pytest.approx(PLANTED_W[1:], abs=1e-6)
    assert rep["errors"]["quadratic"]["max_mm"] < 1e-6
    out = Scene.load(tmp_path / "o" / "scene.json")
    assert len(out.joint_overrides) == s.topology.n_joints
