"""Snap-fit modules (``Part::FeaturePython``) on a node or across a joint; solids from ``geometry.modules``."""
import contextlib
import json

import FreeCAD

from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.core.scene import DEFAULT_HINGE
from metamaterial_wb.core.scene.names import plate_side_mm
from metamaterial_wb.objects.common import (OUTPUT, ProxyBase, attach_proxy, count_execute, ensure_property,
                                            json_property, tag_proxy)

# module types of the fabrication package (geometry/modules.py); joint modules sit across a joint
MODULE_TYPES = ["servo_housing", "connection_hub", "stable_hub", "friction_pad", "constraint_clip"]
JOINT_MODULES = {"servo_housing", "stable_hub", "constraint_clip"}
MODULE_ALIASES = {"clip": "constraint_clip", "angular_constraint": "constraint_clip", "servo": "servo_housing",
                  "hub": "connection_hub", "pad": "friction_pad"}
_RUN_BY_SCENE = set()   # (document, module name) that SceneProxy.execute runs itself: their errors mark them invalid


@contextlib.contextmanager
def run_by_scene(m):
    """``with run_by_scene(m): m.recompute()``: the Scene runs its module ``m``; a failure marks ``m`` invalid."""
    key = (m.Document.Name, m.Name)
    _RUN_BY_SCENE.add(key)
    try:
        yield
    finally:
        _RUN_BY_SCENE.discard(key)


def _scene_runs_next(obj, sc):
    """Whether the Scene ``sc`` runs after the module in this recompute and marks it itself: it links the module
    (so depends on it) and the module is not being run by it."""
    return (obj.Document.Name, obj.Name) not in _RUN_BY_SCENE and \
        any(o.Name == obj.Name for o in getattr(sc, "Modules", []))


