"""The linear lattice model's fast paths change its speed, not its answer.

Reference: the same model with the fast paths switched off (``core/lattice/linalg.reference_paths``): the
KKT matrix assembled on its full pattern and factored by sparse LU (SuperLU with pivoting), the hinge-chain
positions by LU, no CHOLMOD, no Schur complement, no planar shortcuts. Both are run on the five standard
scenes of the fidelity benchmark at amplitudes 0.05 and 0.5, with the default linearisation and with
``about=quadratic``; node rotations, positions and D must agree to rounding (1e-10).
"""
import re

import numpy as np
import pytest

from metamaterial_wb.bench import fidelity
from metamaterial_wb.core.lattice import linalg as lattice_linalg
from metamaterial_wb.core.lattice import solve as lattice_solve
import metamaterial_wb.core.lattice as lattice
from metamaterial_wb.core.models import run_model

SCENES = {amp: fidelity.standard_scenes(amp) for amp in (0.05, 0.5)}


def _run(scene, about, reference):
    lattice.clear_cache()
    if reference:
        with lattice_solve.reference_paths():
            return run_model("linear", scene, about=about)
    return run_model("linear", scene, about=about)


@pytest.mark.parametrize("cholmod", [True, False])
@pytest.mark.parametrize("amp", [0.05, 0.5])
@pytest.mark.parametrize("about", ["quadratic", "flat"])
def test_fast_paths_agree_with_reference(amp, about, cholmod, monkeypatch):
    """With CHOLMOD (Schur complement) and without it (LU of a KKT matrix assembled from the stiffness block)."""
    if cholmod and lattice_linalg._cholmod is None:
        pytest.skip("CHOLMOD (scikit-sparse) not installed")
    for key, _title, scene in SCENES[amp]:
        with monkeypatch.context() as mp:
            if not cholmod:
                mp.setattr(lattice_linalg, "_cholmod", None)
            fast = _run(scene, about, reference=False)
        ref = _run(scene, about, reference=True)
        cell = scene.cell_size_mm
        assert np.abs(fast.rotations - ref.rotations).max() <= 1e-10, key
        assert np.abs(fast.positions_mm - ref.positions_mm).max() <= 1e-10 * cell, key
        assert np.abs(fast.D - ref.D).max() <= 1e-10, key
        assert fast.info.get("step_length", 1.0) == pytest.approx(ref.info.get("step_length", 1.0), abs=1e-10)
        assert fast.info["contact_hinges"] == ref.info["contact_hinges"], key
        # something was actually solved (the comparison is not between two empty results)
        assert np.abs(ref.D).max() > 0.5 * amp, key


def test_reference_switch_is_restored_and_really_different():
    """The switch turns the fast paths off inside the block only, and the fast path really is another
    computation (its factorisation object differs) where CHOLMOD is installed."""
    from metamaterial_wb.core.lattice.geometry import LatticeGeometry

    scene = SCENES[0.5][1][2]
    geo = LatticeGeometry(scene)
    with lattice_solve.reference_paths():
        ref_lin = lattice_solve.LinearLattice(scene, geo)
    fast_lin = lattice_solve.LinearLattice(scene, geo)
    assert type(ref_lin.lu).__name__ == "SuperLU"
    if lattice_linalg._cholmod is not None:
        assert isinstance(fast_lin.lu, lattice_solve.SchurKKT)
    else:
        pytest.skip("CHOLMOD (scikit-sparse) not installed: the fast path is the LU path")


def _quadratic_cases():
    import glob
    import os

    from metamaterial_wb.core.scene import Scene

    cases = [(f"{key}@{amp}", sc) for amp in SCENES for key, _t, sc in SCENES[amp]]
    root = os.path.join(os.path.dirname(__file__), "..", "..", "examples")
    for path in sorted(glob.glob(os.path.join(root, "*.json"))):
        try:
            cases.append((os.path.basename(path), Scene.load(path)))
        except Exception:          # not a metamaterial scene (e.g. a sleeve specification)
            continue
    names = Scene.grid(1, 6).topology.joint_names
    # an island: two strips joined only through a clipped joint's nodes, every hinge k1 = 1
    cases.append(("island", Scene.from_dict({"layout": {"grid": [1, 6]},
                                             "joints": [{"joint": j, "k1": 1.0} for j in names],
                                             "constraints": [{"name": "c", "joint": "V0,3", "value": 0.0}]})))
    # islands next to a driven part, per-joint stiffness overrides, an actuator and an equal clip sharing a node
    cases.append(("driven+island", Scene.from_dict({
        "layout": {"grid": [4, 4]},
        "joints": [{"joint": "H1,1", "k1": 0.3, "k2": 2.5}, {"joint": "V2,2", "k2": 0.01}],
        "actuators": [{"name": "m", "joint": "H1,1", "value": 0.7}],
        "constraints": [{"name": "c", "joint": "V1,1", "value": 0.7}, {"name": "z", "joint": "H3,2", "value": -0.2}]})))
    cases.append(("nothing fixed", Scene.from_dict({"layout": {"grid": [3, 3]}})))
    return cases


