"""Per-joint data, the tilted hinge's closed forms and the rotation limits of the sheet (the scalar half of
the kinematics, docs/kinematics.md; :mod:`core.kinematics` re-exports every name).

The hinge tilts are always given (``tilts_rad``) or read from the scene as stored (per-joint overrides, else
``joint_config``): the design stage, which sits above, configures a scene that has axes but no joint
configuration and passes its tilts down (``core.design.joint_tilts_rad``).
"""
import math

import numpy as np

from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.core.scene.names import MAX_TILT_DEG  # noqa: F401 - the scene format's tilt range
from metamaterial_wb.core.scene.sections import MATERIAL_FIELDS, material_value

OPENING_LIMIT_RAD = math.pi / 4       # widest pitch of the rotating-squares mechanism
DEFAULT_HINGE_STRAIN_LIMIT = MATERIAL_FIELDS["hinge_strain_limit"][0]  # peak bending strain of a TPU hinge
_TILT_EPS = 1e-12


# ----------------------------------------------------------------------------------------------
# per-joint data
# ----------------------------------------------------------------------------------------------
def plate_side_mm(scene):
    """``scene.plate_side_mm`` (kept for callers): the side of every node plate, mm.

    Parameters
    ----------
    scene : Scene

    Returns
    -------
    float
    """
    return scene.plate_side_mm


def hinge_strain_limit(scene):
    """Peak bending strain a hinge may take (``scene.material.hinge_strain_limit``, default 0.5).

    Parameters
    ----------
    scene : Scene

    Returns
    -------
    float

    Raises
    ------
    SceneError
        A value outside (0, 5] (``core.scene.sections.MATERIAL_FIELDS``).
    """
    return material_value(scene.material, "hinge_strain_limit")


def joint_hinge_arrays(scene):
    """Per joint ``(length_mm, width_mm, thickness_mm)`` arrays with per-joint overrides applied.

    Parameters
    ----------
    scene : Scene

    Returns
    -------
    tuple of numpy.ndarray
        ``(length_mm, width_mm, thickness_mm)``, each of shape ``(n_joints,)``.
    """
    m = scene.topology.n_joints
    lh = np.full(m, float(scene.hinge["length_mm"]))
    wh = np.full(m, float(scene.hinge["width_mm"]))
    th = np.full(m, float(scene.hinge["thickness_mm"]))
    for name, ov in scene.joint_overrides.items():
        if not any(k in ov for k in ("length_mm", "width_mm", "thickness_mm")):
            continue
        k = _joint_index(scene, name)
        lh[k] = ov.get("length_mm", lh[k])
        wh[k] = ov.get("width_mm", wh[k])
        th[k] = ov.get("thickness_mm", th[k])
    return lh, wh, th


def _joint_index(scene, name):
    from metamaterial_wb.core.scene import parse_joint
    kind, i, j = parse_joint(name)
    return scene.topology.joint_id(kind, i, j)


def tilts_from_config_deg(scene, config):
    """Signed tilt (deg) of every joint from a joint configuration ``config`` (``{joint: {"tilt_deg":
    ...}}``) with the scene's per-joint ``tilt_deg`` overrides winning.

    Parameters
    ----------
    scene : Scene
    config : dict
        Joint name -> configuration entry (``scene.joint_config`` or a freshly computed one).

    Returns
    -------
    numpy.ndarray
        Shape ``(n_joints,)``, degrees, in topology joint order.
    """
    from metamaterial_wb.core.scene import parse_joint
    topo = scene.topology
    t = np.zeros(topo.n_joints)
    for name, cfg in config.items():
        if "tilt_deg" in cfg:
            t[topo.joint_id(*parse_joint(name))] = float(cfg["tilt_deg"])
    for name, ov in scene.joint_overrides.items():
        if "tilt_deg" in ov:
            t[topo.joint_id(*parse_joint(name))] = float(ov["tilt_deg"])
    return t


