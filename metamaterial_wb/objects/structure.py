"""Parametric document objects that mirror a :class:`~metamaterial_wb.core.scene.Scene`.

Document tree made by :func:`make_structure` (all inside one ``App::Part``)::

    Metamaterial (App::Part)
      Scene        App::FeaturePython  full scene JSON (SceneJSON) + typed properties; solves
      NodeShape    Part::FeaturePython one rigid node (built once, cached by its parameters)
      HingeShape   Part::FeaturePython one flexible hinge
      Nodes        App::Link array of NodeShape, one element per node (PlacementList)
      Hinges       App::Link array of HingeShape, one element per joint
      Motor_<name> / Constraint_<name>  Part::FeaturePython markers (red sphere / blue disc)
      Module_<n>   Part::FeaturePython snap-fit add-ons

Dependencies (what recomputes when a property changes):

* a marker's ``Joint``/``Value``/profile -> the marker, then ``Scene`` (it links the markers in
  ``Items``) which re-solves and places nodes, hinges and markers. The shape sources re-execute as
  dependants of ``Scene`` but rebuild nothing unless their own parameters changed.
* ``Scene.CellSize`` / hinge sizes -> ``Scene`` and the shape sources (rebuilt).
* The arrays and markers are *placed* by ``Scene.execute`` through hidden links (no dependency
  edge), and task panels move the same placements without any recompute.

Truth: typed properties (cell size, hinge sizes, layout rows, global deformation, model) and the
marker / module objects win; ``SceneJSON`` is rewritten from them after every recompute and keeps
everything else (axes, joint configuration, per-joint overrides, unknown keys).
"""
import json

import FreeCAD

from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.core.scene import DEFAULT_HINGE, Scene
from metamaterial_wb.core.scene.names import plate_side_mm
from metamaterial_wb.objects.common import (HIDDEN, OUTPUT, READONLY, ProxyBase, attach_proxy, attach_view_provider,
                                            count_execute, ensure_property)
from metamaterial_wb.objects import engine as _engine

# module types of the fabrication package (geometry/modules.py); joint modules sit across a joint
MODULE_TYPES = ["servo_housing", "connection_hub", "stable_hub", "friction_pad", "constraint_clip"]
JOINT_MODULES = {"servo_housing", "stable_hub", "constraint_clip"}
MODULE_ALIASES = {"clip": "constraint_clip", "angular_constraint": "constraint_clip", "servo": "servo_housing",
                  "hub": "connection_hub", "pad": "friction_pad"}
PROFILE_SHAPES = ["none", "sine", "constant", "steps", "keyframes"]

_SOLVERS = {}   # (doc name, scene object name) -> (scene JSON, model, LiveSolver): reused by panels


def _models():
    try:
        from metamaterial_wb.core.models import model_names
        names = list(model_names())
    except Exception:  # pragma: no cover
        names = []
    return names if "quadratic" in names else ["quadratic"] + names


def layout_rows(cells):
    """Cells -> rows of '#' and '.' from row 0 / column 0."""
    cells = [tuple(int(x) for x in c) for c in cells]
    if len(cells) == 0:
        return []
    r1 = max(c[0] for c in cells)
    c1 = max(c[1] for c in cells)
    cs = set(map(tuple, cells))
    return ["".join("#" if (i, j) in cs else "." for j in range(c1 + 1)) for i in range(r1 + 1)]


def cells_from_rows(rows):
    return [(i, j) for i, r in enumerate(rows) for j, ch in enumerate(r) if ch in "#Xx1"]


