"""The sleeve's PLA caps are the cap the pressure curve uses (audit: they ignored ``actuator.core_diameter_mm``).

The seed's actuator (002, SI S1.1) is an inflatable core - a membrane closed by two PLA caps of the core's diameter -
held in PLA rings glued inside the sleeve's end bars: the cap closes the ring's opening and the membrane pushes on it
with the pressure times the cap's area (``pv.cap_area_mm2``). The STEP's caps must have the diameter the prediction
uses (``SleeveSpec.core_diameter``, given or the automatic default), the end rings an opening that cap fits in, and
a cap the ring cannot hold (wider than the sleeve's inside less two ring walls) is refused by the spec check."""
import json
import math

import pytest

from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.core.sleeve.spec import MIN_FEATURE_MM, SleeveSpec

SEED = {"format": "metamaterial-sleeve", "version": 1, "name": "seed combination 2", "L_mm": 18, "c_mm": 4,
        "delta_mm": 0.5, "T_mm": 1.8, "shear_modulus_MPa": 28,
        "cell_types": [{"t_mm": 1.098, "h_mm": 7.092}, {"t_mm": 1.098, "h_mm": 7.488}], "ring": [0, 0, 1, 1]}
CAP_MM = 2.0          # the caps' thickness (geometry.sleeve.build_end_pieces' cap_mm)


def _spec(cap=None):
    d = json.loads(json.dumps(SEED))
    if cap is not None:
        d["actuator"] = {"core_diameter_mm": cap, "membrane_kPa_per_mL": 0}
    return SleeveSpec(d)


def _radii(solid):
    """Radii of the solid's cylindrical faces about the z axis."""
    out = []
    for f in solid.Faces:
        s = f.Surface
        if type(s).__name__ == "Cylinder" and abs(abs(s.Axis.z) - 1) < 1e-9:
            out.append(s.Radius)
    return out


def _step_parts(folder):
    """The STEP read back: caps (2 mm thick discs) and end rings (the PLA tubes), each with its radii."""
    import Part
    sh = Part.read(str(folder / "sleeve.step"))
    caps, rings, sleeve = [], [], []
    for s in sh.Solids:
        bb = s.BoundBox
        if abs(bb.ZLength - CAP_MM) < 1e-6:
            caps.append(s)
        elif len(s.Faces) <= 4:                  # a plain tube: two cylinders, two annuli
            rings.append(s)
        else:
            sleeve.append(s)
    return caps, rings, sleeve


@pytest.mark.parametrize("cap", [24.6, 12.0, None])
def test_the_exported_caps_are_the_predictions_cap_and_fit_the_rings(fc, tmp_path, cap):
    from metamaterial_wb.export.sleeve import export_sleeve
    spec = _spec(cap)
    d = spec.core_diameter                      # what pv.cap_diameter_mm reports and pv.peaks_kPa divide by
    if cap is not None:
        assert d == cap
    export_sleeve(spec, str(tmp_path), step=True, threemf=False)
    caps, rings, sleeve = _step_parts(tmp_path)
    assert len(caps) == 2 and len(rings) == 2 and len(sleeve) == 1, (len(caps), len(rings), len(sleeve))
    inner_r = spec.inner_diameter_mm / 2
    for c in caps:
        assert 2 * max(_radii(c)) == pytest.approx(d, abs=1e-6), "the cap is not the prediction's cap"
        assert c.BoundBox.XLength == pytest.approx(d, abs=1e-4)
        # the full disc's area is the prediction's (the bottom cap less its supply-tube hole)
        full = c.Volume + sum(math.pi * r * r * CAP_MM for r in _radii(c) if r < d / 2 - 1e-6)
        assert full == pytest.approx(math.pi * d * d / 4 * CAP_MM, rel=1e-6)
    for r in rings:
        radii = sorted(_radii(r))
        assert len(radii) == 2
        opening, outer = radii
        assert outer == pytest.approx(inner_r, abs=1e-6)          # glued inside the sleeve's end bar
        assert 2 * opening == pytest.approx(d, abs=1e-6)         # the cap fits the opening, no play
        assert outer - opening >= MIN_FEATURE_MM - 1e-9          # a ring wall the printer makes
    # each cap sits in a ring's opening (coaxial, inside the ring's height): it closes that end
    for c in caps:
        cz = c.BoundBox
        assert any(r.BoundBox.ZMin - 1e-6 <= cz.ZMin and cz.ZMax <= r.BoundBox.ZMax + 1e-6 for r in rings)
        assert abs(cz.Center.x) < 1e-6 and abs(cz.Center.y) < 1e-6


def test_the_two_caps_differ_as_the_specs_do(fc, tmp_path):
    """The audit's pair: 24.6 and 12 mm caps give different parts (both were 22.21 mm before)."""
    from metamaterial_wb.geometry.sleeve import build_end_pieces
    a = build_end_pieces(_spec(24.6))
    b = build_end_pieces(_spec(12.0))
    assert a["cap_top"].BoundBox.XLength == pytest.approx(24.6, abs=1e-4)
    assert b["cap_top"].BoundBox.XLength == pytest.approx(12.0, abs=1e-4)
    assert b["cap_bottom"].BoundBox.XLength == pytest.approx(12.0, abs=1e-4)


def test_a_cap_the_end_ring_cannot_hold_is_refused_naming_both_values_and_the_range():
    """The ring needs a wall of at least one extrusion (MIN_FEATURE_MM) around the cap: a cap wider than the inner
    diameter less two walls is refused at load, naming the cap, the inner diameter and the allowed range."""
    inner = _spec().inner_diameter_mm                      # 26.21 mm
    top = inner - 2 * MIN_FEATURE_MM                       # 25.41 mm
    with pytest.raises(SceneError) as ei:
        _spec(26.0)                                        # under the inner diameter, over what a ring allows
    e = ei.value
    assert e.field == "actuator.core_diameter_mm"
    assert "26.0" in e.message and f"{inner:.6g}" in e.message and f"(0, {top:.6g}]" in e.message
    assert "ring" in e.message
    assert _spec(top).core_diameter == top                  # on the bound it loads
    # the automatic cap of a sleeve too narrow for the default is the largest a ring holds
    narrow = json.loads(json.dumps(SEED))
    narrow.update(L_mm=14, c_mm=3, ring=[0, 0, 0], cell_types=[{"t_mm": 0.9, "h_mm": 5}])
    s = SleeveSpec(narrow)
    assert s.core_diameter == pytest.approx(s.inner_diameter_mm - 2 * MIN_FEATURE_MM, rel=1e-12)
    assert "ring" in s.core_diameter_note


def test_a_cap_too_small_for_the_supply_tube_is_refused_by_the_end_piece_check():
    """The bottom cap carries the 4 mm supply-tube hole with 0.4 mm of cap around it: a smaller cap is fine for the
    prediction but refused before --step / --3mf / --render build it, naming the cap and the range."""
    spec = _spec(4.0)
    with pytest.raises(SceneError) as ei:
        spec.check_end_pieces()
    e = ei.value
    assert e.field == "actuator.core_diameter_mm"
    assert "4.0" in e.message and "4.8" in e.message and "tube" in e.message and "allowed" in e.message
    _spec(4.8).check_end_pieces()
