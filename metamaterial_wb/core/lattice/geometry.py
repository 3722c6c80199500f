"""Geometry and beam stiffness of the rigid-node / beam-hinge lattice (models "linear" and "nonlinear").

Every node ``N(i,j)`` is a rigid square plate of side ``s = cell_size - lh`` (``lh`` = the scene's hinge
length, which sets the gap between plates) centred at ``(j P, -i P, 0)`` with ``P`` the cell size, as in
``core/kinematics.py``. Every joint is a hinge beam that joins one corner of each plate along the edge
line (same checkerboard corner rule as ``core/kinematics.py``, so that D = +1 closes the cells).

Hinge frame (columns of ``Q0``, in the flat state): ``e1`` along the hinge from plate A to plate B,
``e2`` in-plane across the hinge (the width direction), ``e3`` the sheet normal (the thickness
direction). A tilted hinge (``scene.joint_tilt_deg(name)``, bending cells) has its cross-section
turned by the tilt ``alpha`` about ``e1``: ``e3' = cos(alpha) e3 - sin(alpha) e2``. Its soft bending axis
is ``e3'``, so a relative rotation ``psi`` of the two plates about ``e3'`` has an in-plane part
``psi cos(alpha)`` and an out-of-plane fold ``psi sin(alpha)`` about the in-plane axis across the hinge
(``e2``): the fold of the seed's bending cells (docs/fidelity.md, "Tilted hinges").

Beam: TPU Timoshenko beam of the joint's own flexible length ``L`` (``length_mm``), in-plane width
``w`` (``width_mm``) and out-of-plane thickness ``t`` (``thickness_mm``); modulus ``E`` from
``scene.material["hinge_modulus_MPa"]`` (default 26 MPa, TPU 95A) and Poisson ratio
``scene.material["hinge_poisson_ratio"]`` (default 0.45). The beam is clamped in plate A's hinge frame;
its deformation is ``eps = (u, Theta)``: ``u`` the position of B's hinge end in A's hinge frame minus
the rest chord, ``Theta`` the rotation vector of B's hinge frame relative to A's. The 6 x 6 stiffness
``K`` is the clamped-free (tip) stiffness of the beam: axial ``EA/L``, torsion ``GJ/L``, and two
bending blocks ``EI/((1+Phi) L^3) [[12, -+6L], [-+6L, (4+Phi) L^2]]`` with the shear parameter
``Phi = 12 EI / (kappa G A L^2)``.
"""
import math

import numpy as np

from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.core.numbers import inward_g
from metamaterial_wb.core.scene.sections import MATERIAL_FIELDS, material_value

DEFAULT_MODULUS_MPA = MATERIAL_FIELDS["hinge_modulus_MPa"][0]   # TPU 95A, tensile modulus (printed, datasheet)
DEFAULT_POISSON = MATERIAL_FIELDS["hinge_poisson_ratio"][0]
SHEAR_COEFFICIENT = 5.0 / 6.0   # rectangular section


def hinge_material(scene):
    return material_value(scene.material, "hinge_modulus_MPa"), material_value(scene.material, "hinge_poisson_ratio")


def torsion_constant(w, t):
    """Saint-Venant torsion constant of a w x t rectangle (mm^4), Roark's approximation."""
    b = np.minimum(w, t)
    h = np.maximum(w, t)
    r = b / h
    return h * b ** 3 * (1.0 / 3.0 - 0.21 * r * (1.0 - r ** 4 / 12.0))


def beam_tip_stiffness(L, w, t, E, nu):
    """(m, 6, 6) clamped-free stiffness in the hinge frame, DOF order (u1, u2, u3, T1, T2, T3)."""
    L = np.asarray(L, float)
    w = np.asarray(w, float)
    t = np.asarray(t, float)
    G = E / (2.0 * (1.0 + nu))
    A = w * t
    I3 = t * w ** 3 / 12.0      # in-plane bending (soft for w < t)
    I2 = w * t ** 3 / 12.0      # out-of-plane bending
    J = torsion_constant(w, t)
    m = L.size
    K = np.zeros((m, 6, 6))
    K[:, 0, 0] = E * A / L
    K[:, 3, 3] = G * J / L
    for (ui, ti, sgn, I) in ((1, 5, -1.0, I3), (2, 4, 1.0, I2)):
        phi = 12.0 * E * I / (SHEAR_COEFFICIENT * G * A * L ** 2)
        c = E * I / ((1.0 + phi) * L ** 3)
        K[:, ui, ui] = 12.0 * c
        K[:, ui, ti] = K[:, ti, ui] = sgn * 6.0 * L * c
        K[:, ti, ti] = (4.0 + phi) * L ** 2 * c
    return K


def scene_rotation_limits(scene, tilts_rad):
    """D = +-1 rotations: core/kinematics.rotation_limits (the same D scale as the quadratic model)."""
    from metamaterial_wb.core import kinematics
    return kinematics.rotation_limits(scene, tilts_rad)


