"""The live preview of the task panels: a Coin overlay that never writes the document.

While a panel previews (Simulate, Animate, Rotary axes, Folded shape), the structure's ``Nodes`` /
``Hinges`` link arrays are hidden in the 3D view (their view provider's display-mode switch, a Coin field,
not the ``Visibility`` property) and ONE Coin group draws every node plate and hinge box instead: per
group an ``SoCoordinate3`` (8 corners per box) and an ``SoIndexedFaceSet`` built once; per frame the
corners are the poses applied to the boxes' half sizes in one matrix product
(``objects.display.box_corners``) and written with one ``point.setValues`` call. The motor markers and
modules follow through their view provider's Coin transform (``setTransformation``), not their
``Placement``.

Nothing of this is a document property, so a preview never marks a document modified and leaves nothing
to undo; OK writes the chosen values and recomputes once (one transaction), Cancel only calls
:meth:`Preview.remove`, which shows the link arrays again and puts the markers back on their placements.
"""
import time

import numpy as np

import FreeCAD
import FreeCADGui

from metamaterial_wb.objects import display

# the six faces of a box, counter-clockwise seen from outside (corner order display.BOX_SIGNS)
BOX_FACES = np.array([[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]])


def face_indices(n):
    """``coordIndex`` of n boxes (8 corners each): 6 quads per box, each closed by -1."""
    idx = (BOX_FACES[None, :, :] + 8 * np.arange(n)[:, None, None]).reshape(-1, 4)
    return np.hstack([idx, -np.ones((len(idx), 1), dtype=int)]).ravel().tolist()


def global_placement(obj):
    """The object's placement in the document's global frame (through its App::Part containers)."""
    pl = FreeCAD.Placement(obj.Placement)
    parent = obj.getParentGeoFeatureGroup() if hasattr(obj, "getParentGeoFeatureGroup") else None
    while parent is not None:
        pl = parent.Placement.multiply(pl)
        parent = parent.getParentGeoFeatureGroup()
    return pl


def _colour(arr, default):
    try:
        c = arr.LinkedObject.ViewObject.ShapeColor
        return tuple(float(x) for x in c[:3])
    except Exception:  # pragma: no cover - no view object
        return default


class _Boxes:
    """One Coin group of boxes: transform (the array's global placement), material, corners, faces."""

    def __init__(self, coin, arr, n, rgb):
        self.root = coin.SoSeparator()
        tr = coin.SoTransform()
        g = global_placement(arr)
        tr.translation.setValue(g.Base.x, g.Base.y, g.Base.z)
        tr.rotation.setValue(*g.Rotation.Q)
        mat = coin.SoMaterial()
        mat.diffuseColor = rgb
        self.coords = coin.SoCoordinate3()
        self.faces = coin.SoIndexedFaceSet()
        self.faces.coordIndex.setValues(0, 30 * n, face_indices(n))
        for node in (tr, mat, self.coords, self.faces):
            self.root.addChild(node)
        self.n = n

    def write(self, corners):
        pts = np.ascontiguousarray(corners.reshape(-1, 3), dtype=np.float32)
        self.coords.point.setValues(0, len(pts), pts)
        if self.coords.point.getNum() != len(pts):    # fewer elements than before (never while dragging)
            self.coords.point.setNum(len(pts))


