"""Scene -> dynamic model. Two reduced models, both planar in a vertical plane (side view):

* ``sheet`` (the seed's worm, any layout): every *column* of nodes becomes one rigid body (the
  side view of a flat sheet lying on the floor); consecutive columns are joined by the H hinges
  between them (pin spring ``E w t / l`` and bending spring ``E w t^3 / (12 l)`` per hinge, TPU).
  Servos are position sources: the actuators' values (motion profiles over time) give the node
  deformations D through the quadratic model (superposition of per-actuator responses, solved once),
  and D sets each cell's pitch (rotating squares, ``kinematics.uniform_pitch_mm``) and, for tilted
  hinges, its out-of-plane fold ``gamma = 2 phi tan(tilt)`` (physics note 3.5). Friction pads
  (``modules: {"type": "friction_pad", "node": "N0,3", "mu": 1.2, "thickness_mm": 2}``) add a contact
  point with their own friction coefficient ``thickness_mm`` below their node (``PAD_KEYS``: the
  fabrication module's fields; any other field is refused).
* ``belt`` (seed 2): a closed chain of N curvature-changing cells (the layout ``{"chain": N}``),
  each split into ``segments_per_cell`` rigid segments joined by torsional/axial springs. A cell's
  rest curvature is the ring's ``2 pi / (N l)`` plus the bimorph ``kappa = 2 sqrt(3) eps / h`` with
  strain linear in pressure, reached with a first-order fill time. Gaits: the open-loop timed
  sequence (normal torque: one cell; high torque: the opposite pair; tau_on / tau_off) and the
  distributed closed-loop rule (core/gait.py, Algorithm 1, n1 / n2), or per-cell actuator profiles.

Frame: x along the floor towards increasing column (cell) index, y up from the floor (SI units).
"""
from __future__ import annotations

import math

import numpy as np

from ..errors import SceneError, check_integer, check_number
from .controllers import BeltController, SheetController  # noqa: F401  (moved; imported from here too)
from .system import PlanarSystem

G0 = 9.81

DEFAULTS = {
    "model": None,                 # "sheet" | "belt"; default: "belt" if the "belt" object is given
    "gravity_m_s2": G0,
    "incline_deg": 0.0,
    "friction": 0.4,               # default Coulomb coefficient of the bodies on the floor
    "damping_ratio": 0.05,         # hinge dampers, fraction of critical
    "density_kg_m3": 1240.0,       # rigid nodes (PLA)
    "hinge_modulus_mpa": 26.0,     # hinges (TPU 95A)
    "servo_mass_g": 9.0,           # each servo adds its mass to the nodes of its joint
    "contact": {"penetration_tol_mm": 0.2, "support_points": 4, "damping_ratio": 0.5},
    "integrator": {"method": "auto", "dt_s": None},
    "initial_state": None,         # "settled" (static equilibrium under gravity and the actuation at
                                   # t = 0) | "as_built"; default: "settled" for sheets, "as_built" for belts
}

BELT_DEFAULTS = {
    "cell_length_mm": None,        # default: the scene's cell_size_mm
    "width_mm": 30.0,
    "thickness_mm": 6.0,
    "density_kg_m3": 1070.0,       # silicone
    "modulus_kpa": 1500.0,
    "extra_mass_g": 29.0,          # electronics / valve per cell (seed: 0.64 lb for 8 cells)
    "segments_per_cell": None,     # default 4 (<= 64 cells) or 1
    "pressure_kpa": 31.0,          # 4.5 psi
    "strain_per_kpa": 0.001,       # eps = strain_per_kpa * p
    "fill_time_s": 0.5,
    "ground_threshold_mm": None,   # a cell "touches the ground" if a contact point is this close (default h/2)
    "boundary_stiffness_ratio": 1.0,  # bending stiffness of the hinge between two cells (valve / PCB) / inside a cell
    "initial_pressure": "vented",  # "vented": every cell starts at 0 kPa; "gait": the cells start at the pressures
                                   # the gait commands at t = 0 (closed loop: its decision for the initial contacts)
    "loss_factor": 0.0,            # silicone hysteresis: extra bending damper eta * kr / (2 pi f) (Kelvin-Voigt)
    "loss_frequency_hz": 1.0,      # ... matched at this frequency (a rolling step of the belt)
    "start_rotation_deg": 0.0,     # the ring is released turned by this angle (which part of it touches first)
}

