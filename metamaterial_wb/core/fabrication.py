"""Fabrication parameters and their validation (no FreeCAD import: checked before any geometry).

Every dimension is in millimetres, every angle in degrees. The parameters come from the scene
(``cell_size_mm``, ``hinge`` + per-joint overrides, ``joint_config`` tilts) and from an optional
top-level ``"fabrication"`` object of the scene (docs/fabrication.md); keyword overrides (CLI,
tests) win over both.

Conventions (docs/fabrication.md, "Geometry convention"):

* node ``N(i,j)``: a square plate of side ``s = cell_size_mm - hinge.length_mm`` centred at
  ``x = j * cell_size_mm``, ``y = -i * cell_size_mm``; the sheet spans ``0 <= z <= T`` (z = 0 is the
  print bed, ``T = sheet_thickness_mm``);
* hinges sit at the plate corners of core/kinematics.py (checkerboard), flush with the plate edge;
* sockets: a through hole at the middle of each side, ``socket_inset_mm`` from the edge, with a
  counterbore (the snap ledge) on both faces, so that modules plug in from the top or the bottom.
"""
import math
from dataclasses import dataclass, field, asdict

import numpy as np

from metamaterial_wb.core.errors import SceneError, check_integer, check_number
from metamaterial_wb.core.materials import MATERIALS  # noqa: F401 - the one table (core/materials.py)
from metamaterial_wb.core.numbers import inward_g
from metamaterial_wb.core.scene import parse_joint

MIN_WALL_MM = 0.8        # default thinnest wall between two features: two nozzle widths (fabrication.nozzle_mm)
NOISE_MM = 1e-10         # a printed bound (rounded inwards: inward_g) absorbs float noise this size; checks allow 1e-9


FAB_DEFAULTS = {
    "sheet_thickness_mm": None,      # None: the thickest hinge (hinge.thickness_mm)
    "clearance_mm": 0.2,             # FDM fit clearance for sockets and plugs (per side)
    "anchor_neck_mm": 1.0,           # length of the hinge neck buried in the node (the hook's lip)
    "anchor_depth_mm": 2.0,          # depth of the enlarged anchor head behind the neck
    "anchor_margin_mm": 1.2,         # how much wider than the hinge the anchor head is
    "sockets": True,                 # snap-fit sockets on the four sides of every node
    "socket_diameter_mm": 3.2,       # through hole
    "socket_inset_mm": 3.5,          # hole centre to plate edge
    "socket_lip_mm": 0.5,            # radial size of the snap ledge (counterbore radius - hole radius)
    "socket_lip_height_mm": 1.5,     # counterbore depth on each face
    "rigid_material": "PLA",
    "flexible_material": "TPU",
    "module_material": "ABS",        # the seed prints snap-fits in ABS (PLA is too brittle)
    "rigid_extruder": 1,
    "flexible_extruder": 2,
    "tolerance_mm": 0.05,            # tessellation (3MF) chord tolerance
    "limit_design_tilt": False,      # True: the design stage's maximum fold keeps every tilt printable
    "nozzle_mm": 0.4,                # nozzle diameter: every wall is at least two nozzle widths
    "simulation_only": None,         # a reason (text): this scene is not meant to be printed; build refuses
}


@dataclass(frozen=True)
class HingeSpec:
    """One hinge shape (all that makes two hinges geometrically different).

    Attributes
    ----------
    length_mm, width_mm, thickness_mm : float
        The joint's hinge sizes (``Scene.hinge_sizes(joint)``).
    tilt_deg : float
        Signed tilt the design stage gives it.
    """
    length_mm: float
    width_mm: float
    thickness_mm: float
    tilt_deg: float

    def key(self):
        """Rounded tuple identifying the shape (equal keys: one B-rep, placed copies).

        Returns
        -------
        tuple of float
        """
        return (round(self.length_mm, 6), round(self.width_mm, 6), round(self.thickness_mm, 6),
                round(self.tilt_deg, 6))


