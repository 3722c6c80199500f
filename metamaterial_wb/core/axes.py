"""Rotary axes (seed 000, section 4.1): the geometric rules of ``scene.axes`` and one :class:`AxisPlan` per
axis (cells it runs through, joints it crosses). Pure topology: no kinematics. :mod:`core.design` builds the
joint configuration on these plans and re-exports the names.
"""
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

from metamaterial_wb.core.errors import SceneError


@dataclass
class AxisPlan:
    """One validated axis: which cells it runs through and which joints it crosses.

    Attributes
    ----------
    index : int
        Position of the axis in ``scene.axes``.
    direction : str
        ``"vertical"`` or ``"horizontal"``.
    line : int
        The grid line it runs along.
    fold_deg : float
        Requested fold at D = +1.
    label : str
        Name for messages (:func:`axis_label`).
    segments : list of tuple
        ``(first, last)`` cell indices along the line.
    cells : list of tuple
        ``(i, j)`` cells the axis runs through.
    joints : numpy.ndarray
        Indices of the joints it crosses (topology order).
    joint_names : list of str
    label_name : str
        The axis's name, or ``v<line>`` / ``h<line>``.
    """
    index: int
    direction: str
    line: int
    fold_deg: float
    label: str
    segments: list                      # [(first, last)] cell indices along the line
    cells: list                         # covered cells (i, j)
    joints: np.ndarray                  # crossed joint indices
    joint_names: list = field(default_factory=list)

    label_name: str = ""                # the axis's name, or v<line> / h<line>

    @property
    def field(self):
        return f"axes[{self.index}]"


def axis_label(k, axis):
    """Human-readable name of axis ``k`` for messages.

    Parameters
    ----------
    k : int
        Index in ``scene.axes``.
    axis : Axis

    Returns
    -------
    str
        ``"axes[k] (name: direction line n)"``.
    """
    nm = f"{axis.name!r}, " if axis.name else ""
    return f"axes[{k}] ({nm}{axis.direction} line {axis.line})"


def _runs(values):
    """Maximal runs of consecutive integers in a sorted list -> [(first, last)]."""
    runs = []
    for v in values:
        if runs and v == runs[-1][1] + 1:
            runs[-1][1] = v
        else:
            runs.append([v, v])
    return [tuple(r) for r in runs]


def plan_axes(scene):
    """Validate the axes geometrically and return one :class:`AxisPlan` per axis.

    Errors (SceneError naming the axes): a line through no cell; from/to that stop short of the
    structure's boundary; two axes on one line; crossing axes; an axis that does not cut the
    structure in two.

    Parameters
    ----------
    scene : Scene

    Returns
    -------
    list of AxisPlan
        One per axis, in scene order.

    Raises
    ------
    SceneError
        An axis that breaks a rule (named in the message).
    """
    topo = scene.topology
    ca = topo.cell_array
    plans = []
    for k, ax in enumerate(scene.axes):
        label = axis_label(k, ax)
        col = 1 if ax.direction == "vertical" else 0       # which cell coordinate is the line
        along = 0 if ax.direction == "vertical" else 1
        on_line = np.sort(ca[ca[:, col] == ax.line, along]).tolist()
        if not on_line:
            what = "column" if ax.direction == "vertical" else "row"
            lo, hi = int(ca[:, col].min()), int(ca[:, col].max())
            raise SceneError(f"axes[{k}].line", f"{label} runs through no cell: the layout has no cell in "
                                                f"{what} {ax.line}; allowed {what}s with cells: {lo}..{hi}")
        segs = _runs(on_line)
        lo_hi = {}
        for key in ("from", "to"):
            if key in ax.extra:
                v = ax.extra[key]
                if isinstance(v, bool) or not isinstance(v, int):
                    raise SceneError(f"axes[{k}].{key}", f"{label}: expected a cell index along the line, got {v!r}")
                lo_hi[key] = v
        first = lo_hi.get("from", on_line[0])
        last = lo_hi.get("to", on_line[-1])
        if first > last:
            raise SceneError(f"axes[{k}]", f"{label}: from = {first} is after to = {last}")
        covered = []
        for s0, s1 in segs:
            if s1 < first or s0 > last:
                continue
            if s0 < first or s1 > last:
                stop = first if s0 < first else last
                end_cell = (s0 if s0 < first else s1)
                cell = (end_cell, ax.line) if ax.direction == "vertical" else (ax.line, end_cell)
                where = "from" if s0 < first else "to"
                raise SceneError(f"axes[{k}].{where}",
                                 f"{label} stops short at cell index {stop}: the structure continues on its line "
                                 f"to cell {list(cell)}; an axis must run through the whole structure to its "
                                 f"boundary (cover {s0}..{s1} on this stretch, or leave from/to out)")
            covered.append((s0, s1))
        if not covered:
            raise SceneError(f"axes[{k}]", f"{label}: from {first} to {last} covers no cell of the line "
                                           f"(cells at {on_line[0]}..{on_line[-1]})")
        cells, joints = [], []
        for s0, s1 in covered:
            for t in range(s0, s1 + 1):
                cells.append((t, ax.line) if ax.direction == "vertical" else (ax.line, t))
            for t in range(s0, s1 + 2):          # node rows (columns) bounding the stretch
                j = (topo.joint_id("H", t, ax.line) if ax.direction == "vertical"
                     else topo.joint_id("V", ax.line, t))
                if j >= 0:
                    joints.append(j)
        joints = np.array(sorted(set(joints)), dtype=np.int64)
        plans.append(AxisPlan(k, ax.direction, ax.line, ax.fold_deg, label, covered, cells, joints,
                              [topo.joint_names[j] for j in joints] if joints.size < 10000 else [],
                              ax.name or f"{ax.direction[0]}{ax.line}"))

    # two axes on one line
    seen = {}
    for p in plans:
        key = (p.direction, p.line)
        if key in seen:
            q = seen[key]
            raise SceneError(p.field, f"{q.label} and {p.label} lie on the same line; give one axis per line")
        seen[key] = p
    # crossing axes share a cell
    vert = [p for p in plans if p.direction == "vertical"]
    hor = [p for p in plans if p.direction == "horizontal"]
    for pv in vert:
        cv = set(pv.cells)
        for ph in hor:
            common = cv.intersection(ph.cells)
            if common:
                c = sorted(common)[0]
                raise SceneError(f"axes[{max(pv.index, ph.index)}]",
                                 f"{pv.label} and {ph.label} cross at cell {list(c)}; axes may not cross one "
                                 f"another (a cell cannot bend about two directions at once)")
    # every axis cuts the structure in two (backstop for layouts where a stretch is not a chord)
    n, m = topo.n_nodes, topo.n_joints
    a, b = topo.joint_pairs[:, 0], topo.joint_pairs[:, 1]
    for p in plans:
        keep = np.ones(m, dtype=bool)
        keep[p.joints] = False
        G = sp.coo_matrix((np.ones(int(keep.sum())), (a[keep], b[keep])), shape=(n, n))
        _, lab = connected_components(G, directed=False)
        same = lab[a[p.joints]] == lab[b[p.joints]]
        if np.any(same):
            jn = topo.joint_names[int(p.joints[np.flatnonzero(same)[0]])]
            raise SceneError(p.field, f"{p.label} does not cut the structure in two: the nodes of joint {jn} stay "
                                      f"connected around the end of the axis; an axis must run through the whole "
                                      f"structure to its boundary")
    return plans