INITIAL_PRESSURES = ("vented", "gait")

# a friction pad's fields: the fabrication's (geometry/modules.py, a test keeps them equal); the dynamics reads
# node, mu, thickness_mm and side, and weighs the pad as ABS whatever its material
PAD_KEYS = {"type", "name", "side", "material", "extruder", "node", "mu", "thickness_mm", "pocket_depth_mm",
            "pocket_inset_mm"}

GAIT_TYPES = ("none", "open_loop", "closed_loop")
INCLINE_RANGE_DEG = (-60.0, 60.0)   # dynamics.incline_deg (and simulate --incline)


def _obj(field, value):
    if not isinstance(value, dict):
        raise SceneError(field, f"expected an object, got {value!r}")
    return value


def _merge(field, given, defaults):
    given = _obj(field, given)
    for k in given:
        if k not in defaults:
            raise SceneError(f"{field}.{k}", f"unknown field; allowed: {sorted(defaults)}")
    out = dict(defaults)
    out.update(given)
    return out


def dynamics_config(scene):
    """Validated ``dynamics`` object of a scene (defaults filled in)."""
    raw = scene.extra.get("dynamics", {})
    allowed = dict(DEFAULTS, belt=None, gait=None)
    cfg = _merge("dynamics", raw, allowed)
    cfg["contact"] = _merge("dynamics.contact", raw.get("contact", {}), DEFAULTS["contact"])
    cfg["integrator"] = _merge("dynamics.integrator", raw.get("integrator", {}), DEFAULTS["integrator"])
    f = "dynamics"
    cfg["gravity_m_s2"] = check_number(f"{f}.gravity_m_s2", cfg["gravity_m_s2"], 0.0, 100.0, "m/s^2")
    cfg["incline_deg"] = check_number(f"{f}.incline_deg", cfg["incline_deg"], *INCLINE_RANGE_DEG, "deg")
    cfg["friction"] = check_number(f"{f}.friction", cfg["friction"], 0.0, 10.0)
    cfg["damping_ratio"] = check_number(f"{f}.damping_ratio", cfg["damping_ratio"], 0.0, 10.0)
    cfg["density_kg_m3"] = check_number(f"{f}.density_kg_m3", cfg["density_kg_m3"], 1.0, 30000.0, "kg/m^3")
    cfg["hinge_modulus_mpa"] = check_number(f"{f}.hinge_modulus_mpa", cfg["hinge_modulus_mpa"], 1e-4, 1e6,
                                            "MPa")
    cfg["servo_mass_g"] = check_number(f"{f}.servo_mass_g", cfg["servo_mass_g"], 0.0, 1e4, "g")
    c = cfg["contact"]
    c["penetration_tol_mm"] = check_number(f"{f}.contact.penetration_tol_mm", c["penetration_tol_mm"], 0.0,
                                           100.0, "mm", low_open=True)
    check_integer(f"{f}.contact.support_points", c["support_points"], 1, 1_000_000, "the points the weight rests on")
    c["damping_ratio"] = check_number(f"{f}.contact.damping_ratio", c["damping_ratio"], 0.0, 10.0)
    it = cfg["integrator"]
    from .integrators import METHODS
    if it["method"] not in METHODS:
        raise SceneError(f"{f}.integrator.method", f"{it['method']!r}; allowed: {', '.join(METHODS)}")
    if it["dt_s"] is not None:
        it["dt_s"] = check_number(f"{f}.integrator.dt_s", it["dt_s"], 0.0, 1.0, "s", low_open=True)
    model = cfg["model"] or ("belt" if cfg["belt"] is not None else "sheet")
    if model not in ("sheet", "belt"):
        raise SceneError(f"{f}.model", f"{model!r}; allowed: \"sheet\" (rigid nodes, e.g. the worm) or \"belt\"")
    cfg["model"] = model
    init = cfg["initial_state"] or ("as_built" if model == "belt" else "settled")
    if init not in ("settled", "as_built"):
        raise SceneError(f"{f}.initial_state", f"{init!r}; allowed: \"settled\" (static equilibrium under "
                         f"gravity and the actuators' values at t = 0) or \"as_built\"")
    cfg["initial_state"] = init
    if model == "belt":
        cfg["belt"] = _belt_config(scene, cfg["belt"] or {})
        _belt_reads_none_of(scene, raw)
    elif cfg["belt"] is not None:
        raise SceneError(f"{f}.belt", "only used with \"model\": \"belt\"")
    cfg["gait"] = _gait_config(cfg["gait"], model, scene)
    if model == "belt" and cfg["gait"]["type"] != "none" and scene.actuators:
        raise SceneError("actuators", f"{len(scene.actuators)} actuator(s) beside the belt's "
                                      f"{cfg['gait']['type']} gait, which drives every cell itself: they would be "
                                      "ignored; remove them, or use \"gait\": {\"type\": \"none\"} to drive the "
                                      "cells by the actuators' profiles")
    return cfg


