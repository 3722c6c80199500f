"""Snap-fit pins designed from the cantilever formula against the material's allowable strain."""
import math

import pytest

from metamaterial_wb.core.errors import SceneError

from fabhelpers import make_scene


def _params(**kw):
    from metamaterial_wb.core.design import effective_tilts_deg
    from metamaterial_wb.core.fabrication import fabrication_params
    sc = make_scene({"chain": 2}, **kw)
    return fabrication_params(sc, effective_tilts_deg(sc))


@pytest.mark.parametrize("material", ["PLA", "ABS", "PETG"])
def test_designed_strain_within_the_material_limit(material):
    from metamaterial_wb.geometry.snapfit import ALLOWABLE_STRAIN, design_snap_fit
    p = _params()
    sf = design_snap_fit(p, material)
    # closed form, from the socket: y = lip - clearance, L = T - (lip height - clearance)
    assert sf.deflection_mm == pytest.approx(0.5 - 0.2)
    assert sf.length_mm == pytest.approx(7.0 - (1.5 - 0.2))
    assert sf.strain == pytest.approx(1.5 * sf.thickness_mm * sf.deflection_mm / sf.length_mm ** 2, rel=1e-12)
    assert sf.strain <= ALLOWABLE_STRAIN[material] + 1e-12 and sf.limit == ALLOWABLE_STRAIN[material]
    assert sf.thickness_mm >= p.min_wall_mm
    # the slot lets both prongs close by the barb's interference without touching
    assert sf.slot_mm >= 2 * sf.deflection_mm
    assert sf.slot_mm == pytest.approx(2 * (p.socket_radius_mm - p.clearance_mm - sf.thickness_mm))


def test_old_pin_was_overstrained():
    """Today's pin (0.98 mm prongs, slot ending at 0.65 T above the tip) against the same formula:
    about 3.7 % -- over PLA's and ABS's limits; the designed one is not."""
    from metamaterial_wb.geometry.snapfit import cantilever_strain, design_snap_fit
    p = _params()
    old = cantilever_strain(0.98, 0.3, (0.2 + 0.65 * 7.0) - 1.3)
    assert old > 0.03
    assert design_snap_fit(p, "PLA").strain < 0.015 + 1e-12


def test_no_pin_fits_a_thin_sheet():
    """A 3 mm sheet leaves 2.2 mm prongs: a 0.8 mm prong bent 0.3 mm is strained 7.4 % > 2 % (ABS)."""
    from metamaterial_wb.geometry.snapfit import design_snap_fit
    p = _params(hinge={"length_mm": 2, "width_mm": 0.8, "thickness_mm": 3},
                fabrication={"socket_lip_height_mm": 1.0})
    with pytest.raises(SceneError) as e:
        design_snap_fit(p, "ABS", "modules[0]")
    msg = str(e.value)
    assert e.value.field == "modules[0].material"
    assert f"{100 * 1.5 * 0.8 * 0.3 / 2.2 ** 2:.3g} %" in msg and "thicker sheet" in msg


def test_built_pin_has_the_designed_prongs(fc):
    """On the built solid: the pin's slot is the designed width and ends at the module's underside, so
    the free prong length is the designed L."""
    from metamaterial_wb.geometry.build import build_scene
    r = build_scene(make_scene({"chain": 2}, modules=[{"type": "connection_hub", "name": "h", "node": "N0,0",
                                                       "material": "PLA"}]), progress=False)
    spec = r.modules[0]
    hub = r.placed_shape(r.by_name("h_hub_rivet_1"))   # the double rivet in the E socket (lower end)
    import Part
    # a thin probe slab at mid-prong height through the E pin (x = 9 - 3.5 = 5.5 in the node frame)
    T = r.params.sheet_thickness_mm
    z = 0.5 * (1.3 + T)
    def slot_at(z):
        cut = hub.common(Part.makeBox(6, 6, 0.01, fc.Vector(5.5 - 3, -3, z)))
        xs = sorted({round(v.X, 9) for v in cut.Vertexes})
        return min(b - a for a, b in zip(xs, xs[1:]) if a < 5.5 < b)     # the gap across the pin's axis

    assert slot_at(z) == pytest.approx(spec.snap.slot_mm, abs=1e-6)
    # the slot runs up to the module's underside (z = T), so the free prong length is T - barb top
    assert slot_at(T - 0.05) == pytest.approx(spec.snap.slot_mm, abs=1e-6)
    assert spec.snap.slot_top_mm == pytest.approx(T)