# ----------------------------------------------------------------------------------------------
# Scene
# ----------------------------------------------------------------------------------------------
class SceneProxy(ProxyBase):
    Type = "MetamaterialScene"
    SCHEMA = 1

    def __init__(self, obj):
        attach_proxy(obj, self)
        self._ensure_properties(obj)

    def _ensure_properties(self, obj):
        ensure_property(obj, "App::PropertyString", "SceneJSON", "Scene",
                        "The full scene (docs/scene-format.md), rewritten after every recompute")
        ensure_property(obj, "App::PropertyString", "SceneName", "Scene", "Name of the design")
        ensure_property(obj, "App::PropertyStringList", "Layout", "Layout",
                        "Cell layout, one string per row: '#' a cell, '.' none")
        ensure_property(obj, "App::PropertyLength", "CellSize", "Layout", "Cell pitch (mm)", 20.0)
        ensure_property(obj, "App::PropertyLength", "HingeLength", "Hinge", "Flexible hinge length (mm)",
                        DEFAULT_HINGE["length_mm"])
        ensure_property(obj, "App::PropertyLength", "HingeWidth", "Hinge", "Flexible hinge width (mm)",
                        DEFAULT_HINGE["width_mm"])
        ensure_property(obj, "App::PropertyLength", "HingeThickness", "Hinge",
                        "Hinge (and sheet) thickness (mm)", DEFAULT_HINGE["thickness_mm"])
        if ensure_property(obj, "App::PropertyEnumeration", "Model", "Simulation", "Simulation model"):
            obj.Model = _models()
            obj.Model = "quadratic"
        ensure_property(obj, "App::PropertyBool", "UseGlobal", "Simulation",
                        "Show the global deformation (every D = GlobalDeformation) instead of the actuators")
        ensure_property(obj, "App::PropertyFloatConstraint", "GlobalDeformation", "Simulation",
                        "Global deformation g in [-1, 1]", (0.0, -1.0, 1.0, 0.05))
        ensure_property(obj, "App::PropertyLinkList", "Items", "Simulation", "Motors and angular constraints")
        ensure_property(obj, "App::PropertyLinkList", "Modules", "Modules", "Snap-fit modules")
        ensure_property(obj, "App::PropertyLinkHidden", "NodeArray", "Display", "Link array of the nodes")
        ensure_property(obj, "App::PropertyLinkHidden", "HingeArray", "Display", "Link array of the hinges")
        ensure_property(obj, "App::PropertyInteger", "NodeCount", "Result", "Number of nodes", attr=OUTPUT,
                        readonly=True)
        ensure_property(obj, "App::PropertyInteger", "JointCount", "Result", "Number of joints", attr=OUTPUT,
                        readonly=True)
        ensure_property(obj, "App::PropertyFloat", "K1", "Result", "k1 of the global hinge size", attr=OUTPUT,
                        readonly=True)
        ensure_property(obj, "App::PropertyFloat", "K2", "Result", "k2 of the global hinge size", attr=OUTPUT,
                        readonly=True)
        ensure_property(obj, "App::PropertyFloatList", "Deformation", "Result", "D per node (solved)",
                        attr=OUTPUT, readonly=True)
        ensure_property(obj, "App::PropertyStringList", "SolveWarnings", "Result", "Solver warnings",
                        attr=OUTPUT, readonly=True)

    def onDocumentRestored(self, obj):
        self._ensure_properties(obj)
        # the model list may have grown since the file was saved
        try:
            cur = obj.Model
            obj.Model = _models()
            if cur in obj.getEnumerationsOfProperty("Model"):
                obj.Model = cur
        except Exception:  # pragma: no cover
            pass

    def execute(self, obj):
        count_execute(obj)
        scene = compose_scene(obj)
        from metamaterial_wb.objects.design_adapter import ensure_configured
        design_warnings = ensure_configured(scene)   # axes without (or with a stale) joint configuration
        solver = solver_for(obj, scene)
        frame = solver.frame(global_deformation=obj.GlobalDeformation if obj.UseGlobal else None)
        text = scene.to_json()
        if obj.SceneJSON != text:
            obj.SceneJSON = text
        obj.NodeCount = scene.topology.n_nodes
        obj.JointCount = scene.topology.n_joints
        try:
            from metamaterial_wb.core.calibration import default_calibration
            cal = default_calibration()
            obj.K1 = cal.k1(scene.hinge["length_mm"])
            obj.K2 = cal.k2(scene.hinge["width_mm"], scene.hinge["thickness_mm"])
        except Exception:
            pass
        obj.Deformation = [float(x) for x in frame.D]
        module_warnings = []
        for m in obj.Modules:
            if getattr(getattr(m, "Proxy", None), "Type", "") != "MetamaterialModule":
                continue
            try:
                if m.Proxy.refresh(m, scene):
                    m.purgeTouched()
            except SceneError as exc:
                module_warnings.append(str(exc))
        obj.SolveWarnings = list(design_warnings) + list(solver.warnings) + module_warnings
        apply_frame(obj, solver, frame, purge=True)


