"""The shape sources: one rigid node and one flexible hinge (``Part::FeaturePython``), each built once per
set of sizes and shown many times through the ``Nodes`` / ``Hinges`` link arrays."""
import json

import FreeCAD

from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.core.scene.names import plate_side_mm
from metamaterial_wb.objects.common import OUTPUT, ProxyBase, attach_proxy, count_execute, ensure_property, tag_proxy


# the 3D view is simplified (issue 14): said where the user looks, in the tree's Description column (Label2) of
# the shape sources and their link arrays, and in the property editor (the Simplified property's description)
SIMPLIFIED_NOTE = ("Simplified view: stand-in boxes, not the printable B-rep (hinge pockets, per-joint hinge "
                   "tilts and lengths, module sockets); Export builds the printable parts")
SIMPLIFIED_DOC = ("True: the 3D view draws every {what} as the same stand-in box, not the printable B-rep (hinge "
                  "pockets, per-joint hinge tilts and lengths, module sockets). Export (geometry.build) makes the "
                  "printable parts.")


def describe_simplified(shape_source):
    """Write the note into the Description (Label2) of a shape source and of the link arrays showing it."""
    for o in [shape_source] + [o for o in shape_source.InList if o.TypeId == "App::Link"]:
        if not o.Label2:
            o.Label2 = SIMPLIFIED_NOTE


class _ShapeSource(ProxyBase):
    WHAT = "part"

    def __init__(self, obj):
        attach_proxy(obj, self)
        self._ensure_properties(obj)

    def _ensure_properties(self, obj):
        ensure_property(obj, "App::PropertyLink", "Scene", "Base", "The scene whose sizes this shape follows")
        ensure_property(obj, "App::PropertyString", "BuiltFor", "Base", "Parameters of the current shape",
                        attr=OUTPUT, readonly=True, hidden=True)
        ensure_property(obj, "App::PropertyInteger", "BuildCount", "Base", "Shape builds (this session)",
                        attr=OUTPUT | 2, readonly=True, hidden=True)
        ensure_property(obj, "App::PropertyBool", "Simplified", "Display", SIMPLIFIED_DOC.format(what=self.WHAT),
                        True, attr=OUTPUT, readonly=True)

    def onDocumentRestored(self, obj):
        self._ensure_properties(obj)
        tag_proxy(obj, self)   # files saved before the split name objects.structure (still importable)
        describe_simplified(obj)

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
    """One rigid node, drawn as a plate (side x side x t): a stand-in for the printable node of
    ``geometry.build`` (see ``Simplified``)."""
    Type = "MetamaterialNodeShape"
    WHAT = "node"

    def params(self, sc):
        return {"cell_size_mm": sc.CellSize.Value, "length_mm": sc.HingeLength.Value,
                "width_mm": sc.HingeWidth.Value, "thickness_mm": sc.HingeThickness.Value}

    def build(self, p):
        import Part
        s = plate_side_mm(p["cell_size_mm"], p["length_mm"])
        t = p["thickness_mm"]
        return Part.makeBox(s, s, t, FreeCAD.Vector(-s / 2, -s / 2, -t / 2))


class HingeShapeProxy(_ShapeSource):
    """One flexible hinge along x: length x width x thickness, centred (a stand-in, see ``Simplified``)."""
    Type = "MetamaterialHingeShape"
    WHAT = "hinge"

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