@dataclass
class FabParams:
    """Validated fabrication parameters of one scene (:func:`fabrication_params`): every dimension in mm.

    Attributes
    ----------
    cell_size_mm, sheet_thickness_mm, clearance_mm : float
    anchor_neck_mm, anchor_depth_mm, anchor_margin_mm : float
        The hinge anchor hooked into the node plates.
    sockets : bool
    socket_diameter_mm, socket_inset_mm, socket_lip_mm, socket_lip_height_mm : float
    rigid_material, flexible_material, module_material : str
        Keys of ``core.materials.MATERIALS``.
    rigid_extruder, flexible_extruder : int
    tolerance_mm : float
        3MF chord tolerance.
    hinges : dict
        Joint name -> :class:`HingeSpec`.
    nozzle_mm : float
    sheet_from_hinge : bool
        The sheet thickness was taken from the thickest hinge.
    plate_side_mm_global : float
        ``Scene.plate_side_mm``.
    """
    cell_size_mm: float
    sheet_thickness_mm: float
    clearance_mm: float
    anchor_neck_mm: float
    anchor_depth_mm: float
    anchor_margin_mm: float
    sockets: bool
    socket_diameter_mm: float
    socket_inset_mm: float
    socket_lip_mm: float
    socket_lip_height_mm: float
    rigid_material: str
    flexible_material: str
    module_material: str
    rigid_extruder: int
    flexible_extruder: int
    tolerance_mm: float
    hinges: dict = field(default_factory=dict)   # joint name -> HingeSpec
    nozzle_mm: float = 0.4
    sheet_from_hinge: bool = False                 # sheet thickness taken from the thickest hinge

    @property
    def min_wall_mm(self):
        """Thinnest wall any builder may leave: two nozzle widths."""
        return 2.0 * self.nozzle_mm

    @property
    def socket_radius_mm(self):
        return 0.5 * self.socket_diameter_mm

    @property
    def counterbore_radius_mm(self):
        return self.socket_radius_mm + self.socket_lip_mm

    plate_side_mm_global: float = 0.0              # node plate side s = cell - hinge.length_mm (scene-wide)

    @property
    def gap_mm(self):
        return self.cell_size_mm - self.plate_side_mm_global

    def as_dict(self):
        d = asdict(self)
        d["hinges"] = {k: asdict(v) for k, v in self.hinges.items()}
        return d


def _num(name, value, low=None, high=None, low_open=False, high_open=False, unit="mm"):
    return check_number(f"fabrication.{name}", value, low, high, unit, low_open=low_open, high_open=high_open)


def _raw_params(scene, overrides):
    raw = dict(FAB_DEFAULTS)
    given = scene.extra.get("fabrication", {}) if hasattr(scene, "extra") else {}
    if given is None:
        given = {}
    if not isinstance(given, dict):
        raise SceneError("fabrication", f"expected an object of fabrication parameters, got {given!r}")
    for k, v in list(given.items()) + list(overrides.items()):
        if k not in FAB_DEFAULTS:
            raise SceneError(f"fabrication.{k}", f"unknown fabrication parameter; allowed: {sorted(FAB_DEFAULTS)}")
        if v is not None or k == "sheet_thickness_mm":
            raw[k] = v
    return raw


def _lip(name, value, nozzle_mm, where):
    """An anchor size that is also the width of the node's lip (docs/fabrication.md, "Anchors that hook"): the node
    material between the plate edge and the anchor head, which alone holds the hinge in its node, is
    ``anchor_neck_mm`` long and ``anchor_margin_mm`` wide. Like every wall: at least two nozzle widths."""
    from metamaterial_wb.core.errors import in_range, range_message

    v = _num(name, value, 0.0, 50.0, low_open=True)
    low = 2.0 * nozzle_mm
    if not in_range(v, low, 50.0):
        raise SceneError(f"fabrication.{name}",
                         f"{range_message(value, low, 50.0, 'mm')}: it is the lip of node material {where} "
                         f"(the hook that holds the hinge in its node), a wall of at least two nozzle widths "
                         f"({inward_g(low, up=True)} mm for fabrication.nozzle_mm = {nozzle_mm:g})")
    return v


