"""Making the document objects that mirror a :class:`~metamaterial_wb.core.scene.Scene` (the FreeCAD
Draft / FEM way: one document-object family per file, the make functions here).

Document tree made by :func:`make_structure` (all inside one ``App::Part``)::

    Metamaterial (App::Part)
      Scene        App::FeaturePython  full scene JSON (SceneJSON) + typed properties; solves
      NodeShape    Part::FeaturePython one rigid node (built once, cached by its parameters)
      HingeShape   Part::FeaturePython one flexible hinge
      Nodes        App::Link array of NodeShape, one element per node (PlacementList)
      Hinges       App::Link array of HingeShape, one element per joint (ScaleList: per-joint hinge sizes)
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

Files: ``scene.py`` (SceneProxy, composing and solving), ``shapes.py`` (NodeShapeProxy, HingeShapeProxy),
``item.py`` (ItemProxy), ``module.py`` (ModuleProxy), ``display.py`` (placing a solved frame);
``structure.py`` re-exports them under their old names, so documents saved before the split (their
proxies stored as ``metamaterial_wb.objects.structure.SceneProxy`` ...) still open.
"""
import json

import FreeCAD

from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.core.scene import Scene
from metamaterial_wb.objects.common import attach_view_provider
from metamaterial_wb.objects.item import ItemProxy
from metamaterial_wb.objects.module import MODULE_ALIASES, MODULE_TYPES, ModuleProxy
from metamaterial_wb.objects.scene import SceneProxy, load_typed_properties
from metamaterial_wb.objects.shapes import HingeShapeProxy, NodeShapeProxy, describe_simplified


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
    for src in (ns, hs):
        describe_simplified(src)
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
