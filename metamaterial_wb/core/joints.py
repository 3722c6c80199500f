"""One pivot per joint: where a printed hinge turns, in sheet coordinates (pure numpy, no FreeCAD).

The kinematics (core/kinematics.py) joins two plates by a hinge of length ``lh`` between their
corners; node B turns relative to node A by ``theta = phi_B - phi_A`` about the sheet normal. The
printed hinge is a TPU blade of that free length lying along the plate edge line, ``width`` wide
(docs/fabrication.md). Every module that turns with the joint or holds it (the servo shaft, the
constraint clip, the stable hub) uses the pivot computed here, so that what prints turns as simulated.

Joint frame (shared with geometry/sheet.py): origin at the gap centre on the plate edge line, ``u``
from node A (the joint's first node) to node B, ``v = z x u``; the plates lie on ``side * v > 0``
(``side = -1`` when i + j is even, the checkerboard corner rule of the kinematics).

Pivot. A blade bent with uniform curvature by ``theta`` (an end moment) has its free end on the
circular arc of its own length ``L``; the fixed point of that rigid motion of B (the pole) stays at
the blade's mid-length and moves towards the inside of the bend by ``L (1/theta - cot(theta/2)/2)``.
A servo turns B about one *fixed* axis, so no shaft follows the pole; what must hold is the blade's
length: the end-to-end distance of its two ends after B turned by theta about the shaft must stay
the end-to-end distance of a blade of arc length ``L`` bent by theta, ``L sin(theta/2)/(theta/2)``,
else the servo stretches or crushes the TPU along its stiff axis. A shaft on the blade centre keeps
that only to about +-28 deg (error ``1 - (t/2) cot(t/2)``). Turning about a point at ``x`` from A's
end along the blade gives ``chord^2 = L^2 - 2 x (L - x)(1 - cos theta)``, which matches the arc to
second order when ``x (L - x) = L^2 / 12``, i.e. ``x = L (1/2 - 1/sqrt 6) = 0.092 L`` from A's end
(the housing's side; the mirror point near B's end is as good). The blade then bends unevenly (more
near A's end) but keeps its length: the servo bends it instead of stretching it.
:func:`best_pivot` starts there and minimises the worst error over the design range (minimax,
golden sections along and across the blade): an 8 mm blade turned -81 .. +81 deg keeps its length
within 0.2 %. :func:`length_ratio` is that end-to-end distance over the arc's; the build reports its
worst value per servo (docs/fabrication.md, "Servo pivot"; manifest).
"""
import functools
import math
from dataclasses import dataclass

import numpy as np

PIVOT_LENGTH_TOLERANCE = 0.02      # the servo's pivot keeps the hinge length within 2 % over its range


def joint_frame(kind, i, j, cell_mm, plate_side_mm):
    """``(x, y, angle_deg, side)``: origin of the joint frame (gap centre on the edge line), the
    direction of ``u`` (0 for H joints, -90 for V joints) and the plate side of ``v``.

    Parameters
    ----------
    kind : str
        ``"H"`` or ``"V"``.
    i, j : int
        The joint's grid indices.
    cell_mm : float
        Cell size.
    plate_side_mm : float
        Node plate side (cell - hinge length).

    Returns
    -------
    tuple
        ``(x, y, angle_deg, side)``.
    """
    c, s = float(cell_mm), float(plate_side_mm)
    side = -1 if (i + j) % 2 == 0 else 1
    if kind == "H":
        y = -i * c + (0.5 * s if side < 0 else -0.5 * s)
        return (j * c + 0.5 * c, y, 0.0, side)
    x = j * c + (0.5 * s if side < 0 else -0.5 * s)
    return (x, -i * c - 0.5 * c, -90.0, side)


def length_ratio(length_mm, offset_mm, theta_rad, along_mm=0.0):
    """End-to-end distance of the blade over that of its uniformly bent arc (``L sinc(theta/2)``) when
    node B turns by ``theta`` (rad, array) about the point ``(along, offset)`` of the joint frame
    shifted to the blade centre (``along`` on u from the blade's mid-length, ``offset`` on v).

    Parameters
    ----------
    length_mm : float
        Free hinge length L.
    offset_mm : float
        Lateral pivot offset (along v).
    theta_rad : array_like
        Rotation of B relative to A.
    along_mm : float, optional
        Pivot shift along u.

    Returns
    -------
    numpy.ndarray
        The ratio, shaped like ``theta_rad``.
    """
    L = float(length_mm)
    d, e = float(along_mm), float(offset_mm)
    th = np.asarray(theta_rad, dtype=float)
    c, s = np.cos(th), np.sin(th)
    # B's blade end (L/2, 0) relative to the pivot (d, e), turned, back; A's end stays at (-L/2, 0)
    bx, by = 0.5 * L - d, -e
    x = d + c * bx - s * by
    y = e + s * bx + c * by
    chord = np.hypot(x + 0.5 * L, y)
    return chord / (L * np.sinc(th / (2.0 * math.pi)))


