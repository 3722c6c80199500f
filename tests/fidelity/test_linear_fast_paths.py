"""The linear lattice model's fast paths change its speed, not its answer.

Reference: the same model with the fast paths switched off (``core/lattice/solve.reference_paths``): the
KKT matrix assembled on its full pattern and factored by sparse LU (SuperLU with pivoting), the hinge-chain
positions by LU, no CHOLMOD, no Schur complement, no planar shortcuts. Both are run on the five standard
scenes of the fidelity benchmark at amplitudes 0.05 and 0.5, with the default linearisation and with
``about=quadratic``; node rotations, positions and D must agree to rounding (1e-10).
"""
import numpy as np
import pytest

from metamaterial_wb.core import fidelity
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


@pytest.mark.parametrize("amp", [0.05, 0.5])
@pytest.mark.parametrize("about", ["quadratic", "flat"])
def test_fast_paths_agree_with_reference(amp, about):
    for key, _title, scene in SCENES[amp]:
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
    if lattice_solve._cholmod is not None:
        assert isinstance(fast_lin.lu, lattice_solve.SchurKKT)
    else:
        pytest.skip("CHOLMOD (scikit-sparse) not installed: the fast path is the LU path")
