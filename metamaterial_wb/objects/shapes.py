"""The shape sources: one rigid node and one flexible hinge (``Part::FeaturePython``), each built once per
set of sizes and shown many times through the ``Nodes`` / ``Hinges`` link arrays."""
import json

import FreeCAD

from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.objects.common import OUTPUT, ProxyBase, attach_proxy, count_execute, ensure_property, tag_proxy


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
        tag_proxy(obj, self)   # files saved before the split name objects.structure (still importable)

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
        s = p["cell_size_mm"] - p["length_mm"]
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
