"""Module sizes inside their documented ranges build, and the ranges are what the geometry needs: servo dims whose
pilot holes vanish or go negative, a stable hub platform that leaves no wall around its M3 hole, a clip on a
tilted joint and the servo-fit advice (audit of the export side). All refused before any geometry, one line
naming the field, the value and the allowed range; a geometry-kernel failure names the module."""
import math
import re

import pytest

from metamaterial_wb.core.errors import SceneError

from fabhelpers import make_scene

SERVO = {"type": "servo_housing", "name": "servo", "joint": "V0,1", "servo": "SG90"}


def _parse(modules, layout=None, **kw):
    from metamaterial_wb.core.design import effective_tilts_deg
    from metamaterial_wb.core.fabrication import fabrication_params
    from metamaterial_wb.geometry.modules import parse_modules
    sc = make_scene(layout or {"grid": [2, 3]}, modules=modules, **kw)
    return parse_modules(sc, fabrication_params(sc, effective_tilts_deg(sc)))


def _refused(modules, **kw):
    with pytest.raises(SceneError) as e:
        _parse(modules, **kw)
    return e.value


@pytest.mark.parametrize("dims, field, allowed", [
    ({"screw_diameter_mm": 0.2}, "dims.screw_diameter_mm", "[0.7, 3.3]"),    # crashed (OCCDomainError)
    ({"screw_diameter_mm": 0.3}, "dims.screw_diameter_mm", "[0.7, 3.3]"),    # built zero-radius pilot holes
    ({"screw_diameter_mm": 4.0}, "dims.screw_diameter_mm", "[0.7, 3.3]"),    # pilot through the seat's end
    ({"tab_z_mm": 0.5}, "dims.tab_z_mm", "[3.8, 20.2]"),                      # crashed (Multi cut failed)
    ({"tab_z_mm": 3.0}, "dims.tab_z_mm", "[3.8, 20.2]"),                      # a 1.2 mm deep pilot
])
def test_servo_dims_that_leave_no_pilot_hole_are_refused(dims, field, allowed):
    err = _refused([dict(SERVO, dims=dims)])
    assert err.field == f"modules[0].{field} (servo)", err.field
    value = list(dims.values())[0]
    assert str(err).startswith(f"modules[0].{field} (servo): {value!r} mm is outside the allowed range {allowed}")
    assert "pilot" in err.message


def test_servo_dims_at_their_lower_bounds_build(fc):
    """The smallest screw and the lowest tabs the ranges allow give one valid housing with open pilot holes."""
    from metamaterial_wb.geometry.modules import build_module
    from metamaterial_wb.geometry.parts import BuildResult
    from metamaterial_wb.core.design import effective_tilts_deg
    from metamaterial_wb.core.fabrication import fabrication_params
    from metamaterial_wb.geometry.modules import parse_modules
    sc = make_scene({"grid": [1, 2]}, modules=[dict(SERVO, joint="H0,0", dims={"screw_diameter_mm": 0.7,
                                                                                 "tab_z_mm": 2.5})])
    p = fabrication_params(sc, effective_tilts_deg(sc))
    res = BuildResult(sc, p)
    build_module(res, parse_modules(sc, p)[0])
    housing = res.shapes[res.by_name("servo_housing").key]
    assert housing.isValid() and len(housing.Solids) == 1


def test_a_kernel_failure_while_building_a_module_names_the_module(fc, monkeypatch):
    import Part
    from metamaterial_wb.geometry import modules
    from metamaterial_wb.geometry.parts import BuildResult
    from metamaterial_wb.core.design import effective_tilts_deg
    from metamaterial_wb.core.fabrication import fabrication_params
    sc = make_scene({"chain": 2}, modules=[{"type": "friction_pad", "name": "pad", "node": "N0,0"}])
    p = fabrication_params(sc, effective_tilts_deg(sc))
    spec = modules.parse_modules(sc, p)[0]
    kernel = [Part.OCCDomainError("creation of cylinder failed"),
              RuntimeError({"sclassname": "N4Base12RuntimeErrorE", "sErrMsg": "Multi cut failed",
                            "swhat": "Multi cut failed"})]
    for exc in kernel:
        def fail(*a, exc=exc, **k):
            raise exc
        monkeypatch.setattr(modules, "build_friction_pad", fail)
        with pytest.raises(SceneError) as e:
            modules.build_module(BuildResult(sc, p), spec)
        assert e.value.field == "modules[0] (pad)" and re.search("cylinder failed|Multi cut failed", str(e.value))
        assert "\n" not in str(e.value)
    for exc in (RuntimeError("a programming error"), TypeError("a programming error")):   # stay visible
        def bug(*a, exc=exc, **k):
            raise exc
        monkeypatch.setattr(modules, "build_friction_pad", bug)
        with pytest.raises(type(exc)):
            modules.build_module(BuildResult(sc, p), spec)