def max_length_error(length_mm, offset_mm, lo_deg, hi_deg, n=241, along_mm=0.0):
    """Worst ``|length_ratio - 1|`` over ``[lo_deg, hi_deg]`` (sampled at ``n`` angles).

    Parameters
    ----------
    length_mm : float
        Free hinge length.
    offset_mm : float
        Lateral pivot offset.
    lo_deg, hi_deg : float
        The rotation range.
    n : int, optional
        Number of samples.
    along_mm : float, optional
        Pivot shift along u.

    Returns
    -------
    float
    """
    th = np.radians(np.linspace(min(lo_deg, 0.0), max(hi_deg, 0.0), n))
    return float(np.max(np.abs(length_ratio(length_mm, offset_mm, th, along_mm) - 1.0)))


def _golden(f, a, b, n=50):
    g = 0.5 * (math.sqrt(5.0) - 1.0)
    x1, x2 = b - g * (b - a), a + g * (b - a)
    f1, f2 = f(x1), f(x2)
    for _ in range(n):
        if f1 <= f2:
            b, x2, f2 = x2, x1, f1
            x1 = b - g * (b - a)
            f1 = f(x1)
        else:
            a, x1, f1 = x1, x2, f2
            x2 = a + g * (b - a)
            f2 = f(x2)
    return 0.5 * (a + b)


def _pole_bracket(L, lo, hi):
    def pole(t):
        return 0.0 if abs(t) < 1e-9 else L * (1.0 / t - 0.5 / math.tan(0.5 * t))
    return min(pole(lo), pole(hi), 0.0) - 1e-9, max(pole(lo), pole(hi), 0.0) + 1e-9


def best_pivot_offset(length_mm, lo_deg, hi_deg, along_mm=0.0):
    """Lateral offset (mm, along v, from the blade centre line) of the fixed pivot at ``along_mm`` that
    keeps the blade's length error smallest over ``[lo_deg, hi_deg]`` (minimax, golden section
    bracketed by the pole's travel).

    Parameters
    ----------
    length_mm : float
        Free hinge length.
    lo_deg, hi_deg : float
        The rotation range.
    along_mm : float, optional
        Pivot position along u.

    Returns
    -------
    float
        The offset (mm).
    """
    L = float(length_mm)
    lo, hi = math.radians(min(lo_deg, 0.0)), math.radians(max(hi_deg, 0.0))
    a, b = _pole_bracket(L, lo, hi)
    return _golden(lambda e: max_length_error(L, e, math.degrees(lo), math.degrees(hi), along_mm=along_mm), a, b)


ALONG_SECOND_ORDER = 0.5 - 1.0 / math.sqrt(6.0)     # x / L from A's end where the chord matches to theta^2


def best_pivot(length_mm, lo_deg, hi_deg):
    """``(along, offset)`` (mm, from the blade centre: along u towards B, across along v) of the fixed
    shaft that keeps the blade's length error smallest over ``[lo_deg, hi_deg]`` (worst case over
    the range). Near A's end: a minimax around ``x = L (1/2 - 1/sqrt 6)`` (exact to second order).
    Cached (about 0.2 s per new range).

    Parameters
    ----------
    length_mm : float
        Free hinge length.
    lo_deg, hi_deg : float
        The rotation range.

    Returns
    -------
    tuple of float
        ``(along, offset)`` in mm.
    """
    return _best_pivot(float(length_mm), float(min(lo_deg, 0.0)), float(max(hi_deg, 0.0)))


@functools.lru_cache(maxsize=256)
def _best_pivot(L, lo, hi):
    if hi - lo < 1e-9:
        return 0.0, 0.0
    d0 = (ALONG_SECOND_ORDER - 0.5) * L

    def worst(d):
        return max_length_error(L, best_pivot_offset(L, lo, hi, d), lo, hi, along_mm=d)

    d = _golden(worst, d0 - 0.08 * L, min(d0 + 0.08 * L, -0.3 * L), n=40)
    return d, best_pivot_offset(L, lo, hi, d)


def node_parity(ij):
    """Checkerboard parity of a node: +1 when i+j is even, else -1.

    Parameters
    ----------
    ij : tuple of int
        The node's grid indices.

    Returns
    -------
    float
    """
    return 1.0 if (ij[0] + ij[1]) % 2 == 0 else -1.0


def relative_rotation_deg(a_ij, D, closing_rad, opening_rad):
    """Rotation of node B relative to node A (deg, about +z) when both nodes of the joint hold ``D``:
    ``phi = (-1)^(i+j) D phi_max(sign D)``, ``theta = phi_B - phi_A = -2 (-1)^(i_A+j_A) D phi_max``.

    Parameters
    ----------
    a_ij : tuple of int
        Grid indices of node A.
    D : float or numpy.ndarray
        Deformation held by both nodes.
    closing_rad, opening_rad : float
        phi_max for D < 0 and D > 0.

    Returns
    -------
    float or numpy.ndarray
        theta in degrees.
    """
    D = np.asarray(D, dtype=float)
    mag = np.where(D >= 0, closing_rad, opening_rad)
    return np.degrees(-2.0 * node_parity(a_ij) * D * mag)


