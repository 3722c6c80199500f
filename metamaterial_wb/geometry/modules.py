"""Snap-fit modules: separate prints (ABS by default) that plug into the node sockets.

Scene format (docs/scene-format.md, "## Modules")::

    "modules": [
      {"type": "servo_housing", "joint": "V0,1", "servo": "SG90"},
      {"type": "friction_pad", "node": "N0,0", "mu": 0.9},
      {"type": "connection_hub", "node": "N2,6"},
      {"type": "stable_hub", "joint": "H0,2"},
      {"type": "constraint_clip", "joint": "V1,0", "angle_deg": 20}
    ]

Every module plugs in with split snap pins (radius = socket radius - clearance, a barb that latches
under the socket's counterbore ledge; prongs sized by geometry/snapfit.py). The servo housing itself
is built in geometry/servo.py, the other modules' shapes in geometry/module_shapes.py. ``side`` says
which face of the sheet it sits on: "top" (default; z > sheet thickness) or "bottom" (mirrored;
default of the friction pad, the face that touches the ground).

Frames: a node module is built around its node centre; a joint module around the joint midpoint
(halfway between the two node centres) with ``u`` pointing from its first node ``A`` to its second
node ``B``. The servo shaft and the clip's turn sit on the joint's pivot (core/joints.py: the hinge
blade's centre, shifted for the design range), not on the midpoint. All checks run in :func:`parse_modules`, before any
geometry.
"""
import math
import re
from dataclasses import dataclass, field, replace

from metamaterial_wb.core.errors import SceneError, check_integer, check_number, in_range, range_message
from metamaterial_wb.core.fabrication import joint_pivot
from metamaterial_wb.core.numbers import inward, inward_g
from metamaterial_wb.core.scene.sections import module_name_error
from metamaterial_wb.geometry.fc import kernel_error
from metamaterial_wb.geometry.module_shapes import (  # noqa: F401  (re-exported: the shapes live in module_shapes.py)
    DOWEL_DIAMETER_MM, HUB_HOLE_RADIUS_MM, HUB_POST_HALF_MM, build_connection_hub, build_constraint_clip,
    build_friction_pad, build_stable_hub, hub_dowel_points, pocket_strips)
from metamaterial_wb.geometry.rivet import BENDING as RIVET_BENDING, HEAD_HEIGHT_MM
from metamaterial_wb.geometry.snapfit import design_snap_fit
from metamaterial_wb.geometry.solids import (  # noqa: F401
    PIN_OVERLAP_MM, _fc, _finish, _lateral_points, _pins_at, adapter_pin_points, box, clip_waiting_rivets, make_pin,
    rivet_parts, riveted)
from metamaterial_wb.geometry.servo import (  # noqa: F401  (re-exported: the servo housing lives in servo.py)
    CABLE_SLOT_MM, SERVO_KEYS, SERVO_OPTIONAL, SERVO_PRESETS, _check_servo_fit, _servo_dims, blind_rivet_problem,
    build_servo_housing, servo_layout)

MODULE_TYPES = ("servo_housing", "connection_hub", "stable_hub", "friction_pad", "constraint_clip")
JOINT_MODULES = ("servo_housing", "stable_hub", "constraint_clip")
NODE_MODULES = ("connection_hub", "friction_pad")
# modules held by separate rivet pins that print lying (geometry/rivet.py, bending along the layers); the
# servo housing too where blind rivets fit (servo.blind_rivet_problem; else it fuses upright pins): :func:`is_riveted`
RIVETED_TYPES = ("stable_hub", "friction_pad", "constraint_clip", "connection_hub")


def is_riveted(spec):
    """Whether a module is held by separate rivet pins (printed lying) rather than fused upright pins."""
    return spec.type in RIVETED_TYPES or bool(spec.values.get("blind_rivets"))

