"""Every bound a fabrication refusal prints can be typed back: the build's limits (hinge tilt, socket sizes, anchor
and hinge lengths, module walls, servo screws, the FE hinge law's aspect range) are printed rounded inwards (a
maximum down, a minimum up) to the digits shown, so that the printed bound typed back is accepted and the refused
value lies outside the printed range (an audit: the fish's 0.8 mm hinges fit their node plates up to a tilt of
32.456 deg, printed "allowed tilt range [-32.5, 32.5] deg", and a tilt of 32.48 was refused inside it; the same
kind as core/design.py's folds, tests/unit/test_design_limit_rounding.py)."""
import copy
import json
import os
import re

import numpy as np
import pytest

from metamaterial_wb import EXAMPLES_DIR
from metamaterial_wb.core import fabrication
from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.core.fabrication import fabrication_params, max_fabricable_tilt_deg
from metamaterial_wb.core.scene import Scene

NUM = r"(-?\d+(?:\.\d+)?(?:e[+-]?\d+)?)"


def fish(**fab):
    with open(os.path.join(EXAMPLES_DIR, "fish.json"), encoding="utf-8") as f:
        d = json.load(f)
    if fab:
        d["fabrication"] = dict(fab)
    return d


def with_(d, **changes):
    """A copy of scene dict ``d``; ``fabrication`` and ``hinge`` changes are merged, the rest replaced."""
    d = copy.deepcopy(d)
    for k, v in changes.items():
        if k in ("fabrication", "hinge"):
            d.setdefault(k, {}).update(v)
        else:
            d[k] = v
    return d


def refusal(d, modules=False):
    """The SceneError building scene dict ``d`` raises (its fabrication parameters, ``modules``: and its modules),
    or None."""
    scene = Scene.from_dict(d)
    try:
        p = fabrication_params(scene)
        if modules:
            from metamaterial_wb.geometry.modules import parse_modules
            parse_modules(scene, p)
    except SceneError as e:
        return e
    return None


def refused(d, field, modules=False):
    e = refusal(d, modules)
    assert e is not None and e.field == field, (field, e)
    return str(e)


def accepted(d, field, modules=False):
    """``d`` is not refused for ``field`` (another, later check may still refuse it)."""
    e = refusal(d, modules)
    assert e is None or e.field != field, f"refused again: {e}"


def number(pattern, text):
    m = re.search(pattern.replace("NUM", NUM), text)
    assert m, (pattern, text)
    return [float(g) for g in m.groups()]


def test_the_fish_hinge_tilt_range_types_back(monkeypatch):
    """The concrete case: 32.48 deg is beyond the 32.456 deg limit, so it lies outside the printed range, and
    both printed ends typed back as the hinge's tilt are accepted; the fold it names is one it makes at most."""
    true_max = max_fabricable_tilt_deg(Scene.from_dict(fish()), 0.8, ignore_switch=True)
    assert 32.45 < true_max < 32.46
    folds = []
    orig = fabrication._printable_fold_deg

    def spy(*a):
        folds.append(orig(*a))
        return folds[-1]
    monkeypatch.setattr(fabrication, "_printable_fold_deg", spy)
    for tilt in (32.48, -32.48, 32.46):
        d = with_(fish(), joints=[{"joint": "H0,0", "tilt_deg": tilt}])
        msg = refused(d, "joints H0,0.tilt_deg")
        lo, hi = number(r"allowed tilt range \[NUM, NUM\] deg", msg)
        assert lo == -hi and hi <= true_max, msg
        assert not lo <= tilt <= hi, f"{tilt} refused inside the printed range: {msg}"
        for back in (lo, hi):
            accepted(with_(d, joints=[{"joint": "H0,0", "tilt_deg": back}]), "joints H0,0.tilt_deg")
        fold, = number(r"a fold of at most NUM deg per joint", msg)
        assert folds and fold <= folds[-1], (fold, folds[-1], msg)


def test_a_sheet_too_thin_for_the_sockets_types_back():
    """The sheet as thick as its hinges (1 mm) with 0.4167 mm nozzles: the ledges and the wall need 3.8334 mm
    (printed 3.83 before, which is refused): the hinge thickness, the plate thickness and the ledge height printed
    all type back."""
    d = with_(fish(nozzle_mm=0.4167), hinge={"thickness_mm": 1.0})
    msg = refused(d, "hinge.thickness_mm")
    need, = number(r"allowed range \[NUM, \.\.\.\) mm", msg)
    assert not need <= 1.0, msg
    accepted(with_(d, hinge={"thickness_mm": need}), "hinge.thickness_mm")
    sheet, = number(r"fabrication.sheet_thickness_mm \(the plates\) to at least NUM mm", msg)
    accepted(with_(d, fabrication={"sheet_thickness_mm": sheet}), "fabrication.socket_lip_height_mm")
    lip, = number(r"fabrication.socket_lip_height_mm to at most NUM mm", msg)
    accepted(with_(d, fabrication={"socket_lip_height_mm": lip}), "hinge.thickness_mm")


