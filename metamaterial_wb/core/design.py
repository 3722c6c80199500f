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
  achievable fold of each axis is limited by the hinge tilt range (``MAX_TILT_DEG``, 80 deg), the hinge strain at
  D = +1 and plate contact across the fold (:func:`axis_limits`).
* Joint configuration: every crossed joint gets the hinge tilt that folds it by ``fold_deg`` at
  D = +1 (``tan(gamma/2) = -tan(alpha) sin(phi_A)``, docs/kinematics.md); stored in
  ``scene.joint_config`` as ``{"H0,1": {"tilt_deg": ..., "fold_deg": ..., "axis": ...}}``.
* Global deformation ``g``: every D = g (perfect propagation) gives the shapes between flat (0),
  the target (+1) and the reverse fold (-1).
"""
import math

import numpy as np

from metamaterial_wb.core import kinematics as kin
from metamaterial_wb.core.axes import AxisPlan, _runs, axis_label, plan_axes  # noqa: F401 - re-exported
from metamaterial_wb.core.errors import SceneError, check_number
from metamaterial_wb.core.numbers import inward  # noqa: F401 - re-exported (tests, callers of design.inward)


# ----------------------------------------------------------------------------------------------
# limits
# ----------------------------------------------------------------------------------------------
SLACK_DEG = 1e-9       # a fold this far beyond a maximum is still accepted (the maximum is computed)


def _fab_tilt(scene, widths, ignore_switch):
    """``(max printable tilt deg, width mm)`` of the narrowest-margin hinge among ``widths``."""
    from metamaterial_wb.core.fabrication import max_fabricable_tilt_deg

    ws = sorted(set(np.round(np.asarray(widths, dtype=float), 9).tolist()))
    if not ws:
        return 90.0, 0.0
    return min((max_fabricable_tilt_deg(scene, w, ignore_switch=ignore_switch), w) for w in ws)


def printable_fold_deg(scene, plan, phi_c=None):
    """``(fold deg, max tilt deg, width mm)``: the largest fold of an axis whose hinge tilts the
    default fabrication (core/fabrication.py) can print, whatever ``limit_design_tilt`` says.

    Parameters
    ----------
    scene : Scene
    plan : AxisPlan
    phi_c : float, optional
        Closing rotation of the untilted sheet (rad); default :func:`planar_closing_rad`.

    Returns
    -------
    tuple of float
        ``(fold_deg, max_tilt_deg, width_mm)``.
    """
    phi_c = planar_closing_rad(scene) if phi_c is None else phi_c
    _lh, wh, _th = kin.joint_hinge_arrays(scene)
    tilt, w = _fab_tilt(scene, wh[plan.joints], ignore_switch=True)
    fold = 2.0 * math.atan(math.tan(math.radians(max(tilt, 0.0))) * math.sin(phi_c))
    return math.degrees(fold), tilt, w


def planar_closing_rad(scene):
    """Node rotation at D = +1 of the untilted sheet (the state the target fold is defined in).

    Parameters
    ----------
    scene : Scene

    Returns
    -------
    float
        Radians.
    """
    return kin.rotation_limit_info(scene, np.zeros(scene.topology.n_joints))["closing_rad"]


def axis_limits(scene, plan, phi_c=None):
    """``(max_fold_deg, binding)`` of one axis at D = +1.

    Limits, per crossed joint: hinge tilt |alpha| <= 80 deg (fold ``2 atan(tan 80 sin phi_c)``),
    when the scene's ``fabrication.limit_design_tilt`` is true, the tilt that the printed hinge can
    have inside its node plate (``core.fabrication.max_fabricable_tilt_deg``; otherwise it is only
    reported, see :func:`printable_fold_deg`), hinge strain <= the scene's limit at D = +1, plate
    contact across the fold ``2 atan(lh / t)``.

    Parameters
    ----------
    scene : Scene
    plan : AxisPlan
    phi_c : float, optional
        Closing rotation of the untilted sheet (rad); default :func:`planar_closing_rad`.

    Returns
    -------
    tuple
        ``(max_fold_deg, binding)``: the limit (deg) and a text naming what binds.
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
                     f"{inward(max(fab[0], 0.0), 1)} deg (docs/fabrication.md)")]
    val, why = min(cands, key=lambda c: c[0])
    return math.degrees(val), why