def _params(scene, raw, hinges, thick):
    c = float(scene.cell_size_mm)
    T = raw["sheet_thickness_mm"]
    from_hinge = T is None
    T = thick if T is None else _num("sheet_thickness_mm", T, 0.0, 200.0, low_open=True)
    clr = _num("clearance_mm", raw["clearance_mm"], 0.0, 2.0)
    nozzle = _num("nozzle_mm", raw["nozzle_mm"], 0.1, 1.2)
    _bool("limit_design_tilt", raw["limit_design_tilt"])      # read by the design stage: checked on every scene
    return FabParams(
        cell_size_mm=c, sheet_thickness_mm=T, clearance_mm=clr,
        anchor_neck_mm=_lip("anchor_neck_mm", raw["anchor_neck_mm"], nozzle, "in front of the anchor head"),
        anchor_depth_mm=_num("anchor_depth_mm", raw["anchor_depth_mm"], 0.0, 50.0, low_open=True),
        anchor_margin_mm=_lip("anchor_margin_mm", raw["anchor_margin_mm"], nozzle, "beside the neck, that the head "
                                                                                  "bears on"),
        sockets=_bool("sockets", raw["sockets"]),
        socket_diameter_mm=_num("socket_diameter_mm", raw["socket_diameter_mm"], 0.0, 50.0, low_open=True),
        socket_inset_mm=_num("socket_inset_mm", raw["socket_inset_mm"], 0.0, 100.0, low_open=True),
        socket_lip_mm=_num("socket_lip_mm", raw["socket_lip_mm"], 0.0, 20.0, low_open=True),
        socket_lip_height_mm=_num("socket_lip_height_mm", raw["socket_lip_height_mm"], 0.0, 50.0, low_open=True),
        rigid_material=_material("rigid_material", raw["rigid_material"]),
        flexible_material=_material("flexible_material", raw["flexible_material"]),
        module_material=_material("module_material", raw["module_material"]),
        rigid_extruder=_extruder("rigid_extruder", raw["rigid_extruder"]),
        flexible_extruder=_extruder("flexible_extruder", raw["flexible_extruder"]),
        tolerance_mm=_num("tolerance_mm", raw["tolerance_mm"], 0.001, 1.0),
        hinges=hinges,
        plate_side_mm_global=scene.plate_side_mm,
        nozzle_mm=nozzle,
        sheet_from_hinge=from_hinge,
    )


def fabrication_params(scene, tilts_deg=None, **overrides):
    """Validated fabrication parameters of ``scene`` (builds no geometry).

    Parameters
    ----------
    scene : Scene
    tilts_deg : array_like, optional
        Signed hinge tilt (deg) of every joint in topology order, as the kinematics sees it
        (``core.design.effective_tilts_deg(scene)``, which configures a scene with axes but no joint
        configuration on the fly). Default: the tilts stored in the scene (per-joint overrides, else
        ``joint_config``); a scene with axes but no joint configuration then raises.
    **overrides
        Fabrication parameters (``FAB_DEFAULTS`` keys) that win over the scene's ``"fabrication"``.

    Returns
    -------
    FabParams

    Raises
    ------
    SceneError
        A parameter outside its range, a simulation-only scene, or a hinge that does not fit its plate.
    """
    raw = _raw_params(scene, overrides)
    why = raw["simulation_only"]
    if why is not None:
        if not isinstance(why, str) or not why.strip():
            raise SceneError("fabrication.simulation_only", f"expected a reason (text) why the scene is not printed, "
                                                            f"got {why!r}")
        raise SceneError("fabrication.simulation_only", f"scene {getattr(scene, 'name', '') or ''!r} is "
                                                        f"simulation-only: {why.strip()}")
    hinges = {}
    thick = 0.0
    tilts = _tilts_deg(scene, tilts_deg)
    for name in scene.topology.joint_names:
        h = scene.joint_hinge(name)
        tilt = tilts[name]
        hinges[name] = HingeSpec(float(h["length_mm"]), float(h["width_mm"]), float(h["thickness_mm"]), tilt)
        thick = max(thick, float(h["thickness_mm"]))
    p = _params(scene, raw, hinges, thick)
    _check_fit(p, scene)
    return p