def scene_object_of(obj):
    """The Scene object for any object of a structure (or None)."""
    if obj is None:
        return None
    if getattr(getattr(obj, "Proxy", None), "Type", "") == "MetamaterialScene":
        return obj
    for o in getattr(obj, "InList", []) + getattr(obj, "OutList", []):
        if getattr(getattr(o, "Proxy", None), "Type", "") == "MetamaterialScene":
            return o
    if obj.TypeId == "App::Part":
        for o in obj.Group:
            if getattr(getattr(o, "Proxy", None), "Type", "") == "MetamaterialScene":
                return o
    for p in getattr(obj, "InList", []):
        if p.TypeId == "App::Part":
            return scene_object_of(p)
    for o in getattr(obj, "InList", []):  # link arrays -> shape source -> scene
        if getattr(getattr(o, "Proxy", None), "Type", "") in ("MetamaterialNodeShape", "MetamaterialHingeShape"):
            return o.Scene
    if obj.TypeId == "App::Link":
        src = obj.LinkedObject
        if src is not None and hasattr(src, "Scene"):
            return src.Scene
    return None


def find_scene_objects(doc):
    return [o for o in doc.Objects if getattr(getattr(o, "Proxy", None), "Type", "") == "MetamaterialScene"]


def compose_scene(obj):
    """The :class:`Scene` that the object and its markers / modules describe (validated)."""
    data = json.loads(obj.SceneJSON) if (obj.SceneJSON or "").strip() else {
        "format": "metamaterial-scene", "version": 1, "layout": {"grid": [1, 1]}}
    if obj.SceneName:
        data["name"] = obj.SceneName
    data["cell_size_mm"] = float(obj.CellSize.Value)
    data["hinge"] = {"length_mm": float(obj.HingeLength.Value), "width_mm": float(obj.HingeWidth.Value),
                     "thickness_mm": float(obj.HingeThickness.Value)}
    rows = [str(r) for r in obj.Layout]
    if rows:
        try:
            from metamaterial_wb.core.scene import cells_from_layout
            current = layout_rows(cells_from_layout(data.get("layout", {})))
        except SceneError:
            current = None
        if [r.rstrip(".") for r in rows] != [r.rstrip(".") for r in (current or [])]:
            data["layout"] = {"rows": rows}
    acts, cons = [], []
    for it in obj.Items:
        if getattr(getattr(it, "Proxy", None), "Type", "") != "MetamaterialItem":
            continue
        (acts if it.Kind == "actuator" else cons).append(item_to_dict(it))
    data["actuators"] = acts
    data["constraints"] = cons
    mods = [module_to_dict(m) for m in obj.Modules
            if getattr(getattr(m, "Proxy", None), "Type", "") == "MetamaterialModule"]
    if mods:
        data["modules"] = mods
    else:
        data.pop("modules", None)
    if obj.UseGlobal:
        data["global_deformation"] = float(obj.GlobalDeformation)
    else:
        data.pop("global_deformation", None)
    try:
        return Scene.from_dict(data)
    except SceneError as exc:
        raise SceneError(exc.field, f"{exc.message} (object {obj.Label})") from None


def solver_for(obj, scene=None):
    """A :class:`LiveSolver` for the Scene object, reused while the scene and the model are unchanged."""
    scene = scene or compose_scene(obj)
    key = (obj.Document.Name, obj.Name)
    text = scene.to_json()
    model = obj.Model or "quadratic"
    hit = _SOLVERS.get(key)
    if hit and hit[0] == text and hit[1] == model:
        return hit[2]
    s = _engine.LiveSolver(scene, model=model)
    _SOLVERS[key] = (text, model, s)
    return s


def set_scene_fields(obj, **fields):
    """Change top-level fields of SceneJSON (axes, joint_config, joints, ...); ``None`` removes one."""
    data = json.loads(obj.SceneJSON) if (obj.SceneJSON or "").strip() else {}
    for k, v in fields.items():
        if v is None:
            data.pop(k, None)
        else:
            data[k] = v
    Scene.from_dict(dict(data, actuators=[], constraints=[], modules=[]))  # validate what we can
    obj.SceneJSON = json.dumps(data, indent=1)


def load_typed_properties(obj, scene):
    """Scene -> typed properties and SceneJSON (no markers)."""
    obj.SceneJSON = scene.to_json()
    obj.SceneName = scene.name or ""
    obj.CellSize = scene.cell_size_mm
    obj.HingeLength = scene.hinge["length_mm"]
    obj.HingeWidth = scene.hinge["width_mm"]
    obj.HingeThickness = scene.hinge["thickness_mm"]
    obj.Layout = layout_rows(scene.cells)
    if scene.global_deformation is not None:
        obj.UseGlobal = True
        obj.GlobalDeformation = scene.global_deformation