def test_lean_quadratic_solve_equals_the_quadratic_model():
    """``about=quadratic``'s predictor solves the quadratic model leanly (free block only, one right-hand
    side): D equals ``core/solver.solve_scene`` on every example scene, the standard scenes, islands (D = 0),
    stiffness overrides and shared nodes."""
    from metamaterial_wb.core.solver import solve_scene

    cases = _quadratic_cases()
    assert len(cases) >= 14
    from metamaterial_wb.core.errors import MetamaterialError

    solved = 0
    for name, sc in cases:
        try:
            ref = solve_scene(sc)[0]
        except MetamaterialError as exc:       # e.g. a hinge outside the calibration table: same refusal
            with pytest.raises(MetamaterialError, match=re.escape(str(exc))):
                lattice_solve.quadratic_D(sc)
            continue
        solved += 1
        lean = lattice_solve.quadratic_D(sc)
        assert np.abs(lean - ref).max() <= 1e-11 * max(1.0, np.abs(ref).max()), name
        assert np.array_equal(lean == 0.0, ref == 0.0) or np.abs(ref[lean == 0.0]).max() < 1e-12, name
    assert solved >= 14


def test_lean_quadratic_solve_rejects_like_the_quadratic_model():
    from metamaterial_wb.core.errors import MetamaterialError
    from metamaterial_wb.core.scene import Scene
    from metamaterial_wb.core.solver import solve_scene

    sc = Scene.from_dict({"layout": {"grid": [3, 3]}, "actuators": [{"name": "m", "joint": "H1,1", "value": 0.5}]})
    sc.actuators[0].value = 1.5            # bypassing validation: the quadratic model's own check answers
    with pytest.raises(MetamaterialError) as ref:
        solve_scene(sc)
    with pytest.raises(MetamaterialError) as lean:
        lattice_solve.quadratic_D(sc)
    assert str(lean.value) == str(ref.value)


@pytest.mark.parametrize("arc", [True, False])
def test_planar_element_state_equals_the_general_one(arc):
    """The 2-D kernel gives ElementState's strains, hinge forces, Jacobian and material tangent on the DOFs a
    planar scene keeps, at a planar state far from the flat sheet (plates turned up to 0.6 rad, hinges
    stretched and sheared, one hinge bent past pi/2 relative rotation)."""
    from metamaterial_wb.core import kinematics
    from metamaterial_wb.core.lattice.geometry import LatticeGeometry
    from metamaterial_wb.core.lattice.mechanics import ElementState, PlanarElementState

    scene = SCENES[0.5][4][2]                    # mixed hinge sizes
    geo = LatticeGeometry(scene)
    rng = np.random.default_rng(3)
    phi = rng.uniform(-0.6, 0.6, geo.n)
    phi[geo.b[0]] = phi[geo.a[0]] + 1.9
    R = kinematics.rotation_matrices(phi)
    X = geo.X0 + rng.normal(scale=0.3, size=geo.X0.shape) * np.array([1.0, 1.0, 0.0])
    assert PlanarElementState.applies(geo, R)
    ref = ElementState(geo, X, R, tangent=False, arc=arc)
    fast = PlanarElementState(geo, X, R, arc=arc)
    inplane = [0, 1, 5, 6, 7, 11]
    assert np.abs(fast.eps - ref.eps).max() <= 1e-12 * np.abs(ref.eps).max()
    assert np.abs(fast.J[:, :, inplane] - ref.J[:, :, inplane]).max() <= 1e-12 * np.abs(ref.J).max()
    assert np.abs(fast.grad[:, inplane] - ref.grad[:, inplane]).max() <= 1e-12 * np.abs(ref.grad).max()
    Hm = np.transpose(ref.J, (0, 2, 1)) @ (geo.K @ ref.J)
    sub = np.ix_(np.arange(geo.m), inplane, inplane)
    assert np.abs(fast.H[sub] - Hm[sub]).max() <= 1e-12 * np.abs(Hm).max()
    assert np.abs(ref.eps[:, 5]).max() > 1.8         # the large relative rotation is really there


def test_fast_linear_model_uses_the_fast_kernels():
    from metamaterial_wb.core.lattice.geometry import LatticeGeometry
    from metamaterial_wb.core.lattice.mechanics import PlanarElementState

    made = []
    orig = PlanarElementState.__init__

    def spy(self, *a, **k):
        made.append(1)
        orig(self, *a, **k)

    PlanarElementState.__init__ = spy
    try:
        scene = SCENES[0.5][1][2]
        run_model("linear", scene, about="quadratic")
        n_fast = len(made)
        with lattice_solve.reference_paths():
            lattice.clear_cache()
            run_model("linear", scene, about="quadratic")
    finally:
        PlanarElementState.__init__ = orig
    assert n_fast >= 1 and len(made) == n_fast            # used on the fast path, never on the reference path
    eye = np.broadcast_to(np.eye(3), (4, 3, 3))
    assert PlanarElementState.applies(LatticeGeometry(scene), eye)
    assert not PlanarElementState.applies(LatticeGeometry(SCENES[0.5][3][2]), eye)      # tilted hinges: 3-D
