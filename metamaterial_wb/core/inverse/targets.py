"""Targets of the inverse design: node positions / poses, target fold angles, target surfaces.

A target file (JSON, ``docs/inverse.md``) is one frame or a sequence of keyframes::

    {"format": "metamaterial-target", "version": 1,
     "align": "rigid",                       # none | rigid | similarity (nodes and surfaces)
     "nodes": [{"name": "N0,3", "position_mm": [x, y, z], "rotation": [[...]] (optional),
                "weight": 1}],
     "rotation_weight_mm": 0,                # mm of error per radian of rotation error (0: ignore)
     "folds": [{"joint": "H0,1", "fold_deg": 30}, {"axis": "tail", "fold_deg": -40}],
     "fold_weight_mm_per_deg": 1,
     "surface": {"file": "cylinder.stl", "nodes": ["N0,0", ...] (optional: all nodes)},
     "keyframes": [{"time_s": 0, ...frame fields...}, ...], "period_s": 4 (optional)}

A ``solve`` result file (``"format": "metamaterial-result"``) is accepted as it is (its nodes'
positions are the target): a full JSON result, the JSON half of a ``solve --npz`` result (its arrays are read
from the ``.npz`` beside it, ``core.resultfile.read_result``) or that ``.npz`` itself; it needs the node poses
(not ``--fields D`` / ``joints`` alone), a converged solve and the scene's sheet: its ``cell_size_mm`` (with its
node names: the rest positions) must be the scene's (a result without it, from an older version, is read with a
warning in ``Target.info["warnings"]``). A bare ``.stl`` / ``.obj`` path is a surface
target of every node.
Every check raises :class:`TargetError` naming the field, the value and what is allowed.
"""
import os
from dataclasses import dataclass, field

import numpy as np

from metamaterial_wb.core.errors import SceneError, check_integer, check_number
from metamaterial_wb.core.inverse.search import joints_text
from metamaterial_wb.core.inverse.surface import Surface, TargetError, check_mesh, load_mesh
from metamaterial_wb.core.scene import parse_joint
from metamaterial_wb.core.scene.names import _short

FORMAT = "metamaterial-target"
COORD_MAX_MM = 10 ** 6          # target coordinates (positions, surface vertices) within [-1e6, 1e6] mm (1 km)
WEIGHT_MAX = 10 ** 6            # node weights in [0, 1e6]; rotation_weight_mm in [0, 1e6]; fold weight in (0, 1e6]
TIME_MAX_S = 10 ** 6            # keyframe times in [0, 1e6] s; period_s up to 1e6 s
_NODE_KEYS = {"name", "i", "j", "position_mm", "rotation", "weight"}
_RESULT_NODE_KEYS = {"D", "rotation_deg"}    # a solve result's node output fields: accepted, not used
_FOLD_KEYS = {"joint", "axis", "fold_deg"}
_SURFACE_KEYS = {"file", "triangles", "nodes"}
_SHARED_KEYS = ("align", "rotation_weight_mm", "fold_weight_mm_per_deg")
_TOP_KEYS = {"format", "version", "description"}
ALIGN_MODES = ("none", "rigid", "similarity")
_FRAME_KEYS = {"nodes", "folds", "surface", "align", "rotation_weight_mm", "fold_weight_mm_per_deg", "time_s",
               "name"}


@dataclass
class NodeTerm:
    idx: np.ndarray                    # (p,) node indices
    pos: np.ndarray                    # (p, 3) mm
    weight: np.ndarray                 # (p,)
    rot: np.ndarray = None             # (p, 3, 3) or None
    rot_weight_mm: float = 0.0


@dataclass
class FoldTerm:
    A: np.ndarray                      # (q, m) averaging matrix over joints (one row per target)
    joints: np.ndarray                 # joint indices used by any row
    target_deg: np.ndarray             # (q,)
    labels: list
    weight_mm_per_deg: float = 1.0


@dataclass
class SurfaceTerm:
    surface: Surface
    idx: np.ndarray
    source: str = ""


@dataclass
class Frame:
    """One target shape (a keyframe)."""
    time_s: float = 0.0
    nodes: NodeTerm = None
    folds: FoldTerm = None
    surface: SurfaceTerm = None
    align: str = "rigid"
    name: str = ""

    @property
    def has_positions(self):
        return self.nodes is not None or self.surface is not None


@dataclass
class Target:
    frames: list
    period_s: float = None
    source: str = ""
    info: dict = field(default_factory=dict)