class Preview:
    """The Coin preview of one structure (see the module doc). ``show(solver, frame)`` per frame."""

    def __init__(self, scene_obj, scene):
        from pivy import coin
        self.coin = coin
        self.obj = scene_obj
        self.view = None
        gd = FreeCADGui.getDocument(scene_obj.Document.Name)
        if gd is not None and hasattr(gd.ActiveView, "getSceneGraph"):
            self.view = gd.ActiveView
        self.root = coin.SoSeparator()
        self.root.setName("MetamaterialPreview")
        hints = coin.SoShapeHints()
        hints.vertexOrdering = coin.SoShapeHints.COUNTERCLOCKWISE
        hints.shapeType = coin.SoShapeHints.SOLID
        self.root.addChild(hints)
        self.groups = {}
        self.hidden = []          # (switch, whichChild before)
        self.moved = []           # view objects whose Coin transform the preview moved
        self.last = None          # (positions, quaternions, hinge positions, hinge quaternions, corners)
        self.frames = 0
        self.timings = {}
        self.set_scene(scene)
        self.active = False

    def set_scene(self, scene):
        """The scene whose hinge sizes the boxes follow (a panel that edits per-joint sizes calls this)."""
        self.node_half, self.hinge_half = display.box_half_sizes(self.obj, scene)

    def _activate(self):
        for arr in display.own_arrays(self.obj):      # a copy of a Scene never hides the original's arrays
            if arr is None:
                continue
            vo = getattr(arr, "ViewObject", None)
            sw = getattr(vo, "SwitchNode", None) if vo is not None else None
            if sw is None:
                continue
            self.hidden.append((sw, sw.whichChild.getValue()))
            sw.whichChild = self.coin.SO_SWITCH_NONE
        if self.view is not None:
            self.view.getSceneGraph().addChild(self.root)
        self.active = True

    def _group(self, key, arr, n):
        g = self.groups.get(key)
        if g is None or g.n != n:
            if g is not None:
                self.root.removeChild(g.root)
            rgb = _colour(arr, (0.80, 0.84, 0.90) if key == "nodes" else (0.95, 0.55, 0.15))
            g = self.groups[key] = _Boxes(self.coin, arr, n, rgb)
            self.root.addChild(g.root)
        return g

    def show(self, solver, frame):
        """Draw one solved frame: corners of every node and hinge box, markers / modules moved.
        ``timings`` (ms): corners (numpy), coin (the two ``setValues``), markers."""
        t0 = time.perf_counter()
        if not self.active:
            self._activate()
        nc = display.box_corners(frame.positions, frame.quaternions, self.node_half,
                                 getattr(frame, "rotations", None))
        hc = display.box_corners(frame.hinge_positions, frame.hinge_quaternions, self.hinge_half) \
            if len(self.hinge_half) == len(frame.hinge_positions) else np.zeros((0, 8, 3))
        t1 = time.perf_counter()
        nodes, hinges = display.own_arrays(self.obj)
        if nodes is not None:
            self._group("nodes", nodes, len(nc)).write(nc)
        if hinges is not None and len(hc):
            self._group("hinges", hinges, len(hc)).write(hc)
        t2 = time.perf_counter()
        doc = self.obj.Document
        for name, pl in display.marker_placements(self.obj, solver, frame).items():
            o = doc.getObject(name)
            vo = getattr(o, "ViewObject", None)
            if vo is not None and hasattr(vo, "setTransformation"):
                vo.setTransformation(pl.toMatrix())
                if o not in self.moved:
                    self.moved.append(o)
        self.last = (frame.positions, frame.quaternions, frame.hinge_positions, frame.hinge_quaternions, nc, hc)
        self.frames += 1
        t3 = time.perf_counter()
        self.timings = {"corners": 1000 * (t1 - t0), "coin": 1000 * (t2 - t1), "markers": 1000 * (t3 - t2)}

    # what is shown (picking, tests) --------------------------------------------------------
    def placements(self, kind):
        """The shown poses of ``"nodes"`` / ``"hinges"`` as ``FreeCAD.Placement`` (in the array's frame,
        as its ``PlacementList`` would be); None before the first frame."""
        if self.last is None:
            return None
        p, q = (self.last[0], self.last[1]) if kind == "nodes" else (self.last[2], self.last[3])
        return display.to_placements(p, q)

    def corners(self, kind):
        """The shown corners (n, 8, 3) in float64 (the array's frame) of ``"nodes"`` / ``"hinges"``."""
        return None if self.last is None else (self.last[4] if kind == "nodes" else self.last[5])

    def coin_points(self, kind):
        """The corners as the Coin node holds them (float32, global frame applied by its transform: read
        back here in the array's frame)."""
        g = self.groups.get(kind)
        if g is None:
            return None
        n = g.coords.point.getNum()
        return np.array([tuple(g.coords.point[i].getValue()) for i in range(n)], dtype=float).reshape(-1, 8, 3)

    def remove(self):
        """Take the preview out: link arrays shown again, markers / modules back on their placements."""
        for sw, which in self.hidden:
            try:
                sw.whichChild = which
            except Exception:  # pragma: no cover - view provider gone
                pass
        self.hidden = []
        for o in self.moved:
            try:
                o.ViewObject.setTransformation(o.Placement.toMatrix())
            except Exception:  # pragma: no cover - object deleted meanwhile
                pass
        self.moved = []
        if self.view is not None and self.active:
            try:
                self.view.getSceneGraph().removeChild(self.root)
            except Exception:  # pragma: no cover - view already gone
                pass
        self.active = False