def max_fabricable_tilt_deg(scene, width_mm, ignore_switch=False, **overrides):
    """Largest hinge tilt (deg) whose tilted anchor still fits along the node plate edge.

    The same criterion as the build's check (``_check_fit``): anchor width ``w / cos(tilt) + margin``
    plus the shear ``T tan(tilt)`` through the sheet must stay clear of the side's socket. The design
    stage uses it so that the maximum fold it reports is one that can be printed. Returns a negative
    number when even an untilted hinge of this width does not fit, and 90 when the scene's
    ``fabrication.limit_design_tilt`` is false (the default) unless ``ignore_switch``.

    Parameters
    ----------
    scene : Scene
    width_mm : float
        Hinge blade width.
    ignore_switch : bool
        Compute the limit even when ``fabrication.limit_design_tilt`` is false.
    **overrides
        Fabrication parameters as in :func:`fabrication_params`.

    Returns
    -------
    float
        Degrees (90: no limit; negative: no tilt fits).
    """
    raw = _raw_params(scene, overrides)
    if not ignore_switch and not _bool("limit_design_tilt", raw["limit_design_tilt"]):
        return 90.0
    thick = max([float(scene.hinge["thickness_mm"])] +
                [float(scene.joint_hinge(n)["thickness_mm"]) for n in scene.joint_overrides])
    p = _params(scene, raw, {}, thick)
    return _max_tilt_deg(p, width_mm)


def _edge_room_mm(p):
    """Room along a plate edge, from the corner, for a hinge anchor: half the side less the side's socket
    ledge and a wall, or without sockets less a wall (two nozzle widths) only."""
    w = p.min_wall_mm
    return 0.5 * p.plate_side_mm_global - ((p.counterbore_radius_mm + w) if p.sockets else w)


def _max_tilt_deg(p, width_mm):
    """Largest tilt (deg) whose anchor (``w / cos + margin``, sheared by ``T tan``) fits the edge room;
    -1 when even an untilted hinge does not fit."""
    T = p.sheet_thickness_mm
    room = _edge_room_mm(p)

    def reach(t):
        return width_mm / math.cos(t) + p.anchor_margin_mm + T * math.tan(t)

    if reach(0.0) > room:
        return -1.0
    lo, hi = 0.0, math.radians(89.9)
    if reach(hi) <= room:
        return math.degrees(hi)
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if reach(mid) <= room:
            lo = mid
        else:
            hi = mid
    return math.degrees(lo)


def _tilts_deg(scene, tilts_deg=None):
    """``{joint name: tilt deg}`` from the tilts given (topology order), else the scene's stored ones."""
    names = scene.topology.joint_names
    if tilts_deg is None:
        from metamaterial_wb.core.kinematics import stored_tilts_rad
        t = np.degrees(stored_tilts_rad(scene))
    else:
        t = np.asarray(tilts_deg, dtype=float)
        if t.shape != (len(names),):
            raise SceneError("joint_config", f"expected {len(names)} hinge tilts (one per joint), got shape {t.shape}")
    topo = scene.topology
    return {n: float(t[topo.joint_id(*parse_joint(n))]) for n in names}


def tilts_rad(scene, p):
    """Tilt (rad) of every joint of ``scene`` in topology order, as the build ``p`` uses them.

    Parameters
    ----------
    scene : Scene
    p : FabParams

    Returns
    -------
    numpy.ndarray
        Shape ``(n_joints,)``.
    """
    topo = scene.topology
    t = np.zeros(topo.n_joints)
    for n, h in p.hinges.items():
        t[topo.joint_id(*parse_joint(n))] = math.radians(h.tilt_deg)
    return t