def _num(v, where, low=None, high=None, unit="", low_open=False, high_open=False):
    """``v`` as a float, or a TargetError at ``where`` naming the value and the allowed range
    (``core.errors.check_number``'s wording; a boolean is not a number)."""
    try:
        return check_number(where, v, low, high, unit, low_open, high_open)
    except SceneError as exc:
        raise TargetError(where, exc.message) from None


def _keys(d, allowed, where):
    """Refuse a key of the object ``d`` that is not in ``allowed`` (a misspelt key is not ignored)."""
    unknown = sorted(str(k) for k in d if k not in allowed)
    if unknown:
        raise TargetError(f"{where}.{unknown[0]}" if where else unknown[0],
                          f"unknown field; allowed: {', '.join(sorted(allowed))}")


def _point(p, where):
    """``[x, y, z]`` (mm, each within ``COORD_RANGE_MM``) as a list of floats."""
    if not isinstance(p, (list, tuple)) or len(p) != 3:
        raise TargetError(where, f"expected [x, y, z] in mm, got {_short(p)}")
    return [_num(x, f"{where}[{k}]", -COORD_MAX_MM, COORD_MAX_MM, "mm") for k, x in enumerate(p)]


def _node_index(scene, name, where):
    topo = scene.topology
    if isinstance(name, str) and name.startswith("N") and "," in name:
        try:
            i, j = (int(x) for x in name[1:].split(","))
        except ValueError:
            i = j = None
    elif isinstance(name, (list, tuple)) and len(name) == 2:
        i, j = name
    else:
        i = j = None
    ok = all(isinstance(x, int) and not isinstance(x, bool) and abs(x) < 2 ** 31 for x in (i, j))
    k = topo.node_id(i, j) if ok else -1
    if k < 0:
        ij = topo.node_ij()
        raise TargetError(where, f"node {name!r} does not exist in this scene ({topo.n_nodes} nodes, "
                                 f"N{ij[:, 0].min()},{ij[:, 1].min()} .. N{ij[:, 0].max()},{ij[:, 1].max()})")
    return int(k)


def _parse_nodes(scene, items, rw, where, rw_field):
    if not isinstance(items, list) or not items:
        raise TargetError(where, "expected a non-empty list of nodes with position_mm")
    idx, pos, w, rot = [], [], [], []
    seen = {}
    plain_rot = []                     # nodes whose rotation is not a copied solve result's (with rotation_deg)
    for k, it in enumerate(items):
        f = f"{where}[{k}]"
        if not isinstance(it, dict):
            raise TargetError(f, f"expected an object with name and position_mm, got {_short(it)}")
        _keys(it, _NODE_KEYS | _RESULT_NODE_KEYS, f)
        if ("i" in it) != ("j" in it):
            raise TargetError(f"{f}.{'j' if 'i' in it else 'i'}", "missing: give both \"i\" (row) and \"j\" (column)")
        if "i" in it:
            ij = scene.topology.node_ij()
            for c, key in enumerate("ij"):
                try:
                    check_integer(f"{f}.{key}", it[key], int(ij[:, c].min()), int(ij[:, c].max()),
                                  "the node's row" if key == "i" else "the node's column")
                except SceneError as exc:
                    raise TargetError(exc.field, exc.message) from None
        name = it.get("name", [it.get("i"), it.get("j")] if "i" in it else None)
        n = _node_index(scene, name, f"{f}.name")
        if "name" in it and "i" in it and _node_index(scene, [it["i"], it["j"]], f"{f}.i") != n:
            raise TargetError(f"{f}.i", f"i = {it['i']}, j = {it['j']} is another node than name {name!r}; allowed: "
                                        f"the same node (or only one of the two)")
        if n in seen:
            raise TargetError(f"{f}.name", f"node {name!r} is already given by {seen[n]}")
        seen[n] = f
        pos.append(_point(it.get("position_mm"), f"{f}.position_mm"))
        w.append(_num(it.get("weight", 1.0), f"{f}.weight", 0, WEIGHT_MAX))
        r = it.get("rotation")
        if r is not None:
            rot.append(_rotation(r, f"{f}.rotation"))
            if "rotation_deg" not in it:
                plain_rot.append(f"{f}.rotation")
        idx.append(n)
    if sum(w) <= 0:
        raise TargetError(where, "every node has weight 0: nothing to fit")
    R = None
    if rw > 0:
        if len(rot) != len(idx):
            raise TargetError(rw_field, f"{rw} > 0 needs a rotation for every target node "
                                        f"({len(rot)} of {len(idx)} have one)")
        R = np.array(rot)
    elif plain_rot:
        # a node copied from a solve result's nodes list (it carries rotation_deg) is read as it is: its rotation
        # came with it and is not used at weight 0 (docs/inverse.md); a rotation written on purpose is not ignored
        raise TargetError(rw_field, f"rotations given but rotation_weight_mm is 0: they would be ignored "
                                    f"({len(plain_rot)} of {len(idx)} target nodes have one, first "
                                    f"{plain_rot[0]}); allowed: a weight in (0, {WEIGHT_MAX}] mm per radian, "
                                    f"or drop rotation")
    return NodeTerm(np.array(idx), np.array(pos), np.array(w), R, rw)