COMMON_KEYS = {"type", "name", "side", "material", "extruder"}
TYPE_KEYS = {
    "servo_housing": {"joint", "servo", "dims", "housing_node", "wall_mm", "floor_mm", "pad_mm"},
    "connection_hub": {"node", "thickness_mm"},
    "stable_hub": {"joint", "height_mm", "platform_mm", "beam_width_mm", "beam_height_mm"},
    "friction_pad": {"node", "mu", "thickness_mm", "pocket_depth_mm", "pocket_inset_mm"},
    "constraint_clip": {"joint", "angle_deg", "thickness_mm"},
}
TYPE_DEFAULTS = {
    "servo_housing": {"wall_mm": 1.6, "floor_mm": 1.6, "pad_mm": 2.0},
    "connection_hub": {"thickness_mm": 3.0},
    "stable_hub": {"height_mm": 6.0, "platform_mm": 8.0, "beam_width_mm": 1.2, "beam_height_mm": 3.0},
    "friction_pad": {"thickness_mm": 3.0, "pocket_depth_mm": 1.5, "pocket_inset_mm": 1.5},
    "constraint_clip": {"thickness_mm": 3.0},
}
# dimensions that are walls of the printed module: at least two nozzle widths (fabrication.nozzle_mm)
WALL_KEYS = {
    "servo_housing": ("wall_mm", "floor_mm", "pad_mm"),
    "connection_hub": ("thickness_mm",),
    "stable_hub": ("beam_width_mm", "beam_height_mm"),
    "friction_pad": ("thickness_mm", "pocket_inset_mm"),
    "constraint_clip": ("thickness_mm",),
}
TYPE_ALIASES = {"clip": "constraint_clip", "angular_constraint": "constraint_clip", "servo": "servo_housing",
                "hub": "connection_hub", "pad": "friction_pad"}
# module names whose files would be the sheet's: NAME_<name>.step / .3mf (export/package.output_names)
RESERVED_NAMES = {"sheet": "NAME_sheet.step and NAME_sheet.3mf (the sheet's)",
                  "sheet_components": "NAME_sheet_components.3mf (the sheet's components layout)",
                  "assembly": "NAME_assembly.step (the assembly)"}
# the scene's own node pattern (Scene._node): ASCII digits only (\d took '٣', which int() reads as 3); the spaces
# around stay those the scene accepts (re.ASCII would refuse here a node name the scene loaded)
_NODE_RE = re.compile(r"^\s*[Nn]\s*\(?\s*([0-9]{1,9})\s*,\s*([0-9]{1,9})\s*\)?\s*\Z")


@dataclass
class ModuleSpec:
    index: int
    type: str
    name: str
    side: str
    material: str
    extruder: int
    node: tuple = None                 # (i, j) for node modules
    joint: str = None                  # joint name for joint modules
    a: tuple = None                    # joint modules: first node (i, j) (housing / u < 0)
    b: tuple = None                    # second node (i, j)
    values: dict = field(default_factory=dict)
    sockets: list = field(default_factory=list)    # [((i, j), "N"|"E"|"S"|"W")]
    mu: float = None
    pivot: object = None               # joint modules that turn with / hold the joint: core.joints.JointPivot
    snap: object = None                # geometry.snapfit.SnapFit of its pins
    note: str = None                   # what the build could not do as designed (the manifest says it)

    @property
    def field(self):
        return f"modules[{self.index}] ({self.name})"

    def target_fields(self):
        """Where the module sits, as the manifest and the part info name it: joint and its two nodes, or node."""
        out = {}
        if self.joint:
            out["joint"] = self.joint
            out["nodes"] = [f"N{self.a[0]},{self.a[1]}", f"N{self.b[0]},{self.b[1]}"]
        if self.node:
            out["node"] = f"N{self.node[0]},{self.node[1]}"
        return out


def parse_node(text, scene, field_name):
    m = _NODE_RE.match(text) if isinstance(text, str) else None
    if not m:
        raise SceneError(field_name, f"{text!r} is not a node name; write \"N<i>,<j>\" (row i, column j)")
    ij = (int(m.group(1)), int(m.group(2)))
    if ij not in scene.topology.node_index:
        nodes = scene.topology.nodes
        raise SceneError(field_name, f"node N{ij[0]},{ij[1]} does not exist in this layout ({len(nodes)} nodes; "
                                     f"rows 0..{max(n[0] for n in nodes)}, columns 0..{max(n[1] for n in nodes)})")
    return ij