def actuator_value_range(scene, joint):
    """``(lo, hi)`` of D that the scene drives on ``joint``: the range of its actuators' motion
    profiles; the full range [-1, 1] for an actuator without a profile (it may be set to anything);
    ``None`` when nothing drives it.

    Parameters
    ----------
    scene : Scene
    joint : str
        A joint name.

    Returns
    -------
    tuple of float or None
    """
    vals = []
    for act in scene.actuators:
        if act.joint != joint:
            continue
        vals.append(float(act.value))
        p = act.profile
        if not p:
            vals += [-1.0, 1.0]
        else:
            shape = p.get("shape", "sine")
            if shape == "sine":
                off, amp = float(p.get("offset", 0.0)), float(p.get("amplitude", 1.0))
                vals += [off - amp, off + amp]
            elif shape == "constant":
                vals.append(float(p.get("value", 0.0)))
            else:
                vals += [float(v) for v in p.get("values", [])]
    if not vals:
        return None
    return (min(vals + [0.0]), max(vals + [0.0]))


@dataclass
class JointPivot:
    joint: str
    point_mm: tuple          # (x, y, z) in sheet coordinates (z: mid-thickness)
    axis: tuple              # unit vector of the relative-rotation axis (sheet normal for untilted hinges)
    range_deg: tuple         # design range of theta (B relative to A), deg
    value_range: tuple       # the D range it comes from
    offset_mm: float         # lateral shift of the pivot from the blade centre line (along v)
    length_mm: float         # free hinge length
    length_error: float      # worst |end-to-end distance / (L sinc(theta/2)) - 1| over the range
    along_mm: float = 0.0    # shift of the pivot along u (A -> B) from the blade's mid-length

    def as_dict(self):
        """The pivot as a JSON-ready dict (coordinates rounded to 1e-6 mm).

        Returns
        -------
        dict
        """
        return {"joint": self.joint, "point_mm": [round(float(c), 6) for c in self.point_mm],
                "axis": [float(c) for c in self.axis], "range_deg": [round(float(c), 6) for c in self.range_deg],
                "value_range": [float(c) for c in self.value_range], "offset_mm": round(self.offset_mm, 6),
                "along_mm": round(self.along_mm, 6),
                "length_mm": self.length_mm, "length_error": round(self.length_error, 6)}


def joint_pivot(scene, joint, cell_mm, plate_side_mm, hinge, sheet_thickness_mm, value_range=None, limits=None,
                range_deg=None):
    """The pivot of ``joint`` (a :class:`JointPivot`). ``hinge``: the joint's sizes (``length_mm``,
    ``width_mm``, ``tilt_deg``). ``value_range``: the D range of the design (default: the scene's
    actuators on this joint, else the full range [-1, 1]); ``range_deg`` (theta of B relative to A)
    overrides the range taken from the values (a clip's fixed angle).

    Parameters
    ----------
    scene : Scene
    joint : str
        A joint name.
    cell_mm : float
        Cell size.
    plate_side_mm : float
        Node plate side.
    hinge : dict
        The joint's ``length_mm``, ``width_mm`` and optional ``tilt_deg``.
    sheet_thickness_mm : float
        Sheet thickness (the pivot sits at mid-thickness).
    value_range : tuple of float, optional
        D range of the design.
    limits : tuple of float, optional
        ``(closing, opening)`` rotation limits (rad); default from the scene.
    range_deg : tuple of float, optional
        Fixed theta range (overrides ``value_range``).

    Returns
    -------
    JointPivot
    """
    from metamaterial_wb.core.kinematics import rotation_limits
    from metamaterial_wb.core.scene import joint_nodes, parse_joint

    kind, i, j = parse_joint(joint)
    a, _ = joint_nodes(kind, i, j)
    if value_range is None:
        value_range = actuator_value_range(scene, joint) or (-1.0, 1.0)
    if range_deg is None:
        closing, opening = limits if limits is not None else rotation_limits(scene)
        th = relative_rotation_deg(a, np.array(value_range), closing, opening)
        range_deg = (float(th.min()), float(th.max()))
    lo, hi = float(min(range_deg[0], 0.0)), float(max(range_deg[1], 0.0))
    L = float(hinge["length_mm"])
    tilt = math.radians(float(hinge.get("tilt_deg", 0.0)))
    wn = float(hinge["width_mm"]) / math.cos(tilt)
    d, e = best_pivot(L, lo, hi)
    x, y, ang, side = joint_frame(kind, i, j, cell_mm, plate_side_mm)
    v = side * 0.5 * wn + e                       # along v from the edge line
    ca, sa = math.cos(math.radians(ang)), math.sin(math.radians(ang))
    px, py = x + ca * d - sa * v, y + sa * d + ca * v    # u = (cos, sin), v = z x u = (-sin, cos)
    # a tilted hinge leans by its tilt about u (right-hand rule): the axis turns from z towards -v
    axis = (sa * math.sin(tilt), -ca * math.sin(tilt), math.cos(tilt))
    return JointPivot(joint, (px, py, 0.5 * float(sheet_thickness_mm)), axis, (lo, hi), tuple(value_range), e, L,
                      max_length_error(L, e, lo, hi, along_mm=d), d)