def rotation_limits(scene, p):
    """``(closing_rad, opening_rad)`` of ``scene`` with the hinge tilts of the build ``p``.

    Parameters
    ----------
    scene : Scene
    p : FabParams

    Returns
    -------
    tuple of float
    """
    from metamaterial_wb.core.kinematics import rotation_limits as _limits
    return _limits(scene, tilts_rad(scene, p))


def _bool(name, v):
    if not isinstance(v, bool):
        raise SceneError(f"fabrication.{name}", f"expected true or false, got {v!r}")
    return v


def _material(name, v):
    if not isinstance(v, str) or v.upper() not in MATERIALS:
        raise SceneError(f"fabrication.{name}", f"{v!r} is not a known material; allowed: {sorted(MATERIALS)}")
    return v.upper()


def _extruder(name, v):
    return check_integer(f"fabrication.{name}", v, 1, 16, "an extruder number, 1-based")


def _printable_fold_deg(scene, p, tilt_deg):
    """The fold (deg) a joint of this tilt makes at full deformation (closing rotation), or None."""
    try:
        from metamaterial_wb.core.kinematics import fold_from_tilt
        closing, _ = rotation_limits(scene, p)
        return abs(math.degrees(float(fold_from_tilt(math.radians(tilt_deg), closing))))
    except Exception:          # noqa: BLE001 - only a hint in an error message
        return None