@pytest.mark.parametrize("sheet", [3.0, 3.0112, 1.0013])
def test_socket_ledges_too_high_for_the_sheet_type_back(sheet):
    """(T - 2 nozzle widths) / 2 = 1.1056 mm was printed as "(0, 1.11] mm", and 1.11 is refused."""
    d = fish(sheet_thickness_mm=sheet)
    msg = refused(d, "fabrication.socket_lip_height_mm")
    hi, = number(r"allowed range \(0, NUM\] mm", msg)
    assert not 0 < 1.5 <= hi, msg
    accepted(with_(d, fabrication={"socket_lip_height_mm": hi}), "fabrication.socket_lip_height_mm")


def test_a_socket_too_narrow_for_its_plug_types_back():
    """A 0.1236 mm clearance needs a socket wider than 0.6472 mm (printed "more than 0.647", refused)."""
    d = fish(clearance_mm=0.1236, socket_diameter_mm=0.6)
    msg = refused(d, "fabrication.socket_diameter_mm")
    lo, = number(r"use more than NUM mm", msg)
    assert not 0.6 > lo, msg
    accepted(with_(d, fabrication={"socket_diameter_mm": lo}), "fabrication.socket_diameter_mm")


@pytest.mark.parametrize("inset", [2.0, 9.0])
def test_the_socket_inset_range_types_back(inset):
    """A 3.2064 mm socket: its ledges need an inset of at least 2.9032 mm (printed 2.9 before, refused)."""
    d = fish(socket_diameter_mm=3.2064, socket_inset_mm=inset)
    msg = refused(d, "fabrication.socket_inset_mm")
    lo, hi = number(r"allowed range \[NUM, NUM\] mm", msg)
    assert not lo <= inset <= hi, msg
    for back in (lo, hi):
        accepted(with_(d, fabrication={"socket_inset_mm": back}), "fabrication.socket_inset_mm")


def test_a_hinge_longer_than_the_gap_types_back():
    """A 7.99996 mm gap between the plates was printed "(0, 8] mm": an 8 mm hinge refused inside it."""
    d = with_(fish(), hinge={"length_mm": 7.99996}, joints=[{"joint": "H0,0", "length_mm": 8.0}])
    msg = refused(d, "joints H0,0.length_mm")
    hi, = number(r"allowed range \(0, NUM\] mm", msg)
    assert not 0 < 8.0 <= hi, msg
    accepted(with_(d, joints=[{"joint": "H0,0", "length_mm": hi}]), "joints H0,0.length_mm")


def test_hinges_too_long_for_the_anchors_type_back():
    """6.002 mm deep anchors leave the hinges at most 7.196 mm (printed 7.2 before, refused)."""
    d = fish(anchor_depth_mm=6.002)
    msg = refused(d, "hinge.length_mm")
    hi, = number(r"allowed range \(0, NUM\] mm", msg)
    most, = number(r"may be at most NUM mm long", msg)
    assert most == hi and not 0 < 8.0 <= hi, msg
    accepted(with_(d, hinge={"length_mm": hi}), "hinge.length_mm")


def test_anchors_too_deep_for_any_hinge_type_back():
    """8.0012 mm hinges leave anchors at most 5.5994 mm deep (printed 5.6 before, refused)."""
    d = with_(fish(anchor_depth_mm=10), hinge={"length_mm": 8.0012})
    msg = refused(d, "fabrication.anchor_depth_mm")
    hi, = number(r"allowed range \(0, NUM\] mm", msg)
    assert not 0 < 10 <= hi, msg
    accepted(with_(d, fabrication={"anchor_depth_mm": hi}), "fabrication.anchor_depth_mm")


def test_the_anchor_lip_wall_types_back():
    """0.4167 mm nozzles: a lip of at least 0.8334 mm (its advice printed 0.833 before, refused)."""
    d = fish(nozzle_mm=0.4167, anchor_neck_mm=0.5)
    msg = refused(d, "fabrication.anchor_neck_mm")
    lo, = number(r"a wall of at least two nozzle widths \(NUM mm", msg)
    assert not lo <= 0.5, msg
    accepted(with_(d, fabrication={"nozzle_mm": 0.4167, "anchor_neck_mm": lo}), "fabrication.anchor_neck_mm")


