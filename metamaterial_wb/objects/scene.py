"""The Scene document object (``App::FeaturePython``): the scene JSON, its typed properties, and the solve.

``SceneProxy.execute`` composes the :class:`~metamaterial_wb.core.scene.Scene` from its typed properties,
markers (``objects/item.py``) and modules (``objects/module.py``), solves it with a cached
:class:`~metamaterial_wb.core.live.LiveSolver` and places the display (``objects/display.py``).
The document tree and its dependencies are described in ``objects/make.py``.
"""
import json

from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.core.live import LiveSolver
from metamaterial_wb.core.scene import DEFAULT_HINGE, Scene
from metamaterial_wb.objects.common import (OUTPUT, ProxyBase, attach_proxy, count_execute, ensure_property,
                                            ensure_range, json_property, tag_proxy)
from metamaterial_wb.objects.display import apply_frame, apply_hinge_scales, check_own_arrays
from metamaterial_wb.objects.item import VALUE_RANGE, item_to_dict
from metamaterial_wb.objects.module import module_to_dict, run_by_scene, sheet_error

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
                        "Global deformation g in [-1, 1]", (0.0,) + VALUE_RANGE)
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
        ensure_range(obj, "GlobalDeformation", *VALUE_RANGE)   # FreeCAD does not save the limits
        tag_proxy(obj, self)   # files saved before the split name objects.structure (still importable)
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
        check_own_arrays(obj)      # a copy of this Scene alone must not move the original's nodes and hinges
        scene = compose_scene(obj)
        from metamaterial_wb.objects.design_adapter import ensure_configured
        # configures axes without (or with a stale) joint configuration; the design check's warnings every time
        design_warnings = ensure_configured(scene)
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
        failed = []     # (label, error) of the modules that stay invalid
        for m in obj.Modules:
            if getattr(getattr(m, "Proxy", None), "Type", "") != "MetamaterialModule":
                continue
            error = None
            try:
                if m.isValid():
                    if m.Proxy.refresh(m, scene):
                        m.purgeTouched()
                    continue
            except SceneError as exc:
                error = str(exc)
            # FreeCAD keeps an object's error state until it runs the object itself: run the module, so that it is
            # marked invalid with its own message (not left showing its old solid as valid), or cleared once it
            # builds again; a module that stays invalid is listed here (whether it failed now or at its own run)
            with run_by_scene(m):
                m.recompute()
            if not m.isValid():
                failed.append((m.Label, error or m.getStatusString()))
        module_warnings = modules_failed(failed)
        stand_ins = [m.Label for m in obj.Modules if getattr(m, "GeometrySource", "").startswith("stand-in (")]
        if stand_ins:      # the sheet itself cannot be built: say why once (not every module's fault)
            module_warnings.append(f"modules {', '.join(stand_ins)} show stand-ins: Export refuses the sheet itself: "
                                   f"{sheet_error(scene)}")
        obj.SolveWarnings = list(design_warnings) + list(solver.warnings) + module_warnings
        apply_frame(obj, solver, frame, purge=True)
        apply_hinge_scales(obj, scene, purge=True)


    def scene(self, obj):
        """The composed :class:`Scene` of ``obj`` (what modules ask their hidden-linked Scene for)."""
        return compose_scene(obj)


def modules_failed(failed, shown=6):
    """SolveWarnings lines of the failed modules ``failed`` ((label, error) pairs, an error naming its module as
    ``module <label>: ...``): one line per cause, so that a cause several modules share (the snap-fit clearance
    preference at or above the socket lip: every module) is said once, with how many modules and which (the first
    ``shown``); a module failing for its own reason keeps its own line."""
    causes = {}     # cause -> [(label, error)], in the modules' order
    for label, text in failed:
        own = f"module {label}: "
        causes.setdefault(text[len(own):] if text.startswith(own) else text, []).append((label, text))
    lines = []
    for cause, mods in causes.items():
        if len(mods) == 1:
            lines.append(mods[0][1])
            continue
        labels = [label for label, _ in mods]
        names = ", ".join(labels[:shown]) + (f" and {len(labels) - shown} more" if len(labels) > shown else "")
        lines.append(f"{len(labels)} modules ({names}): {cause}")
    return lines


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
    data = json_property(obj, "SceneJSON", "the scene as a JSON object (docs/scene-format.md)") or {
        "format": "metamaterial-scene", "version": 1, "layout": {"grid": [1, 1]}}
    if obj.SceneName:
        data["name"] = obj.SceneName
    data["cell_size_mm"] = float(obj.CellSize.Value)
    data["hinge"] = {"length_mm": float(obj.HingeLength.Value), "width_mm": float(obj.HingeWidth.Value),
                     "thickness_mm": float(obj.HingeThickness.Value)}
    rows = [str(r) for r in obj.Layout]
    if not rows and (obj.SceneJSON or "").strip():
        raise SceneError("Layout", f"empty (object {obj.Label}); give at least one row with a cell, e.g. ['###']")
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
    s = LiveSolver(scene, model=model)
    _SOLVERS[key] = (text, model, s)
    return s


def set_scene_fields(obj, **fields):
    """Change top-level fields of SceneJSON (axes, joint_config, joints, ...); ``None`` removes one. Fields equal
    to the stored ones write nothing (``common.assign``)."""
    data = json_property(obj, "SceneJSON", "the scene as a JSON object (docs/scene-format.md)")
    old = dict(data)
    for k, v in fields.items():
        if v is None:
            data.pop(k, None)
        else:
            data[k] = v
    if data == old:
        return
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



def scene_json(scene_obj):
    """The composed scene (typed properties + markers + modules) as JSON text."""
    return compose_scene(scene_obj).to_json()