def _rotation(r, where):
    """A 3 x 3 proper rotation matrix (a list of three rows of three numbers, orthonormal, det +1)."""
    if not isinstance(r, (list, tuple)) or len(r) != 3 or \
            not all(isinstance(row, (list, tuple)) and len(row) == 3 for row in r):
        raise TargetError(where, f"expected a 3 x 3 rotation matrix (three rows of three numbers), got {_short(r)}")
    Rm = np.array([[_num(x, f"{where}[{a}][{b}]", -1.0 - 1e-6, 1.0 + 1e-6) for b, x in enumerate(row)]
                   for a, row in enumerate(r)])
    if np.abs(Rm.T @ Rm - np.eye(3)).max() > 1e-6 or np.linalg.det(Rm) < 0:
        raise TargetError(where, "expected a 3 x 3 proper rotation matrix (orthonormal rows, determinant +1)")
    return Rm


def fold_ranges_deg(scene):
    """Reachable fold range (deg) of every joint over D in [-1, 1] (kinematic model): ``(lo, hi)``."""
    from metamaterial_wb.core import kinematics as kin
    from metamaterial_wb.core.design import joint_tilts_rad
    tilt = joint_tilts_rad(scene)
    closing, opening = kin.rotation_limits(scene, tilt)
    par = kin.joint_parity(scene)
    vals = []
    for phi in (closing, -opening):
        vals.append(np.degrees(kin.fold_from_tilt(tilt, par * phi)))
    vals = np.array(vals)
    return vals.min(axis=0) + 0.0, vals.max(axis=0) + 0.0       # + 0.0: an untilted joint's range is [0, 0], not -0


def _g(x):
    """``x`` printed with 4 significant digits, never as a negative zero (a -0.0, or a tiny negative that rounds
    to 0, reads 0)."""
    text = f"{float(x):.4g}"
    return text[1:] if text.startswith("-") and float(text) == 0 else text


def _parse_folds(scene, items, wf, where):
    from metamaterial_wb.core import design
    if not isinstance(items, list) or not items:
        raise TargetError(where, "expected a non-empty list of {\"joint\" or \"axis\", \"fold_deg\"}")
    topo = scene.topology
    lo, hi = fold_ranges_deg(scene)
    plans = None
    rows, target, labels = [], [], []
    for k, it in enumerate(items):
        f = f"{where}[{k}]"
        if isinstance(it, dict):
            _keys(it, _FOLD_KEYS, f)
        if not isinstance(it, dict) or "fold_deg" not in it or ("joint" in it) == ("axis" in it):
            raise TargetError(f, f"expected {{\"joint\": \"H0,1\", \"fold_deg\": 30}} or {{\"axis\": NAME, "
                                 f"\"fold_deg\": 30}}, got {_short(it)}")
        val = _num(it["fold_deg"], f"{f}.fold_deg")
        row = np.zeros(topo.n_joints)
        if "joint" in it:
            try:
                kind, i, j = parse_joint(it["joint"], f"{f}.joint")
            except Exception as exc:
                raise TargetError(f"{f}.joint", str(exc)) from None
            jid = topo.joint_id(kind, i, j)
            if jid < 0:
                raise TargetError(f"{f}.joint", f"joint {it['joint']!r} does not exist in this scene "
                                                f"({joints_text(topo)})")
            row[jid] = 1.0
            label = str(it["joint"])
            rlo, rhi = lo[jid], hi[jid]
        else:
            plans = design.plan_axes(scene) if plans is None else plans
            names = {p.label_name: p for p in plans}
            names.update({str(p.index): p for p in plans})
            p = names.get(str(it["axis"]))
            if p is None:
                raise TargetError(f"{f}.axis", f"{it['axis']!r} is not an axis of the scene; it has "
                                               f"{sorted(q.label_name for q in plans) or 'none'}")
            js = np.asarray(p.joints, dtype=np.int64)
            row[js] = 1.0 / len(js)
            label = f"axis {p.label_name}"
            rlo, rhi = float(np.mean(lo[js])) + 0.0, float(np.mean(hi[js])) + 0.0
        if not (rlo - 1e-9 <= val <= rhi + 1e-9):
            raise TargetError(f"{f}.fold_deg", f"{val!r} deg at {label} is unreachable: the reachable range of "
                                               f"the scene's hinges is [{_g(rlo)}, {_g(rhi)}] deg "
                                               f"(tilt and rotation limits; docs/kinematics.md)")
        rows.append(row)
        target.append(val)
        labels.append(label)
    A = np.array(rows)
    return FoldTerm(A, np.flatnonzero(np.any(A != 0, axis=0)), np.array(target), labels, wf)


