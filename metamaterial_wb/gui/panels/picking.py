"""Picking joints and nodes in the 3D view at any hinge size.

A hinge of the default 2 mm sheet covers 0-2 pixels at fit-all, so picking by what lies under the
cursor (FreeCAD's selection) mostly lands on a node corner. The :class:`Picker` instead takes the click
ray (from the camera through the cursor) and picks the joint whose hinge midpoint (the midpoint of its
two node centres, as displayed) lies nearest to that ray, within half a cell pitch; nodes likewise by
their centres. The candidate under the cursor is highlighted (a yellow marker) and named in the panel
before the click; a click picks it and is consumed, so FreeCAD's own selection does not act on it.
A panel that watches both kinds but takes only one (Add module: a node or a joint, by module) says so with
``is_target(kind)``: a candidate of the other kind is still named in the panel (as no target) but not lit.
"""
import numpy as np

import FreeCAD
import FreeCADGui

from metamaterial_wb.gui.preview import global_placement
from metamaterial_wb.objects import structure


def ray_through(view, x, y):
    """``(origin, unit direction)`` (numpy, mm, global) of the ray through view pixel (x, y) (Coin
    coordinates: origin bottom left)."""
    p = view.getPoint(int(x), int(y))
    p = np.array([p.x, p.y, p.z])
    kind = ""
    try:
        kind = view.getCameraType()
    except Exception:  # pragma: no cover
        pass
    if kind == "Perspective":
        cam = np.array(vec_values(view.getCameraNode().position.getValue(), 3), dtype=float)
        d = p - cam
        o = cam
    else:
        v = view.getViewDirection()
        d = np.array([v.x, v.y, v.z])
        o = p - 1e4 * d / max(np.linalg.norm(d), 1e-12)
    return o, d / max(np.linalg.norm(d), 1e-12)


def vec_values(v, n):
    """The ``n`` components of a Coin vector (SbVec2s / SbVec3f) as floats. Indexing works on every
    pivy; ``getValue()`` returns an opaque pointer for SbVec2s on FreeCAD 1.1's pivy (Python 3.14)."""
    try:
        return tuple(float(v[i]) for i in range(n))
    except Exception:  # pragma: no cover - an older pivy without __getitem__
        return tuple(float(c) for c in v.getValue())


def nearest_to_ray(points, origin, direction):
    """Index of the point nearest to the ray and its distance (mm)."""
    rel = np.asarray(points, dtype=float) - origin
    along = rel @ direction
    perp = rel - along[:, None] * direction[None, :]
    dist = np.linalg.norm(perp, axis=1)
    k = int(np.argmin(dist))
    return k, float(dist[k])


