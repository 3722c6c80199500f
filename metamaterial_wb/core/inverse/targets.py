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
positions are the target). A bare ``.stl`` / ``.obj`` path is a surface target of every node.
Every check raises :class:`TargetError` naming the field, the value and what is allowed.
"""
import json
import math
import os
from dataclasses import dataclass, field

import numpy as np

from metamaterial_wb.core.inverse.surface import Surface, TargetError, load_mesh
from metamaterial_wb.core.scene import parse_joint

FORMAT = "metamaterial-target"
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


def _num(v, where):
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        raise TargetError(where, f"expected a number, got {v!r}")
    if not math.isfinite(float(v)):
        raise TargetError(where, f"{v!r} is not a finite number (NaN or inf)")
    return float(v)


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
    k = topo.node_id(i, j) if isinstance(i, int) and isinstance(j, int) else -1
    if k < 0:
        ij = topo.node_ij()
        raise TargetError(where, f"node {name!r} does not exist in this scene ({topo.n_nodes} nodes, "
                                 f"N{ij[:, 0].min()},{ij[:, 1].min()} .. N{ij[:, 0].max()},{ij[:, 1].max()})")
    return int(k)


def _parse_nodes(scene, items, frame, where):
    if not isinstance(items, list) or not items:
        raise TargetError(where, "expected a non-empty list of nodes with position_mm")
    idx, pos, w, rot = [], [], [], []
    seen = {}
    for k, it in enumerate(items):
        f = f"{where}[{k}]"
        if not isinstance(it, dict):
            raise TargetError(f, f"expected an object with name and position_mm, got {it!r}")
        name = it.get("name", [it.get("i"), it.get("j")] if "i" in it else None)
        n = _node_index(scene, name, f"{f}.name")
        if n in seen:
            raise TargetError(f"{f}.name", f"node {name!r} is already given by {seen[n]}")
        seen[n] = f
        p = it.get("position_mm")
        if not isinstance(p, (list, tuple)) or len(p) != 3:
            raise TargetError(f"{f}.position_mm", f"expected [x, y, z] in mm, got {p!r}")
        pos.append([_num(x, f"{f}.position_mm") for x in p])
        w.append(_num(it.get("weight", 1.0), f"{f}.weight"))
        if w[-1] < 0:
            raise TargetError(f"{f}.weight", f"{w[-1]} is outside the allowed range [0, inf)")
        r = it.get("rotation")
        if r is not None:
            Rm = np.asarray(r, dtype=float) if isinstance(r, list) else None
            if Rm is None or Rm.shape != (3, 3) or not np.all(np.isfinite(Rm)) or \
                    np.abs(Rm.T @ Rm - np.eye(3)).max() > 1e-6 or np.linalg.det(Rm) < 0:
                raise TargetError(f"{f}.rotation", "expected a 3 x 3 proper rotation matrix (finite, orthonormal)")
            rot.append(Rm)
        idx.append(n)
    if sum(w) <= 0:
        raise TargetError(where, "every node has weight 0: nothing to fit")
    rw = _num(frame.get("rotation_weight_mm", 0.0), "rotation_weight_mm")
    if rw < 0:
        raise TargetError("rotation_weight_mm", f"{rw} is outside the allowed range [0, inf)")
    R = None
    if rw > 0:
        if len(rot) != len(idx):
            raise TargetError("rotation_weight_mm", f"{rw} > 0 needs a rotation for every target node "
                                                    f"({len(rot)} of {len(idx)} have one)")
        R = np.array(rot)
    return NodeTerm(np.array(idx), np.array(pos), np.array(w), R, rw)


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
    return vals.min(axis=0), vals.max(axis=0)


def _parse_folds(scene, items, frame, where):
    from metamaterial_wb.core import design
    if not isinstance(items, list) or not items:
        raise TargetError(where, "expected a non-empty list of {\"joint\" or \"axis\", \"fold_deg\"}")
    topo = scene.topology
    lo, hi = fold_ranges_deg(scene)
    plans = None
    rows, target, labels = [], [], []
    for k, it in enumerate(items):
        f = f"{where}[{k}]"
        if not isinstance(it, dict) or "fold_deg" not in it or ("joint" in it) == ("axis" in it):
            raise TargetError(f, f"expected {{\"joint\": \"H0,1\", \"fold_deg\": 30}} or {{\"axis\": NAME, "
                                 f"\"fold_deg\": 30}}, got {it!r}")
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
                                                f"({topo.n_joints} joints)")
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
            rlo, rhi = float(np.mean(lo[js])), float(np.mean(hi[js]))
        if not (rlo - 1e-9 <= val <= rhi + 1e-9):
            raise TargetError(f"{f}.fold_deg", f"{val!r} deg at {label} is unreachable: the reachable range of "
                                               f"the scene's hinges is [{rlo:.4g}, {rhi:.4g}] deg "
                                               f"(tilt and rotation limits; docs/kinematics.md)")
        rows.append(row)
        target.append(val)
        labels.append(label)
    A = np.array(rows)
    wf = _num(frame.get("fold_weight_mm_per_deg", 1.0), "fold_weight_mm_per_deg")
    if wf <= 0:
        raise TargetError("fold_weight_mm_per_deg", f"{wf} is outside the allowed range (0, inf)")
    return FoldTerm(A, np.flatnonzero(np.any(A != 0, axis=0)), np.array(target), labels, wf)


def _sheet_bbox(scene):
    from metamaterial_wb.core.kinematics import flat_positions_mm
    p = flat_positions_mm(scene)
    h = 0.5 * scene.cell_size_mm
    return p.min(axis=0) - h, p.max(axis=0) + h


def _parse_surface(scene, spec, base_dir, where, mesh_loader=None):
    if isinstance(spec, str):
        spec = {"file": spec}
    if not isinstance(spec, dict) or "file" not in spec and "triangles" not in spec:
        raise TargetError(where, f"expected {{\"file\": \"shape.stl\"}}, got {spec!r}")
    if "triangles" in spec:
        tri, src = np.asarray(spec["triangles"], dtype=float), "triangles"
    else:
        path = spec["file"]
        if not os.path.isabs(path):
            path = os.path.join(base_dir or ".", path)
        if not os.path.exists(path):
            raise TargetError(f"{where}.file", f"{path!r} does not exist")
        tri = (mesh_loader or load_mesh)(path)
        src = path
    surf = Surface(tri)
    names = spec.get("nodes")
    idx = (np.arange(scene.topology.n_nodes) if names is None else
           np.array([_node_index(scene, nm, f"{where}.nodes[{k}]") for k, nm in enumerate(names)]))
    if idx.size == 0:
        raise TargetError(f"{where}.nodes", "empty: no node to match to the surface")
    lo, hi = _sheet_bbox(scene)
    slo, shi = surf.bbox
    gap = float(np.linalg.norm(np.maximum(0.0, np.maximum(slo - hi, lo - shi))))
    diag = float(np.linalg.norm(hi - lo))
    if gap > 0.5 * diag:
        raise TargetError(where, f"the surface {src!r} is {gap:.1f} mm from the flat sheet (bounding boxes), more than "
                                 f"half the sheet's diagonal ({0.5 * diag:.1f} mm); the rigid alignment is a local "
                                 f"refinement: place the surface over the sheet")
    return SurfaceTerm(surf, idx, src)


def _align(value, field):
    """``value`` if it is one of ``ALIGN_MODES``, else a TargetError at ``field``."""
    if value not in ALIGN_MODES:
        raise TargetError(field, f"{value!r}; allowed: {', '.join(ALIGN_MODES)}")
    return value


def parse_frame(scene, d, base_dir=None, where="", mesh_loader=None):
    pre = f"{where}." if where else ""
    if not isinstance(d, dict):
        raise TargetError(where or "target", f"expected an object, got {type(d).__name__}")
    unknown = set(d) - _FRAME_KEYS - {"format", "version", "keyframes", "period_s", "description"}
    if unknown:
        raise TargetError(f"{pre}{sorted(unknown)[0]}", f"unknown field; allowed: {sorted(_FRAME_KEYS)}")
    fr = Frame(time_s=_num(d.get("time_s", 0.0), f"{pre}time_s"), name=str(d.get("name", "")))
    align = fr.align = _align(d.get("align", "rigid"), f"{pre}align")
    if "nodes" in d:
        fr.nodes = _parse_nodes(scene, d["nodes"], d, f"{pre}nodes")
        if len(fr.nodes.idx) < 3 and align != "none":
            fr.align = "none"          # fewer than 3 points do not fix a rigid transform
    if "folds" in d:
        fr.folds = _parse_folds(scene, d["folds"], d, f"{pre}folds")
    if "surface" in d:
        fr.surface = _parse_surface(scene, d["surface"], base_dir, f"{pre}surface", mesh_loader)
    if fr.nodes is None and fr.folds is None and fr.surface is None:
        raise TargetError(where or "target", "empty: give nodes, folds or surface (or keyframes of them)")
    return fr


def _from_result(scene, d):
    nodes = d.get("nodes")
    if not isinstance(nodes, list) or not nodes:
        raise TargetError("nodes", "the result file has no nodes")
    items = [{"name": nd.get("name", [nd.get("i"), nd.get("j")]), "position_mm": nd.get("position_mm"),
              "rotation": nd.get("rotation")} for nd in nodes]
    return {"nodes": items, "align": "rigid"}


def parse_target(scene, data, base_dir=None, mesh_loader=None):
    """A :class:`Target` from a dict (a target document or a ``solve`` result)."""
    if not isinstance(data, dict):
        raise TargetError("", f"a target is a JSON object, got {type(data).__name__}")
    fmt = data.get("format", FORMAT)
    if fmt == "metamaterial-result":
        data = _from_result(scene, data)
    elif fmt != FORMAT:
        raise TargetError("format", f"{fmt!r}; expected \"{FORMAT}\" or a solve result \"metamaterial-result\"")
    if "keyframes" in data:
        kf = data["keyframes"]
        if not isinstance(kf, list) or not kf:
            raise TargetError("keyframes", "expected a non-empty list of frames")
        shared = {k: v for k, v in data.items() if k in ("align", "rotation_weight_mm", "fold_weight_mm_per_deg")}
        _align(shared.get("align", "rigid"), "align")     # the shared value's own place, not a frame's
        frames = []
        for k, f in enumerate(kf):
            if not isinstance(f, dict):
                raise TargetError(f"keyframes[{k}]", f"expected an object, got {f!r}")
            merged = dict(shared)
            merged.update(f)
            merged.setdefault("time_s", float(k))
            frames.append(parse_frame(scene, merged, base_dir, f"keyframes[{k}]", mesh_loader))
        times = [f.time_s for f in frames]
        if any(t1 <= t0 for t0, t1 in zip(times, times[1:])) or times[0] < 0:
            raise TargetError("keyframes", f"times {times} must start at >= 0 s and increase strictly")
        period = data.get("period_s")
        if period is not None:
            period = _num(period, "period_s")
            if period <= times[-1]:
                raise TargetError("period_s", f"{period} s must be longer than the last keyframe time {times[-1]} s")
        return Target(frames, period)
    return Target([parse_frame(scene, data, base_dir, "", mesh_loader)])


def load_target(scene, path, mesh_loader=None):
    """A :class:`Target` from a file: target JSON, ``solve`` result JSON, or a mesh (STL / OBJ)."""
    ext = os.path.splitext(path)[1].lower()
    if not os.path.exists(path):
        raise TargetError("", f"file {path!r} does not exist")
    if ext != ".json":
        t = Target([parse_frame(scene, {"surface": {"file": os.path.abspath(path)}}, None, "", mesh_loader)])
    else:
        with open(path, encoding="utf-8") as f:
            try:
                data = json.loads(f.read())
            except json.JSONDecodeError as exc:
                raise TargetError("", f"{path}: not valid JSON: {exc.msg} at line {exc.lineno}") from None
        t = parse_target(scene, data, os.path.dirname(os.path.abspath(path)), mesh_loader)
    t.source = path
    return t