def _sheet_bbox(scene):
    from metamaterial_wb.core.kinematics import flat_positions_mm
    p = flat_positions_mm(scene)
    h = 0.5 * scene.cell_size_mm
    return p.min(axis=0) - h, p.max(axis=0) + h


def _parse_surface(scene, spec, base_dir, where, mesh_loader=None, check_scale=True):
    if isinstance(spec, str):
        spec = {"file": spec}
    if isinstance(spec, dict):
        _keys(spec, _SURFACE_KEYS, where)
    if not isinstance(spec, dict) or ("file" in spec) == ("triangles" in spec):
        raise TargetError(where, f"expected {{\"file\": \"shape.stl\"}} or {{\"triangles\": [[[x, y, z] x 3], ...]}} "
                                 f"(one of the two), got {_short(spec)}")
    if "triangles" in spec:
        tri, src = check_mesh(_triangles(spec["triangles"], f"{where}.triangles"), f"{where}.triangles"), "triangles"
    else:
        path = spec["file"]
        if not isinstance(path, str) or not path:
            raise TargetError(f"{where}.file", f"expected a file name, got {_short(path)}")
        if not os.path.isabs(path):
            path = os.path.join(base_dir or ".", path)
        if not os.path.exists(path):
            raise TargetError(f"{where}.file", f"{path!r} does not exist")
        tri = (mesh_loader or load_mesh)(path)
        src = path
    surf = Surface(tri)
    names = spec.get("nodes")
    if names is not None and not isinstance(names, list):
        raise TargetError(f"{where}.nodes", f"expected a list of node names, got {_short(names)}")
    if names is None:
        idx = np.arange(scene.topology.n_nodes)
    else:
        seen = {}
        for k, nm in enumerate(names):
            n = _node_index(scene, nm, f"{where}.nodes[{k}]")
            if n in seen:                                  # the words of a repeated nodes[] entry
                raise TargetError(f"{where}.nodes[{k}]", f"node {nm!r} is already given by {seen[n]}")
            seen[n] = f"{where}.nodes[{k}]"
        idx = np.array(list(seen), dtype=np.int64)
    if idx.size == 0:
        raise TargetError(f"{where}.nodes", "empty: no node to match to the surface")
    slo, shi = surf.bbox
    if check_scale:
        _check_surface_units(scene, idx, slo, shi, src, where)
    lo, hi = _sheet_bbox(scene)
    gap = float(np.linalg.norm(np.maximum(0.0, np.maximum(slo - hi, lo - shi))))
    diag = float(np.linalg.norm(hi - lo))
    if gap > 0.5 * diag:
        raise TargetError(where, f"the surface {src!r} is {gap:.1f} mm from the flat sheet (bounding boxes); allowed: "
                                 f"at most half the sheet's diagonal ({0.5 * diag:.1f} mm): place the surface over the "
                                 f"sheet (a surface that far is taken for a mistake: another file, or units other than "
                                 f"mm)")
    return SurfaceTerm(surf, idx, src)


NODE_SCALE_RANGE = (0.2, 5.0)   # target / flat distance of neighbouring nodes (cells do not stretch; about 0.9-1.4)
SURFACE_SCALE_RANGE = (0.05, 200.0)   # surface / flat extent of its nodes (bounding-box diagonals; metres give 0.001)