def _joint_of_node(scene, ij):
    """A stable hub given by one node (the GUI's form): the joint to its right, else left, below, above."""
    i, j = ij
    for name in (f"H{i},{j}", f"H{i},{j - 1}", f"V{i},{j}", f"V{i - 1},{j}"):
        if scene.topology.has_joint(name):
            return name
    raise SceneError("modules", f"node N{i},{j} has no joint")


def _lateral_labels(a, b):
    """Socket labels of the two sides parallel to the A -> B direction."""
    return ("N", "S") if a[0] == b[0] else ("E", "W")


def parse_modules(scene, p):
    """Validate ``scene.modules`` against the layout and the fabrication parameters.

    Returns a list of :class:`ModuleSpec`; raises SceneError naming the module, the value and the
    allowed range. Also rejects two modules that use the same socket of the same face.
    """
    mods = scene.modules or []
    if not isinstance(mods, list):
        raise SceneError("modules", f"expected a list of modules, got {mods!r}")
    specs = []
    names = set()
    used = {}
    for k, item in enumerate(mods):
        f = f"modules[{k}]"
        if not isinstance(item, dict):
            raise SceneError(f, f"expected an object with \"type\" and a node or joint, got {item!r}")
        typ = TYPE_ALIASES.get(item.get("type"), item.get("type"))
        if typ == "stable_hub" and "node" in item and "joint" not in item:
            item = dict(item)
            item["joint"] = _joint_of_node(scene, parse_node(item.pop("node"), scene, f"{f}.node"))
        if typ not in MODULE_TYPES:
            raise SceneError(f"{f}.type", f"{typ!r} is not a module type; allowed: {list(MODULE_TYPES)}")
        allowed = COMMON_KEYS | TYPE_KEYS[typ]
        for key in item:
            if key not in allowed:
                raise SceneError(f"{f}.{key}", f"unknown field for a {typ}; allowed: {sorted(allowed)}")
        name = item.get("name", f"{typ}_{k + 1}")
        bad_name = module_name_error(f"{f}.name", name)       # the scene's naming rule (core/scene/sections.py)
        if bad_name is not None:
            raise bad_name
        if name.casefold() in RESERVED_NAMES:
            from metamaterial_wb.geometry.parts import safe_stem
            files = RESERVED_NAMES[name.casefold()].replace("NAME", safe_stem(scene.name) if scene.name else "NAME")
            raise SceneError(f"{f}.name", f"{name!r} is reserved: its files would replace {files}; allowed: any "
                                          f"other name")
        if name.casefold() in names:
            raise SceneError(f"{f}.name", f"module name {name!r} is used twice (names that differ only in case "
                                          f"name the same file on Windows and macOS); allowed: a name of its own")
        names.add(name.casefold())
        side = item.get("side", "bottom" if typ == "friction_pad" else "top")
        if side not in ("top", "bottom"):
            raise SceneError(f"{f}.side", f"{side!r}; allowed: \"top\" or \"bottom\"")
        mat = item.get("material", p.module_material)
        from metamaterial_wb.core.materials import MATERIALS
        if not isinstance(mat, str) or mat.upper() not in MATERIALS:
            raise SceneError(f"{f}.material", f"{mat!r} is not a known material; allowed: {sorted(MATERIALS)}")
        ext = item.get("extruder", p.rigid_extruder)
        check_integer(f"{f}.extruder", ext, 1, 16, "an extruder number, 1-based")
        spec = ModuleSpec(k, typ, name, side, mat.upper(), ext)
        if p.sockets:
            spec.snap = design_snap_fit(p, spec.material, f)
            if typ in RIVETED_TYPES:       # separate pins printed lying: they bend along the layers
                spec.snap = replace(spec.snap, bending=RIVET_BENDING)
        values = dict(TYPE_DEFAULTS[typ])
        for key in TYPE_DEFAULTS[typ]:
            if key in item:
                values[key] = check_number(f"{f}.{key} ({name})", item[key], 0.0, 200.0, "mm", low_open=True)
        spec.values = values
        for key in WALL_KEYS.get(typ, ()):
            if values[key] < p.min_wall_mm - 1e-9:
                wall = inward_g(p.min_wall_mm, up=True)       # rounded up: typed back it is accepted
                raise SceneError(f"{f}.{key} ({name})", f"{values[key]} mm is thinner than two nozzle widths ({wall} "
                                 f"mm for fabrication.nozzle_mm = {p.nozzle_mm}); allowed range [{wall}, 200] mm")
        if typ in JOINT_MODULES:
            if "joint" not in item:
                raise SceneError(f"{f}.joint", f"a {typ} sits on a joint; give \"joint\": \"H<i>,<j>\" or \"V<i>,<j>\"")
            spec.joint = scene._joint(item["joint"], f"{f}.joint ({name})")
            from metamaterial_wb.core.scene import parse_joint, joint_nodes
            a, b = joint_nodes(*parse_joint(spec.joint))
            if typ == "servo_housing" and "housing_node" in item:
                hn = parse_node(item["housing_node"], scene, f"{f}.housing_node ({name})")
                if hn not in (a, b):
                    raise SceneError(f"{f}.housing_node ({name})", f"N{hn[0]},{hn[1]} is not a node of joint "
                                                                   f"{spec.joint} (N{a[0]},{a[1]} or N{b[0]},{b[1]})")
                if hn == b:
                    a, b = b, a
            spec.a, spec.b = a, b
            lat = _lateral_labels(a, b)
            spec.sockets = [(a, lat[0]), (a, lat[1]), (b, lat[0]), (b, lat[1])]
        else:
            if "node" not in item:
                raise SceneError(f"{f}.node", f"a {typ} sits on a node; give \"node\": \"N<i>,<j>\"")
            spec.node = parse_node(item["node"], scene, f"{f}.node ({name})")
            spec.sockets = [(spec.node, s) for s in ("E", "N", "W", "S")]
        if (typ in JOINT_MODULES or typ in NODE_MODULES) and not p.sockets:
            raise SceneError(f"{f} ({name})", "modules plug into the node sockets, but fabrication.sockets is false")
        if typ == "servo_housing":
            spec.values.update(_servo_dims(item, f, name, p))
            _untilted(spec, p, f, "a servo's vertical shaft cannot be coaxial with it")
            spec.pivot = joint_pivot(scene, p, spec.joint)
            su, sv = to_module_frame(spec, p, spec.pivot.point_mm)
            spec.values["shaft_u_mm"], spec.values["shaft_v_mm"] = round(su, 6), round(sv, 6)
            _check_servo_fit(spec, p, f)
            _adapter_sockets(spec, p)
            why = blind_rivet_problem(spec, p)
            spec.values["blind_rivets"] = 0.0 if why else 1.0
            if why:
                spec.note = f"pins fused upright (bending across the layers): {why}"
            elif spec.snap is not None:
                spec.snap = replace(spec.snap, bending=RIVET_BENDING)
        elif typ == "connection_hub":
            half = 0.5 * spec.values["thickness_mm"]
            if half < p.min_wall_mm - 1e-9:
                raise SceneError(f"{f}.thickness_mm ({name})",
                                 f"{spec.values['thickness_mm']} mm: the hub prints as two halves, each at least "
                                 f"{inward_g(p.min_wall_mm, up=True)} mm (two nozzle widths) thick; allowed range "
                                 f"[{inward_g(2 * p.min_wall_mm, up=True)}, 200] mm")
        elif typ == "friction_pad":
            if "mu" in item:
                spec.mu = check_number(f"{f}.mu ({name})", item["mu"], 0.0, 10.0)
            v = spec.values
            W = p.min_wall_mm
            if v["pocket_depth_mm"] > v["thickness_mm"] - PIN_OVERLAP_MM - W + 1e-9:
                raise SceneError(f"{f}.pocket_depth_mm ({name})",
                                 f"{v['pocket_depth_mm']} mm leaves less than {W:.3g} mm (two nozzle widths) above "
                                 f"the pins in a {v['thickness_mm']} mm pad; allowed range (0, "
                                 f"{inward_g(v['thickness_mm'] - PIN_OVERLAP_MM - W, slack=1e-10)}] mm")
            head = HEAD_HEIGHT_MM + 0.2          # the rivet heads sit recessed at least this deep
            if v["thickness_mm"] - max(v["pocket_depth_mm"], head) < W - 1e-9:
                raise SceneError(f"{f}.thickness_mm ({name})",
                                 f"{v['thickness_mm']} mm leaves less than {W:.3g} mm (two nozzle widths) under the "
                                 f"rivet heads recessed {max(v['pocket_depth_mm'], head):.3g} mm (the pocket depth, "
                                 f"at least {head:.3g} mm); allowed range "
                                 f"[{inward_g(W + max(v['pocket_depth_mm'], head), up=True)}, 200] mm")
            if 2 * v["pocket_inset_mm"] >= p.plate_side_mm_global - 2.0:
                raise SceneError(f"{f}.pocket_inset_mm ({name})", f"{v['pocket_inset_mm']} mm leaves no pocket")
        elif typ == "constraint_clip":
            _untilted(spec, p, f, "the clip, built turning its second plate about the vertical, would hold "
                                  "another motion than the joint's")
            if "angle_deg" in item:
                lo, hi = _clip_range(scene, spec)
                spec.values["angle_deg"] = check_number(
                    f"{f}.angle_deg ({name})", item["angle_deg"], lo, hi, "deg")
            else:
                spec.values["angle_deg"] = _constraint_angle(scene, spec, f)
            spec.pivot = joint_pivot(scene, p, spec.joint, range_deg=(spec.values["angle_deg"],) * 2)
        elif typ == "stable_hub":
            v = spec.values
            # the platform (and the M3 hole of what it carries) sits over the joint's pivot along the joint
            spec.pivot = joint_pivot(scene, p, spec.joint)
            pu = round(to_module_frame(spec, p, spec.pivot.point_mm)[0], 6)
            v["pivot_u_mm"] = pu
            room = 2.0 * (0.5 * p.cell_size_mm - HUB_POST_HALF_MM - 1.0 - abs(pu))
            low = 2.0 * (HUB_HOLE_RADIUS_MM + p.min_wall_mm)      # two nozzle widths around the M3 hole
            if not (in_range(v["platform_mm"], low) and v["platform_mm"] < room):
                shown = range_message(v["platform_mm"], low, math.floor(room * 100) / 100, "mm", high_open=True)
                raise SceneError(f"{f}.platform_mm ({name})",
                                 f"{shown}: the platform needs two nozzle widths ({p.min_wall_mm:.3g} mm) of wall around its "
                                 f"{2 * HUB_HOLE_RADIUS_MM:g} mm M3 hole, and room for the beams between the posts "
                                 f"on the node centres ({p.cell_size_mm} mm apart, platform over the joint's pivot "
                                 f"{pu:+.3g} mm off the midpoint)")
        for ij, lab in spec.sockets:
            # a snap pin runs through the whole socket, so a top and a bottom module cannot share one either
            key = (ij, lab)
            if key in used:
                other, oside = used[key]
                raise SceneError(f"{f} ({name})", f"modules {other!r} ({oside}) and {name!r} ({side}) collide: both "
                                                  f"put a snap pin into socket {lab} of node N{ij[0]},{ij[1]} (a pin "
                                                  f"runs through the whole socket); move one of them to another "
                                                  f"node or joint")
            used[key] = (name, side)
        specs.append(spec)
    return specs


