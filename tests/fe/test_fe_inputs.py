"""Bad inputs to the FE rung's public entry points are refused with the value and the allowed range, before any mesh
is built or ccx is run; nothing is clamped, truncated or rounded (a negative mesh size used to run with a fallback
and return a wrong stiffness, ``increments=2.5`` became 2, a zero became a ZeroDivisionError)."""
import math

import pytest

from metamaterial_wb.core.errors import MetamaterialError
from metamaterial_wb.core.sleeve.cell import CellGeometry
from metamaterial_wb.fe import ccx, hinge, patch, sleeve2d, sleeve3d

NAN = float("nan")
REAL_RUN = ccx.run                       # the module's own run (the fixture below replaces it)


@pytest.fixture(autouse=True)
def no_ccx(monkeypatch):
    """Every check must come before ccx: a solver that reached it fails the test."""
    def ran(*a, **k):
        raise AssertionError("ccx was run")
    monkeypatch.setattr(ccx, "run", ran)


def _spec(**kw):
    return hinge.HingeSpec(**kw)


def _mutated(**kw):
    s = hinge.HingeSpec()
    s.__dict__.update(kw)
    return s


CASES = [
    # the hinge: mesh size, the spec's sizes and moduli, the bending deck's increments
    (lambda: hinge.hinge_mesh(_spec(), -0.4), r"h: -0\.4 mm; allowed: "),
    (lambda: hinge.hinge_mesh(_spec(), 0.0), r"h: 0\.0 mm; allowed: "),
    (lambda: hinge.hinge_mesh(_spec(), NAN), r"h: nan mm; allowed: "),
    (lambda: hinge.hinge_mesh(_spec(), 1e-4), r"h: 0\.0001 mm; allowed: .*elements"),
    (lambda: hinge.stiffness(_spec(), -0.4), r"h: -0\.4 mm; allowed: "),
    (lambda: hinge.bending_curve(_spec(), 0.0), r"h: 0\.0 mm; allowed: "),
    (lambda: _spec(thickness=0.0), r"thickness: 0\.0 mm; allowed: "),
    (lambda: _spec(thickness=-7.0), r"thickness: -7\.0 mm; allowed: "),
    (lambda: _spec(width=NAN), r"width: nan mm; allowed: "),
    (lambda: _spec(E=-26.0), r"E: -26\.0 MPa; allowed: "),
    (lambda: _spec(E=0.0), r"E: 0\.0 MPa; allowed: "),
    (lambda: _spec(nu=0.5), r"nu: 0\.5; allowed: 0 <= nu < 0\.5"),
    (lambda: _spec(nu=-0.1), r"nu: -0\.1; allowed: 0 <= nu < 0\.5"),
    (lambda: _spec(plate_E=0.0), r"plate_E: 0\.0 MPa; allowed: "),
    (lambda: hinge.stiffness_deck(_mutated(E=-1.0), hinge.hinge_mesh(_spec(), 0.8)), r"E: -1\.0 MPa; allowed: "),
    (lambda: hinge.stiffness(_mutated(nu=0.5), 0.8), r"nu: 0\.5; allowed: "),
    (lambda: hinge.bending_deck(_spec(), hinge.hinge_mesh(_spec(), 0.8), 10, increments=0),
     r"increments: 0; allowed: an integer >= 1"),
    (lambda: hinge.bending_deck(_spec(), hinge.hinge_mesh(_spec(), 0.8), 10, increments=-3), r"increments: -3; allowed"),
    (lambda: hinge.bending_curve(_spec(), 0.8, 10, increments=2.5), r"increments: 2\.5; allowed"),
    (lambda: hinge.bending_deck(_spec(), hinge.hinge_mesh(_spec(), 0.8), NAN), r"angle_deg: nan deg; allowed"),
    # the patch: mesh size, elements through the thickness, increments, moduli
    (lambda: patch.patch_deck(patch.patch_scene(0.05), h=-0.5, nz=2), r"h: -0\.5 mm; allowed: "),
    (lambda: patch.patch_deck(patch.patch_scene(0.05), h=0.0, nz=2), r"h: 0\.0 mm; allowed: "),
    (lambda: patch.patch_deck(patch.patch_scene(0.05), h=0.5, nz=0), r"nz: 0; allowed: an integer from 1 to"),
    (lambda: patch.patch_deck(patch.patch_scene(0.05), h=0.5, nz=-2), r"nz: -2; allowed: "),
    (lambda: patch.patch_deck(patch.patch_scene(0.05), h=0.5, nz=2.5), r"nz: 2\.5; allowed: "),
    (lambda: patch.patch_deck(patch.patch_scene(0.05), h=0.5, nz=2, increments=0), r"increments: 0; allowed: "),
    (lambda: patch.patch_deck(patch.patch_scene(0.05), h=0.5, nz=2, E=-1.0), r"E: -1\.0 MPa; allowed: "),
    (lambda: patch.patch_deck(patch.patch_scene(0.05), h=0.5, nz=2, nu=0.5), r"nu: 0\.5; allowed: "),
    (lambda: patch.solve_patch(patch.patch_scene(0.05), -0.5, 2), r"h: -0\.5 mm; allowed: "),
    # the flat sleeve: refinement, cells, travel, increments
    (lambda: sleeve2d.cell_deck(CellGeometry(), r=0), r"r: 0; allowed: an integer from 1 to 8"),
    (lambda: sleeve2d.cell_deck(CellGeometry(), r=-1), r"r: -1; allowed: an integer from 1 to 8"),
    (lambda: sleeve2d.cell_deck(CellGeometry(), r=1.5), r"r: 1\.5; allowed: an integer from 1 to 8"),
    (lambda: sleeve2d.cell_mesh(CellGeometry(), 1.5), r"r: 1\.5; allowed: an integer from 1 to 8"),
    (lambda: sleeve2d.cell_mesh(CellGeometry(), 1, 0), r"cells: 0; allowed: an integer from 1 to 64"),
    (lambda: sleeve2d.cell_deck(CellGeometry(), r=1, d_max=-5.0), r"d_max: -5\.0 mm; allowed: 0 < d_max <= 27 mm"),
    (lambda: sleeve2d.cell_deck(CellGeometry(), r=1, increments=0), r"increments: 0; allowed: an integer >= 1"),
    (lambda: sleeve2d.solve_cell(CellGeometry(), 1, increments=2.5), r"increments: 2\.5; allowed: "),
    (lambda: sleeve2d.ring_deck(CellGeometry(), n_cells=0), r"n_cells: 0; allowed: an integer from 2 to 64"),
    (lambda: sleeve2d.ring_deck(CellGeometry(), n_cells=1), r"n_cells: 1; allowed: an integer from 2 to 64"),
    (lambda: sleeve2d.ring_deck(CellGeometry(), n_cells=4.5), r"n_cells: 4\.5; allowed: "),
    (lambda: sleeve2d.ring_deck(CellGeometry(), r=0), r"r: 0; allowed: an integer from 1 to 8"),
    (lambda: sleeve2d.ring_deck(CellGeometry(), d_max=0.0), r"d_max: 0\.0 mm; allowed: 0 < d_max <= 27 mm"),
    (lambda: sleeve2d.ring_deck(CellGeometry(), increments=-1), r"increments: -1; allowed: "),
    (lambda: sleeve2d.solve_ring(CellGeometry(), 4, 1, d_max=NAN), r"d_max: nan mm; allowed: "),
    # the curved sleeve: increments were truncated (2.5 -> 2)
    (lambda: sleeve3d.ring_deck3d(CellGeometry(), increments=2.5), r"increments: 2\.5; allowed: an integer"),
    (lambda: sleeve3d.ring_deck3d(CellGeometry(), increments=0), r"increments: 0; allowed: an integer"),
    (lambda: sleeve3d.step_text("static", False, 2.5, False, ""), r"increments: 2\.5; allowed: an integer"),
]