# ----------------------------------------------------------------------------------------------
# placing the display from a solved frame (no recompute)
# ----------------------------------------------------------------------------------------------
def _offset_positions(pos, quat, offset):
    R = _engine.quaternions_to_matrices(quat)
    return pos + R @ offset


def apply_frame(obj, solver, frame, purge=True):
    """Write node / hinge / marker / module placements for a solved frame. Nothing is recomputed."""
    nodes = obj.NodeArray
    hinges = obj.HingeArray
    if nodes is not None:
        pl = _engine.to_placements(frame.positions, frame.quaternions)
        if nodes.ElementCount != len(pl):
            nodes.ElementCount = len(pl)
        nodes.PlacementList = pl
        if purge:
            nodes.purgeTouched()
    if hinges is not None:
        pl = _engine.to_placements(frame.hinge_positions, frame.hinge_quaternions)
        if hinges.ElementCount != len(pl):
            hinges.ElementCount = len(pl)
        hinges.PlacementList = pl
        if purge:
            hinges.purgeTouched()
    place_markers(obj, solver, frame, purge)


def marker_placements(obj, solver, frame):
    """``{object name: Placement}`` of the markers and modules for a frame."""
    import numpy as np

    out = {}
    t = float(obj.HingeThickness.Value)
    for it in list(obj.Items) + list(obj.Modules):
        typ = getattr(getattr(it, "Proxy", None), "Type", "")
        try:
            if typ == "MetamaterialItem":
                k = solver.joint_index(it.Joint)
                p, q = frame.hinge_positions[k], frame.hinge_quaternions[k]
            elif typ == "MetamaterialModule" and it.TargetKind == "joint":
                # module frame: midpoint of the two node centres, u from the first to the second node
                k = solver.joint_index(it.Target)
                a, b = solver.ja[k], solver.jb[k]
                p, q = 0.5 * (frame.positions[a] + frame.positions[b]), frame.hinge_quaternions[k]
            elif typ == "MetamaterialModule":
                k = solver.node_index(it.Target)
                p, q = frame.positions[k], frame.quaternions[k]
            else:
                continue
        except SceneError:
            continue
        # markers sit on the top face; module solids are built on a sheet spanning z = 0..t
        lift = 0.5 * t + float(it.Radius.Value) if typ == "MetamaterialItem" else -0.5 * t
        pos = _offset_positions(np.asarray([p]), np.asarray([q]), np.array([0.0, 0.0, lift]))[0]
        out[it.Name] = _engine.to_placements(pos[None, :], np.asarray([q]))[0]
    return out


def place_markers(obj, solver, frame, purge=True):
    pls = marker_placements(obj, solver, frame)
    doc = obj.Document
    for name, pl in pls.items():
        o = doc.getObject(name)
        if o is not None:
            o.Placement = pl
            if purge:
                o.purgeTouched()


def display_state(obj):
    """Everything a panel changes, to restore it on close."""
    st = {}
    for arr in (obj.NodeArray, obj.HingeArray):
        if arr is not None:
            st[arr.Name] = ("list", list(arr.PlacementList))
    for it in list(obj.Items) + list(obj.Modules):
        st[it.Name] = ("pl", FreeCAD.Placement(it.Placement))
    return st


def restore_display(obj, state):
    doc = obj.Document
    for name, (kind, val) in state.items():
        o = doc.getObject(name)
        if o is None:
            continue
        if kind == "list":
            if o.ElementCount != len(val):
                o.ElementCount = len(val)
            o.PlacementList = val
        else:
            o.Placement = val
        o.purgeTouched()


# ----------------------------------------------------------------------------------------------
# shape sources
# ----------------------------------------------------------------------------------------------
class _ShapeSource(ProxyBase):
    def __init__(self, obj):
        attach_proxy(obj, self)
        self._ensure_properties(obj)

    def _ensure_properties(self, obj):
        ensure_property(obj, "App::PropertyLink", "Scene", "Base", "The scene whose sizes this shape follows")
        ensure_property(obj, "App::PropertyString", "BuiltFor", "Base", "Parameters of the current shape",
                        attr=OUTPUT, readonly=True, hidden=True)
        ensure_property(obj, "App::PropertyInteger", "BuildCount", "Base", "Shape builds (this session)",
                        attr=OUTPUT | 2, readonly=True, hidden=True)

    def onDocumentRestored(self, obj):
        self._ensure_properties(obj)

    def params(self, sc):
        raise NotImplementedError

    def build(self, params):
        raise NotImplementedError

    def execute(self, obj):
        count_execute(obj)
        sc = obj.Scene
        if sc is None:
            raise SceneError(obj.Label, "no Scene linked")
        params = self.params(sc)
        key = json.dumps(params, sort_keys=True)
        if obj.BuiltFor == key and not obj.Shape.isNull():
            return
        obj.Shape = self.build(params)
        obj.BuiltFor = key
        obj.BuildCount = obj.BuildCount + 1