# ----------------------------------------------------------------------------------------------
# joint configuration
# ----------------------------------------------------------------------------------------------
def compute_joint_config(scene, plans=None, strict=True):
    """``(joint_config, report)`` from the scene's axes; does not change the scene.

    ``strict``: a fold beyond the maximum is an error giving the maximum (else it is reported).

    Parameters
    ----------
    scene : Scene
    plans : list of AxisPlan, optional
        From :func:`plan_axes` (computed when omitted).
    strict : bool
        A fold beyond the maximum raises (else it is only reported).

    Returns
    -------
    tuple
        ``(joint_config, report)``: ``{joint: {"axis", "tilt_deg", "fold_deg"}}`` and the per-axis report.

    Raises
    ------
    SceneError
        Invalid axes, or (``strict``) a fold beyond an axis' maximum.
    """
    plans = plan_axes(scene) if plans is None else plans
    topo = scene.topology
    phi_c = planar_closing_rad(scene)
    par = kin.joint_parity(scene)
    config, rows = {}, []
    for p in plans:
        mx, why = axis_limits(scene, p, phi_c)
        if abs(p.fold_deg) > mx + SLACK_DEG:
            if strict:
                raise SceneError(f"axes[{p.index}].fold_deg",
                                 f"{p.fold_deg:g} deg on {p.label} is beyond the maximum achievable fold: "
                                 f"allowed range [-{inward(mx)}, {inward(mx)}] deg (bound by {why})")
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

    Parameters
    ----------
    scene : Scene
        Changed in place: its ``joint_config``.
    strict : bool
        See :func:`compute_joint_config`.

    Returns
    -------
    dict
        ``{"axes": [...], "closing_deg", "limits", "warnings"}``.
    """
    config, report = compute_joint_config(scene, strict=strict)
    warnings = []
    for name, cfg in hand_written(scene).items():     # kept: a tilt set by hand, on any joint
        if name in config:
            warnings.append(f"joint_config.{name}: its hand-written tilt_deg = {cfg.get('tilt_deg', 0.0):g} wins "
                            f"over the configured {config[name]['tilt_deg']:.3f} deg of axis {config[name]['axis']}")
        config[name] = dict(cfg)
    for name, ov in scene.joint_overrides.items():
        if "tilt_deg" in ov and "axis" in config.get(name, {}):
            warnings.append(f"joint {name}: its override tilt_deg = {ov['tilt_deg']} wins over the configured "
                            f"{config[name]['tilt_deg']:.3f} deg of axis {config[name]['axis']}")
    for row in report["axes"]:
        if abs(row["fold_deg"]) > row["printable_fold_deg"] + SLACK_DEG:
            # the need rounded up, the limits down: the text never reads "needs 32.5, fits 32.5"
            warnings.append(
                f"axis {row['axis']}: fold {row['fold_deg']:g} deg needs hinge tilts up to "
                f"{inward(row['tilt_deg'], 1, up=True, slack=0.0)} deg, "
                f"but a {row['printable_width_mm']:g} mm wide hinge fits its node plate only up to "
                f"{inward(max(row['printable_tilt_deg'], 0.0), 1)} deg "
                f"(printable fold <= {inward(row['printable_fold_deg'])} deg); "
                f"`build` will reject it: use longer or narrower hinges, a thinner sheet, or set "
                f"fabrication.limit_design_tilt to make this a hard limit")
    scene.joint_config = config
    tilts = np.radians(effective_tilts_deg(scene))
    info = kin.rotation_limit_info(scene, tilts)
    par = kin.joint_parity(scene)
    topo = scene.topology
    for row in report["axes"]:
        names = [n for n, c in config.items() if c.get("axis") == row["axis"]]
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

    Parameters
    ----------
    scene : Scene
        Changed in place when it needs configuring.

    Returns
    -------
    dict or None
        The report of :func:`configure`, or None.
    """
    if not scene.axes:
        return None
    if not scene.joint_config:
        return configure(scene)
    hand = hand_written(scene)
    designed = {k: c for k, c in scene.joint_config.items() if k not in hand}
    want = {k: c for k, c in compute_joint_config(scene)[0].items() if k not in hand}
    same = set(want) == set(designed) and all(
        abs(float(want[k]["tilt_deg"]) - float(designed[k].get("tilt_deg", 0.0))) < 1e-6 for k in want)
    if not same:
        report = configure(scene)
        report["warnings"].insert(0, "the scene's joint_config did not match its axes (stale design); "
                                     "it was recomputed - run `design` to store the new one")
        return report
    return None


def hand_written(scene):
    """The entries of ``scene.joint_config`` set by hand (without ``axis``): design keeps them, and they win over an
    axis' tilt on their joint."""
    return {k: c for k, c in scene.joint_config.items() if "axis" not in c}