def _untilted(spec, p, f, why):
    """Refuse a module whose geometry turns about the vertical on a joint with a tilted hinge."""
    tilt = p.hinges[spec.joint].tilt_deg
    if abs(tilt) > 1e-9:
        raise SceneError(f"{f}.joint ({spec.name})",
                         f"joint {spec.joint} has a tilted hinge ({tilt:g} deg): its relative rotation axis leans "
                         f"from the sheet normal, and {why}; allowed: an untilted joint (tilt 0)")


def _adapter_sockets(spec, p):
    """The horn adapter prints upside down on a block that must stay outside the circle the housing
    sweeps about the shaft (geometry/servo.py). A lateral socket of node B whose blind rivet socket
    (its undercut and two nozzle widths around it) would reach into that circle (the seed's 20 mm cells,
    the gripper's and the fish's pivot-side socket) is replaced by B's far socket (the side away from A)
    when that one lies clear: ``values["pin_b_swap_v"]`` is the v sign (module frame) of the lateral
    pin moved."""
    from metamaterial_wb.geometry.sheet import socket_positions

    lay = servo_layout(spec, p)
    su, sv = spec.values["shaft_u_mm"], spec.values["shaft_v_mm"]
    c = p.cell_size_mm
    bx, by = spec.b[1] * c, -spec.b[0] * c
    uv = {lab: to_module_frame(spec, p, (bx + x, by + y)) for lab, x, y in socket_positions(p)}
    # the blind rivet's socket (undercut + two nozzle widths) must lie in the block, outside the circle
    ring = p.counterbore_radius_mm + p.min_wall_mm
    inside = {lab: math.hypot(u - su, v - sv) < lay["col_u0"] + ring - 1e-9 for lab, (u, v) in uv.items()}
    spec.values["pin_b_swap_v"] = 0.0
    lat = [lab for ij, lab in spec.sockets if ij == spec.b]
    bad = [lab for lab in lat if inside[lab]]
    far = max(uv, key=lambda lab: uv[lab][0])
    if len(bad) == 1 and not inside[far]:
        spec.sockets = [(ij, far if (ij == spec.b and lab == bad[0]) else lab) for ij, lab in spec.sockets]
        spec.values["pin_b_swap_v"] = 1.0 if uv[bad[0]][1] > 0 else -1.0


