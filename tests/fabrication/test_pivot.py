"""One pivot per joint (core/joints.py): the servo shaft is coaxial with the hinge's relative-rotation
axis, so that turning node B about the built shaft bends the hinge instead of stretching it."""
import math

import numpy as np
import pytest

from fabhelpers import EXAMPLES, make_scene


def _shaft_axis(adapter, hub_r):
    """Centre and axis of the built horn-hub pocket (the servo shaft) of a horn adapter."""
    cyl = [f for f in adapter.Faces if f.Surface.__class__.__name__ == "Cylinder"
           and abs(f.Surface.Radius - hub_r) < 1e-9]
    assert cyl, "no horn hub pocket"
    c, a = cyl[0].Surface.Center, cyl[0].Surface.Axis
    return np.array([c.x, c.y, c.z]), np.array([a.x, a.y, a.z])


def _blade_ends(result, joint):
    """The two ends of the built hinge blade's free length (centre line, mid-thickness), found on the
    solids: the hinge part minus the two node plates' envelopes, A's end first."""
    import Part
    from metamaterial_wb.core.scene import joint_nodes, parse_joint
    import FreeCAD as App
    p = result.params
    hinge = [q for q in result.parts if q.role == "hinge" and q.info["joint"] == joint][0]
    hs = result.placed_shape(hinge)
    kind, i, j = parse_joint(joint)
    ends = []
    s, T = p.plate_side_mm_global, p.sheet_thickness_mm
    free = hs
    for (a, b) in joint_nodes(kind, i, j):
        cx, cy = b * p.cell_size_mm, -a * p.cell_size_mm
        free = free.cut(Part.makeBox(s, s, T + 2, App.Vector(cx - 0.5 * s, cy - 0.5 * s, -1)))
    bb = free.BoundBox
    centre = np.array([bb.Center.x, bb.Center.y, bb.Center.z])
    (ia, ja), (ib, jb) = joint_nodes(kind, i, j)
    u = np.array([jb - ja, -(ib - ia), 0.0], dtype=float)
    half = 0.5 * (abs(u[0]) * bb.XLength + abs(u[1]) * bb.YLength)
    return centre - half * u, centre + half * u, 2 * half


def _rotate(pt, centre, axis, deg):
    a = axis / np.linalg.norm(axis)
    t = math.radians(deg)
    v = pt - centre
    return centre + v * math.cos(t) + np.cross(a, v) * math.sin(t) + a * np.dot(a, v) * (1 - math.cos(t))


def _length_errors(end_a, end_b, centre, axis, degs, L):
    out = []
    for d in degs:
        b = _rotate(end_b, centre, axis, d)
        chord = np.linalg.norm(b - end_a)
        th = math.radians(d)
        out.append(chord / (L * (np.sinc(th / (2 * math.pi)))) - 1.0)
    return np.array(out)


@pytest.fixture(scope="module")
def fish(fc):
    from metamaterial_wb.core.scene import Scene
    from metamaterial_wb.geometry.build import build_scene
    return build_scene(Scene.load(f"{EXAMPLES}/fish_modules.json"), progress=False)


def test_fish_head_servo_turns_node_b_about_the_hinge(fish):
    """Rotate node B about the *built* shaft through the design range: the hinge's effective length
    (circular blade through its two built ends) stays within 2 %; the old shaft position (midpoint of
    the node centres, 9.5 mm from the hinge) stretches it by far more."""
    r = fish
    spec = [m for m in r.modules if m.name == "servo_head"][0]
    centre, axis = _shaft_axis(r.placed_shape(r.by_name("servo_head_horn_adapter")),
                               0.5 * spec.values["horn_hub_diameter_mm"] + r.params.clearance_mm)
    assert abs(axis[2]) == pytest.approx(1.0)
    end_a, end_b, L = _blade_ends(r, "V0,1")
    assert L == pytest.approx(8.0, abs=1e-6)
    lo, hi = spec.pivot.range_deg
    assert (lo, hi) == pytest.approx((-27.0, 2 * 0.3 * math.degrees(
        __import__("metamaterial_wb.core.design", fromlist=["x"]).rotation_limits(r.scene)[0])), abs=1e-6)
    degs = np.linspace(lo, hi, 41)
    err = _length_errors(end_a, end_b, centre, axis, degs, L)
    assert np.max(np.abs(err)) <= 0.02
    assert np.max(np.abs(err)) == pytest.approx(spec.pivot.length_error, abs=2e-3)   # the reported value
    # today's shaft: the midpoint of the node centres (27, -13.5)
    old = _length_errors(end_a, end_b, np.array([27.0, -13.5, 0.0]), axis, degs, L)
    assert np.max(np.abs(old)) > 0.2


