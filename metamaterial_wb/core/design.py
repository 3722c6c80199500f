"""Design stage (seed 000, section 4.1): rotary axes, folded target shape, joint configuration.

* An axis is a straight grid line through a cell row or column (``scene.axes``). A vertical axis
  with ``line`` k runs down cell column k and crosses every joint ``H(i, k)``; a horizontal axis with
  ``line`` k runs along cell row k and crosses every joint ``V(k, j)``. Optional ``"from"`` / ``"to"``
  (cell indices along the line, inclusive) restrict it to part of the line, but every stretch of
  cells it touches must be covered from boundary to boundary (the seed's rule: an axis continues on
  its line to the end of the structure). Axes may not cross one another (a cell cannot bend about
  two directions at once) and two axes may not share a line.
* ``fold_deg`` is the fold about the axis in the fully deformed state (every D = +1); positive
  raises the far side (higher column / higher row) towards +z of the near side. The largest
  achievable fold of each axis is limited by the hinge tilt range (80 deg), the hinge strain at
  D = +1 and plate contact across the fold (:func:`axis_limits`).
* Joint configuration: every crossed joint gets the hinge tilt that folds it by ``fold_deg`` at
  D = +1 (``tan(gamma/2) = -tan(alpha) sin(phi_A)``, docs/kinematics.md); stored in
  ``scene.joint_config`` as ``{"H0,1": {"tilt_deg": ..., "fold_deg": ..., "axis": ...}}``.
* Global deformation ``g``: every D = g (perfect propagation) gives the shapes between flat (0),
  the target (+1) and the reverse fold (-1).
"""
import math
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

from metamaterial_wb.core import kinematics as kin
from metamaterial_wb.core.errors import SceneError, check_number


@dataclass
class AxisPlan:
    """One validated axis: which cells it runs through and which joints it crosses."""
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


# ----------------------------------------------------------------------------------------------
# limits
# ----------------------------------------------------------------------------------------------
def _fab_tilt(scene, widths, ignore_switch):
    """``(max printable tilt deg, width mm)`` of the narrowest-margin hinge among ``widths``."""
    from metamaterial_wb.core.fabrication import max_fabricable_tilt_deg

    ws = sorted(set(np.round(np.asarray(widths, dtype=float), 9).tolist()))
    if not ws:
        return 90.0, 0.0
    return min((max_fabricable_tilt_deg(scene, w, ignore_switch=ignore_switch), w) for w in ws)


def printable_fold_deg(scene, plan, phi_c=None):
    """``(fold deg, max tilt deg, width mm)``: the largest fold of an axis whose hinge tilts the
    default fabrication (core/fabrication.py) can print, whatever ``limit_design_tilt`` says."""
    phi_c = planar_closing_rad(scene) if phi_c is None else phi_c
    _lh, wh, _th = kin.joint_hinge_arrays(scene)
    tilt, w = _fab_tilt(scene, wh[plan.joints], ignore_switch=True)
    fold = 2.0 * math.atan(math.tan(math.radians(max(tilt, 0.0))) * math.sin(phi_c))
    return math.degrees(fold), tilt, w


def planar_closing_rad(scene):
    """Node rotation at D = +1 of the untilted sheet (the state the target fold is defined in)."""
    return kin.rotation_limit_info(scene, np.zeros(scene.topology.n_joints))["closing_rad"]


def axis_limits(scene, plan, phi_c=None):
    """``(max_fold_deg, binding)`` of one axis at D = +1.

    Limits, per crossed joint: hinge tilt |alpha| <= 80 deg (fold ``2 atan(tan 80 sin phi_c)``),
    when the scene's ``fabrication.limit_design_tilt`` is true, the tilt that the printed hinge can
    have inside its node plate (``core.fabrication.max_fabricable_tilt_deg``; otherwise it is only
    reported, see :func:`printable_fold_deg`), hinge strain <= the scene's limit at D = +1, plate
    contact across the fold ``2 atan(lh / t)``.
    """
    phi_c = planar_closing_rad(scene) if phi_c is None else phi_c
    lh, wh, th = kin.joint_hinge_arrays(scene)
    js = plan.joints
    eps = kin.hinge_strain_limit(scene)
    tilt_max = math.radians(kin.MAX_TILT_DEG)
    g_tilt = 2.0 * math.atan(math.tan(tilt_max) * math.sin(phi_c))
    fab = _fab_tilt(scene, wh[js], ignore_switch=False)
    g_fab = 2.0 * math.atan(math.tan(math.radians(max(fab[0], 0.0))) * math.sin(phi_c))
    psi_max = 2.0 * lh[js] * eps / wh[js]
    ratio = np.cos(0.5 * np.minimum(psi_max, math.pi)) / math.cos(phi_c)
    g_strain = np.where(psi_max >= math.pi, math.pi, 2.0 * np.arccos(np.clip(ratio, -1.0, 1.0)))
    g_contact = kin.fold_contact_rad(lh[js], th[js])
    names = plan.joint_names or [scene.topology.joint_names[int(j)] for j in js]
    ks, kc = int(np.argmin(g_strain)), int(np.argmin(g_contact))
    cands = [(g_tilt, f"hinge tilt limit {kin.MAX_TILT_DEG:g} deg at closing rotation "
                      f"{math.degrees(phi_c):.2f} deg"),
             (float(g_strain[ks]), f"hinge strain {eps:g} at joint {names[ks]}"),
             (float(g_contact[kc]), f"plate contact across the fold 2 atan(lh/t) at joint {names[kc]}"),
             (g_fab, f"fabrication: a {fab[1]:g} mm wide hinge fits its node plate up to a tilt of "
                     f"{max(fab[0], 0.0):.1f} deg (docs/fabrication.md)")]
    val, why = min(cands, key=lambda c: c[0])
    return math.degrees(val), why