def test_a_module_wall_types_back():
    """A stable hub's 0.5 mm beams with 0.4167 mm nozzles: "allowed range [0.833, 200]" refused 0.833."""
    hub = {"type": "stable_hub", "name": "hub", "joint": "H0,0", "beam_width_mm": 0.5}
    d = with_(fish(nozzle_mm=0.4167), modules=[hub])
    field = "modules[0].beam_width_mm (hub)"
    msg = refused(d, field, modules=True)
    lo, hi = number(r"allowed range \[NUM, NUM\] mm", msg)
    thinner, = number(r"thinner than two nozzle widths \(NUM mm", msg)
    assert thinner == lo and not lo <= 0.5 <= hi, msg
    accepted(with_(d, modules=[dict(hub, beam_width_mm=lo)]), field, modules=True)


def test_a_connection_hub_too_thin_for_its_halves_types_back():
    """Each half of a hub at least two 0.4167 mm nozzle widths, 0.8334 mm (printed 0.833 before)."""
    hub = {"type": "connection_hub", "name": "hub", "node": "N0,0", "thickness_mm": 1.0}
    d = with_(fish(nozzle_mm=0.4167), modules=[hub])
    field = "modules[0].thickness_mm (hub)"
    msg = refused(d, field, modules=True)
    half, = number(r"each at least NUM mm", msg)
    lo, hi = number(r"allowed range \[NUM, NUM\] mm", msg)
    assert half >= 2 * 0.4167 and not lo <= 1.0 <= hi, msg
    accepted(with_(d, modules=[dict(hub, thickness_mm=lo)]), field, modules=True)
    accepted(with_(d, modules=[dict(hub, thickness_mm=2 * half)]), field, modules=True)


@pytest.mark.parametrize("pad", [{"pocket_depth_mm": 3.0, "thickness_mm": 3.0},
                                 {"thickness_mm": 2.0, "pocket_depth_mm": 0.1}])
def test_friction_pad_limits_type_back(pad):
    """A pocket as deep as the pad, a pad thinner than its recessed rivet heads and a wall (0.4167 mm nozzles)."""
    item = dict({"type": "friction_pad", "name": "pad", "node": "N0,0"}, **pad)
    d = with_(fish(nozzle_mm=0.4167), modules=[item])
    key = "pocket_depth_mm" if pad["pocket_depth_mm"] == 3.0 else "thickness_mm"
    field = f"modules[0].{key} (pad)"
    msg = refused(d, field, modules=True)
    if key == "pocket_depth_mm":
        lo, hi = 0.0, number(r"allowed range \(0, NUM\] mm", msg)[0]
    else:
        lo, hi = number(r"allowed range \[NUM, NUM\] mm", msg)
    assert not lo <= pad[key] <= hi, msg
    accepted(with_(d, modules=[dict(item, **{key: hi if key == "pocket_depth_mm" else lo})]), field, modules=True)


def test_a_servo_screw_off_its_tab_types_back():
    """SG90 tabs 31.9134 mm over both (4.4567 mm each): "allowed range (0, 4.46) mm" refused 4.457 and 4.46."""
    servo = {"type": "servo_housing", "name": "s", "joint": "H0,0", "servo": "SG90",
             "dims": {"tab_length_mm": 31.9134, "screw_inset_mm": 4.457}}
    d = with_(fish(), modules=[servo])
    field = "modules[0].dims.screw_inset_mm (s)"
    msg = refused(d, field, modules=True)
    hi, = number(r"allowed range \(0, NUM\) mm", msg)
    tab, = number(r"outside the NUM mm tab", msg)
    assert tab == hi and not 0 < 4.457 < hi, msg
    accepted(with_(d, modules=[dict(servo, dims=dict(servo["dims"], screw_inset_mm=hi))]), field, modules=True)


@pytest.mark.parametrize("ratio", [7.5004, 7.50001, 1.2499, 1.24999])
def test_the_fe_hinge_law_range_types_back(ratio):
    """A hinge 7.5004 times as long as wide was "7.5 ... outside the FE-calibrated range [1.25, 7.5]"."""
    from metamaterial_wb.core.lattice.geometry import fe_hinge_factors
    with pytest.raises(SceneError) as e:
        fe_hinge_factors(np.array([ratio]), np.array([1.0]), np.array([1.0]))
    v, lo, hi = number(r"length / width NUM is outside the FE-calibrated range \[NUM, NUM\]", str(e.value))
    assert not lo <= v <= hi, str(e.value)
    for back in (lo, hi):
        assert fe_hinge_factors(np.array([back]), np.array([1.0]), np.array([1.0])).shape == (1, 6)
