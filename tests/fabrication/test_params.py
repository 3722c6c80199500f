"""Invalid fabrication parameters and modules fail with clear errors BEFORE any geometry is built."""
import json
import os
import subprocess
import sys

import pytest

from metamaterial_wb.core.errors import SceneError

from fabhelpers import REPO, make_scene


@pytest.fixture
def no_geometry(monkeypatch):
    """Make every geometry builder explode: an error raised first proves validation came before geometry."""
    from metamaterial_wb.geometry import modules, sheet

    def boom(*a, **k):
        raise AssertionError("geometry was built before the parameters were validated")

    for mod, names in ((sheet, ("make_node", "make_hinge", "make_stub", "socket_tools")),
                       (modules, ("make_pin", "box", "build_servo_housing", "build_friction_pad"))):
        for n in names:
            monkeypatch.setattr(mod, n, boom)


def _build(scene, **kw):
    from metamaterial_wb.geometry.build import build_scene
    return build_scene(scene, progress=False, **kw)


def test_defaults_are_valid_and_follow_the_scene():
    from metamaterial_wb.core.design import effective_tilts_deg
    from metamaterial_wb.core.fabrication import fabrication_params
    sc = make_scene({"grid": [2, 2]}, cell_size_mm=24, hinge={"length_mm": 3, "width_mm": 1, "thickness_mm": 6})
    p = fabrication_params(sc, effective_tilts_deg(sc))
    assert p.plate_side_mm_global == pytest.approx(21.0)
    assert p.sheet_thickness_mm == pytest.approx(6.0)       # defaults to the thickest hinge
    assert p.clearance_mm == pytest.approx(0.2)
    assert len(p.hinges) == sc.topology.n_joints == 12


def test_hinge_longer_than_gap(no_geometry):
    sc = make_scene({"chain": 2}, joints=[{"joint": "H0,1", "length_mm": 3.5}])     # gap is 2 mm
    with pytest.raises(SceneError) as e:
        _build(sc)
    msg = str(e.value)
    assert "H0,1" in msg and "3.5" in msg and "gap" in msg and "(0, 2]" in msg


def test_hinge_too_long_for_the_anchors(no_geometry):
    # a 9.5 mm hinge in a 20 mm cell leaves a 10.5 mm plate: no room for 3 mm anchors and the sockets
    sc = make_scene({"chain": 1}, hinge={"length_mm": 9.5, "width_mm": 0.8, "thickness_mm": 7})
    with pytest.raises(SceneError) as e:
        _build(sc)
    assert "length_mm" in e.value.field and "at most" in str(e.value)


def test_negative_clearance(no_geometry):
    sc = make_scene({"chain": 1}, fabrication={"clearance_mm": -0.1})
    with pytest.raises(SceneError) as e:
        _build(sc)
    assert e.value.field == "fabrication.clearance_mm" and "-0.1" in str(e.value) and "[0.0, 2.0]" in str(e.value)


def test_tilt_too_steep_for_the_plate(no_geometry):
    sc = make_scene({"chain": 2}, joint_config={"H0,1": {"tilt_deg": 60}})
    with pytest.raises(SceneError) as e:
        _build(sc)
    assert "H0,1" in str(e.value) and "tilt" in str(e.value)


def test_unknown_fabrication_key(no_geometry):
    with pytest.raises(SceneError) as e:
        _build(make_scene({"chain": 1}, fabrication={"clearence_mm": 0.2}))
    assert "clearence_mm" in str(e.value) and "clearance_mm" in str(e.value)


@pytest.mark.parametrize("module, field, words", [
    ({"type": "servo_housing", "joint": "V0,7"}, "modules[0].joint", ["V0,7", "does not exist"]),
    ({"type": "stable_hub", "joint": "H5,0"}, "modules[0].joint", ["H5,0", "does not exist"]),
    ({"type": "friction_pad", "node": "N4,0"}, "modules[0].node", ["N4,0", "does not exist"]),
    ({"type": "friction_pad"}, "modules[0].node", ["node"]),
    ({"type": "laser"}, "modules[0].type", ["laser", "servo_housing"]),
    ({"type": "servo_housing", "joint": "V0,1", "servo": "XYZ1"}, "modules[0].servo", ["XYZ1", "SG90"]),
    ({"type": "servo_housing", "joint": "V0,1", "servo": "custom", "dims": {"body_length_mm": 20}},
     "modules[0].dims", ["missing"]),
    ({"type": "constraint_clip", "joint": "H0,0"}, "modules[0].angle_deg", ["no constraint"]),
    ({"type": "constraint_clip", "joint": "H0,0", "angle_deg": 75}, "modules[0].angle_deg", ["75", "allowed range [-6.369477073, 60.0]"]),
    ({"type": "friction_pad", "node": "N0,0", "mu": -1}, "modules[0].mu", ["-1"]),
])
def test_bad_modules(no_geometry, module, field, words):
    # the scene reader checks a module's node / joint against the layout; the fabrication package the rest
    with pytest.raises(SceneError) as e:
        _build(make_scene({"grid": [1, 3]}, modules=[module]))
    assert e.value.field.startswith(field), e.value.field
    for w in words:
        assert w in str(e.value), str(e.value)