@pytest.mark.parametrize("call,msg", CASES, ids=[f"case{i}" for i in range(len(CASES))])
def test_bad_input_is_refused_with_its_value_and_range(call, msg):
    with pytest.raises(MetamaterialError, match=msg) as exc:
        call()
    assert isinstance(exc.value, ValueError) and "allowed: " in str(exc.value)


def test_a_run_without_a_time_limit_is_refused():
    with pytest.raises(MetamaterialError, match=r"timeout_s: -1 s; allowed: timeout_s > 0 s"):
        REAL_RUN("*HEADING\n", "j", timeout_s=-1)


def test_good_inputs_still_pass():
    """Integral floats are integers (not rounded: they are whole); the defaults and the bounds' own ends pass."""
    g = CellGeometry()
    assert sleeve2d.cell_deck(g, r=1.0, increments=4.0)[1]["r"] == 1
    assert sleeve2d.ring_deck(g, n_cells=2, increments=4)[1]["n_cells"] == 2
    assert sleeve3d.ring_deck3d(g, increments=2.0)[1]["increments"] == 2
    s = _spec(nu=0.0)
    m = hinge.hinge_mesh(s, 0.8)
    assert "*ELASTIC\n26,0\n" in hinge.stiffness_deck(s, m)
    assert "\n0.5,1.0," in hinge.bending_deck(s, m, 10.0, increments=2)
    assert patch.patch_deck(patch.patch_scene(0.05), h=0.5, nz=2, increments=2)[1]["nz"] == 2
    assert math.isclose(sleeve2d.cell_deck(g, 1, d_max=1.5 * g.L)[1]["d_max_mm"], 27.0)
