"""The linear lattice linearised about the quadratic model's state (``--option about=quadratic``).

References that do not come from the code under test: the nonlinear model's equilibrium (a fixed point of
any linearisation that carries the state's residual forces, constraint offsets and contact correctly), the
rotating-squares mechanism's closed form, the second-order convergence of a first-order method towards the
nonlinear reference as the actuation shrinks, and the nonlinear reference on a near-mechanism chain at the
working amplitude, where the flat-sheet linearisation is far off.
"""
import json
import math
import subprocess
import sys

import numpy as np
import pytest

from metamaterial_wb.bench import fidelity
from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.core.lattice.geometry import LatticeGeometry
from metamaterial_wb.core.lattice.mechanics import hinge_strains
from metamaterial_wb.core.lattice.solve import ChainPositions, LinearLattice, node_twist, quadratic_state
from metamaterial_wb.core.models import run_model
from metamaterial_wb.core.scene import Scene

REPO = __file__.rsplit("/tests/", 1)[0]


def grid(rows, cols, actuators=(), **extra):
    d = {"format": "metamaterial-scene", "version": 1, "layout": {"grid": [rows, cols]},
         "actuators": list(actuators)}
    d.update(extra)
    return Scene.from_dict(d)


def _chain05():
    return dict((k, s) for k, _, s in fidelity.standard_scenes(0.5))["chain"]


@pytest.mark.parametrize("tangent", ["material", "full"])
@pytest.mark.parametrize("which", ["grid10", "bending"])
def test_the_nonlinear_equilibrium_is_a_fixed_point(which, tangent):
    """Linearised about the nonlinear model's own solution (plates in contact on the 10 x 10 grid, folded
    plates on the bending strip), the one solve must not move: the state's hinge forces, the actuators' constraint
    offsets and the contact springs balance there. A sign or offset error in any of them moves it."""
    sc = dict((k, s) for k, _, s in fidelity.standard_scenes(0.5))[which]
    ref = run_model("nonlinear", sc, **fidelity.REFERENCE_OPTIONS)
    assert ref.converged
    geo = LatticeGeometry(sc)
    lin = LinearLattice(sc, geo, base=(np.asarray(ref.positions_mm), np.asarray(ref.rotations)), tangent=tangent)
    if which == "grid10":
        assert np.any(lin.kappa_c < 0)          # some hinges are past the contact onset at that state
    X, R, q, mu = lin.solve()
    assert np.abs(q).max() <= 1e-6
    assert np.abs(X - ref.positions_mm).max() <= 1e-6 * sc.cell_size_mm
    assert np.abs(R - ref.rotations).max() <= 1e-6


@pytest.mark.parametrize("value", [0.5, -0.6])
def test_uniform_mechanism_is_reproduced_exactly(value):
    """Every joint actuated alike: the quadratic state is the exact rotating-squares mechanism (no hinge
    stretched), so the solve keeps it: D = value everywhere, pitch = lh sin(phi)/phi + s (cos phi -+ sin phi)."""
    sc0 = grid(3, 3)
    sc = grid(3, 3, [{"name": f"a{k}", "joint": n, "value": value} for k, n in enumerate(sc0.topology.joint_names)])
    geo = LatticeGeometry(sc)
    res = run_model("linear", sc, about="quadratic")
    assert res.converged and res.info["about"] == "quadratic"
    phi = abs(value) * (geo.closing_rad if value > 0 else geo.opening_rad)
    lh, s = sc.hinge["length_mm"], geo.plate_side_mm
    pitch = lh * math.sin(phi) / phi + s * (math.cos(phi) - math.copysign(1, value) * math.sin(phi))
    a, b = sc.topology.node_index[(1, 0)], sc.topology.node_index[(1, 3)]
    assert np.linalg.norm(res.positions_mm[b] - res.positions_mm[a]) / 3 == pytest.approx(pitch, rel=1e-8)
    assert np.abs(res.D - value).max() <= 1e-7


def test_error_against_the_nonlinear_model_is_second_order_in_the_actuation():
    """A first-order method about a first-order-accurate state: its plate-angle error against the nonlinear
    reference (rigid turn removed) falls ~4 x when the actuation halves (contact off in both: its onset
    would make the answers piecewise)."""
    acts = [{"name": "m1", "joint": "H2,1", "value": 0.02}, {"name": "m2", "joint": "V1,3", "value": -0.015}]
    errs = []
    for f in (1.0, 0.5, 0.25):
        sc = grid(5, 5, [dict(a, value=a["value"] * f) for a in acts])
        ref = run_model("nonlinear", sc, tol=1e-11, contact=False)
        res = run_model("linear", sc, about="quadratic", contact=False)
        d = node_twist(res.rotations) - node_twist(ref.rotations)
        errs.append(np.abs(d - d.mean()).max())
    assert errs[0] > 0
    for e1, e2 in zip(errs, errs[1:]):
        assert 3.5 <= e1 / e2 <= 4.5