# ----------------------------------------------------------------------------------------------
# joint configuration
# ----------------------------------------------------------------------------------------------
def compute_joint_config(scene, plans=None, strict=True):
    """``(joint_config, report)`` from the scene's axes; does not change the scene.

    ``strict``: a fold beyond the maximum is an error giving the maximum (else it is reported).
    """
    plans = plan_axes(scene) if plans is None else plans
    topo = scene.topology
    phi_c = planar_closing_rad(scene)
    par = kin.joint_parity(scene)
    config, rows = {}, []
    for p in plans:
        mx, why = axis_limits(scene, p, phi_c)
        if abs(p.fold_deg) > mx + 1e-9:
            if strict:
                raise SceneError(f"axes[{p.index}].fold_deg",
                                 f"{p.fold_deg:g} deg on {p.label} is beyond the maximum achievable fold: "
                                 f"allowed range [-{mx:.2f}, {mx:.2f}] deg (bound by {why})")
        g = math.radians(p.fold_deg)
        tilts = np.degrees(kin.tilt_for_fold(g, par[p.joints] * phi_c))
        for j, t in zip(p.joints.tolist(), tilts.tolist()):
            config[topo.joint_names[j]] = {"tilt_deg": round(float(t), 9), "fold_deg": p.fold_deg,
                                           "axis": p.label_name}
        pf, ptilt, pw = printable_fold_deg(scene, p, phi_c)
        rows.append({"axis": p.label_name, "index": p.index, "direction": p.direction, "line": p.line,
                     "fold_deg": p.fold_deg, "max_fold_deg": mx, "binding": why,
                     "printable_fold_deg": pf, "printable_tilt_deg": ptilt, "printable_width_mm": pw,
                     "joints": len(p.joints), "tilt_deg": float(np.abs(tilts).max()) if tilts.size else 0.0,
                     "cells": [list(c) for c in p.cells]})
    return config, {"axes": rows, "closing_deg": math.degrees(phi_c)}


def configure(scene, strict=True):
    """Run the joint configuration and store it in ``scene.joint_config`` (replacing any old one).

    Returns a report: per axis its fold, maximum, what binds, tilts; the rotation limits after
    configuration (with what binds); the reverse fold at D = -1 per axis; warnings.
    """
    config, report = compute_joint_config(scene, strict=strict)
    warnings = []
    for name, ov in scene.joint_overrides.items():
        if "tilt_deg" in ov and name in config:
            warnings.append(f"joint {name}: its override tilt_deg = {ov['tilt_deg']} wins over the configured "
                            f"{config[name]['tilt_deg']:.3f} deg of axis {config[name]['axis']}")
    for row in report["axes"]:
        if abs(row["fold_deg"]) > row["printable_fold_deg"] + 1e-9:
            warnings.append(
                f"axis {row['axis']}: fold {row['fold_deg']:g} deg needs hinge tilts up to {row['tilt_deg']:.1f} deg, "
                f"but a {row['printable_width_mm']:g} mm wide hinge fits its node plate only up to "
                f"{max(row['printable_tilt_deg'], 0.0):.1f} deg (printable fold <= {row['printable_fold_deg']:.2f} deg); "
                f"`build` will reject it: use longer or narrower hinges, a thinner sheet, or set "
                f"fabrication.limit_design_tilt to make this a hard limit")
    scene.joint_config = config
    tilts = np.radians(effective_tilts_deg(scene))
    info = kin.rotation_limit_info(scene, tilts)
    par = kin.joint_parity(scene)
    topo = scene.topology
    for row in report["axes"]:
        names = [n for n, c in config.items() if c["axis"] == row["axis"]]
        if names:
            j = topo.joint_index[names[0]] if topo.n_joints < 10000 else _jid(topo, names[0])
            phi_rev = -par[j] * info["opening_rad"]
            phi_fwd = par[j] * info["closing_rad"]
            row["fold_at_D1_deg"] = float(np.degrees(kin.fold_from_tilt(tilts[j], phi_fwd)))
            row["fold_at_Dminus1_deg"] = float(np.degrees(kin.fold_from_tilt(tilts[j], phi_rev)))
    report["limits"] = info
    report["warnings"] = warnings
    return report


