"""Issue 16's "Done when", one test per example set-up (the fish, the seed's worm set-up, the gripper):
every module snaps on within its material's allowable strain, the servo turns its joint about the
hinge pivot (hinge length within 2 %: tests/fabrication/test_pivot.py, measured on the built solids
for the same three set-ups), colliding set-ups are refused, every part prints without supports."""
import copy
import json
import os

import pytest

from fabhelpers import EXAMPLES, make_scene

SETUPS = ("fish_modules", "worm", "gripper")


def _setup(name):
    """The scene dict of an example set-up. The worm: the seed's crawler with its servo on the end
    joint and the friction pad under the other end (test_pivot.py builds the same one)."""
    if name == "worm":
        return {"format": "metamaterial-scene", "version": 1, "name": "worm", "layout": {"chain": 8},
                "actuators": [{"name": "rear", "joint": "V0,0", "value": 0.0,
                               "profile": {"shape": "sine", "amplitude": 1.0}}],
                "modules": [{"type": "servo_housing", "name": "servo_rear", "joint": "V0,0"},
                            {"type": "friction_pad", "name": "pad_front", "node": "N0,8"}]}
    with open(os.path.join(EXAMPLES, f"{name}.json")) as f:
        return json.load(f)


def _specs(d):
    from metamaterial_wb.core.scene import Scene
    from metamaterial_wb.geometry.modules import parse_modules
    from metamaterial_wb.core.design import effective_tilts_deg
    from metamaterial_wb.core.fabrication import fabrication_params
    sc = Scene.from_dict(d)
    return parse_modules(sc, fabrication_params(sc, effective_tilts_deg(sc)))


@pytest.mark.parametrize("setup", SETUPS)
def test_every_module_snaps_within_the_allowable_strain(setup):
    """Cantilever formula (strain = 1.5 t y / L^2) recomputed from the chosen prong sizes, against the
    material's allowable strain, for every module of the set-up."""
    specs = _specs(_setup(setup))
    assert specs
    for s in specs:
        sf = s.snap
        assert sf is not None, s.name
        assert sf.strain == pytest.approx(1.5 * sf.thickness_mm * sf.deflection_mm / sf.length_mm ** 2, rel=1e-9)
        assert 0 < sf.strain <= sf.limit, (s.name, sf)


@pytest.mark.parametrize("setup", SETUPS)
def test_servo_pivot_keeps_the_hinge_length(setup):
    """The pivot each servo was given (the same one the built shaft sits on: test_pivot.py measures it
    on the solids) keeps the hinge's end-to-end distance within 2 % over the joint's design range."""
    servos = [s for s in _specs(_setup(setup)) if s.type == "servo_housing"]
    assert servos
    for s in servos:
        assert s.pivot.length_error <= 0.02, (s.name, s.pivot.range_deg, s.pivot.length_error)


@pytest.mark.parametrize("setup", SETUPS)
def test_colliding_setup_is_refused(setup):
    """A friction pad under a servo's own node (the seed's worm set-up) puts two snap pins into one
    socket: refused before any geometry, naming both modules and the socket."""
    from metamaterial_wb.core.errors import SceneError
    d = copy.deepcopy(_setup(setup))
    servo = [m for m in _specs(d) if m.type == "servo_housing"][0]
    i, j = servo.a
    d["modules"].append({"type": "friction_pad", "name": "pad_under_servo", "node": f"N{i},{j}", "side": "bottom"})
    with pytest.raises(SceneError) as e:
        _specs(d)
    msg = str(e.value)
    assert "collide" in msg and "'pad_under_servo' (bottom)" in msg and f"of node N{i},{j}" in msg, msg


@pytest.mark.xfail(strict=True, reason="issue 16 item 5 (print poses without supports) is not done: the servo "
                                       "housing (inverted, its cavity ceiling is a 12.9 mm bridge; upright, the tub "
                                       "overhangs the horn adapter's pad) and the horn adapter (an L of pad, column "
                                       "and arm) need supports in every axis-aligned pose; snap pins print upright")
@pytest.mark.parametrize("setup", SETUPS)
def test_every_module_part_prints_without_supports(fc, setup):
    """The exported mesh of every module part, in the pose the build chooses, passes the support check
    (largest flat face on the bed, no overhang beyond 45 deg, bridges under 10 mm)."""
    from metamaterial_wb.core.scene import Scene
    from metamaterial_wb.export.mesh import part_meshes
    from metamaterial_wb.export.printpose import lay_out_best_poses
    from metamaterial_wb.geometry.build import build_scene
    r = build_scene(Scene.from_dict(_setup(setup)), progress=False)
    bad = {}
    for group, parts in r.groups().items():
        if group == "sheet":
            continue
        _, reps = lay_out_best_poses(part_meshes(r, parts))
        bad.update({k: v["unsupported_area_mm2"] for k, v in reps.items() if not v["supports_free"]})
    assert not bad, bad