def _check_fit(p, scene=None):
    """Everything that must fit inside a node plate, checked joint by joint (clear errors). Every wall
    left between two features is at least two nozzle widths (``p.min_wall_mm``)."""
    T = p.sheet_thickness_mm
    W = p.min_wall_mm
    if p.rigid_extruder == p.flexible_extruder and p.rigid_material != p.flexible_material:
        raise SceneError("fabrication.flexible_extruder",
                         f"{p.flexible_extruder}, the rigid parts' extruder, but the hinges are "
                         f"{p.flexible_material} and the nodes {p.rigid_material}: one extruder prints one filament, "
                         f"so a slicer would print both in one; allowed: an extruder other than "
                         f"{p.rigid_extruder}, or the same material for both")
    _check_anchor_depth(p, W)
    if p.sockets:
        if 2 * p.socket_lip_height_mm + W > T + 1e-9:
            lip_hi = inward_g((T - W) / 2, slack=NOISE_MM)     # printed bounds rounded inwards: they type back
            if p.sheet_from_hinge:
                need = inward_g(2 * p.socket_lip_height_mm + W, up=True)
                raise SceneError("hinge.thickness_mm",
                                 f"the sheet is as thick as its thickest hinge, {T} mm, but the snap-fit sockets need "
                                 f"at least {need} mm (a {p.socket_lip_height_mm} mm ledge on both faces and a "
                                 f"{W:.3g} mm wall between them); allowed range [{need}, ...) mm, or set "
                                 f"fabrication.sheet_thickness_mm (the plates) to at least {need} mm, "
                                 f"fabrication.socket_lip_height_mm to at most {lip_hi} mm, or "
                                 f"fabrication.sockets to false")
            raise SceneError("fabrication.socket_lip_height_mm",
                             f"{p.socket_lip_height_mm} mm on both faces of a {T} mm sheet leaves less than "
                             f"{W:.3g} mm (two nozzle widths) of hole between the ledges; allowed range (0, "
                             f"{lip_hi}] mm")
        if p.socket_diameter_mm <= 2 * p.clearance_mm + 0.4:
            raise SceneError("fabrication.socket_diameter_mm",
                             f"{p.socket_diameter_mm} mm leaves no plug after the clearance of {p.clearance_mm} mm "
                             f"per side; use more than {inward_g(2 * p.clearance_mm + 0.4, up=True)} mm")
        inset_lo = p.counterbore_radius_mm + W
        # the four sockets sit at the middles of the sides, d = side / 2 - inset from the centre: neighbours are
        # d sqrt(2) apart, and their ledges must leave a wall of two nozzle widths between them
        inset_hi = 0.5 * p.plate_side_mm_global - (2.0 * p.counterbore_radius_mm + W) / math.sqrt(2.0)
        if not inset_lo - 1e-9 <= p.socket_inset_mm <= inset_hi + 1e-9:
            where = ("closer than two nozzle widths to the plate edge" if p.socket_inset_mm < inset_lo else
                     f"so close to the plate's centre that neighbouring sockets are less than {W:.3g} mm (two nozzle "
                     f"widths) apart")
            lo, hi = inward_g(inset_lo, up=True, slack=NOISE_MM), inward_g(inset_hi, slack=NOISE_MM)
            span = (f"allowed range [{lo}, {hi}] mm on a {p.plate_side_mm_global:.4g} mm node "
                    f"plate" if inset_hi >= inset_lo else
                    f"no inset fits on a {p.plate_side_mm_global:.4g} mm node plate (at least {lo} mm "
                    f"from the edge, at most {hi} mm); use larger cells, a smaller socket_diameter_mm or "
                    f"sockets: false")
            raise SceneError("fabrication.socket_inset_mm",
                             f"{p.socket_inset_mm} mm puts the socket ledges (radius {p.counterbore_radius_mm:.3g} mm) "
                             f"{where}; {span}")
    for name, h in p.hinges.items():
        f = f"joints {name}"

        def field(key, name=name, f=f):
            """``hinge.<key>`` where the joint takes the scene's default hinge (no joints[] entry sets it)."""
            own = scene is None or key in scene.joint_overrides.get(name, {})
            return f"{f}.{key}" if own else f"hinge.{key}"
        s = p.plate_side_mm_global
        gap = p.cell_size_mm - p.plate_side_mm_global
        if h.length_mm > gap + 1e-9:
            gap_txt = inward_g(gap, 4, slack=NOISE_MM)
            raise SceneError(field("length_mm"),
                             f"hinge {name} is {h.length_mm} mm long but the gap between the node plates is "
                             f"{gap_txt} mm (cell {p.cell_size_mm} mm - plate side {p.plate_side_mm_global:.4g} mm, "
                             f"set by hinge.length_mm); allowed range (0, {gap_txt}] mm (shorter hinges get rigid "
                             f"stubs)")
        if h.thickness_mm > T + 1e-9:
            raise SceneError(field("thickness_mm"), f"hinge thickness {h.thickness_mm} mm exceeds the sheet thickness "
                                                  f"{T} mm; allowed range (0, {T}] mm")
        tilt = math.radians(h.tilt_deg)
        shift = T * abs(math.tan(tilt))
        wa = anchor_width_mm(p, h)
        # in-plane room: along the edge the (tilted) anchor must stay clear of the side's socket
        reach = wa + shift
        room_edge = _edge_room_mm(p)
        if reach > room_edge:
            # the need rounded up, the room and the limits down: never "needs 6.6 mm but has 6.6 mm"
            room, needs = inward_g(room_edge), inward_g(reach, up=True)
            has = (f"the plate (side {s:.3g} mm) has {room} mm before the socket" if p.sockets else
                   f"the plate (side {s:.3g} mm, no sockets) has {room} mm: half its side less a "
                   f"{W:.3g} mm wall (two nozzle widths)")
            t_max = _max_tilt_deg(p, h.width_mm)
            if h.tilt_deg and t_max >= 0:
                fold = _printable_fold_deg(scene, p, t_max) if scene is not None else None
                fold_txt = (f" (at this sheet's full deformation that is a fold of at most {inward_g(fold)} deg per "
                            f"joint)") if fold is not None else ""
                raise SceneError(f"{f}.tilt_deg",
                                 f"hinge {name} (width {h.width_mm} mm, tilt {h.tilt_deg:.4g} deg) needs {needs} "
                                 f"mm along the plate edge but {has}; allowed tilt range [-{inward_g(t_max)}, "
                                 f"{inward_g(t_max)}] deg for this hinge{fold_txt}; fold less, or use longer hinges, "
                                 f"larger cells, a thinner sheet or a smaller "
                                 f"fabrication.anchor_margin_mm (now {p.anchor_margin_mm} mm)")
            raise SceneError(field("width_mm"),
                             f"hinge {name} (width {h.width_mm} mm, tilt {h.tilt_deg:.4g} deg) needs {needs} mm "
                             f"along the plate edge but {has}; reduce the width, the tilt or the anchor margin")