def _check_surface_units(scene, idx, slo, shi, src, where):
    """Refuse a surface in other units than mm, as node positions are (``_check_node_units``): the diagonal of the
    surface's bounding box against that of the flat plates of the nodes matched to it (``idx``) must be within
    ``SURFACE_SCALE_RANGE``. A folding sheet can wrap a surface smaller than its flat self (a strip rolled on a
    rod) and lie on a far larger one (a floor), hence a wider range than the nodes'; metres give 0.001, inches
    0.04, micrometres 1000."""
    from metamaterial_wb.core.kinematics import flat_positions_mm
    p = flat_positions_mm(scene)[np.asarray(idx, dtype=np.int64)]
    h = 0.5 * scene.cell_size_mm
    d_nodes = float(np.linalg.norm((p.max(axis=0) + h) - (p.min(axis=0) - h)))
    d_surf = float(np.linalg.norm(np.asarray(shi, dtype=float) - np.asarray(slo, dtype=float)))
    if not d_nodes > 0:
        return
    ratio = d_surf / d_nodes
    lo, hi = SURFACE_SCALE_RANGE
    if not lo <= ratio <= hi:
        raise TargetError(where, f"the surface {src!r} is {_g(d_surf)} mm across (bounding-box diagonal): "
                                 f"{ratio:.3g} times the {idx.size} sheet node(s) matched to it ({_g(d_nodes)} mm "
                                 f"across on the flat sheet, plates included); allowed: {lo:g} to {hi:g} times: "
                                 f"give the surface in mm (metres? give mm: scale the file by 1000; a surface "
                                 f"that small or large is taken for a mistake: units other than mm), or align: "
                                 f"similarity to fit the scale")


def _check_node_units(scene, nodes, where):
    """Refuse node positions in other units than mm, as a surface far from the sheet is refused: the median
    distance of the target's neighbouring nodes (two nodes of one joint) against theirs on the flat sheet must be
    within ``NODE_SCALE_RANGE`` (the cells are rigid plates: a bending or opening sheet keeps it near 1; metres
    give 0.001). Not checked when the target has no two neighbouring nodes."""
    from metamaterial_wb.core.kinematics import flat_positions_mm
    pairs = np.asarray(scene.topology.joint_pairs, dtype=np.int64).reshape(-1, 2)
    at = {int(n): k for k, n in enumerate(nodes.idx)}
    both = [(at[int(a)], at[int(b)], int(a), int(b)) for a, b in pairs if int(a) in at and int(b) in at]
    if not both:
        return
    k = np.array(both, dtype=np.int64)
    flat = flat_positions_mm(scene)
    d_flat = np.linalg.norm(flat[k[:, 2]] - flat[k[:, 3]], axis=1)
    d_tgt = np.linalg.norm(nodes.pos[k[:, 0]] - nodes.pos[k[:, 1]], axis=1)
    ok = d_flat > 0
    if not np.any(ok):
        return
    ratio = float(np.median(d_tgt[ok] / d_flat[ok]))
    lo, hi = NODE_SCALE_RANGE
    if not lo <= ratio <= hi:
        raise TargetError(where, f"neighbouring target nodes are {_g(float(np.median(d_tgt[ok])))} mm apart "
                                 f"(median of {int(ok.sum())} pairs), {ratio:.3g} times their distance on the flat "
                                 f"sheet ({_g(float(np.median(d_flat[ok])))} mm); allowed: {lo:g} to {hi:g} times "
                                 f"(the cells do not stretch): give position_mm in mm (a target that small or large "
                                 f"is taken for a mistake: units other than mm, e.g. metres), or align: similarity "
                                 f"to fit the scale")


def _triangles(items, where):
    """``(t, 3, 3)`` triangles of a ``surface.triangles`` list: each three ``[x, y, z]`` points in mm."""
    if not isinstance(items, list) or not items:
        raise TargetError(where, f"expected a non-empty list of triangles [[x, y, z], [x, y, z], [x, y, z]] (mm), "
                                 f"got {_short(items)}")
    out = []
    for k, t in enumerate(items):
        if not isinstance(t, (list, tuple)) or len(t) != 3:
            raise TargetError(f"{where}[{k}]", f"expected a triangle: three points [x, y, z] (mm), got {_short(t)}")
        out.append([_point(q, f"{where}[{k}][{c}]") for c, q in enumerate(t)])
    return np.array(out, dtype=float)


def _align(value, field):
    """``value`` if it is one of ``ALIGN_MODES``, else a TargetError at ``field``."""
    if value not in ALIGN_MODES:
        raise TargetError(field, f"{value!r}; allowed: {', '.join(ALIGN_MODES)}")
    return value


def _weights(d, pre=""):
    """``(rotation_weight_mm, fold_weight_mm_per_deg)`` of the frame (or shared top) ``d``, each range-checked:
    [0, 1e6] mm per radian and (0, 1e6] mm per degree (defaults 0 and 1)."""
    rw = _num(d.get("rotation_weight_mm", 0.0), f"{pre}rotation_weight_mm", 0, WEIGHT_MAX, "mm")
    wf = _num(d.get("fold_weight_mm_per_deg", 1.0), f"{pre}fold_weight_mm_per_deg", 0, WEIGHT_MAX, "mm/deg",
              low_open=True)
    return rw, wf