def global_D(scene, g):
    """The seed's Global Deformation slider: every D = g in [-1, 1].

    Parameters
    ----------
    scene : Scene
    g : float
        Global deformation in [-1, 1].

    Returns
    -------
    numpy.ndarray
        Shape ``(n_nodes,)``.

    Raises
    ------
    SceneError
        ``g`` outside [-1, 1].
    """
    g = check_number("global_deformation", g, -1.0, 1.0)
    return np.full(scene.topology.n_nodes, g)


def format_report(report):
    """Human-readable lines for the CLI.

    Parameters
    ----------
    report : dict
        From :func:`configure`.

    Returns
    -------
    list of str
    """
    lines = []
    for r in report["axes"]:
        lines.append(f"axis {r['axis']} ({r['direction']} line {r['line']}): fold {r['fold_deg']:g} deg at D=+1 "
                     f"(max +-{inward(r['max_fold_deg'])} deg, bound by {r['binding']}"
                     + (f"; printable +-{inward(r['printable_fold_deg'])} deg" if "printable_fold_deg" in r else "")
                     + f"); {r['joints']} joints tilted "
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
    """Raise a SceneError naming the axes when the axes break a rule; return the plans otherwise.

    Parameters
    ----------
    scene : Scene

    Returns
    -------
    list of AxisPlan
    """
    return plan_axes(scene)


def suggest_axis(scene, fold_deg=30.0, tries=40):
    """An axis ``scene`` accepts, for a message to suggest (``{"direction", "line", "fold_deg"}``), or None.

    The lines with cells are tried from the middle of the layout out (vertical first, then horizontal), each
    checked as :func:`configure` checks it; the fold is ``fold_deg`` or, when the hinges cannot print that, the
    largest whole degree they can (so ``build`` takes it too), else the largest whole degree ``configure`` takes.

    Parameters
    ----------
    scene : Scene
        Not changed (a copy is tried).
    fold_deg : float, optional
    tries : int, optional
        At most this many lines are tried.

    Returns
    -------
    dict or None
    """
    from metamaterial_wb.core.scene import Axis

    ca = scene.topology.cell_array
    if len(ca) == 0:
        return None
    cands = []
    for direction, col in (("vertical", 1), ("horizontal", 0)):
        lines = sorted(set(int(v) for v in ca[:, col]))
        mid = (lines[0] + lines[-1]) / 2.0
        cands += [(direction, v) for v in sorted(lines, key=lambda v: (abs(v - mid), v))]
    for direction, line in cands[:tries]:
        sc = scene.copy()
        sc.axes = [Axis(direction, line, 0.0)]
        try:
            plan = plan_axes(sc)[0]
            phi_c = planar_closing_rad(sc)
            most = axis_limits(sc, plan, phi_c)[0]
            printable = printable_fold_deg(sc, plan, phi_c)[0]
        except SceneError:
            continue
        for fold, printed in ((fold_deg, True), (math.floor(printable), True), (math.floor(most), False)):
            if not 1 <= fold <= min(fold_deg, most) or (printed and fold > printable):
                continue
            sc.axes = [Axis(direction, line, float(fold))]
            try:
                configure(sc)
            except SceneError:
                continue
            return {"direction": direction, "line": line, "fold_deg": int(fold) if fold == int(fold) else fold}
    return None


def max_folds_deg(scene):
    """Maximum achievable fold (deg, at D = +1) of every axis, in scene order.

    Parameters
    ----------
    scene : Scene

    Returns
    -------
    list of float
    """
    phi_c = planar_closing_rad(scene)
    return [axis_limits(scene, p, phi_c)[0] for p in plan_axes(scene)]


def max_fold_deg(scene, axis_index):
    """Maximum achievable fold (deg, at D = +1) of axis number ``axis_index``.

    Parameters
    ----------
    scene : Scene
    axis_index : int

    Returns
    -------
    float
    """
    plans = plan_axes(scene)
    if not 0 <= axis_index < len(plans):
        raise SceneError("axes", f"axis index {axis_index} is outside the allowed range [0, {len(plans) - 1}]")
    return axis_limits(scene, plans[axis_index])[0]


def configure_scene(scene, strict=True):
    """A configured copy of ``scene`` (the input is not changed).

    Parameters
    ----------
    scene : Scene
    strict : bool
        See :func:`compute_joint_config`.

    Returns
    -------
    Scene
        A copy with ``joint_config`` set.
    """
    sc = scene.copy()
    configure(sc, strict=strict)
    return sc