def test_near_mechanism_chain_at_working_amplitude_beats_the_flat_linearisation():
    """The 1 x 20 chain at amplitude 0.5 (a near-mechanism: 2 x 0.8 mm hinges on 18 mm cells): linearised at the
    flat sheet the lattice misses the nonlinear reference by more than the quadratic model does (measured
    ratio 1.19); linearised about the quadratic model's state it keeps well under half of the flat
    linearisation's error (measured 0.21 of the quadratic model's error)."""
    sc = _chain05()
    ref = run_model("nonlinear", sc, **fidelity.REFERENCE_OPTIONS)
    e = {name: fidelity.compare(sc, run_model(*args), ref)["rms_D"]
         for name, args in (("quadratic", ("quadratic", sc)),)}
    e["flat"] = fidelity.compare(sc, run_model("linear", sc, about="flat"), ref)["rms_D"]
    e["about"] = fidelity.compare(sc, run_model("linear", sc, about="quadratic"), ref)["rms_D"]
    assert e["about"] < 0.5 * e["flat"]
    assert e["about"] < 0.5 * e["quadratic"]


@pytest.mark.parametrize("which", ["grid10", "bending"])
def test_step_length_slope_is_the_derivative_of_the_merit_along_the_returned_poses(which):
    """The line search's analytic slope at the quadratic state equals a central difference of the merit
    (nonlinear energy + constraint penalty) along the poses the model returns (hinge-chain positions), on a
    planar grid and on the folded bending strip; the chosen step never has a higher merit than the full one."""
    sc = dict((k, s) for k, _, s in fidelity.standard_scenes(0.5))[which]
    geo = LatticeGeometry(sc)
    chain = ChainPositions(geo)
    _D, Xb, Rb = quadratic_state(sc, geo, chain)
    lin = LinearLattice(sc, geo, base=(Xb, Rb), tangent="material")
    lin._chain = chain
    X1, R1, q, mu = lin.solve()
    nu = 2.0 * float(np.abs(mu).max())
    h = 1e-6

    def merit(a):
        return lin.merit(hinge_strains(geo, *lin.pose(q, a)), nu)
    fd = (merit(h) - merit(-h)) / (2 * h)
    assert lin.merit_slope(q, nu) == pytest.approx(fd, rel=1e-4)
    assert lin.merit_slope(q, nu) < 0
    alpha, Xa, Ra = lin.line_search(q, mu, X1, R1)
    assert 0 < alpha <= 2
    assert lin.merit(hinge_strains(geo, Xa, Ra), nu) <= lin.merit(hinge_strains(geo, X1, R1), nu)


def test_option_is_validated_and_cli_output_format_is_unchanged(tmp_path):
    sc = grid(3, 3, [{"name": "m1", "joint": "H1,1", "value": 0.3}])
    with pytest.raises(SceneError, match="about"):
        run_model("linear", sc, about="curved")
    p = tmp_path / "s.json"
    p.write_text(sc.to_json())
    docs = {}
    for extra in (["--option", "about=flat"], ["--option", "about=quadratic"], []):
        out = tmp_path / f"r{'-'.join(extra) or 'default'}.json"
        r = subprocess.run([sys.executable, "-m", "metamaterial_wb", "solve", str(p), "--out", str(out), "--model",
                            "linear"] + extra, cwd=REPO, capture_output=True, text=True)
        assert r.returncode == 0, r.stderr
        docs[extra[-1] if extra else "default"] = json.loads(out.read_text())
    flat, quad, default = docs["about=flat"], docs["about=quadratic"], docs["default"]
    assert set(flat) == set(quad) == set(default)
    assert set(flat["nodes"][0]) == set(quad["nodes"][0])
    # same scene, different linearisation point: close (small actuation), not identical
    D0 = np.array([n["D"] for n in flat["nodes"]])
    D2 = np.array([n["D"] for n in quad["nodes"]])
    assert 0 < np.abs(D0 - D2).max() < 0.1
    # the default is about=quadratic
    assert np.array_equal(np.array([n["D"] for n in default["nodes"]]), D2)


def test_no_load_is_the_flat_sheet():
    sc = grid(3, 3, [{"name": "m1", "joint": "H1,1", "value": 0.0}])
    res = run_model("linear", sc, about="quadratic")
    assert res.converged and np.all(res.D == 0)


def test_default_is_about_quadratic_and_falls_back_to_flat_where_the_quadratic_model_cannot_predict():
    sc = grid(3, 3, [{"name": "m1", "joint": "H1,1", "value": 0.3}])
    res = run_model("linear", sc)
    assert res.info["about"] == "quadratic" and not res.warnings
    assert np.array_equal(res.D, run_model("linear", sc, about="quadratic").D)
    # hinges outside the calibration table: the quadratic model refuses the scene ...
    odd = grid(3, 3, [{"name": "m1", "joint": "H1,1", "value": 0.3}],
               hinge={"length_mm": 9.99, "width_mm": 0.8, "thickness_mm": 7})
    with pytest.raises(SceneError, match="calibration table"):
        run_model("quadratic", odd)
    with pytest.raises(SceneError, match="calibration table"):          # asked for explicitly: refused too
        run_model("linear", odd, about="quadratic")
    # ... the default linear model still solves it, at the flat sheet, and says so
    res = run_model("linear", odd)
    flat = run_model("linear", odd, about="flat")
    assert res.info["about"] == "flat" and "calibration table" in res.info["about_fallback"]
    assert any("linearised at the flat sheet instead" in w for w in res.warnings)
    assert np.array_equal(res.D, flat.D) and res.converged