def test_two_modules_on_one_socket(no_geometry):
    sc = make_scene({"grid": [1, 3]}, modules=[{"type": "servo_housing", "joint": "H0,1"},
                                               {"type": "stable_hub", "joint": "H0,1"}])
    with pytest.raises(SceneError) as e:
        _build(sc)
    assert "collide" in str(e.value) and "servo_housing_1" in str(e.value) and "stable_hub_2" in str(e.value)
    assert "socket N of node N0,1" in str(e.value)


def test_worm_setup_servo_on_end_node_with_pad_under_it_is_refused(no_geometry):
    """The seed's worm set-up: a servo on the end joint (top) and a friction pad under the end node
    (bottom). Both snap pins run through the same sockets (42.65 mm^3 of overlap): refused, naming
    both modules and the socket, before any geometry."""
    sc = make_scene({"chain": 8}, actuators=[{"name": "rear", "joint": "V0,0", "value": 0.0}],
                    modules=[{"type": "servo_housing", "name": "servo_rear", "joint": "V0,0"},
                             {"type": "friction_pad", "name": "pad_rear", "node": "N0,0"}])
    with pytest.raises(SceneError) as e:
        _build(sc)
    msg = str(e.value)
    assert "'servo_rear' (top)" in msg and "'pad_rear' (bottom)" in msg and "socket E of node N0,0" in msg


def test_servo_too_big_for_small_cells(no_geometry):
    sc = make_scene({"chain": 2}, cell_size_mm=14, hinge={"length_mm": 1, "width_mm": 0.8, "thickness_mm": 7},
                    fabrication={"socket_inset_mm": 2.9},   # (the default 3.5 puts a 13 mm plate's sockets together)
                    modules=[{"type": "servo_housing", "joint": "V0,1", "servo": "MG90S"}])
    with pytest.raises(SceneError) as e:
        _build(sc)
    assert "cells of at least" in str(e.value)


def test_cli_error_is_one_line_and_writes_nothing(tmp_path):
    scene = {"format": "metamaterial-scene", "version": 1, "layout": {"chain": 2},
             "modules": [{"type": "servo_housing", "joint": "V3,3"}]}
    sp = tmp_path / "s.json"
    sp.write_text(json.dumps(scene))
    out = tmp_path / "out"
    r = subprocess.run([sys.executable, "-m", "metamaterial_wb", "build", str(sp), "--out", str(out), "--modules"],
                       cwd=REPO, capture_output=True, encoding="utf-8", errors="replace", timeout=120)
    assert r.returncode == 2, r.stderr
    lines = [ln for ln in r.stderr.splitlines() if ln.strip()]
    assert len(lines) == 1 and "V3,3" in lines[0] and "does not exist" in lines[0]
    assert not out.exists() or not os.listdir(out)


def test_axes_without_joint_config_tilt_the_hinges_like_the_kinematics():
    """A scene with axes but no joint_config is configured on the fly (as the kinematics does), so the
    printed hinges are the ones the simulation bends; tilts steeper than the plate allows are errors."""
    from metamaterial_wb.core.design import compute_joint_config, effective_tilts_deg
    from metamaterial_wb.core.fabrication import fabrication_params
    base = dict(cell_size_mm=25, hinge={"length_mm": 5, "width_mm": 1.0, "thickness_mm": 7},
                axes=[{"direction": "vertical", "line": 1, "fold_deg": 10}],
                fabrication={"anchor_margin_mm": 0.8})      # the gripper's: 35 deg tilts keep 0.8 mm walls
    sc = make_scene({"chain": 3}, **base)
    p = fabrication_params(sc, effective_tilts_deg(sc))
    config = compute_joint_config(sc)[0]
    assert set(config) == {"H0,1", "H1,1"}
    for name, h in p.hinges.items():
        want = config.get(name, {}).get("tilt_deg", 0.0)
        assert h.tilt_deg == pytest.approx(want) and (want != 0.0) == (name in config)
    steep = make_scene({"chain": 3}, **dict(base, axes=[{"direction": "vertical", "line": 1, "fold_deg": 30}]))
    with pytest.raises(SceneError, match="tilt"):
        fabrication_params(steep, effective_tilts_deg(steep))
    with pytest.raises(SceneError, match="joint configuration"):   # stored tilts only: configure first
        fabrication_params(steep)


def test_snap_barb_must_pass_the_hole(no_geometry):
    """A 1 mm ledge makes the barb 1.6 mm wider than the hole: the slot that lets it close leaves
    prongs thinner than two nozzle widths, so no pin fits (the sheet alone still builds)."""
    with pytest.raises(SceneError) as e:
        _build(make_scene({"chain": 1}, fabrication={"socket_lip_mm": 1.0},
                          modules=[{"type": "connection_hub", "node": "N0,0"}]))
    assert e.value.field == "modules[0].material" and "slot" in str(e.value)
    assert "fabrication.socket_lip_mm" in str(e.value)