def parse_frame(scene, d, base_dir=None, where="", mesh_loader=None):
    pre = f"{where}." if where else ""
    if not isinstance(d, dict):
        raise TargetError(where or "target", f"expected an object, got {type(d).__name__}")
    _keys(d, _FRAME_KEYS | (set() if where else _TOP_KEYS), where)
    fr = Frame(time_s=_num(d.get("time_s", 0.0), f"{pre}time_s", 0, TIME_MAX_S, "s") + 0.0,   # -0 s is 0 s
               name=str(d.get("name", "")))
    align = fr.align = _align(d.get("align", "rigid"), f"{pre}align")
    rw, wf = _weights(d, pre)          # checked even when the frame has no nodes / folds to weigh
    if "nodes" in d:
        fr.nodes = _parse_nodes(scene, d["nodes"], rw, f"{pre}nodes", f"{pre}rotation_weight_mm")
        if align != "similarity":                  # a similarity alignment fits the scale: any unit fits
            _check_node_units(scene, fr.nodes, f"{pre}nodes")
        if len(fr.nodes.idx) < 3 and align != "none":
            fr.align = "none"          # fewer than 3 points do not fix a rigid transform
    if "folds" in d:
        fr.folds = _parse_folds(scene, d["folds"], wf, f"{pre}folds")
    if "surface" in d:
        fr.surface = _parse_surface(scene, d["surface"], base_dir, f"{pre}surface", mesh_loader,
                                    check_scale=align != "similarity")     # as the nodes' units
    if fr.nodes is None and fr.folds is None and fr.surface is None:
        raise TargetError(where or "target", "empty: give nodes, folds or surface (or keyframes of them)")
    return fr


def _from_result(d, source=None, scene=None):
    """The target frame of a ``solve`` result ``d`` (its nodes' positions; rotations are not used).

    ``d`` is a JSON result (``nodes`` list) or the JSON half of ``solve --npz`` (an ``"arrays"`` entry, no
    ``nodes``): its arrays are read through ``core.resultfile.read_result`` from the ``.npz`` beside ``source``
    (the JSON file's path). A result that did not converge, one written without the poses
    (``--fields D`` / ``joints``), or one of another sheet (:func:`_check_sheet`) is refused. Returns the frame
    dict and a warning text or None."""
    src = f"the result file {source!r}" if source else "the result"
    own = getattr(scene, "name", None)
    theirs = d.get("scene")     # named in the message only: a renamed copy (an inverse answer) has the same nodes
    if d.get("converged") is False:
        raise TargetError("converged", f"false: {src} is of a solve that did not converge (its node positions are "
                                       f"not an equilibrium of the scene); allowed: a converged result (solve "
                                       f"again, e.g. with more load_steps or max_iter)")
    fields = d.get("fields")
    no_poses = isinstance(fields, list) and "poses" not in fields
    if "nodes" not in d and "arrays" in d:
        if not source:
            raise TargetError("arrays", f"{src} is the JSON half of a `solve --npz` result: its node data is in the "
                                        f".npz file beside it; allowed: load it from its file (--target R.json)")
        from metamaterial_wb.core.resultfile import read_result
        try:
            _, arrays = read_result(source)
        except SceneError as exc:
            raise TargetError(exc.field, exc.message) from None
        if "position_mm" not in arrays:
            no_poses = True
        else:
            ij = np.asarray(arrays["ij"]).reshape(-1, 2).tolist()
            pos = np.asarray(arrays["position_mm"], dtype=float).reshape(-1, 3).tolist()
            if len(ij) != len(pos):
                raise TargetError("arrays.file", f"{src}: {len(ij)} nodes but {len(pos)} positions in its arrays")
            nodes = [{"name": f"N{i},{j}", "position_mm": p} for (i, j), p in zip(ij, pos)]
    else:
        nodes = d.get("nodes")
        if isinstance(nodes, list) and nodes and any(isinstance(nd, dict) and "position_mm" not in nd
                                                     for nd in nodes):
            no_poses = no_poses or not isinstance(fields, list)
    if no_poses:
        wrote = f"written with --fields {','.join(str(f) for f in fields)}" if isinstance(fields, list) else \
            "its nodes lack position_mm"
        raise TargetError("nodes", f"{src} has no node positions: {wrote}; node positions need --fields poses "
                                   f"(or all)")
    if not isinstance(nodes, list) or not nodes:
        raise TargetError("nodes", f"{src} has no nodes")
    n_scene = getattr(getattr(scene, "topology", None), "n_nodes", None)
    if n_scene is not None and len(nodes) != n_scene:   # a result lists every node of its scene
        raise TargetError("nodes", f"{src} has {len(nodes)} nodes, this scene {own or ''} has {n_scene}: it is a "
                                   f"result of another sheet (its scene field says {theirs!r}); allowed: a solve "
                                   f"result of a scene with this scene's nodes (every node name must be one of "
                                   f"this scene's, as in a renamed copy or an inverse answer)")
    items = []
    for k, nd in enumerate(nodes):
        if not isinstance(nd, dict):
            raise TargetError(f"nodes[{k}]", f"expected a result node object, got {_short(nd)}")
        items.append({"name": nd.get("name", [nd.get("i"), nd.get("j")]), "position_mm": nd.get("position_mm")})
    warning = _check_sheet(d, items, scene, src)
    return {"nodes": items, "align": "rigid"}, warning