def to_module_frame(spec, p, xy):
    """Sheet coordinates (x, y) -> the module frame (u, v) of :func:`module_placement` (pure math)."""
    c = p.cell_size_mm
    if spec.node is not None:
        return (xy[0] - spec.node[1] * c, xy[1] + spec.node[0] * c)
    (ia, ja), (ib, jb) = spec.a, spec.b
    ax, ay, bx, by = ja * c, -ia * c, jb * c, -ib * c
    ang = math.atan2(by - ay, bx - ax)
    dx, dy = xy[0] - 0.5 * (ax + bx), xy[1] - 0.5 * (ay + by)
    ca, sa = math.cos(ang), math.sin(ang)
    return (ca * dx + sa * dy, -sa * dx + ca * dy)


def _clip_angle(scene, spec, D):
    """Relative in-plane rotation (deg) of node B to node A at deformation ``D`` of the clip's joint."""
    from metamaterial_wb.core.design import rotation_limits

    closing, opening = rotation_limits(scene)
    mag = closing if D >= 0 else opening
    pa = 1.0 if (spec.a[0] + spec.a[1]) % 2 == 0 else -1.0
    return math.degrees(-2.0 * pa * D * mag)


def _clip_range(scene, spec):
    """The angles (deg) a clip on ``spec``'s joint may hold: what the joint turns between D = -1 and D = +1
    (beyond, the plates would overlap), within [-60, 60]."""
    a, b = sorted((_clip_angle(scene, spec, -1.0), _clip_angle(scene, spec, 1.0)))
    return max(a, -60.0), min(b, 60.0)