SHEET_ONLY = {"density_kg_m3": "dynamics.belt.density_kg_m3", "hinge_modulus_mpa": "dynamics.belt.modulus_kpa",
              "servo_mass_g": "dynamics.belt.extra_mass_g"}


def _belt_reads_none_of(scene, raw):
    """The sheet's fields and friction pads on a belt scene: refused (the belt model reads neither)."""
    for key, instead in SHEET_ONLY.items():
        if key in raw:
            raise SceneError(f"dynamics.{key}", f"only used by the sheet model; the belt's is {instead}")
    for k, mod in enumerate(scene.modules):
        if isinstance(mod, dict) and mod.get("type") in ("friction_pad", "pad"):
            raise SceneError(f"modules[{k}]", "a friction pad is a sheet's contact; the belt model has none (its "
                                              "cells touch the floor with dynamics.friction)")


def _belt_config(scene, raw):
    f = "dynamics.belt"
    b = _merge(f, raw, BELT_DEFAULTS)
    if "chain" not in scene.layout:
        raise SceneError("layout", "a belt is a closed chain of cells: give the layout as {\"chain\": N}")
    n = scene.layout["chain"]
    if n < 3:
        raise SceneError("layout.chain", f"{n} cells cannot close into a belt; give at least 3")
    b["cells"] = n
    if b["cell_length_mm"] is None:
        b["cell_length_mm"] = scene.cell_size_mm
    b["cell_length_mm"] = check_number(f"{f}.cell_length_mm", b["cell_length_mm"], 0.01, 1000.0, "mm")
    b["width_mm"] = check_number(f"{f}.width_mm", b["width_mm"], 0.01, 1000.0, "mm")
    b["thickness_mm"] = check_number(f"{f}.thickness_mm", b["thickness_mm"], 0.01, 100.0, "mm")
    b["density_kg_m3"] = check_number(f"{f}.density_kg_m3", b["density_kg_m3"], 1.0, 30000.0, "kg/m^3")
    b["modulus_kpa"] = check_number(f"{f}.modulus_kpa", b["modulus_kpa"], 0.1, 1e8, "kPa")
    b["extra_mass_g"] = check_number(f"{f}.extra_mass_g", b["extra_mass_g"], 0.0, 1e5, "g")
    if b["segments_per_cell"] is None:
        b["segments_per_cell"] = 4 if n <= 64 else 1
    k = check_integer(f"{f}.segments_per_cell", b["segments_per_cell"], 1, 32)
    b["boundary_stiffness_ratio"] = check_number(f"{f}.boundary_stiffness_ratio", b["boundary_stiffness_ratio"],
                                                 1e-3, 1e4)
    if b["boundary_stiffness_ratio"] != 1.0 and k < 2:
        raise SceneError(f"{f}.boundary_stiffness_ratio", "needs segments_per_cell >= 2 (a hinge inside each cell)")
    b["pressure_kpa"] = check_number(f"{f}.pressure_kpa", b["pressure_kpa"], 0.0, 1000.0, "kPa")
    b["strain_per_kpa"] = check_number(f"{f}.strain_per_kpa", b["strain_per_kpa"], 0.0, 1.0, "1/kPa")
    b["fill_time_s"] = check_number(f"{f}.fill_time_s", b["fill_time_s"], 0.0, 100.0, "s")
    if b["ground_threshold_mm"] is None:
        b["ground_threshold_mm"] = 0.5 * b["thickness_mm"]
    b["ground_threshold_mm"] = check_number(f"{f}.ground_threshold_mm", b["ground_threshold_mm"], 0.0, 1000.0,
                                            "mm")
    b["loss_factor"] = check_number(f"{f}.loss_factor", b["loss_factor"], 0.0, 10.0)
    b["loss_frequency_hz"] = check_number(f"{f}.loss_frequency_hz", b["loss_frequency_hz"], 0.0, 1e4, "Hz",
                                          low_open=True)
    b["start_rotation_deg"] = check_number(f"{f}.start_rotation_deg", b["start_rotation_deg"], -360.0, 360.0, "deg")
    if b["initial_pressure"] not in INITIAL_PRESSURES:
        raise SceneError(f"{f}.initial_pressure", f"{b['initial_pressure']!r}; allowed: \"vented\" (every cell at "
                                                  f"0 kPa) or \"gait\" (the pressures the gait commands at t = 0)")
    return b