def stored_tilts_rad(scene):
    """Signed tilt (rad) of every joint as stored in the scene (overrides, else ``joint_config``).

    The kinematics never configures a scene itself (that is the design stage, which sits above it):
    a scene with rotary axes but no joint configuration raises; pass the tilts of
    ``core.design.joint_tilts_rad(scene)`` instead.

    Parameters
    ----------
    scene : Scene

    Returns
    -------
    numpy.ndarray
        Shape ``(n_joints,)``, radians.

    Raises
    ------
    SceneError
        ``joint_config`` when the scene has axes but no joint configuration.
    """
    if scene.axes and not scene.joint_config:
        raise SceneError("joint_config", f"scene {getattr(scene, 'name', '') or ''!r} has {len(scene.axes)} rotary "
                                         f"axes but no joint configuration: run `design` on it, or pass the tilts "
                                         f"(core.design.joint_tilts_rad(scene))")
    return np.radians(tilts_from_config_deg(scene, scene.joint_config))


def _tilts(scene, tilts_rad):
    return stored_tilts_rad(scene) if tilts_rad is None else np.asarray(tilts_rad, dtype=float)


def joint_parity(scene):
    """+1 where the first node of the joint has even i+j, else -1.

    Parameters
    ----------
    scene : Scene

    Returns
    -------
    numpy.ndarray
        Shape ``(n_joints,)``, values +-1.
    """
    ij = scene.topology.joint_ij()
    return np.where((ij[:, 0] + ij[:, 1]) % 2 == 0, 1.0, -1.0)


def joint_fold_vectors(scene):
    """Fold vector ``f = u x z`` of every joint (flat frame): -y for H joints, -x for V joints.

    Parameters
    ----------
    scene : Scene

    Returns
    -------
    numpy.ndarray
        Shape ``(n_joints, 3)``.
    """
    topo = scene.topology
    f = np.zeros((topo.n_joints, 3))
    f[:topo.n_h, 1] = -1.0
    f[topo.n_h:, 0] = -1.0
    return f


# ----------------------------------------------------------------------------------------------
# the tilted hinge (closed forms)
# ----------------------------------------------------------------------------------------------
def fold_from_tilt(tilt_rad, phi_a_rad):
    """Fold (rad) of a joint with tilt ``alpha`` when its first node turns in plane by ``phi_A``
    and its second by ``-phi_A``: ``tan(gamma/2) = -tan(alpha) sin(phi_A)`` (exact).

    Parameters
    ----------
    tilt_rad : array_like
        Hinge tilt ``alpha``.
    phi_a_rad : array_like
        In-plane rotation of the joint's first node.

    Returns
    -------
    numpy.ndarray
        Fold ``gamma`` (rad).
    """
    return -2.0 * np.arctan(np.tan(tilt_rad) * np.sin(phi_a_rad))


def tilt_for_fold(fold_rad, phi_a_rad):
    """Inverse of :func:`fold_from_tilt`: the tilt that gives ``fold`` at ``phi_A`` (phi_A != 0).

    Parameters
    ----------
    fold_rad : array_like
    phi_a_rad : float
        Non-zero.

    Returns
    -------
    numpy.ndarray
        Tilt (rad).
    """
    return np.arctan(-np.tan(0.5 * np.asarray(fold_rad)) / np.sin(phi_a_rad))


def hinge_rotation(fold_rad, phi_rad):
    """Total rotation ``psi`` of a hinge: ``cos(psi/2) = cos(gamma/2) cos(phi)``.

    Parameters
    ----------
    fold_rad : array_like
    phi_rad : array_like
        In-plane rotation of the node.

    Returns
    -------
    numpy.ndarray
        ``psi`` (rad).
    """
    c = np.cos(0.5 * np.asarray(fold_rad)) * np.cos(phi_rad)
    return 2.0 * np.arccos(np.clip(c, -1.0, 1.0))


def hinge_strain(psi_rad, width_mm, length_mm):
    """Peak bending strain of a flexure of in-plane width ``w`` bent by ``psi`` over length ``lh``
    (uniform curvature): ``w psi / (2 lh)``. For a tilted hinge the flexure wall turns with its axis,
    so the same width bends (docs/kinematics.md).

    Parameters
    ----------
    psi_rad, width_mm, length_mm : array_like

    Returns
    -------
    numpy.ndarray
        Strain (dimensionless).
    """
    return np.asarray(width_mm) * np.asarray(psi_rad) / (2.0 * np.asarray(length_mm))