REST_TOL_MM = 1e-6      # rest positions of a result's sheet and the scene's: equal up to float round-off


def _check_sheet(d, items, scene, src):
    """Refuse a result of another sheet: node names alone do not tell the sheets apart (a 3 x 3 grid of 20 mm cells
    and one of 25 mm cells have the same names), the rest positions do. A node's rest position is
    ``(j, -i) * cell_size_mm`` (``kinematics.flat_positions_mm``), so the result's ``cell_size_mm`` (written by
    ``solve`` since it carries it) and its node names give its sheet's rest positions; any node's differing from
    the scene's by more than ``REST_TOL_MM`` is a :class:`TargetError`. A result without ``cell_size_mm`` (an
    older version's) cannot be told apart: the warning text is returned (None otherwise)."""
    cell = getattr(scene, "cell_size_mm", None)
    if cell is None:
        return None
    if "cell_size_mm" not in d:
        return (f"{src} has no cell_size_mm (written by an older version of solve): whether it is a result of this "
                f"sheet cannot be checked; its node positions are used as they are (solve the scene again to have "
                f"it checked)")
    from metamaterial_wb.core.scene.sections import CELL_SIZE_RANGE
    theirs_cell = _num(d["cell_size_mm"], "cell_size_mm", *CELL_SIZE_RANGE, "mm")
    worst = None
    for it in items:
        name = it["name"]
        try:
            if isinstance(name, str) and not name.startswith("N"):
                raise ValueError(name)
            i, j = (int(x) for x in name[1:].split(",")) if isinstance(name, str) else (int(name[0]), int(name[1]))
        except (TypeError, ValueError, IndexError):
            return None                # not a node name: refused by the node list's own check (named as such)
        d_mm = abs(theirs_cell - cell) * float(np.hypot(i, j))
        if worst is None or d_mm > worst[0]:
            worst = (d_mm, i, j)
    if worst is None or worst[0] <= REST_TOL_MM:
        return None
    d_mm, i, j = worst
    raise TargetError("cell_size_mm", f"{src}: node N{i},{j}'s rest position ({_g(j * theirs_cell)}, "
                                      f"{_g(-i * theirs_cell)}) mm differs from this scene's ({_g(j * cell)}, "
                                      f"{_g(-i * cell)}) mm by {_g(d_mm)} mm (cell_size_mm {theirs_cell:.10g} mm in "
                                      f"the result, {cell:.10g} mm in this scene): the result belongs to another "
                                      f"sheet; allowed: a solve result of this sheet (its node names and "
                                      f"cell_size_mm: rest positions within {REST_TOL_MM:g} mm), a renamed copy of "
                                      f"one, or a target JSON of node positions")


def _check_version(data):
    """A target's ``version`` is 1 (or absent): the only version of the target format."""
    if "version" in data:
        v = data["version"]
        if isinstance(v, bool) or not isinstance(v, (int, float)) or v != 1:
            raise TargetError("version", f"{_short(v)}; allowed: 1 (the target format's only version; or leave it "
                                         f"out)")