def _gait_config(raw, model, scene):
    f = "dynamics.gait"
    if raw is None:
        return {"type": "none"}
    raw = _obj(f, raw)
    typ = raw.get("type", "none")
    if typ not in GAIT_TYPES:
        raise SceneError(f"{f}.type", f"{typ!r}; allowed: {', '.join(GAIT_TYPES)}")
    if typ != "none" and model != "belt":
        raise SceneError(f"{f}.type", f"{typ!r} gaits drive belt cells; this scene uses the \"{model}\" model "
                                      f"(use actuator profiles instead)")
    if typ == "none":
        return _merge(f, raw, {"type": "none"})
    n = scene.layout.get("chain", 0)
    if typ == "open_loop":
        g = _merge(f, raw, {"type": typ, "torque": "normal", "tau_on_s": 1.0, "tau_off_s": 0.3,
                            "start_cell": None, "direction": 1})
        if g["torque"] not in ("normal", "high"):
            raise SceneError(f"{f}.torque", f"{g['torque']!r}; allowed: \"normal\" (one cell) or \"high\" "
                                            f"(the opposite pair)")
        g["tau_on_s"] = check_number(f"{f}.tau_on_s", g["tau_on_s"], 0.0, 1000.0, "s", low_open=True)
        g["tau_off_s"] = check_number(f"{f}.tau_off_s", g["tau_off_s"], 0.0, 1000.0, "s")
        if isinstance(g["direction"], bool) or not isinstance(g["direction"], int) or g["direction"] not in (1, -1):
            raise SceneError(f"{f}.direction", f"{g['direction']!r}; allowed: 1 or -1")
        if g["start_cell"] is None:   # the released ring's mirror of cell 0 is cell N - 1: -1 mirrors +1
            g["start_cell"] = 0 if g["direction"] == 1 else n - 1
        check_integer(f"{f}.start_cell", g["start_cell"], 0, n - 1)
        return g
    g = _merge(f, raw, {"type": typ, "n1": 1, "n2": 0, "control_period_s": 0.02})
    for key in ("n1", "n2"):
        check_integer(f"{f}.{key}", g[key], 0, n - 1, "0 switches the term off")
    if g["n1"] == 0 and g["n2"] == 0:
        raise SceneError(f, "n1 = n2 = 0: no cell would ever inflate; allowed: at least one of n1, n2 above 0")
    g["control_period_s"] = check_number(f"{f}.control_period_s", g["control_period_s"], 0.0, 10.0, "s",
                                         low_open=True)
    return g