def _constraint_angle(scene, spec, f):
    """Relative in-plane rotation (deg) of node B to node A held by the scene's constraint on the joint."""
    for c in scene.constraints:
        if c.joint == spec.joint:
            return _clip_angle(scene, spec, c.value)
    lo, hi = _clip_range(scene, spec)     # the angles the clip takes on this joint (bounds rounded inwards)
    raise SceneError(f"{f}.angle_deg ({spec.name})",
                     f"joint {spec.joint} has no constraint to take the clip's angle from: place a constraint on "
                     f"{spec.joint} first, or give the clip's angle_deg (degrees, in [{inward(lo, up=True)}, "
                     f"{inward(hi)}])")


# ----------------------------------------------------------------------------------------------
# geometry (FreeCAD): the shapes in module_shapes.py (the servo housing's in servo.py), placed here
# ----------------------------------------------------------------------------------------------
def clip_pivot(spec, p, placement=None):
    """The joint's pivot (core/joints.py, for the clip's angle) in the module frame."""
    u, v = to_module_frame(spec, p, spec.pivot.point_mm)
    return (round(u, 6), round(v, 6))


def module_placement(spec, p):
    App, _ = _fc()
    V = App.Vector
    c = p.cell_size_mm
    if spec.node is not None:
        i, j = spec.node
        return App.Placement(V(j * c, -i * c, 0.0), App.Rotation())
    (ia, ja), (ib, jb) = spec.a, spec.b
    ax, ay, bx, by = ja * c, -ia * c, jb * c, -ib * c
    ang = math.degrees(math.atan2(by - ay, bx - ax))
    return App.Placement(V(0.5 * (ax + bx), 0.5 * (ay + by), 0.0), App.Rotation(V(0, 0, 1), ang))