class NodeShapeProxy(_ShapeSource):
    """One rigid node: from ``metamaterial_wb.geometry`` when available, else a plate (side x side x t)."""
    Type = "MetamaterialNodeShape"

    def params(self, sc):
        return {"cell_size_mm": sc.CellSize.Value, "length_mm": sc.HingeLength.Value,
                "width_mm": sc.HingeWidth.Value, "thickness_mm": sc.HingeThickness.Value}

    def build(self, p):
        import Part
        s = plate_side_mm(p["cell_size_mm"], p["length_mm"])
        t = p["thickness_mm"]
        return Part.makeBox(s, s, t, FreeCAD.Vector(-s / 2, -s / 2, -t / 2))


class HingeShapeProxy(_ShapeSource):
    """One flexible hinge along x: length x width x thickness, centred."""
    Type = "MetamaterialHingeShape"

    def params(self, sc):
        return {"length_mm": sc.HingeLength.Value, "width_mm": sc.HingeWidth.Value,
                "thickness_mm": sc.HingeThickness.Value}

    def build(self, p):
        import Part
        # a little longer than the gap so that it visibly joins the two node corners
        L = p["length_mm"] + 2 * p["width_mm"]
        w = p["width_mm"]
        t = p["thickness_mm"]
        return Part.makeBox(L, w, t, FreeCAD.Vector(-L / 2, -w / 2, -t / 2))


# ----------------------------------------------------------------------------------------------
# markers: motors and angular constraints
# ----------------------------------------------------------------------------------------------
class ItemProxy(ProxyBase):
    """A servo (``Kind`` actuator, red sphere) or an angular-constraint clip (constraint, blue disc)."""
    Type = "MetamaterialItem"

    def __init__(self, obj):
        attach_proxy(obj, self)
        self._ensure_properties(obj)

    def _ensure_properties(self, obj):
        if ensure_property(obj, "App::PropertyEnumeration", "Kind", "Item", "actuator (servo) or constraint"):
            obj.Kind = ["actuator", "constraint"]
        ensure_property(obj, "App::PropertyString", "ItemName", "Item", "Name in the scene (unique)")
        ensure_property(obj, "App::PropertyString", "Joint", "Item", "Joint, e.g. V0,1 or H2,3")
        ensure_property(obj, "App::PropertyFloatConstraint", "Value", "Item",
                        "Deformation the item imposes on both nodes of its joint, in [-1, 1]",
                        (0.0, -1.0, 1.0, 0.05))
        if ensure_property(obj, "App::PropertyEnumeration", "ProfileShape", "Motion",
                           "Motion profile over time (actuators)"):
            obj.ProfileShape = PROFILE_SHAPES
        ensure_property(obj, "App::PropertyFloat", "Amplitude", "Motion", "Sine amplitude (0..1)", 0.5)
        ensure_property(obj, "App::PropertyFloat", "FrequencyHz", "Motion", "Sine frequency (Hz)", 0.5)
        ensure_property(obj, "App::PropertyFloat", "PhaseDeg", "Motion", "Sine phase offset (deg)", 0.0)
        ensure_property(obj, "App::PropertyFloat", "Offset", "Motion", "Sine offset", 0.0)
        ensure_property(obj, "App::PropertyString", "ProfileData", "Motion",
                        "JSON of a constant / steps / keyframes profile")
        ensure_property(obj, "App::PropertyString", "ExtraJSON", "Item", "Other fields of the item (JSON)",
                        hidden=True)
        ensure_property(obj, "App::PropertyLength", "Radius", "Display", "Marker size (mm)", 4.0)

    def onDocumentRestored(self, obj):
        self._ensure_properties(obj)

    def execute(self, obj):
        count_execute(obj)
        import Part
        r = max(0.1, float(obj.Radius.Value))
        pl = FreeCAD.Placement(obj.Placement)
        if obj.Kind == "actuator":
            shape = Part.makeSphere(r)
        else:
            shape = Part.makeCylinder(r, 0.6 * r, FreeCAD.Vector(0, 0, -0.3 * r))
        item_to_dict(obj)  # validates the profile fields (raises with the object's name)
        obj.Shape = shape
        obj.Placement = pl