def _gravity(cfg):
    a = math.radians(cfg["incline_deg"])
    g = cfg["gravity_m_s2"]
    return (-g * math.sin(a), -g * math.cos(a))


def _contact_params(system_mass, body_mass, pts_per_body, cfg, n_bodies_total):
    c = cfg["contact"]
    W = max(system_mass * max(cfg["gravity_m_s2"], G0 * 0.1), 1e-9)
    # the whole weight on `support_points` points sinks in by a quarter of the tolerance
    kn = 4.0 * W / (c["support_points"] * c["penetration_tol_mm"] * 1e-3)
    m_pt = body_mass / pts_per_body
    cn = 2.0 * c["damping_ratio"] * np.sqrt(kn * m_pt)
    return kn, cn, kn, cn


# the implicit step of a sheet that asks for none: its corners and pads stick and slip on the floor, and at 1-5 ms
# the step damps that chatter (the worm crawls 2.8x too far, with a closed ledger and a dt study that cannot see
# it: docs/dynamics.md); 0.25 ms is the worm's converged step (docs/dynamics-fidelity.md)
SHEET_DEFAULT_DT = 2.5e-4


class Model:
    """A built model: the system, its initial state, an actuation callback and output helpers."""

    def __init__(self, kind, system, q0, actuate, cfg, info):
        self.kind = kind
        self.system = system
        self.q0 = q0
        self.actuate = actuate
        self.cfg = cfg
        self.info = info

    def com_x(self, q):
        return float(self.system.com_weights() @ q[:, 0])