def fold_contact_rad(length_mm, thickness_mm):
    """Fold at which the plates (thickness t, hinge at mid-thickness, gap lh) meet across a bending
    joint: ``2 atan(lh / t)``.

    Parameters
    ----------
    length_mm, thickness_mm : array_like

    Returns
    -------
    numpy.ndarray
        Fold (rad).
    """
    return 2.0 * np.arctan(np.asarray(length_mm) / np.asarray(thickness_mm))


def _phi_limit_strain(tilt, wh, lh, eps):
    """Largest in-plane rotation whose hinge strain stays <= eps for hinges of tilt ``tilt``."""
    psi_max = 2.0 * lh * eps / wh
    c = np.cos(0.5 * np.minimum(psi_max, math.pi))
    t2 = np.tan(tilt) ** 2
    s2 = (1.0 - c * c) / (1.0 + c * c * t2)
    out = np.arcsin(np.sqrt(np.clip(s2, 0.0, 1.0)))
    return np.where(psi_max >= math.pi, math.pi / 2, out)


def _phi_limit_fold_contact(tilt, lh, th):
    """Largest in-plane rotation before the fold of a tilted joint reaches plate contact."""
    t = np.abs(np.tan(tilt))
    with np.errstate(divide="ignore"):
        s = np.where(t > _TILT_EPS, (lh / th) / np.maximum(t, _TILT_EPS), np.inf)
    return np.where(s >= 1.0, math.pi / 2, np.arcsin(np.minimum(s, 1.0)))


# ----------------------------------------------------------------------------------------------
# rotation limits
# ----------------------------------------------------------------------------------------------
def rotation_limit_info(scene, tilts_rad=None):
    """The node rotation at D = +1 (closing) and D = -1 (opening), with what binds.

    Closing: plate contact ``asin(lh / 2s)``, hinge strain (every joint, its own sizes and tilt),
    fold contact of tilted joints. Opening: the mechanism's 45 degrees, hinge strain, fold contact.
    One limit for the whole sheet (the smallest), so that uniform D is the exact mechanism.

    Parameters
    ----------
    scene : Scene
    tilts_rad : array_like, optional
        Signed hinge tilt (rad) of every joint; default the scene's stored tilts (:func:`stored_tilts_rad`,
        which raises for a scene with axes but no joint configuration: pass ``core.design.joint_tilts_rad``).

    Returns
    -------
    dict
        ``closing_rad``, ``opening_rad`` (and in degrees), ``closing_binding``, ``opening_binding`` (texts),
        ``plate_contact_deg``, ``hinge_strain_limit``.
    """
    lh, wh, th = joint_hinge_arrays(scene)
    tilt = _tilts(scene, tilts_rad)
    eps = hinge_strain_limit(scene)
    s = plate_side_mm(scene)
    lh0 = scene.hinge["length_mm"]
    contact = math.asin(min(1.0, lh0 / (2.0 * s)))
    strain = _phi_limit_strain(tilt, wh, lh, eps) if len(lh) else np.array([math.pi / 2])
    fold = _phi_limit_fold_contact(tilt, lh, th) if len(lh) else np.array([math.pi / 2])

    def jname(k):
        topo = scene.topology
        i, j = topo.joint_ij()[k]
        return f"{'H' if k < topo.n_h else 'V'}{int(i)},{int(j)}"

    def pick(cands):
        label, val = min(cands, key=lambda c: c[1])
        return val, label

    ks, kf = int(np.argmin(strain)), int(np.argmin(fold))
    closing, closing_by = pick([
        (f"plate contact asin(lh/2s) = asin({lh0:g}/(2*{s:g}))", contact),
        (f"hinge strain {eps:g} at joint {jname(ks)}", float(strain[ks])),
        (f"fold contact 2 atan(lh/t) of tilted joint {jname(kf)}", float(fold[kf]))])
    opening, opening_by = pick([
        ("mechanism (45 deg, widest pitch)", OPENING_LIMIT_RAD),
        (f"hinge strain {eps:g} at joint {jname(ks)}", float(strain[ks])),
        (f"fold contact 2 atan(lh/t) of tilted joint {jname(kf)}", float(fold[kf]))])
    return {"closing_rad": float(closing), "opening_rad": float(opening),
            "closing_deg": math.degrees(closing), "opening_deg": math.degrees(opening),
            "closing_binding": closing_by, "opening_binding": opening_by,
            "plate_contact_deg": math.degrees(contact), "hinge_strain_limit": eps}