def item_to_dict(obj):
    d = json.loads(obj.ExtraJSON) if (obj.ExtraJSON or "").strip() else {}
    d.update({"name": obj.ItemName or obj.Name, "joint": obj.Joint, "value": float(obj.Value)})
    if obj.Kind == "actuator" and obj.ProfileShape != "none":
        if obj.ProfileShape == "sine":
            prof = {"shape": "sine", "amplitude": float(obj.Amplitude), "frequency_hz": float(obj.FrequencyHz),
                    "phase_deg": float(obj.PhaseDeg)}
            if obj.Offset:
                prof["offset"] = float(obj.Offset)
        else:
            prof = json.loads(obj.ProfileData) if (obj.ProfileData or "").strip() else {}
            prof["shape"] = obj.ProfileShape
        from metamaterial_wb.core.motion import validate_profile
        try:
            validate_profile(prof, f"{obj.Label}.profile")
        except SceneError:
            raise
        d["profile"] = prof
    return d


def make_item(doc, scene_obj, kind, name, joint, value=0.0, profile=None, extra=None):
    """A motor (kind "actuator") or angular constraint on ``joint``, linked into ``scene_obj.Items``."""
    label = ("Motor_" if kind == "actuator" else "Constraint_") + name
    obj = doc.addObject("Part::FeaturePython", label)
    ItemProxy(obj)
    obj.Kind = kind
    obj.ItemName = name
    obj.Joint = joint
    obj.Value = float(value)
    obj.Radius = 0.2 * float(scene_obj.CellSize.Value)
    if profile:
        p = dict(profile)
        shape = p.pop("shape", "sine")
        obj.ProfileShape = shape
        if shape == "sine":
            obj.Amplitude = float(p.pop("amplitude", 1.0))
            obj.FrequencyHz = float(p.pop("frequency_hz", 1.0))
            obj.PhaseDeg = float(p.pop("phase_deg", 0.0))
            obj.Offset = float(p.pop("offset", 0.0))
        else:
            obj.ProfileData = json.dumps(p)
    if extra:
        obj.ExtraJSON = json.dumps(extra)
    attach_view_provider(obj, "ViewProviderItem")
    scene_obj.Items = list(scene_obj.Items) + [obj]
    _add_to_container(scene_obj, obj)
    return obj


# ----------------------------------------------------------------------------------------------
# modules
# ----------------------------------------------------------------------------------------------
class ModuleProxy(ProxyBase):
    """A snap-fit module on a node (connection hub, friction pad) or across a joint (servo housing,
    stable hub, constraint clip). Its solid comes from ``metamaterial_wb.geometry.modules`` (the same
    builder as the STEP / 3MF export); without that package a stand-in of the right size class is shown.

    The Scene links its modules (it depends on them); a module does not depend on the Scene (hidden link),
    so when the scene's sizes change the Scene refreshes stale module solids itself (see ``refresh``).
    """
    Type = "MetamaterialModule"

    def __init__(self, obj):
        attach_proxy(obj, self)
        self._ensure_properties(obj)

    def _ensure_properties(self, obj):
        if ensure_property(obj, "App::PropertyEnumeration", "ModuleType", "Module", "Kind of module"):
            obj.ModuleType = MODULE_TYPES
        if ensure_property(obj, "App::PropertyEnumeration", "TargetKind", "Module", "node or joint"):
            obj.TargetKind = ["node", "joint"]
        ensure_property(obj, "App::PropertyString", "Target", "Module", "Node (N1,2) or joint (V0,1)")
        ensure_property(obj, "App::PropertyString", "ModuleData", "Module", "Other fields (JSON)")
        # hidden link: the Scene depends on its modules (it links them in Modules), not the reverse
        ensure_property(obj, "App::PropertyLinkHidden", "Scene", "Module", "Scene the module belongs to")
        ensure_property(obj, "App::PropertyString", "GeometrySource", "Module",
                        "Which builder made the shape", attr=OUTPUT, readonly=True)
        ensure_property(obj, "App::PropertyString", "BuiltFor", "Module", "Parameters of the current shape",
                        attr=OUTPUT, readonly=True, hidden=True)

    def onDocumentRestored(self, obj):
        self._ensure_properties(obj)

    def execute(self, obj):
        count_execute(obj)
        sc = obj.Scene
        scene = compose_scene(sc) if sc is not None else None
        self.refresh(obj, scene, force=True)

    def refresh(self, obj, scene, force=False):
        """(Re)build the solid when its parameters changed; raises SceneError naming the module."""
        key = module_build_key(obj, scene)
        if not force and obj.BuiltFor == key and not obj.Shape.isNull():
            return False
        pl = FreeCAD.Placement(obj.Placement)
        shape, source = build_module_shape(obj, scene)
        obj.Shape = shape
        obj.GeometrySource = source
        obj.BuiltFor = key
        obj.Placement = pl
        return True


