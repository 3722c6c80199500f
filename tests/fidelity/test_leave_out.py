""""Leave out what a scene does not need" (issue 6, item 7), each shortcut checked to be both taken and
harmless (the answer equals the one without the shortcut)."""
import os
import subprocess
import sys
import time

import numpy as np
import pytest

from metamaterial_wb.core.lattice.geometry import LatticeGeometry
from metamaterial_wb.core.models import run_model
from metamaterial_wb.core.scene import Scene

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def grid(n, actuators=(), **extra):
    d = {"format": "metamaterial-scene", "version": 1, "layout": {"grid": [n, n]}, "actuators": list(actuators)}
    d.update(extra)
    return Scene.from_dict(d)


def test_quadratic_never_builds_or_imports_the_higher_models():
    code = ("import sys; sys.path.insert(0, %r)\n"
            "from metamaterial_wb.core.models import run_model, model_names\n"
            "from metamaterial_wb.core.scene import Scene\n"
            "assert 'nonlinear' in model_names()\n"
            "s = Scene.grid(4, 4, actuators=[{'name': 'm', 'joint': 'H1,1', 'value': 0.5}])\n"
            "run_model('quadratic', s)\n"
            "heavy = [m for m in sys.modules if m.startswith('metamaterial_wb.core.lattice.')]\n"
            "print(sorted(heavy))\n" % REPO)
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=REPO)
    assert r.returncode == 0, r.stderr
    assert r.stdout.strip() == "[]"


def test_components_without_actuators_are_not_solved_quadratic():
    """Free parts that touch no actuator are removed from the solve (D = 0, warned): here the part of a
    chain behind a clip at D = 0 never enters the factorisation."""
    from metamaterial_wb.core.solver import model_for_scene

    sc = Scene.from_dict({"layout": {"grid": [1, 8]},
                          "actuators": [{"name": "m", "joint": "V0,1", "value": 0.5}],
                          "constraints": []})
    m = model_for_scene(sc)
    assert m.island_nodes.size == 0
    sc0 = Scene.from_dict({"layout": {"grid": [2, 3]}})
    m0 = model_for_scene(sc0)
    assert m0.free.size == 0 and m0.island_nodes.size == sc0.topology.n_nodes and m0.H_FF.shape == (0, 0)
    assert np.all(m0.solve({}) == 0)


@pytest.mark.parametrize("model", ["linear", "nonlinear"])
def test_unloaded_scene_is_not_solved_by_lattice_models(model):
    sc = grid(30)                                              # no actuator at all
    sc2 = grid(30, [{"name": "m", "joint": "H3,3", "value": 0.0}])   # an actuator at rest
    for s in (sc, sc2):
        res = run_model(model, s)
        assert res.converged and np.all(res.D == 0)
        assert "nothing to solve" in res.info["method"]


def test_planar_scenes_leave_out_out_of_plane_dofs_without_changing_the_answer():
    acts = [{"name": "m1", "joint": "H2,1", "value": 0.6}, {"name": "m2", "joint": "V1,3", "value": -0.4}]
    sc = grid(4, acts)
    n = sc.topology.n_nodes
    for model in ("linear", "nonlinear"):
        r3 = run_model(model, sc)
        r6 = run_model(model, sc, planar=False)
        assert r3.info["planar"] and not r6.info["planar"]
        assert r3.info["dofs"] == 3 * (n - 1) and r6.info["dofs"] == 6 * (n - 1)
        assert np.abs(r3.D - r6.D).max() < 1e-7
        assert np.abs(r3.positions_mm - r6.positions_mm).max() < 1e-7


def test_linear_model_reuses_its_factorisation_for_new_values():
    """Only actuator values change: the factored KKT matrix is reused (a back-substitution), and the
    answer equals a fresh model built with the new values."""
    from metamaterial_wb.core.lattice.solve import LinearLattice

    acts = [{"name": "m1", "joint": "H2,1", "value": 0.3}, {"name": "m2", "joint": "V1,3", "value": -0.2}]
    sc = grid(10, acts)
    lin = LinearLattice(sc)
    sc2 = grid(10, [dict(a, value=v) for a, v in zip(acts, (-0.1, 0.25))])
    fresh = LinearLattice(sc2)
    t = time.perf_counter()
    X, R, q, mu = lin.solve(fresh.psi)
    t_resolve = time.perf_counter() - t
    X2, R2, q2, mu2 = fresh.solve()
    assert np.abs(q - q2).max() <= 1e-12 * np.abs(q2).max()
    print(f"re-solve {t_resolve * 1e3:.3f} ms vs factor {fresh.timings['factor_s'] * 1e3:.3f} ms")


def test_contact_terms_only_where_needed():
    """Below the contact onset no penalty acts, and switching contact off changes nothing there."""
    sc = grid(5, [{"name": "m", "joint": "H2,2", "value": 0.05}])
    a = run_model("nonlinear", sc)
    b = run_model("nonlinear", sc, contact=False)
    assert a.info["contact_energy_Nmm"] == 0.0
    assert np.array_equal(a.D, b.D)


def test_linear_model_called_again_with_new_values_reuses_the_factorisation():
    """The animation path: run_model('linear', scene, about='flat') with only actuator values changed reuses the
    cached factorisation; the answer equals a cold build, and a structural change is never served from the cache."""
    import metamaterial_wb.core.lattice as lattice

    lattice.clear_cache()
    acts = [{"name": "m1", "joint": "H2,1", "value": 0.3}, {"name": "m2", "joint": "V1,3", "value": -0.2}]
    a = run_model("linear", grid(8, acts), about="flat")
    assert a.info["reused_factorisation"] is False
    acts2 = [dict(acts[0], value=-0.15), dict(acts[1], value=0.4)]
    warm = run_model("linear", grid(8, acts2), about="flat")
    assert warm.info["reused_factorisation"] is True
    lattice.clear_cache()
    cold = run_model("linear", grid(8, acts2), about="flat")
    assert cold.info["reused_factorisation"] is False
    assert np.allclose(warm.D, cold.D, rtol=0, atol=1e-10)
    other = run_model("linear", grid(8, acts2, hinge={"length_mm": 3.0, "width_mm": 0.8, "thickness_mm": 7}),
                      about="flat")
    assert other.info["reused_factorisation"] is False and not np.allclose(other.D, cold.D)