# ----------------------------------------------------------------------------------------------
# belt
# ----------------------------------------------------------------------------------------------
def build_belt(scene, cfg):
    b = cfg["belt"]
    N = b["cells"]
    k = b["segments_per_cell"]
    S = N * k
    L = b["cell_length_mm"] * 1e-3
    ls = L / k
    w = b["width_mm"] * 1e-3
    h = b["thickness_mm"] * 1e-3
    E = b["modulus_kpa"] * 1e3
    m_seg = b["density_kg_m3"] * ls * w * h + b["extra_mass_g"] * 1e-3 / k
    I_seg = m_seg * (ls * ls + h * h) / 12.0
    mass = np.full(S, m_seg)
    inertia = np.full(S, I_seg)
    system = PlanarSystem(mass, inertia, gravity=_gravity(cfg))
    # ring geometry: counter-clockwise, so the cells on the floor run towards +x with the index
    R = ls / (2.0 * math.sin(math.pi / S))
    phi = -math.pi / 2 + 2 * math.pi * (np.arange(S) + 0.5) / S
    apothem = R * math.cos(math.pi / S)
    cx, cy = 0.0, apothem + h / 2
    q0 = np.column_stack([cx + apothem * np.cos(phi), cy + apothem * np.sin(phi), phi + math.pi / 2])
    a = np.arange(S)
    bb = (a + 1) % S
    kp = E * w * h / ls
    kr = E * w * h ** 3 / 12.0 / ls
    zeta = cfg["damping_ratio"]
    cp = 2 * zeta * math.sqrt(kp * m_seg / 2)
    cr = 2 * zeta * math.sqrt(kr * I_seg / 2)
    base = 2 * math.pi / S
    wrap = np.zeros(S)
    wrap[-1] = -2 * math.pi
    seg_cell = np.arange(S) // k
    boundary = seg_cell[a] != seg_cell[bb]
    ratio = np.where(boundary, b["boundary_stiffness_ratio"], 1.0)
    kr = kr * ratio
    cr = cr * np.sqrt(ratio)
    # viscoelastic silicone (Kelvin-Voigt): a bending damper that dissipates eta * 2 pi * (peak elastic energy)
    # per cycle at loss_frequency_hz, i.e. the loss factor eta = c omega / k at that frequency
    cr = cr + b["loss_factor"] * kr / (2 * math.pi * b["loss_frequency_hz"])
    system.set_hinges(a, bb, np.tile([ls / 2, 0.0], (S, 1)), np.tile([-ls / 2, 0.0], (S, 1)),
                      kp, cp, kr, cr, theta0=base + wrap)
    # two contact points per segment on the outer face
    cb = np.repeat(np.arange(S), 2)
    rc = np.tile([[-0.45 * ls, -h / 2], [0.45 * ls, -h / 2]], (S, 1))
    kn, cn, kt, ct = _contact_params(mass.sum(), m_seg, 2, cfg, S)
    system.set_contacts(cb, rc, cfg["friction"], kn, cn, kt, ct)
    # mirror x: the cells then run clockwise in the side view, so that the strip's upper run has
    # increasing index towards +x and Algorithm 1 as printed (inflate i if c_{i+n1} is on the
    # ground) rolls the belt towards +x. A mirror negates angles and the local x of every point.
    q0[:, 0] *= -1.0
    q0[:, 2] *= -1.0
    system.ra[:, 0] *= -1.0
    system.rb[:, 0] *= -1.0
    system.rc[:, 0] *= -1.0
    system.theta0 *= -1.0
    rot = math.radians(b["start_rotation_deg"])
    if rot != 0.0:
        # release the ring turned about its centre (counter-clockwise in the side view), its lowest point
        # as high above the floor as that of the unturned ring
        y_low = system.contact_points(q0)[:, 1].min()
        c, s_ = math.cos(rot), math.sin(rot)
        x, y = q0[:, 0] - cx, q0[:, 1] - cy
        q0 = np.column_stack([cx + c * x - s_ * y, cy + s_ * x + c * y, q0[:, 2] + rot])
        q0[:, 1] += y_low - system.contact_points(q0)[:, 1].min()
    # hinge -> the cells it belongs to, for the rest curvature. With a stiff boundary (k >= 2) a cell's
    # whole bend kappa * L goes to its k - 1 inner hinges; otherwise it is spread over its k hinges.
    h_cells = np.column_stack([seg_cell[a], seg_cell[bb]])
    if b["boundary_stiffness_ratio"] != 1.0:
        h_weight = np.where(boundary, 0.0, k / (k - 1.0))
    else:
        h_weight = np.ones(S)
    kappa_per_kpa = 2 * math.sqrt(3) * b["strain_per_kpa"] / h        # 1/m per kPa (seed 2, eq. 2)
    ctrl = BeltController(scene, cfg, system, h_cells, -ls * h_weight, -(base + wrap), kappa_per_kpa, seg_cell)
    if b["initial_pressure"] == "gait":
        ctrl.prefill(q0)
    info = {"bodies": S, "cells": N, "segments_per_cell": k, "segment_mass_kg": m_seg,
            "total_mass_kg": float(mass.sum()), "ring_radius_mm": R * 1e3,
            "hinge_kr_Nm_per_rad": sorted({float(x) for x in kr}), "hinge_kp_N_per_m": kp, "contact_kn_N_per_m": kn,
            "kappa_per_kpa_1_per_m": kappa_per_kpa, "gait": cfg["gait"]}
    model = Model("belt", system, q0, ctrl, cfg, info)
    model.seg_cell = seg_cell
    return model


# ----------------------------------------------------------------------------------------------
# sheet (worm, any layout), column-reduced side view
# ----------------------------------------------------------------------------------------------
def _parse_node(text, field):
    import re
    m = re.match(r"^\s*N\s*\(?\s*([0-9]{1,9})\s*,\s*([0-9]{1,9})\s*\)?\s*\Z", str(text))   # ASCII digits
    if not m:
        raise SceneError(field, f"{text!r} is not a node name like \"N0,3\"")
    return int(m.group(1)), int(m.group(2))