def _check_anchor_depth(p, W):
    """The anchors of two opposite hinges and a socket between them must fit across a node plate (side set by
    ``hinge.length_mm``): name the hinge length when a shorter one fits, else the anchor depth."""
    s = p.plate_side_mm_global
    sock = (p.counterbore_radius_mm + W) if p.sockets else W
    depth = p.anchor_neck_mm + p.anchor_depth_mm
    need = depth + sock
    if 2 * need <= s + 1e-9:
        return
    max_len = p.cell_size_mm - 2 * need
    # the plate side needed rounded up, the one there and the printed limits down (they type back)
    why = (f"the anchors ({p.anchor_neck_mm:.3g} mm neck + {p.anchor_depth_mm:.3g} mm deep) and "
           f"{'the sockets' if p.sockets else 'a wall'} need a plate side of at least "
           f"{inward_g(2 * need, up=True)} mm")
    if max_len > 0:
        len_hi = inward_g(max_len, slack=NOISE_MM)
        raise SceneError("hinge.length_mm", f"{p.cell_size_mm - s:.4g} mm leaves a plate side of {inward_g(s)} mm "
                                            f"in a {p.cell_size_mm} mm cell; {why}, so the hinges may be at most "
                                            f"{len_hi} mm long: allowed range (0, {len_hi}] mm, or use a "
                                            f"smaller fabrication.anchor_depth_mm")
    depth_max = 0.5 * s - sock - p.anchor_neck_mm
    span = (f"allowed range (0, {inward_g(depth_max, slack=NOISE_MM)}] mm" if depth_max > 0 else
            "no anchor depth fits: use larger cells or a smaller fabrication.anchor_neck_mm")
    raise SceneError("fabrication.anchor_depth_mm", f"{p.anchor_depth_mm} mm: {why}, and the plate side is "
                                                    f"{inward_g(s)} mm; {span}")


def pin_slot_width_mm(p):
    """Width of the slot that splits a module's snap plug (so that its barb can pass the hole).

    Parameters
    ----------
    p : FabParams

    Returns
    -------
    float
    """
    return max(0.6, 0.3 * 2.0 * (p.socket_radius_mm - p.clearance_mm))


def neck_width_mm(h):
    """In-plane (horizontal) width of the hinge neck: a tilted blade keeps its true width.

    Parameters
    ----------
    h : HingeSpec

    Returns
    -------
    float
    """
    return h.width_mm / math.cos(math.radians(h.tilt_deg))


def anchor_width_mm(p, h):
    """In-plane width (along the plate edge) of the anchor head of hinge spec ``h``.

    Parameters
    ----------
    p : FabParams
    h : HingeSpec

    Returns
    -------
    float
    """
    return neck_width_mm(h) + p.anchor_margin_mm


def joint_pivot(scene, p, joint, value_range=None, range_deg=None):
    """The pivot of ``joint`` (core/joints.py :class:`JointPivot`) for this build's hinge sizes.
    ``range_deg`` (B relative to A) overrides the design range taken from ``value_range`` / the
    scene's actuators.

    Parameters
    ----------
    scene : Scene
    p : FabParams
        Its hinge tilts set the rotation limits (:func:`rotation_limits`).
    joint : str
    value_range : tuple of float, optional
        The D range of the design.
    range_deg : tuple of float, optional
        Relative rotation range (deg) that overrides it.

    Returns
    -------
    core.joints.JointPivot
    """
    from metamaterial_wb.core import joints

    h = p.hinges[joint]
    hinge = {"length_mm": h.length_mm, "width_mm": h.width_mm, "tilt_deg": h.tilt_deg}
    return joints.joint_pivot(scene, joint, p.cell_size_mm, p.plate_side_mm_global, hinge, p.sheet_thickness_mm,
                              value_range=value_range, limits=rotation_limits(scene, p), range_deg=range_deg)