def parse_target(scene, data, base_dir=None, mesh_loader=None, source=None):
    """A :class:`Target` from a dict (a target document or a ``solve`` result). ``source``: the file the dict
    was read from (named in errors; a ``solve --npz`` result's arrays are read beside it)."""
    if not isinstance(data, dict):
        raise TargetError("", f"a target is a JSON object, got {type(data).__name__}")
    from metamaterial_wb.core.inputfile import check_tree
    try:
        check_tree(data)                       # finite, sane numbers and depth, as a scene's (inputfile.check_tree)
    except SceneError as exc:
        raise TargetError(exc.field, exc.message) from None
    fmt = data.get("format", FORMAT)
    warnings = []
    if fmt == "metamaterial-result":
        data, warning = _from_result(data, source, scene)
        warnings += [warning] if warning else []
    elif fmt != FORMAT:
        raise TargetError("format", f"{fmt!r}; expected \"{FORMAT}\" or a solve result \"metamaterial-result\"")
    else:
        _check_version(data)
    if "keyframes" in data:
        kf = data["keyframes"]
        if not isinstance(kf, list) or not kf:
            raise TargetError("keyframes", "expected a non-empty list of frames")
        _keys(data, _TOP_KEYS | set(_SHARED_KEYS) | {"keyframes", "period_s", "name"}, "")
        shared = {k: v for k, v in data.items() if k in _SHARED_KEYS}
        _align(shared.get("align", "rigid"), "align")     # the shared value's own place, not a frame's
        _weights(shared)                                   # likewise the shared weights
        frames = []
        for k, f in enumerate(kf):
            if not isinstance(f, dict):
                raise TargetError(f"keyframes[{k}]", f"expected an object, got {_short(f)}")
            merged = dict(shared)
            merged.update(f)
            merged.setdefault("time_s", float(k))
            frames.append(parse_frame(scene, merged, base_dir, f"keyframes[{k}]", mesh_loader))
        times = [f.time_s for f in frames]
        if any(t1 <= t0 for t0, t1 in zip(times, times[1:])) or times[0] < 0:
            raise TargetError("keyframes", f"times {times} must start at >= 0 s and increase strictly")
        period = data.get("period_s")
        if period is not None:
            period = _num(period, "period_s", 0, TIME_MAX_S, "s", low_open=True)
            if period <= times[-1]:
                raise TargetError("period_s", f"{period} s must be longer than the last keyframe time {times[-1]} s")
        return Target(frames, period, info={"warnings": warnings} if warnings else {})
    if "period_s" in data:
        raise TargetError("period_s", f"{_short(data['period_s'])} without keyframes; allowed: only with a "
                                      f"\"keyframes\" list (the period of the keyframe motion)")
    return Target([parse_frame(scene, data, base_dir, "", mesh_loader)],
                  info={"warnings": warnings} if warnings else {})


def load_target(scene, path, mesh_loader=None):
    """A :class:`Target` from a file: target JSON, ``solve`` result JSON, or a mesh (STL / OBJ)."""
    ext = os.path.splitext(path)[1].lower()
    if not os.path.exists(path):
        raise TargetError("", f"file {path!r} does not exist")
    if os.path.isdir(path):
        raise TargetError("", f"{path!r} is a folder; expected a target file: a target JSON (docs/inverse.md), a "
                              f"solve result (.json, or the .npz of solve --npz) or a surface (.stl, .obj; "
                              f".step/.stp with FreeCAD)")
    if ext == ".npz":                           # the arrays of a `solve --npz` result
        from metamaterial_wb.core.resultfile import read_result
        try:
            meta, arrays = read_result(path)
            if "ij" not in arrays:
                raise KeyError("ij")
        except (OSError, ValueError, KeyError) as exc:
            raise TargetError("", f"{path!r} is not a readable solve result .npz file ({exc})") from None
        doc = dict(meta, format="metamaterial-result")
        if "position_mm" in arrays:
            doc["nodes"] = [{"name": f"N{i},{j}", "position_mm": p} for (i, j), p in
                            zip(np.asarray(arrays["ij"]).reshape(-1, 2).tolist(),
                                np.asarray(arrays["position_mm"], dtype=float).reshape(-1, 3).tolist())]
        else:
            doc["nodes"] = [{}]                 # no positions: refused by _from_result, naming the fields
        t = parse_target(scene, doc, None, mesh_loader, source=path)
    elif ext != ".json":
        t = Target([parse_frame(scene, {"surface": {"file": os.path.abspath(path)}}, None, "", mesh_loader)])
    else:
        from metamaterial_wb.core.inputfile import read_json
        try:
            data = read_json(path, "")          # as a scene is read: inputfile's checks of numbers, depth, text
        except SceneError as exc:
            raise TargetError(exc.field, exc.message) from None
        t = parse_target(scene, data, os.path.dirname(os.path.abspath(path)), mesh_loader, source=path)
    t.source = path
    return t
