"""Fabrication parameters whose lower bound is a printable wall, and switches checked on every scene (audit of the
export side): no geometry, one SceneError naming the field, the value and the allowed range."""
import glob
import os

import pytest

from metamaterial_wb.core.errors import SceneError

from fabhelpers import EXAMPLES, make_scene


def _params(**fab):
    from metamaterial_wb.core.design import effective_tilts_deg
    from metamaterial_wb.core.fabrication import fabrication_params
    sc = make_scene({"chain": 2}, fabrication=fab)
    return fabrication_params(sc, effective_tilts_deg(sc))


@pytest.mark.parametrize("key", ["anchor_neck_mm", "anchor_margin_mm"])
def test_anchor_lip_thinner_than_two_nozzle_widths_is_refused(key):
    """Audit fz/neck01.json, fz/margin01.json: 0.1 mm built a 0.1 mm lip of node material in front of (neck) or
    beside (margin) the anchor head, the only thing that holds the hinge in its node."""
    with pytest.raises(SceneError) as e:
        _params(**{key: 0.1})
    assert str(e.value).startswith(f"fabrication.{key}: 0.1 mm is outside the allowed range [0.8, 50.0]"), \
        str(e.value)
    assert "two nozzle widths" in e.value.message
    with pytest.raises(SceneError, match=r"\[1\.0, 50\.0\]"):
        _params(**{key: 0.9, "nozzle_mm": 0.5})
    assert getattr(_params(**{key: 0.8}), key) == 0.8


def test_limit_design_tilt_is_checked_without_axes():
    """Audit: "limit_design_tilt": "yes" passed on a scene without axes (only the design stage read it)."""
    with pytest.raises(SceneError) as e:
        _params(limit_design_tilt="yes")
    assert e.value.field == "fabrication.limit_design_tilt" and "'yes'" in e.value.message
    _params(limit_design_tilt=True)


def test_every_bundled_example_passes_the_parameter_checks():
    from metamaterial_wb.core.design import effective_tilts_deg
    from metamaterial_wb.core.fabrication import fabrication_params
    from metamaterial_wb.core.scene import Scene
    from metamaterial_wb.geometry.modules import parse_modules
    checked = 0
    for path in sorted(glob.glob(os.path.join(EXAMPLES, "*.json"))):
        try:
            sc = Scene.load(path)
        except SceneError:
            continue                               # not a scene (a target, a sleeve, a channels file)
        if (sc.extra.get("fabrication") or {}).get("simulation_only"):
            continue
        p = fabrication_params(sc, effective_tilts_deg(sc))
        parse_modules(sc, p)
        checked += 1
    assert checked >= 10