STABLE = {"type": "stable_hub", "name": "stable", "joint": "H0,2"}


@pytest.mark.parametrize("platform", [3.0, 3.3, 4.7])
def test_stable_hub_platform_too_small_for_its_m3_hole_is_refused(platform):
    """3.0 mm failed as "the module came out as 2 solids", 3.3 mm built a 0.05 mm wall around the 3.2 mm hole."""
    err = _refused([dict(STABLE, platform_mm=platform)])
    assert err.field == "modules[0].platform_mm (stable)"
    assert str(err).startswith(f"modules[0].platform_mm (stable): {platform!r} mm is outside the allowed range "
                               f"[4.8, "), str(err)
    assert "M3" in err.message and "two nozzle widths" in err.message


def test_stable_hub_platform_bounds_follow_the_nozzle():
    _parse([dict(STABLE, platform_mm=4.8)])
    err = _refused([dict(STABLE, platform_mm=4.8)], fabrication={"nozzle_mm": 0.5})
    assert "[5.2, " in str(err)


def test_constraint_clip_on_a_tilted_joint_is_refused():
    """Audit fz/gclip.json: a clip on a 35 deg hinge was built turning about the vertical axis while its manifest
    gave the joint's tilted pivot axis."""
    err = _refused([{"type": "constraint_clip", "name": "clip", "joint": "H0,1", "angle_deg": 5.0}],
                   layout={"grid": [1, 3]}, joint_config={"H0,1": {"tilt_deg": 20.0}})
    assert err.field == "modules[0].joint (clip)"
    assert "H0,1" in err.message and "tilted" in err.message and "20 deg" in err.message
    _parse([{"type": "constraint_clip", "name": "clip", "joint": "H0,0", "angle_deg": 5.0}],
           layout={"grid": [1, 3]}, joint_config={"H0,1": {"tilt_deg": 20.0}})


def _advice(err):
    cell = re.search(r"cells of at least ([0-9.]+) mm", err.message)
    horn = re.search(r"horn_arm_length_mm at most ([0-9.-]+) mm", err.message)
    wall = re.search(r"wall_mm at most ([0-9.-]+) mm", err.message)
    return [float(m.group(1)) if m else None for m in (cell, horn, wall)]


def test_servo_fit_advice_is_consistent_and_works():
    """Audit fz/mg996r_c25.json: 'needs cells of at least 25 mm (cell_size_mm is 25.0) or horn_arm_length_mm at
    most 19 mm', both the current values. The cell size is rounded up and builds; no horn advice when the
    housing's corners, not the horn, set the column's radius."""
    mg = dict(SERVO, servo="MG996R")
    err = _refused([mg], cell_size_mm=25)
    cell, horn, wall = _advice(err)
    assert cell is not None and cell > 25 and horn is None, err.message
    assert "wall_mm" in err.message
    need, ends = (float(x) for x in re.search(r"needs ([0-9.]+) mm from the shaft.* ends ([0-9.]+) mm",
                                              err.message).groups())
    assert need > ends, err.message                                # the figures shown say why
    _parse([mg], cell_size_mm=cell)                                # the advice works
    if wall is not None:
        _parse([dict(mg, wall_mm=wall)], cell_size_mm=25)


def test_servo_fit_advice_names_wall_mm_and_never_a_negative_horn():
    """Audit fz/servo_wall_big.json: wall_mm 20 suggested 'horn_arm_length_mm at most -7.68 mm' and never
    named wall_mm."""
    err = _refused([dict(SERVO, wall_mm=20.0)])
    cell, horn, wall = _advice(err)
    assert horn is None and "wall_mm" in err.message and "20" in err.message, err.message
    assert wall is not None and wall >= 0.8
    _parse([dict(SERVO, wall_mm=wall)])
    _parse([dict(SERVO, wall_mm=20.0)], cell_size_mm=cell)


def test_servo_fit_advice_suggests_a_shorter_horn_when_the_horn_sets_the_radius():
    err = _refused([dict(SERVO, dims={"horn_arm_length_mm": 19.0})])
    cell, horn, wall = _advice(err)
    assert horn is not None and 0 < horn < 19.0 and wall is None, err.message
    _parse([dict(SERVO, dims={"horn_arm_length_mm": horn})])
    _parse([dict(SERVO, dims={"horn_arm_length_mm": 19.0})], cell_size_mm=cell)
    assert math.isfinite(cell)