class LatticeGeometry:
    """Arrays describing one scene's lattice (built once per scene; the models reuse it)."""

    def __init__(self, scene):
        topo = scene.topology
        self.scene = scene
        P = scene.cell_size_mm
        lh = scene.hinge["length_mm"]
        s = scene.plate_side_mm
        self.plate_side_mm = s
        self.cell_size_mm = P
        self.gap_mm = lh
        a = 0.5 * s
        ij = topo.node_ij()
        self.n = topo.n_nodes
        self.m = topo.n_joints
        self.X0 = np.column_stack([ij[:, 1] * P, -ij[:, 0] * P, np.zeros(self.n)]).astype(float)
        self.parity = np.where((ij[:, 0] + ij[:, 1]) % 2 == 0, 1.0, -1.0)
        self.a = topo.joint_pairs[:, 0].copy()
        self.b = topo.joint_pairs[:, 1].copy()
        m = self.m
        kinds = np.array([k == "H" for (k, _, _) in topo.joints], dtype=bool)
        ji = np.array([i for (_, i, _) in topo.joints], dtype=np.int64)
        jj = np.array([j for (_, _, j) in topo.joints], dtype=np.int64)
        sgn = np.where((ji + jj) % 2 == 0, 1.0, -1.0)
        self.is_h = kinds
        self.joint_parity = sgn
        rA = np.zeros((m, 3))
        rB = np.zeros((m, 3))
        rA[kinds] = np.column_stack([np.full(kinds.sum(), a), sgn[kinds] * a, np.zeros(kinds.sum())])
        rB[kinds] = np.column_stack([np.full(kinds.sum(), -a), sgn[kinds] * a, np.zeros(kinds.sum())])
        v = ~kinds
        rA[v] = np.column_stack([sgn[v] * a, np.full(v.sum(), -a), np.zeros(v.sum())])
        rB[v] = np.column_stack([sgn[v] * a, np.full(v.sum(), a), np.zeros(v.sum())])
        self.rA, self.rB = rA, rB
        e1 = np.zeros((m, 3))
        e1[kinds] = (1.0, 0.0, 0.0)
        e1[v] = (0.0, -1.0, 0.0)
        e3 = np.tile([0.0, 0.0, 1.0], (m, 1))
        e2 = np.cross(e3, e1)
        # per-joint hinge sizes and tilts
        L = np.empty(m)
        w = np.empty(m)
        t = np.empty(m)
        tilt = np.zeros(m)
        base = scene.hinge
        overrides = scene.joint_overrides
        config = scene.joint_config
        for k, name in enumerate(topo.joint_names):
            if name in overrides or name in config:
                h = scene.joint_hinge(name)
                L[k], w[k], t[k] = h["length_mm"], h["width_mm"], h["thickness_mm"]
                tilt[k] = math.radians(scene.joint_tilt_deg(name))
            else:
                L[k], w[k], t[k] = base["length_mm"], base["width_mm"], base["thickness_mm"]
        if scene.axes and not config:
            # axes but no joint configuration yet: the tilts the kinematics would use (design stage)
            from metamaterial_wb.core import design
            tilt = np.radians(design.effective_tilts_deg(scene))
        self.L, self.w, self.t = L, w, t
        self.tilt = tilt
        ca, sa = np.cos(tilt)[:, None], np.sin(tilt)[:, None]
        e2t = ca * e2 + sa * e3
        e3t = -sa * e2 + ca * e3
        self.Q0 = np.stack([e1, e2t, e3t], axis=2)     # (m, 3, 3): columns e1, e2', e3'
        self.planar = bool(np.all(tilt == 0.0))
        self.E, self.nu = hinge_material(scene)
        self.K = beam_tip_stiffness(L, w, t, self.E, self.nu)
        self.rest = lh                                  # rest chord along e1 (the gap between plates)
        self.arc_correction = True                      # exact pure bending at large hinge rotations
        # rotation limits (same rule as core/kinematics.rotation_limits, per scene)
        self.contact_rad = math.asin(min(1.0, lh / (2.0 * s)))   # plate contact (closing sense)
        self.closing_rad, self.opening_rad = scene_rotation_limits(scene, self.tilt)
        self.dofs = np.concatenate([6 * self.a[:, None] + np.arange(6), 6 * self.b[:, None] + np.arange(6)], axis=1)

    # -- helpers ---------------------------------------------------------------------------------
    def phi_max(self, D):
        return np.where(np.asarray(D) >= 0, self.closing_rad, self.opening_rad)

    def D_from_phi(self, phi):
        """Seed units from in-plane node rotations (radians, counter-clockwise)."""
        x = self.parity * np.asarray(phi, float)
        return x / np.where(x >= 0, self.closing_rad, self.opening_rad)

    def phi_from_D(self, D):
        D = np.asarray(D, float)
        return self.parity * D * self.phi_max(D)


