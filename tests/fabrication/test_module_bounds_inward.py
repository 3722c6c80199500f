"""Bounds the module messages print (geometry/modules.py, geometry/servo.py) are rounded inwards: a need up, a
maximum down, so that the printed number typed back is accepted (numbers.inward_g; the fabrication's own bounds:
tests/unit/test_fabrication_limit_rounding.py).

A servo housing whose feet and floor are too thin for a blind rivet socket falls back to fused upright pins, and its
note said "(pad_mm + clearance + floor_mm = 1.8 mm) are thinner than a blind rivet socket (2.02 mm ...)" for a socket
that needs 2.022 mm (socket_lip_height_mm 0.611: ledge + undercut + two 0.4 mm nozzle widths): feet and floor made
2.02 mm thick as told got the same note again."""
import re

from fabhelpers import make_scene

SERVO = {"type": "servo_housing", "name": "s", "joint": "H0,0", "servo": "SG90", "floor_mm": 0.8}
WHY = r"pad_mm \+ clearance \+ floor_mm = ([0-9.]+) mm\) are thinner than a blind rivet socket \(([0-9.]+) mm"


def _note(pad_mm, lip_mm):
    """The note of the servo housing (None: held by blind rivets) and its fabrication parameters."""
    from metamaterial_wb.core.fabrication import fabrication_params
    from metamaterial_wb.geometry.modules import parse_modules
    sc = make_scene({"grid": [2, 2]}, modules=[dict(SERVO, pad_mm=pad_mm)],
                    fabrication={"socket_lip_height_mm": lip_mm, "nozzle_mm": 0.4})
    p = fabrication_params(sc)
    return parse_modules(sc, p)[0].note, p


def test_the_blind_rivet_socket_a_servo_housing_needs_types_back():
    lip = 0.611
    note, p = _note(0.8, lip)
    m = re.search(WHY, note or "")
    assert m, note
    have, need = float(m.group(1)), float(m.group(2))
    exact = 2 * lip + p.min_wall_mm
    assert have < exact and need >= exact, note          # the printed need is one that suffices
    # typed back: pad_mm so that pad_mm + clearance + floor_mm is the printed need
    note, _ = _note(round(need - p.clearance_mm - SERVO["floor_mm"], 6), lip)
    assert not re.search(WHY, note or ""), note


def test_a_need_printed_exactly_stays_as_it_is():
    """socket_lip_height_mm 0.6: the socket needs exactly 2 mm, printed "2 mm" (not 2.01)."""
    note, p = _note(0.8, 0.6)
    m = re.search(WHY, note or "")
    assert m and m.group(2) == "2", note
    note, _ = _note(round(2.0 - p.clearance_mm - SERVO["floor_mm"], 6), 0.6)
    assert not re.search(WHY, note or ""), note