def test_pivot_is_the_blade_centre_for_small_symmetric_ranges(fc):
    """Independent reference: for a symmetric range the minimax offset is 0 (symmetry), and the
    effective length error is the closed form 1 - cos(t/2) / sinc(t/2) = 1 - (t/2) cot(t/2)."""
    from metamaterial_wb.core import joints
    e = joints.best_pivot_offset(8.0, -20.0, 20.0)
    assert e == pytest.approx(0.0, abs=1e-6)
    t = math.radians(20.0)
    assert joints.max_length_error(8.0, 0.0, -20.0, 20.0) == pytest.approx(1 - (t / 2) / math.tan(t / 2), rel=1e-6)
    # the pole of a one-sided range lies towards the inside of the bend (L t / 12 for small t)
    assert joints.best_pivot_offset(8.0, 0.0, 10.0) > 0 > joints.best_pivot_offset(8.0, -10.0, 0.0)


def test_servo_range_beyond_a_fixed_pivot_is_reported(fish):
    """The fish's tail is driven to D = +-0.9 (81 deg of relative rotation): no fixed shaft keeps an
    8 mm blade within 2 %; the build reports the honest worst length error (measured on the solids)."""
    r = fish
    spec = [m for m in r.modules if m.name == "servo_tail"][0]
    centre, axis = _shaft_axis(r.placed_shape(r.by_name("servo_tail_horn_adapter")),
                               0.5 * spec.values["horn_hub_diameter_mm"] + r.params.clearance_mm)
    end_a, end_b, L = _blade_ends(r, "V1,5")
    lo, hi = spec.pivot.range_deg
    err = _length_errors(end_a, end_b, centre, axis, np.linspace(lo, hi, 81), L)
    assert np.max(np.abs(err)) == pytest.approx(spec.pivot.length_error, abs=2e-3)
    assert spec.pivot.length_error > 0.02


def test_clip_turns_about_the_same_pivot(fc):
    from metamaterial_wb.geometry.modules import clip_pivot, parse_modules, to_module_frame
    from metamaterial_wb.core.design import effective_tilts_deg
    from metamaterial_wb.core.fabrication import fabrication_params
    sc = make_scene({"chain": 3}, modules=[{"type": "constraint_clip", "joint": "H0,1", "angle_deg": 10.0}])
    p = fabrication_params(sc, effective_tilts_deg(sc))
    spec = parse_modules(sc, p)[0]
    x, y, _ = spec.pivot.point_mm
    # H0,1 joins N0,1 (odd: bottom corners) and N0,2: gap centre x = 30, blade centre 0.4 mm above y = -9
    assert x == pytest.approx(30.0, abs=1e-9)
    assert y - spec.pivot.offset_mm == pytest.approx(-9.0 + 0.4, abs=1e-9)
    assert clip_pivot(spec, p) == pytest.approx(to_module_frame(spec, p, (x, y)), abs=1e-6)


def test_servo_on_a_tilted_joint_is_refused(fc):
    from metamaterial_wb.core.errors import SceneError
    from metamaterial_wb.geometry.modules import parse_modules
    from metamaterial_wb.core.design import effective_tilts_deg
    from metamaterial_wb.core.fabrication import fabrication_params
    sc = make_scene({"grid": [1, 2]}, cell_size_mm=30, joint_config={"V0,1": {"tilt_deg": 10.0}},
                    modules=[{"type": "servo_housing", "name": "s", "joint": "V0,1"}])
    with pytest.raises(SceneError, match="tilted hinge"):
        parse_modules(sc, fabrication_params(sc, effective_tilts_deg(sc)))