def fixed_items(scene, geo):
    """Actuators and angular constraints as arrays: joint index, value, target relative rotation.

    The target is the rotation of plate B relative to plate A about the hinge's soft axis ``e3'`` that
    puts both nodes at the seed's D = value: in-plane ``phi_B - phi_A = -2 p_A value phi_max``, divided by
    ``cos(tilt)`` for a tilted hinge (only the in-plane part of a rotation about ``e3'`` is ``psi cos(tilt)``).
    """
    topo = scene.topology
    joints, values, names = [], [], []
    for kind, item in scene.fixed_items():
        from metamaterial_wb.core.scene import joint_name, parse_joint
        name = joint_name(*parse_joint(item.joint))
        joints.append(topo.joint_index[name])
        values.append(float(item.value))
        names.append(item.name)
    # two items on one joint (an actuator and a clip): the scene only allows that with equal values
    # (core/scene.check_fixed_conflicts), so they are one constraint here
    keep, seen = [], {}
    for k, (jn, v, n) in enumerate(zip(joints, values, names)):
        if jn in seen:
            if values[seen[jn]] != v:
                raise SceneError(n, f"joint {topo.joint_names[jn]} carries {names[seen[jn]]!r} = {values[seen[jn]]} "
                                    f"and {n!r} = {v}; a joint takes one value")
            continue
        seen[jn] = k
        keep.append(k)
    joints = np.asarray([joints[k] for k in keep], dtype=np.int64)
    values = np.asarray([values[k] for k in keep], dtype=float)
    names = [names[k] for k in keep]
    pA = geo.parity[geo.a[joints]] if joints.size else np.zeros(0)
    psi = hinge_target(geo.tilt[joints], values * geo.phi_max(values), pA) if joints.size else np.zeros(0)
    return joints, values, psi, names


def hinge_target(tilt, phi, parity):
    """Rotation of plate B relative to plate A about the hinge's soft axis that puts the joint in the
    rotating-squares mechanism with in-plane node rotations ``phi_A = p phi``, ``phi_B = -p phi``.

    Untilted: ``-2 p phi``. Tilted: the hinge also folds, ``tan(gamma/2) = -tan(tilt) sin(phi_A)``, and turns
    in all by ``psi`` with ``cos(psi/2) = cos(gamma/2) cos(phi)`` (core/kinematics, exact); for small angles
    ``psi ~ 2 phi / cos(tilt)``.
    """
    tilt = np.asarray(tilt, float)
    phi = np.asarray(phi, float)
    gamma = -2.0 * np.arctan(np.tan(tilt) * np.sin(parity * phi))
    c = np.cos(0.5 * gamma) * np.cos(phi)
    sn = np.sqrt(np.sin(0.5 * gamma) ** 2 + (np.cos(0.5 * gamma) * np.sin(phi)) ** 2)   # sqrt(1 - c^2), stable
    return -np.sign(parity * phi) * 2.0 * np.arctan2(sn, c)


_FE_LAW = None
FE_LAW_PATH = __import__("os").path.join(__import__("os").path.dirname(__file__), "..", "data", "fe_hinge_law.json")
HINGE_LAWS = ("beam", "fe")


def fe_hinge_factors(L, w, t):
    """(m, 6) FE / beam-theory stiffness factors per hinge DOF (u1, u2, u3, T1, T2, T3) from the CalculiX
    hinge study (``core/data/fe_hinge_law.json``), interpolated in the aspect ratio length / width (log scale).
    A hinge outside the calibrated aspect range is a SceneError; the section the factors were measured on
    (0.8 x 7 mm) is in the file's ``assumptions``."""
    global _FE_LAW
    if _FE_LAW is None:
        import json
        with open(FE_LAW_PATH) as f:
            _FE_LAW = json.load(f)
    rows = sorted(_FE_LAW["factors"], key=lambda r: r["aspect"])
    a = np.log([r["aspect"] for r in rows])
    F = np.array([r["fe_over_beam"] for r in rows])
    x = np.log(np.asarray(L, float) / np.asarray(w, float))
    lo, hi = a[0], a[-1]
    bad = (x < lo - 1e-9) | (x > hi + 1e-9)
    if np.any(bad):
        k = int(np.flatnonzero(bad)[0])
        # the range rounded inwards (its ends type back), the refused ratio outwards (it prints outside the range)
        r = inward_g(math.exp(x[k]), 6, up=bool(x[k] > hi))
        raise SceneError("--option hinge_law", f"fe: a hinge of length / width {r} is outside the FE-calibrated range "
                                               f"[{inward_g(math.exp(lo), up=True, slack=1e-10)}, "
                                               f"{inward_g(math.exp(hi), slack=1e-10)}]")
    return np.column_stack([np.interp(x, a, F[:, d]) for d in range(6)])


def apply_hinge_law(geo, law):
    """Set the hinge law of ``geo``: ``"beam"`` (default, Timoshenko beam theory) or ``"fe"`` (the beam stiffness
    scaled per DOF to the CalculiX hinge: ``K <- S K S`` with ``S = diag(sqrt(factors))``, so the diagonal takes
    the FE values and the couplings the geometric mean)."""
    law = "beam" if law is None else law
    if law not in HINGE_LAWS:
        raise SceneError("--option hinge_law", f"{law!r}; allowed: {', '.join(HINGE_LAWS)}")
    geo.hinge_law = law
    if law == "fe":
        f = fe_hinge_factors(geo.L, geo.w, geo.t)
        s = np.sqrt(f)
        geo.K = geo.K * s[:, :, None] * s[:, None, :]
        geo.hinge_law_factors = f
    return geo