def module_to_dict(obj):
    d = json.loads(obj.ModuleData) if (obj.ModuleData or "").strip() else {}
    d["type"] = obj.ModuleType
    d.pop("node", None)
    d.pop("joint", None)
    d[obj.TargetKind] = obj.Target
    return d


from metamaterial_wb import PREFS_PATH  # noqa: E402 - one definition (also gui/preferences.py)


def fabrication_overrides():
    """Clearance and module material from the workbench preferences (same group as gui/preferences.py)."""
    prm = FreeCAD.ParamGet(PREFS_PATH)
    return {"clearance_mm": prm.GetFloat("PrinterClearance", 0.2),
            "module_material": prm.GetString("ModuleMaterial", "ABS") or "ABS"}


def module_build_key(obj, scene):
    d = module_to_dict(obj)
    d["_fab"] = fabrication_overrides()
    if scene is not None:
        d["_scene"] = [scene.cell_size_mm, scene.hinge, [c.to_dict() for c in scene.constraints]]
    return json.dumps(d, sort_keys=True)


def geometry_modules_available():
    try:
        from metamaterial_wb.geometry import modules as gmod  # noqa: F401
        from metamaterial_wb.geometry.build import BuildResult  # noqa: F401
        return hasattr(gmod, "build_module") and hasattr(gmod, "parse_modules")
    except ImportError:
        return False


def build_module_shape(obj, scene):
    """``(solid, source)``: the fabrication package's module in its own frame (sheet from z = 0 to its
    thickness, joint modules with u from the first to the second node), or a stand-in."""
    import Part
    if scene is not None and geometry_modules_available():
        from metamaterial_wb.core.scene import Scene as _Scene
        from metamaterial_wb.geometry.build import BuildResult
        from metamaterial_wb.geometry.modules import build_module, parse_modules
        from metamaterial_wb.core.fabrication import fabrication_params
        # the module only needs the sheet's sizes and sockets: drop axes / tilts (their fit is checked
        # by the export of the sheet) and the other modules (sockets they use are checked there too)
        d = scene.to_dict()
        for k in ("axes", "joint_config", "joints"):
            d.pop(k, None)
        d["modules"] = [module_to_dict(obj)]
        one = _Scene.from_dict(d)
        try:
            p = fabrication_params(one, **fabrication_overrides())
            spec = parse_modules(one, p)[0]
            res = BuildResult(one, p)
            build_module(res, spec)
        except SceneError as exc:
            raise SceneError(f"module {obj.Label}", exc.message if hasattr(exc, "message") else str(exc)) from None
        shapes = [res.shapes[part.key] for part in res.parts]
        # Part.Compound, not Part.makeCompound: the latter kills FreeCAD 1.0/1.1 run from plain Python
        return (shapes[0] if len(shapes) == 1 else Part.Compound(shapes)), "geometry.modules"
    cell = scene.cell_size_mm if scene is not None else 20.0
    t = scene.hinge["thickness_mm"] if scene is not None else 7.0
    side = scene.plate_side_mm if scene is not None else plate_side_mm(cell, DEFAULT_HINGE["length_mm"])
    typ = obj.ModuleType
    V = FreeCAD.Vector
    if typ == "servo_housing":  # SG90-sized body above the joint
        return Part.makeBox(23.0, 12.5, 22.0, V(-11.5, -6.25, t)), "stand-in"
    if typ == "friction_pad":  # under the node
        s = 0.7 * side
        return Part.makeBox(s, s, 3.0, V(-s / 2, -s / 2, -3.0)), "stand-in"
    if typ == "constraint_clip":
        return Part.makeBox(cell, 0.5 * side, 3.0, V(-cell / 2, -0.25 * side, t)), "stand-in"
    if typ == "stable_hub":
        return Part.makeBox(0.6 * cell, 0.6 * cell, 6.0, V(-0.3 * cell, -0.3 * cell, t)), "stand-in"
    return Part.makeCylinder(0.3 * side, 3.0, V(0, 0, t)), "stand-in"