class Picker:
    """Hover highlight + click picking of joints (``on_joint(name)``) and nodes (``on_node(name)``)."""

    def __init__(self, scene_obj, on_joint=None, on_node=None, panel=None):
        from pivy import coin
        self.coin = coin
        self.obj = scene_obj
        self.on_joint, self.on_node, self.panel = on_joint, on_node, panel
        self.scene = structure.compose_scene(scene_obj)
        topo = self.scene.topology
        from metamaterial_wb.core.live import joint_node_indices
        self.joint_names = list(topo.joint_names)
        self.joint_nodes = np.array([joint_node_indices(self.scene, n) for n in self.joint_names], dtype=int) \
            if self.joint_names else np.zeros((0, 2), dtype=int)
        self.node_names = [f"N{i},{j}" for i, j in topo.nodes]
        self.reach = 0.5 * float(self.scene.cell_size_mm)
        self.hover = None
        self.picks = []
        gd = FreeCADGui.getDocument(scene_obj.Document.Name)
        self.view = gd.ActiveView if gd is not None else None
        if self.view is None or not hasattr(self.view, "addEventCallbackPivy"):
            raise RuntimeError("no 3D view")
        self.marker = coin.SoSeparator()
        self.marker.setName("MetamaterialPreselection")
        self.switch = coin.SoSwitch()
        self.switch.whichChild = coin.SO_SWITCH_NONE
        mat = coin.SoMaterial()
        mat.diffuseColor = (1.0, 0.85, 0.0)
        mat.emissiveColor = (0.6, 0.5, 0.0)
        self.translation = coin.SoTranslation()
        sphere = coin.SoSphere()
        sphere.radius = 0.15 * float(self.scene.cell_size_mm)
        for n in (mat, self.translation, sphere):
            self.marker.addChild(n)
        self.switch.addChild(self.marker)
        self.view.getSceneGraph().addChild(self.switch)
        self._cbs = [
            (coin.SoLocation2Event.getClassTypeId(),
             self.view.addEventCallbackPivy(coin.SoLocation2Event.getClassTypeId(), self._moved)),
            (coin.SoMouseButtonEvent.getClassTypeId(),
             self.view.addEventCallbackPivy(coin.SoMouseButtonEvent.getClassTypeId(), self._clicked)),
        ]

    # geometry ---------------------------------------------------------------------------
    def node_centres(self):
        """Node centres as shown: the panel's live preview when it draws the structure, else the link
        array's placements."""
        arr = self.obj.NodeArray
        if arr is None:
            return np.zeros((0, 3))
        g = global_placement(arr)
        prev = getattr(self.panel, "live_preview", None)
        shown = prev.placements("nodes") if prev is not None and prev.active else None
        pts = [g.multVec(p.Base) for p in (shown if shown is not None else arr.PlacementList)]
        return np.array([[v.x, v.y, v.z] for v in pts]).reshape(-1, 3)

    def candidates(self):
        """``[(kind, name, point)]`` arrays: joints (hinge midpoints) and / or nodes (centres)."""
        nodes = self.node_centres()
        out = []
        if self.on_joint and len(self.joint_names) and len(nodes) > int(self.joint_nodes.max(initial=0)):
            mids = 0.5 * (nodes[self.joint_nodes[:, 0]] + nodes[self.joint_nodes[:, 1]])
            out += [("joint", n, p) for n, p in zip(self.joint_names, mids)]
        if self.on_node:
            out += [("node", n, p) for n, p in zip(self.node_names, nodes)]
        return out

    def at(self, x, y):
        """The ``(kind, name, point)`` nearest to the ray through Coin pixel (x, y), or None."""
        cands = self.candidates()
        if not cands:
            return None
        o, d = ray_through(self.view, x, y)
        k, dist = nearest_to_ray([c[2] for c in cands], o, d)
        return cands[k] if dist <= self.reach else None

    # events -----------------------------------------------------------------------------
    def is_target(self, kind):
        """Whether a candidate of ``kind`` (``"joint"`` / ``"node"``) is a target now: the panel's
        ``is_target(kind)`` when it has one, else every kind watched."""
        judge = getattr(self.panel, "is_target", None)
        return True if judge is None else bool(judge(kind))

    def refresh(self):
        """Light the candidate under the cursor again after the panel's targets changed (a new module kind)."""
        self._highlight(self.hover)

    def _highlight(self, hit):
        if hit is None or not self.is_target(hit[0]):
            self.switch.whichChild = self.coin.SO_SWITCH_NONE
        else:
            p = hit[2]
            lift = 0.5 * float(self.obj.HingeThickness.Value)
            self.translation.translation.setValue(float(p[0]), float(p[1]), float(p[2]) + lift)
            self.switch.whichChild = 0

    def _moved(self, cb):
        try:
            x, y = vec_values(cb.getEvent().getPosition(), 2)
            hit = self.at(x, y)
            key = None if hit is None else hit[:2]
            if key != (None if self.hover is None else self.hover[:2]):
                self.hover = hit
                self._highlight(hit)
                if hit is not None and self.panel is not None:
                    self.panel.picked(hit[0], hit[1], hover=True)
        except Exception as exc:  # pragma: no cover - interactive
            FreeCAD.Console.PrintWarning(f"Metamaterial picking: {exc}\n")

    def _clicked(self, cb):
        coin = self.coin
        try:
            ev = cb.getEvent()
            if ev.getButton() != coin.SoMouseButtonEvent.BUTTON1:
                return
            x, y = vec_values(ev.getPosition(), 2)
            hit = self.at(x, y)
            if hit is None:
                return
            cb.setHandled()                     # ours: FreeCAD's selection does not see this click
            if ev.getState() != coin.SoButtonEvent.DOWN:
                return
            self.pick(hit[0], hit[1])
        except Exception as exc:  # pragma: no cover - interactive
            FreeCAD.Console.PrintWarning(f"Metamaterial picking: {exc}\n")

    def pick(self, kind, name):
        self.picks.append((kind, name))
        if self.panel is not None:
            self.panel.picked(kind, name)
        if kind == "joint" and self.on_joint:
            self.on_joint(name)
        elif kind == "node" and self.on_node:
            self.on_node(name)

    def remove(self):
        if self.view is None:
            return
        for typ, cb in self._cbs:
            try:
                self.view.removeEventCallbackPivy(typ, cb)
            except Exception:  # pragma: no cover - view closed
                pass
        try:
            self.view.getSceneGraph().removeChild(self.switch)
        except Exception:  # pragma: no cover
            pass
        self.view = None
