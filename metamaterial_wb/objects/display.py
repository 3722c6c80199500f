"""Placing the display from a solved frame: node / hinge link arrays, markers and modules. Nothing here
recomputes the document; task panels call these while dragging (and restore the placements on close)."""
import FreeCAD
import numpy as np

from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.core.live import quaternions_to_matrices


def to_placements(positions, quaternions):
    """numpy poses -> list of ``FreeCAD.Placement``."""
    # one Matrix per pose: Placement(Matrix) is about 4x cheaper than Placement(Vector, Rotation(q))
    # (Rotation's constructor dominates), and this runs for every element on every live frame
    P = FreeCAD.Placement
    M = FreeCAD.Matrix
    n = len(positions)
    m = np.zeros((n, 4, 4))
    m[:, :3, :3] = quaternions_to_matrices(np.asarray(quaternions, dtype=float))
    m[:, :3, 3] = positions
    m[:, 3, 3] = 1.0
    return [P(M(*row)) for row in m.reshape(n, 16).tolist()]


def _offset_positions(pos, quat, offset):
    R = quaternions_to_matrices(quat)
    return pos + R @ offset


def array_owner(obj, arr):
    """The Scene object that ``arr`` (the Scene ``obj``'s NodeArray or HingeArray) shows, when it is not ``obj``.

    A link array shows a shape source (``NodeShape`` / ``HingeShape``) whose ``Scene`` link names the Scene it
    belongs to. A copy of the Scene alone (``doc.copyObject(scene, True)``) copies the markers and modules it
    links, but not the hidden-linked arrays: its NodeArray / HingeArray still are the original's. Returns None
    for the Scene's own arrays (and for an array without that back-reference).
    """
    src = getattr(arr, "LinkedObject", None) if arr is not None else None
    if src is None or "Scene" not in getattr(src, "PropertiesList", ()):
        return None
    owner = src.Scene
    if owner is None or getattr(getattr(owner, "Proxy", None), "Type", "") != "MetamaterialScene":
        return None
    if owner.Document.Name == obj.Document.Name and owner.Name == obj.Name:
        return None
    return owner


def own_arrays(obj):
    """``(nodes, hinges)``: the Scene's link arrays, None for a missing one or one of another Scene (a copy of a
    Scene never writes into the original's display: :func:`array_owner`)."""
    return tuple(a if array_owner(obj, a) is None else None for a in (obj.NodeArray, obj.HingeArray))


def check_own_arrays(obj):
    """Raise a SceneError naming the Scene when its arrays belong to another Scene (:func:`array_owner`)."""
    for arr in (obj.NodeArray, obj.HingeArray):
        owner = array_owner(obj, arr)
        if owner is not None:
            part = next((p for p in owner.InList if p.TypeId == "App::Part"), None)
            where = f"the whole Metamaterial part ({part.Label!r})" if part is not None else \
                "the whole Metamaterial part"
            raise SceneError(obj.Label, f"its display array {arr.Label!r} belongs to the Scene {owner.Label!r}: a "
                                        f"copy of a Scene alone shares the original's node and hinge arrays and "
                                        f"would move them; copy {where} instead, and delete this copy")


def apply_frame(obj, solver, frame, purge=True):
    """Write node / hinge / marker / module placements for a solved frame. Nothing is recomputed."""
    nodes, hinges = own_arrays(obj)
    if nodes is not None:
        pl = to_placements(frame.positions, frame.quaternions)
        if nodes.ElementCount != len(pl):
            nodes.ElementCount = len(pl)
        nodes.PlacementList = pl
        if purge:
            nodes.purgeTouched()
    if hinges is not None:
        pl = to_placements(frame.hinge_positions, frame.hinge_quaternions)
        if hinges.ElementCount != len(pl):
            hinges.ElementCount = len(pl)
        hinges.PlacementList = pl
        if purge:
            hinges.purgeTouched()
    place_markers(obj, solver, frame, purge)