class ModuleProxy(ProxyBase):
    """A snap-fit module on a node (connection hub, friction pad) or across a joint (servo housing,
    stable hub, constraint clip). Its solid comes from ``metamaterial_wb.geometry.modules`` (the same
    builder as the STEP / 3MF export); without a Scene a stand-in of the right size class is shown.

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
        tag_proxy(obj, self)   # files saved before the split name objects.structure (still importable)
        if obj.BuiltFor and _built_for_other_preferences(obj):   # saved under other preferences: Recompute rebuilds
            obj.touch()

    def execute(self, obj):
        count_execute(obj)
        sc = obj.Scene
        scene = None
        if sc is not None:   # the Scene composes (objects/scene.py imports this module: ask, do not import)
            proxy = getattr(sc, "Proxy", None)
            if not hasattr(proxy, "scene"):
                raise SceneError(f"module {obj.Label}", f"its Scene {sc.Label!r} has no scene proxy")
            try:
                scene = proxy.scene(sc)
            except SceneError:
                # the Scene's own error: it recomputes after its modules (it depends on them) and reports it there;
                # once it is valid again it refreshes this module (SceneProxy.execute). Not this module's fault.
                return
        try:
            self.refresh(obj, scene, force=True)
        except SceneError:
            if scene is None or not _scene_runs_next(obj, sc):
                raise
            # FreeCAD skips an object whose input failed in the same recompute: failing here would stop the Scene
            # (it depends on its modules) from solving, now and on every recompute while this module stays broken.
            # The Scene runs next, refreshes this module and runs it itself (run_by_scene): that run marks it
            # invalid with this message (BuiltFor cleared: its refresh rebuilds, and fails, whatever it held).
            obj.BuiltFor = ""

    def refresh(self, obj, scene, force=False):
        """(Re)build the solid when its parameters changed; raises SceneError naming the module."""
        prepared = prepare_module(obj, scene) if scene is not None else None   # Export's checks, no geometry
        key = module_build_key(obj, scene, prepared)
        if not force and obj.BuiltFor == key and not obj.Shape.isNull():
            return False
        pl = FreeCAD.Placement(obj.Placement)
        shape, source = build_module_shape(obj, scene, prepared)
        obj.Shape = shape
        obj.GeometrySource = source
        obj.BuiltFor = key
        obj.Placement = pl
        return True


def module_to_dict(obj):
    d = json_property(obj, "ModuleData", "an object of the module's other fields, e.g. {\"thickness_mm\": 3}")
    d["type"] = obj.ModuleType
    d.pop("node", None)
    d.pop("joint", None)
    d[obj.TargetKind] = obj.Target
    return d


from metamaterial_wb import PREFS_PATH  # noqa: E402 - one definition (also gui/preferences.py)


# the workbench preferences that are fabrication parameters (their page: gui/preferences.py)
PREFERENCE_PARAMS = {"PrinterClearance": "clearance_mm", "RigidMaterial": "rigid_material",
                     "FlexibleMaterial": "flexible_material", "ModuleMaterial": "module_material"}


# the preferences that shape the modules' solids (``module_build_key``); the page's label of the clearance
MODULE_PREFS = ("PrinterClearance", "ModuleMaterial")
CLEARANCE_PREFERENCE = "Edit > Preferences > Metamaterial > Snap-fit clearance (mm)"
CLEARANCE_FIELD = f"{CLEARANCE_PREFERENCE} (PrinterClearance)"   # the field of its errors


def fabrication_overrides(prefs=MODULE_PREFS):
    """The fabrication parameters the user chose in the workbench preferences ``prefs`` (the modules' solids:
    clearance and module material; Export: all four, ``gui.exporting.preference_overrides``). Chosen: stored in the
    group and not the fabrication default (OK on the preferences page stores every field it shows, so a default
    there is no choice; a text field cleared is not set). The scene's own ``fabrication`` section is used for the
    others, as ``build`` does."""
    from metamaterial_wb.core.fabrication import FAB_DEFAULTS
    prm = FreeCAD.ParamGet(PREFS_PATH)
    out = {}
    for pref in prefs:
        key = PREFERENCE_PARAMS[pref]
        if key == "clearance_mm":
            v = prm.GetFloat(pref) if pref in prm.GetFloats() else None
        else:
            v = (prm.GetString(pref).strip() or None) if pref in prm.GetStrings() else None
        if v is not None and str(v).upper() != str(FAB_DEFAULTS[key]).upper():
            out[key] = v
    return out


def prepare_module(obj, scene):
    """``(one-module scene, FabParams, ModuleSpec)``: the module checked as Export checks it (``build_scene``):
    the fabrication parameters of the whole scene with its effective hinge tilts (axes, joint configuration,
    per-joint hinge sizes), and the module parsed on the scene with this module alone (the sockets other modules
    use are checked by Export). Builds no geometry; raises a SceneError naming the module."""
    from metamaterial_wb.geometry.modules import parse_modules
    try:
        one, p = _fabricated(scene, [module_to_dict(obj)])
        check_clearance_preference(p)
        spec = parse_modules(one, p)[0]
    except SceneError as exc:
        sheet = sheet_error(scene)
        if sheet is not None:     # the sheet itself cannot be built: not this module's fault (a design warning)
            return SheetNotBuilt(sheet)
        raise _module_error(obj, exc) from None
    return one, p, spec


def clearance_preference_clash(lip_mm, snap_pins=True):
    """The clearance preference (not the scene's own) when it is chosen and not below the socket lip ``lip_mm`` the
    modules' snap pins latch on (``geometry.snapfit``), else None; None too when no snap pin is designed
    (``snap_pins`` False: no sockets, or no module exported), where nothing compares the clearance with the lip."""
    clr = fabrication_overrides(("PrinterClearance",)).get("clearance_mm") if snap_pins else None
    return None if clr is None or clr < lip_mm else clr


def check_clearance_preference(p):
    """Refuse a clearance preference that leaves the modules' snap pins no barb (:func:`clearance_preference_clash`
    against ``p.socket_lip_mm``; ``p`` from :func:`_fabricated`). Raises a SceneError naming the preference. Without
    sockets (``p.sockets``) no snap pin is designed: the modules are refused for that (``geometry.modules``)."""
    from metamaterial_wb.geometry.snapfit import no_latch_error
    if clearance_preference_clash(p.socket_lip_mm, p.sockets) is not None:
        raise no_latch_error(p)


def mark_preference_clearance(p, overrides):
    """``p`` (``FabParams``) made with the preferences' ``overrides`` (:func:`fabrication_overrides`), marked when
    they supply the clearance: the snap pins' errors then name the preference, not the scene's fields
    (``geometry.snapfit.clearance_origin``). The modules' solids here, Export's runs (``gui.exporting``). Returns
    ``p``."""
    if "clearance_mm" in (overrides or {}):
        p.clearance_origin = CLEARANCE_FIELD
    return p


class SheetNotBuilt:
    """What :func:`prepare_module` returns when Export refuses the sheet itself (hinge tilts of a fold that do not
    fit their plates, which the Scene's design check reports as a warning): no module can be Export's solid, so it
    shows its stand-in and stays valid; ``message`` is the sheet's error."""

    def __init__(self, message):
        self.message = message


def _fabricated(scene, modules):
    """``(scene, FabParams)``: ``scene`` with only ``modules`` and its fabrication parameters as Export computes
    them (the effective hinge tilts, the workbench's preferences); raises the SceneError Export would."""
    from metamaterial_wb.core.design import effective_tilts_deg
    from metamaterial_wb.core.fabrication import fabrication_params
    from metamaterial_wb.core.scene import Scene as _Scene
    d = scene.to_dict()
    d["modules"] = modules
    one = _Scene.from_dict(d)
    over = fabrication_overrides()
    return one, mark_preference_clearance(fabrication_params(one, effective_tilts_deg(one), **over), over)


def sheet_error(scene):
    """Export's error for the sheet of ``scene`` without its modules (None when the sheet can be built)."""
    try:
        _fabricated(scene, [])
    except SceneError as exc:
        return str(exc)
    return None


def _module_error(obj, exc):
    """The SceneError ``exc`` of the one-module scene, named by the module (its label, once): its field without the
    index and the internal name the one-module scene gives it (``angle_deg (constraint_clip_1)``: the user never
    sees that name; node, joint, thickness_mm), then the builder's message."""
    auto = f"{obj.ModuleType}_1"          # geometry.modules' name of an unnamed module, the first of the scene
    field = (getattr(exc, "field", "") or "").replace("modules[0].", "").replace("modules[0]", "")
    field = field.replace(f"({auto})", "").strip()
    msg = exc.message if hasattr(exc, "message") else str(exc)
    msg = msg.replace(repr(auto), repr(obj.Label))
    return SceneError(f"module {obj.Label}", f"{field}: {msg}" if field else msg)


def _json_default(v):
    tolist = getattr(v, "tolist", None)
    return tolist() if tolist is not None else str(v)


def build_inputs(p, spec):
    """Everything the module builder (``geometry.modules.build_module``) reads: the module's spec (its sizes,
    sockets, the joint's pivot, which follows the motors' D range on the joint and the hinge tilts, the snap
    pins) and the scalar fabrication parameters, with the hinge of the module's joint."""
    from dataclasses import asdict, fields
    fab = {f.name: getattr(p, f.name) for f in fields(p) if f.name != "hinges"}   # not every joint's hinge
    if spec.joint is not None:
        fab["joint_hinge"] = asdict(p.hinges[spec.joint])
    out = {k: getattr(spec, k) for k in ("type", "side", "material", "extruder", "node", "joint", "a", "b",
                                          "values", "sockets", "mu")}
    out["pivot"] = spec.pivot.as_dict() if spec.pivot is not None else None
    out["snap"] = spec.snap.as_dict() if spec.snap is not None else None
    out["fab"] = fab
    return out


def module_build_key(obj, scene, prepared=None):
    """``BuiltFor`` of the module: its fields, and with a scene exactly the builder's inputs (:func:`build_inputs`
    of :func:`prepare_module`), so that the solid is rebuilt when and only when Export would build another one."""
    d = module_to_dict(obj)
    d["_fab"] = fabrication_overrides()
    if scene is not None:
        prepared = prepared or prepare_module(obj, scene)
        if isinstance(prepared, SheetNotBuilt):
            d["_sheet_not_built"] = prepared.message
        else:
            _one, p, spec = prepared
            d["_build"] = build_inputs(p, spec)
    return json.dumps(d, sort_keys=True, default=_json_default)


def build_module_shape(obj, scene, prepared=None):
    """``(solid, source)``: the fabrication package's module in its own frame (sheet from z = 0 to its
    thickness, joint modules with u from the first to the second node), or, without a scene, a stand-in."""
    import Part
    if scene is not None:
        prepared = prepared or prepare_module(obj, scene)
    if scene is not None and not isinstance(prepared, SheetNotBuilt):
        from metamaterial_wb.geometry.build import BuildResult
        from metamaterial_wb.geometry.modules import build_module
        one, p, spec = prepared
        try:
            res = BuildResult(one, p)
            build_module(res, spec)
        except SceneError as exc:
            raise _module_error(obj, exc) from None
        shapes = [res.shapes[part.key] for part in res.parts]
        # Part.Compound, not Part.makeCompound: the latter kills FreeCAD 1.0/1.1 run from plain Python
        return (shapes[0] if len(shapes) == 1 else Part.Compound(shapes)), "geometry.modules"
    cell = scene.cell_size_mm if scene is not None else 20.0
    t = scene.hinge["thickness_mm"] if scene is not None else 7.0
    side = scene.plate_side_mm if scene is not None else plate_side_mm(cell, DEFAULT_HINGE["length_mm"])
    typ = obj.ModuleType
    V = FreeCAD.Vector
    src = "stand-in" if scene is None else "stand-in (the sheet cannot be built; see the Scene's SolveWarnings)"
    if typ == "servo_housing":  # SG90-sized body above the joint
        return Part.makeBox(23.0, 12.5, 22.0, V(-11.5, -6.25, t)), src
    if typ == "friction_pad":  # under the node
        s = 0.7 * side
        return Part.makeBox(s, s, 3.0, V(-s / 2, -s / 2, -3.0)), src
    if typ == "constraint_clip":
        return Part.makeBox(cell, 0.5 * side, 3.0, V(-cell / 2, -0.25 * side, t)), src
    if typ == "stable_hub":
        return Part.makeBox(0.6 * cell, 0.6 * cell, 6.0, V(-0.3 * cell, -0.3 * cell, t)), src
    return Part.makeCylinder(0.3 * side, 3.0, V(0, 0, t)), src


def _built_for_other_preferences(obj):
    """Whether the module ``obj`` holds no valid solid for the current preferences ``MODULE_PREFS``: invalid (its
    error may come from a preference), never built, or built with other preference values (``BuiltFor``)."""
    if not obj.isValid() or not obj.BuiltFor:
        return True
    try:
        return json.loads(obj.BuiltFor).get("_fab") != fabrication_overrides()
    except ValueError:
        return True


def touch_stale_modules():
    """Mark for recompute every module of every open document whose solid is not the one the current preferences
    give (Recompute then rebuilds it, as Export would build it). Returns the touched modules."""
    touched = []
    for doc in FreeCAD.listDocuments().values():
        for o in doc.Objects:
            if getattr(getattr(o, "Proxy", None), "Type", "") == ModuleProxy.Type and hasattr(o, "BuiltFor") \
                    and _built_for_other_preferences(o):
                o.touch()
                touched.append(o)
    return touched


class _PreferenceObserver:
    """Watches the workbench's parameter group (the preferences page's OK, a macro, the parameter editor): a change
    of a preference that shapes the modules' solids touches the stale ones."""

    def onChange(self, grp, name):     # FreeCAD 0.20 - 1.1 call ``onChange(group, name)``
        if name in MODULE_PREFS:
            touch_stale_modules()


_OBSERVER = []   # (group, observer) attached once per session: both kept alive (a group's Python wrapper
#                  detaches its observers when it is freed)


def watch_preferences():
    """Attach the preference observer to the workbench's parameter group (once)."""
    if not _OBSERVER:
        _OBSERVER.append((FreeCAD.ParamGet(PREFS_PATH), _PreferenceObserver()))
        _OBSERVER[0][0].Attach(_OBSERVER[0][1])


watch_preferences()