def rivet_info(shape, placement, spec):
    """Part info of a rivet pin: its print pose (the flat, module frame ``-y``, on the bed: the pose name
    in sheet axes, export/printpose.POSES), length, strain, bending direction and how many barbed ends
    (2: the connection hub's double rivets)."""
    App, _ = _fc()
    d = placement.Rotation.multVec(App.Vector(0, -1, 0))
    k = max(range(3), key=lambda i: abs(d[i]))
    snap = spec.snap
    return {"rivet": True, "print_pose": f"{'+' if d[k] > 0 else '-'}{'xyz'[k]} down",
            "length_mm": round(shape.BoundBox.ZLength, 4), "strain": snap.strain, "limit": snap.limit,
            "bending": snap.bending, "ends": 2 if spec.type == "connection_hub" else 1,
            # blind rivets (servo housing, horn adapter) go in from the far face of the sheet
            "inserted_from": "sheet" if spec.type == "servo_housing" else "module"}


def _fab_key(p):
    return (p.cell_size_mm, p.plate_side_mm_global, p.sheet_thickness_mm, p.clearance_mm, p.socket_diameter_mm,
            p.socket_inset_mm, p.socket_lip_mm, p.socket_lip_height_mm)


def build_module(res, spec):
    """Build (or reuse) the shapes of one module and add its parts to the BuildResult."""
    from metamaterial_wb.geometry.parts import PlacedPart

    App, _ = _fc()
    V = App.Vector
    p = res.params
    pl = module_placement(spec, p)
    extra = ()
    if spec.type == "constraint_clip":
        pivot = clip_pivot(spec, p, pl)
        extra = (pivot,)
    vals = tuple(sorted((k, v) for k, v in spec.values.items()))
    key0 = ("module", spec.type, spec.side, vals, extra, _fab_key(p), spec.snap.key() if spec.snap else None)
    builders = {"servo_housing": build_servo_housing, "connection_hub": build_connection_hub,
                "friction_pad": build_friction_pad, "stable_hub": build_stable_hub}
    if key0 not in res.module_parts:
        try:
            if spec.type == "constraint_clip":
                built = build_constraint_clip(spec, p, extra[0])
            else:
                built = builders[spec.type](spec, p)
        except Exception as exc:           # the geometry kernel's failures only: programming errors stay visible
            why = kernel_error(exc)
            if why is None:
                raise
            raise SceneError(spec.field, f"the geometry kernel could not build this {spec.type} ({why}); its sizes "
                                         f"do not make a solid: check its fields and dims") from None
        if spec.side == "bottom":
            T = p.sheet_thickness_mm
            built = [(n, sh.mirror(V(0, 0, 0.5 * T), V(0, 0, 1))) for n, sh in built]
        res.module_parts[key0] = [n for n, _ in built]
        for n, sh in built:
            res.shapes[key0 + (n,)] = sh
    for n in res.module_parts[key0]:
        info = {"type": spec.type, "module": spec.name, "side": spec.side, **spec.target_fields()}
        if "_rivet_" in n:
            info.update(rivet_info(res.shapes[key0 + (n,)], pl, spec))
        if spec.mu is not None:
            info["mu"] = spec.mu
        if spec.type == "constraint_clip":
            info["angle_deg"] = spec.values["angle_deg"]
            lift = clip_waiting_rivets(spec, p).get(n)          # above its seat (below it on the bottom face)
            if lift:
                info["lifted_mm"] = lift if spec.side == "top" else -lift
        res.parts.append(PlacedPart(f"{spec.name}_{n}", "module", spec.material, spec.extruder, key0 + (n,), pl,
                                    spec.name, info))