def make_module(doc, scene_obj, module_type, target, data=None):
    module_type = MODULE_ALIASES.get(module_type, module_type)
    if module_type not in MODULE_TYPES:
        raise SceneError("module.type", f"{module_type!r}; allowed: {', '.join(MODULE_TYPES)}")
    tgt = str(target).strip().upper()
    # the target's own form decides (a stable hub may be given by a node); the fabrication package
    # validates the combination when it builds the solid
    kind = "node" if tgt.startswith("N") else "joint"
    obj = doc.addObject("Part::FeaturePython", "Module_" + module_type)
    ModuleProxy(obj)
    obj.ModuleType = module_type
    obj.TargetKind = kind
    obj.Target = tgt
    obj.Scene = scene_obj
    if data:
        obj.ModuleData = json.dumps({k: v for k, v in data.items() if k not in ("type", "node", "joint")})
    attach_view_provider(obj, "ViewProviderModule")
    scene_obj.Modules = list(scene_obj.Modules) + [obj]
    _add_to_container(scene_obj, obj)
    return obj


# ----------------------------------------------------------------------------------------------
# making a whole structure
# ----------------------------------------------------------------------------------------------
def _add_to_container(scene_obj, obj):
    for p in scene_obj.InList:
        if p.TypeId == "App::Part":
            p.addObject(obj)
            return


def container_of(scene_obj):
    for p in scene_obj.InList:
        if p.TypeId == "App::Part":
            return p
    return None


def make_structure(doc, scene, recompute=True):
    """Create the document objects of a scene; returns the Scene object."""
    if not isinstance(scene, Scene):
        scene = Scene.from_dict(scene)
    part = doc.addObject("App::Part", "Metamaterial")
    part.Label = scene.name or "Metamaterial"
    sc = doc.addObject("App::FeaturePython", "Scene")
    SceneProxy(sc)
    # the scene JSON without items: markers and modules are the truth for those
    load_typed_properties(sc, scene)
    attach_view_provider(sc, "ViewProviderScene")
    part.addObject(sc)

    ns = doc.addObject("Part::FeaturePython", "NodeShape")
    NodeShapeProxy(ns)
    ns.Scene = sc
    hs = doc.addObject("Part::FeaturePython", "HingeShape")
    HingeShapeProxy(hs)
    hs.Scene = sc
    attach_view_provider(ns, "ViewProviderShapeSource")
    attach_view_provider(hs, "ViewProviderShapeSource")
    nodes = doc.addObject("App::Link", "Nodes")
    nodes.LinkedObject = ns
    nodes.ShowElement = False
    nodes.ElementCount = scene.topology.n_nodes
    hinges = doc.addObject("App::Link", "Hinges")
    hinges.LinkedObject = hs
    hinges.ShowElement = False
    hinges.ElementCount = scene.topology.n_joints
    part.addObjects([ns, hs, nodes, hinges])
    sc.NodeArray = nodes
    sc.HingeArray = hinges
    if FreeCAD.GuiUp:
        for o, vis in ((ns, False), (hs, False)):
            o.ViewObject.Visibility = vis
        from metamaterial_wb.objects.common import set_color
        set_color(ns.ViewObject, (0.80, 0.84, 0.90))
        set_color(hs.ViewObject, (0.95, 0.55, 0.15))

    for a in scene.actuators:
        make_item(doc, sc, "actuator", a.name, a.joint, a.value, a.profile, a.extra)
    for c in scene.constraints:
        make_item(doc, sc, "constraint", c.name, c.joint, c.value, None, c.extra)
    for m in scene.modules or []:
        typ = MODULE_ALIASES.get(m.get("type"), m.get("type")) if isinstance(m, dict) else None
        if typ in MODULE_TYPES and ("node" in m or "joint" in m):
            make_module(doc, sc, typ, m.get("joint") or m.get("node"), m)
        else:
            FreeCAD.Console.PrintWarning(f"Metamaterial: module {m!r} kept in the scene JSON only (not shown)\n")
    if recompute:
        doc.recompute()
    return sc


def load_scene_file(doc, path):
    return make_structure(doc, Scene.load(path))


def scene_json(scene_obj):
    """The composed scene (typed properties + markers + modules) as JSON text."""
    return compose_scene(scene_obj).to_json()


# after every proxy class exists: watch documents, repair those already open (objects/common.py)
from metamaterial_wb.objects.common import install_document_guard  # noqa: E402

install_document_guard()