def hinge_scales(scene, joint_names):
    """Per-element ``(sx, sy, sz)`` of the hinge link array: each joint's :meth:`Scene.hinge_sizes` over the
    scene-wide sizes the one ``HingeShape`` is built with (``HingeShapeProxy.build``: x = length + 2 width,
    y = width, z = thickness, in the element's local frame)."""
    g = scene.hinge
    base = (g["length_mm"] + 2 * g["width_mm"], g["width_mm"], g["thickness_mm"])
    out = []
    for name in joint_names:
        h = scene.hinge_sizes(name)
        out.append((float((h["length_mm"] + 2 * h["width_mm"]) / base[0]), float(h["width_mm"] / base[1]),
                    float(h["thickness_mm"] / base[2])))
    return out


def apply_hinge_scales(obj, scene, purge=True):
    """Write the hinge array's ``ScaleList`` from the per-joint hinge sizes (on recompute, not per live frame:
    sizes do not change while dragging). Written only when it differs, so an unchanged scene costs nothing."""
    hinges = own_arrays(obj)[1]
    if hinges is None or not hasattr(hinges, "ScaleList"):
        return
    scales = hinge_scales(scene, scene.topology.joint_names)
    if hinges.ElementCount != len(scales):
        hinges.ElementCount = len(scales)
    cur = [tuple(v) for v in hinges.ScaleList]
    if len(cur) == len(scales) and all(abs(a - b) < 1e-12 for u, v in zip(cur, scales) for a, b in zip(u, v)):
        return
    hinges.ScaleList = [FreeCAD.Vector(*v) for v in scales]
    if purge:
        hinges.purgeTouched()


def marker_placements(obj, solver, frame):
    """``{object name: Placement}`` of the markers and modules for a frame."""
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
        out[it.Name] = to_placements(pos[None, :], np.asarray([q]))[0]
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
    for arr in own_arrays(obj):
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


# ---- the GUI's coin-level preview (gui/preview.py) -------------------------------------------
# Corner bits of a box: index = ix + 2 iy + 4 iz, coordinate sign -1 / +1 per bit.
BOX_SIGNS = np.array([[(-1.0, 1.0)[(k >> b) & 1] for b in range(3)] for k in range(8)])


def box_half_sizes(obj, scene):
    """``(node (3,), hinges (m, 3))`` half sizes (mm) of the boxes the link arrays show: the node plate of
    ``NodeShapeProxy`` and the hinge of ``HingeShapeProxy`` times its ``ScaleList`` entry (``hinge_scales``),
    from the same properties, so the preview draws what the document draws."""
    from metamaterial_wb.core.scene.names import plate_side_mm
    t = float(obj.HingeThickness.Value)
    s = plate_side_mm(float(obj.CellSize.Value), float(obj.HingeLength.Value))
    node = 0.5 * np.array([s, s, t])
    base = 0.5 * np.array([float(obj.HingeLength.Value) + 2 * float(obj.HingeWidth.Value),
                           float(obj.HingeWidth.Value), t])
    scales = np.asarray(hinge_scales(scene, scene.topology.joint_names), dtype=float).reshape(-1, 3)
    return node, base[None, :] * scales


def box_corners(positions, quaternions, half, rotations=None):
    """(n, 8, 3) corners of n boxes: centre ``positions`` (n, 3), orientation ``quaternions`` (n, 4) (or the
    (n, 3, 3) ``rotations`` when known), half sizes ``half`` (3,) or (n, 3); corner order ``BOX_SIGNS``.
    The half axes (rotation columns times half sizes) of all boxes times the eight sign patterns are one
    matrix product."""
    R = quaternions_to_matrices(np.asarray(quaternions, dtype=float)) if rotations is None else \
        np.asarray(rotations, dtype=float).reshape(-1, 3, 3)
    n = len(R)
    axes = R * np.asarray(half, dtype=float).reshape(-1, 1, 3)          # column j: half axis j of each box
    c = (axes.reshape(3 * n, 3) @ BOX_SIGNS.T).reshape(n, 3, 8).transpose(0, 2, 1)
    return c + np.asarray(positions, dtype=float)[:, None, :]