def rotation_limits(scene, tilts_rad=None):
    """``(closing_rad, opening_rad)``: the node rotation at D = +1 and D = -1 (magnitudes).

    Parameters
    ----------
    scene : Scene
    tilts_rad : array_like, optional
        Signed hinge tilt (rad) of every joint; default the scene's stored tilts (:func:`stored_tilts_rad`,
        which raises for a scene with axes but no joint configuration: pass ``core.design.joint_tilts_rad``).

    Returns
    -------
    tuple of float
    """
    info = rotation_limit_info(scene, tilts_rad)
    return info["closing_rad"], info["opening_rad"]


def node_parity(scene):
    """+1 where a node's i + j is even, else -1.

    Parameters
    ----------
    scene : Scene

    Returns
    -------
    numpy.ndarray
        Shape ``(n_nodes,)``.
    """
    ij = scene.topology.node_ij()
    return np.where((ij[:, 0] + ij[:, 1]) % 2 == 0, 1.0, -1.0)


def node_angles(scene, D, limits=None):
    """In-plane rotation (radians, counter-clockwise positive) of every node for a D field.

    Parameters
    ----------
    scene : Scene
    D : array_like
        Shape ``(n_nodes,)``, values in [-1, 1].
    limits : tuple of float, optional
        ``(closing_rad, opening_rad)``; default :func:`rotation_limits` with the scene's stored tilts.

    Returns
    -------
    numpy.ndarray
        Shape ``(n_nodes,)``, radians.

    Raises
    ------
    SceneError
        A wrong shape or a value outside [-1, 1].
    """
    D = np.asarray(D, dtype=float)
    n = scene.topology.n_nodes
    if D.shape != (n,):
        raise SceneError("D", f"expected {n} values (one per node), got shape {D.shape}")
    bad = ~np.isfinite(D) | (np.abs(D) > 1 + 1e-12)
    if np.any(bad):
        k = int(np.flatnonzero(bad)[0])
        i, j = scene.topology.node_ij()[k]
        raise SceneError("D", f"node N{i},{j} has D = {D[k]!r}, outside the allowed range [-1, 1]")
    closing, opening = limits if limits is not None else rotation_limits(scene)
    mag = np.where(D >= 0, closing, opening)
    return node_parity(scene) * D * mag


def uniform_pitch_mm(scene, D, limits=None):
    """Closed-form node pitch for a uniform D (rotating squares with finite hinges).

    Parameters
    ----------
    scene : Scene
    D : float
        The uniform deformation, in [-1, 1].
    limits : tuple of float, optional
        ``(closing_rad, opening_rad)``; default :func:`rotation_limits` with the scene's stored tilts.

    Returns
    -------
    float
    """
    lh = scene.hinge["length_mm"]
    s = plate_side_mm(scene)
    closing, opening = limits if limits is not None else rotation_limits(scene)
    if D >= 0:
        phi = D * closing
        return lh + s * (math.cos(phi) - math.sin(phi))
    phi = -D * opening
    return lh + s * (math.cos(phi) + math.sin(phi))


def uniform_fold_deg(tilt_deg, phi_a_deg):
    """Fold of one joint for uniform deformation (degrees), see :func:`fold_from_tilt`.

    Parameters
    ----------
    tilt_deg, phi_a_deg : float

    Returns
    -------
    float
    """
    return float(np.degrees(fold_from_tilt(math.radians(tilt_deg), math.radians(phi_a_deg))))