def build_sheet(scene, cfg):
    from .. import design, kinematics
    from ..solver import model_for_scene

    topo = scene.topology
    ij = topo.node_ij()
    cols = np.unique(ij[:, 1])
    C = cols.size
    col_index = {int(c): k for k, c in enumerate(cols)}
    P0 = scene.cell_size_mm * 1e-3
    s = scene.plate_side_mm * 1e-3
    t = scene.hinge["thickness_mm"] * 1e-3
    rho = cfg["density_kg_m3"]
    node_mass = rho * s * s * t
    node_body = np.array([col_index[int(j)] for j in ij[:, 1]])
    mass = np.bincount(node_body, np.full(len(ij), node_mass), C)
    servo_m = cfg["servo_mass_g"] * 1e-3
    from ..scene import joint_nodes, parse_joint
    for act in scene.actuators:
        kind, i, j = parse_joint(act.joint)
        for (ni, nj) in joint_nodes(kind, i, j):
            mass[col_index[nj]] += 0.5 * servo_m
    inertia = mass * (s * s + t * t) / 12.0
    system = PlanarSystem(mass, inertia, gravity=_gravity(cfg))

    # friction pads (the fabrication's module: "mu", "thickness_mm" = how far it stands out, "side")
    pads, faces = [], {}
    for k, mod in enumerate(scene.modules):
        if not isinstance(mod, dict) or mod.get("type") not in ("friction_pad", "pad"):
            continue
        f = f"modules[{k}]"
        for key in mod:
            if key not in PAD_KEYS:
                raise SceneError(f"{f}.{key}", f"unknown field for a friction_pad; allowed: {sorted(PAD_KEYS)}")
        if "node" not in mod:
            raise SceneError(f"{f}.node", "a friction pad sits on a node, e.g. \"node\": \"N0,3\"")
        ni, nj = _parse_node(mod["node"], f"{f}.node")
        if (ni, nj) not in topo.node_index:
            raise SceneError(f"{f}.node", f"node N{ni},{nj} does not exist in this layout")
        mu = check_number(f"{f}.mu", mod.get("mu", 1.0), 0.0, 10.0)
        hp = check_number(f"{f}.thickness_mm", mod.get("thickness_mm", 3.0), 0.0, 50.0, "mm") * 1e-3
        side = mod.get("side", "bottom")
        if side not in ("top", "bottom"):
            raise SceneError(f"{f}.side", f"{side!r}; allowed: \"bottom\" (on the floor) or \"top\"")
        if (ni, nj, side) in faces:       # one pad covers the whole face: a second one would double its weight
            raise SceneError(f"{f}.node", f"N{ni},{nj}'s {side} face already carries {faces[ni, nj, side]}; one "
                                          "friction pad per face")
        faces[ni, nj, side] = f
        mass[col_index[nj]] += 1050.0 * s * s * hp          # ABS pad under the whole node face
        if side == "bottom":
            pads.append((col_index[nj], mu, hp))
    system.mass[:] = mass
    system.inertia[:] = mass * (s * s + t * t) / 12.0
    system.M = np.column_stack([system.mass, system.mass, system.inertia])
    pad_h = max([p[2] for p in pads], default=0.0)

    # bodies: flat on the floor
    x0 = (cols - cols[0]) * P0
    q0 = np.column_stack([x0, np.full(C, pad_h + t / 2), np.zeros(C)])

    # hinges between consecutive columns: sum over the H joints of that gap
    E = cfg["hinge_modulus_mpa"] * 1e6
    gaps = {}
    for name, (kind, i, j) in zip(topo.joint_names, topo.joints):
        if kind != "H":
            continue
        h = scene.joint_hinge(name)
        lh, w, th = h["length_mm"] * 1e-3, h["width_mm"] * 1e-3, h["thickness_mm"] * 1e-3
        g = gaps.setdefault(col_index[j], {"kp": 0.0, "kr": 0.0, "tilt": [], "joints": []})
        g["kp"] += E * w * th / lh
        g["kr"] += E * w * th ** 3 / 12.0 / lh
        g["tilt"].append(math.radians(scene.joint_tilt_deg(name)))
        g["joints"].append(topo.joint_index[name])
    ga = np.array(sorted(gaps))
    if ga.size == 0:
        raise SceneError("layout", "the sheet model needs at least two columns of nodes")
    kp = np.array([gaps[g]["kp"] for g in ga])
    kr = np.array([gaps[g]["kr"] for g in ga])
    tilt = np.array([np.mean(gaps[g]["tilt"]) for g in ga])
    a, bb = ga, ga + 1
    m_eff = mass[a] * mass[bb] / (mass[a] + mass[bb])
    I_eff = inertia[a] * inertia[bb] / (inertia[a] + inertia[bb])
    zeta = cfg["damping_ratio"]
    cp = 2 * zeta * np.sqrt(kp * m_eff)
    cr = 2 * zeta * np.sqrt(kr * I_eff)
    half = np.column_stack([np.full(ga.size, P0 / 2), np.zeros(ga.size)])
    system.set_hinges(a, bb, half, -half, kp, cp, kr, cr, 0.0)

    # contacts: two bottom corners per column body + pads
    cb = [np.repeat(np.arange(C), 2)]
    rc = [np.tile([[-s / 2, -t / 2], [s / 2, -t / 2]], (C, 1))]
    mu = [np.full(2 * C, cfg["friction"])]
    for (body, pmu, hp) in pads:
        cb.append(np.array([body]))
        rc.append(np.array([[0.0, -t / 2 - hp]]))
        mu.append(np.array([pmu]))
    cb = np.concatenate(cb)
    rc = np.concatenate(rc)
    mu = np.concatenate(mu)
    n_pts = np.bincount(cb, minlength=C)
    kn, cn, kt, ct = _contact_params(mass.sum(), mass[cb], n_pts[cb], cfg, C)
    system.set_contacts(cb, rc, mu, kn, cn, kt, ct)

    # servo position sources: D = D_const + basis @ (actuator values)
    qm = model_for_scene(scene)
    names = [it.name for _, it in scene.fixed_items()]
    vals0 = {it.name: it.value for _, it in scene.fixed_items()}
    acts = list(scene.actuators)
    zero = dict(vals0)
    for act in acts:
        zero[act.name] = 0.0
    D_const = qm.solve(zero)
    basis = []
    for act in acts:
        vv = dict(zero)
        vv[act.name] = 1.0
        basis.append(qm.solve(vv) - D_const)
    basis = np.array(basis).T if acts else np.zeros((topo.n_nodes, 0))
    # per gap: the nodes of its cells (columns j and j+1)
    gap_nodes = [np.flatnonzero((ij[:, 1] == cols[g]) | (ij[:, 1] == cols[g] + 1)) for g in ga]
    avg = np.zeros((ga.size, topo.n_nodes))
    for r, nodes in enumerate(gap_nodes):
        avg[r, nodes] = 1.0 / nodes.size
    closing, opening = kinematics.rotation_limits(scene, design.joint_tilts_rad(scene))
    lh0 = scene.hinge["length_mm"] * 1e-3
    ctrl = SheetController(acts, avg @ D_const, avg @ basis, P0, s, lh0, closing, opening, tilt, system)
    info = {"bodies": C, "columns": [int(c) for c in cols], "total_mass_kg": float(mass.sum()),
            "pads": len(pads), "hinge_kp_N_per_m": kp.tolist(), "hinge_kr_Nm_per_rad": kr.tolist(),
            "contact_kn_N_per_m": float(np.max(kn)), "actuators": [a_.name for a_ in acts],
            "fixed_items": names}
    model = Model("sheet", system, q0, ctrl, cfg, info)
    model.node_body = node_body
    model.default_dt = SHEET_DEFAULT_DT
    return model


def build(scene, cfg=None):
    cfg = cfg or dynamics_config(scene)
    return build_belt(scene, cfg) if cfg["model"] == "belt" else build_sheet(scene, cfg)