def _jid(topo, name):
    from metamaterial_wb.core.scene import parse_joint
    return topo.joint_id(*parse_joint(name))


def effective_tilts_deg(scene):
    """Signed tilt (deg) of every joint as the kinematics sees it.

    Per-joint overrides win, then ``scene.joint_config``; a scene with axes but no joint configuration
    is configured on the fly (without changing the scene).

    Parameters
    ----------
    scene : Scene

    Returns
    -------
    numpy.ndarray
        Shape ``(n_joints,)``, degrees, in topology joint order.
    """
    config = scene.joint_config
    if not config and scene.axes:
        config = compute_joint_config(scene)[0]
    return kin.tilts_from_config_deg(scene, config)


def joint_tilts_rad(scene):
    """:func:`effective_tilts_deg` in radians: what to pass as ``tilts_rad`` to core/kinematics.py.

    Parameters
    ----------
    scene : Scene

    Returns
    -------
    numpy.ndarray
        Shape ``(n_joints,)``, radians.
    """
    return np.radians(effective_tilts_deg(scene))


def kinematics_for(scene):
    """A :class:`core.kinematics.Kinematics` of ``scene`` with its effective tilts (configured on the
    fly when the scene has axes but no joint configuration).

    Parameters
    ----------
    scene : Scene

    Returns
    -------
    core.kinematics.Kinematics
    """
    return kin.Kinematics(scene, joint_tilts_rad(scene))


def rotation_limits(scene):
    """``(closing_rad, opening_rad)`` of ``scene`` with its effective tilts (:func:`joint_tilts_rad`).

    Parameters
    ----------
    scene : Scene

    Returns
    -------
    tuple of float
        Node rotation magnitudes at D = +1 and D = -1 (radians).
    """
    return kin.rotation_limits(scene, joint_tilts_rad(scene))


def ensure_configured(scene):
    """Configure a scene that has axes but no joint configuration (used by solve and render).

    A configuration written by ``design`` (its entries name their axis) that no longer matches the
    axes (an axis moved or its fold changed) is recomputed, with a warning in the returned report.
    A hand-written configuration (entries without ``"axis"``) is kept as it is. Returns the report
    of the configuration run, or None when nothing was done.
    """
    if not scene.axes:
        return None
    if not scene.joint_config:
        return configure(scene)
    if all("axis" in c for c in scene.joint_config.values()):
        want = compute_joint_config(scene)[0]
        same = set(want) == set(scene.joint_config) and all(
            abs(float(want[k]["tilt_deg"]) - float(scene.joint_config[k].get("tilt_deg", 0.0))) < 1e-6
            for k in want)
        if not same:
            report = configure(scene)
            report["warnings"].insert(0, "the scene's joint_config did not match its axes (stale design); "
                                         "it was recomputed - run `design` to store the new one")
            return report
    return None


def global_D(scene, g):
    """The seed's Global Deformation slider: every D = g in [-1, 1]."""
    g = check_number("global_deformation", g, -1.0, 1.0)
    return np.full(scene.topology.n_nodes, g)


def format_report(report):
    """Human-readable lines for the CLI."""
    lines = []
    for r in report["axes"]:
        lines.append(f"axis {r['axis']} ({r['direction']} line {r['line']}): fold {r['fold_deg']:g} deg at D=+1 "
                     f"(max +-{r['max_fold_deg']:.2f} deg, bound by {r['binding']}); {r['joints']} joints tilted "
                     f"up to {r['tilt_deg']:.2f} deg; fold at D=-1: {r.get('fold_at_Dminus1_deg', 0.0):.2f} deg")
    lim = report.get("limits")
    if lim:
        lines.append(f"node rotation at D=+1: {lim['closing_deg']:.3f} deg ({lim['closing_binding']}); "
                     f"at D=-1: {lim['opening_deg']:.3f} deg ({lim['opening_binding']})")
    for w in report.get("warnings", []):
        lines.append(f"warning: {w}")
    return lines


# ----------------------------------------------------------------------------------------------
# convenience entry points (GUI adapter, scripts)
# ----------------------------------------------------------------------------------------------
def validate_axes(scene):
    """Raise a SceneError naming the axes when the axes break a rule; return the plans otherwise."""
    return plan_axes(scene)


def max_folds_deg(scene):
    """Maximum achievable fold (deg, at D = +1) of every axis, in scene order."""
    phi_c = planar_closing_rad(scene)
    return [axis_limits(scene, p, phi_c)[0] for p in plan_axes(scene)]


def max_fold_deg(scene, axis_index):
    """Maximum achievable fold (deg, at D = +1) of axis number ``axis_index``."""
    plans = plan_axes(scene)
    if not 0 <= axis_index < len(plans):
        raise SceneError("axes", f"axis index {axis_index} is outside the allowed range [0, {len(plans) - 1}]")
    return axis_limits(scene, plans[axis_index])[0]


def configure_scene(scene, strict=True):
    """A configured copy of ``scene`` (the input is not changed)."""
    sc = scene.copy()
    configure(sc, strict=strict)
    return sc
