"""The angle a servo must turn: the simulated relative rotation of its actuated joint (issue 16, item 9).

An actuator of value ``v`` fixes D = v on both nodes of its joint; the lattice models and dynamics (and the
quadratic kinematics on an untilted joint; on a tilted one its least-squares fold frames turn up to 3.6 % less)
then hold the joint's plate B, relative to plate A, at the rotation about the hinge axis that puts the joint in
the rotating-squares mechanism (``core/lattice/geometry.hinge_target``)::

    untilted joint:  rel = phi_B - phi_A = -2 p_A v phi_max(sign v)
    tilted joint:    |rel| = psi with cos(psi/2) = cos(gamma/2) cos(phi),  tan(gamma/2) = -tan(tilt) sin(phi_A)

``phi_max(+)`` is the closing limit (plate contact ``asin(lh/2s)``, hinge strain, fold contact) and
``phi_max(-)`` the opening limit (45 deg, ...) of ``core/kinematics.rotation_limits``; ``p_A`` the
checkerboard parity of node A. The sign is the servo's: counter-clockwise positive about the shaft, which
points out of plate A's top face along the hinge axis (a servo mounted from below: ``invert``). This is what the
solver reports as ``joints[].hinge_rotation_deg`` (unsigned there), so the servo is told what was simulated,
not ``v * 90 deg`` (at v = 1 a 2 mm-hinge joint closes by 6.4 deg: 90 deg would drive it 14x past plate contact).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from metamaterial_wb.core.errors import SceneError


@dataclass(frozen=True)
class JointRotation:
    joint: str
    tilt_rad: float
    parity_a: float
    closing_rad: float
    opening_rad: float

    def angle_rad(self, v):
        from metamaterial_wb.core.lattice.geometry import hinge_target

        v = np.asarray(v, dtype=float)
        phi = v * np.where(v >= 0, self.closing_rad, self.opening_rad)
        return hinge_target(np.full(v.shape, self.tilt_rad), phi, np.full(v.shape, self.parity_a))

    def angle_deg(self, v):
        """Signed relative rotation (degrees) of the joint for actuator value(s) v in [-1, 1]."""
        out = np.degrees(self.angle_rad(v))
        return float(out) if np.ndim(out) == 0 else out

    def range_deg(self):
        """(lo, hi): the joint's kinematic range, plate contact (v = +1) to full opening (v = -1), ordered."""
        a, b = self.angle_deg(1.0), self.angle_deg(-1.0)
        return (min(a, b), max(a, b))


def joint_rotation(scene, joint, field_name="joint"):
    """The :class:`JointRotation` of ``joint`` (a name such as ``"V0,2"``) of ``scene``."""
    from metamaterial_wb.core import design, kinematics
    from metamaterial_wb.core.scene import joint_name, parse_joint

    name = joint_name(*parse_joint(joint, field_name))
    topo = scene.topology
    if name not in topo.joint_index:
        raise SceneError(field_name, f"{joint!r} is not a joint of the {scene.topology.n_nodes}-node sheet")
    k = topo.joint_index[name]
    tilts = design.joint_tilts_rad(scene)
    closing, opening = kinematics.rotation_limits(scene, tilts)
    tilt = float(tilts[k])
    a = int(topo.joint_pairs[k][0])
    parity = float(kinematics.node_parity(scene)[a])
    if not (math.isfinite(closing) and math.isfinite(opening)):
        raise SceneError(field_name, f"joint {name}: rotation limits {closing!r} / {opening!r} rad are not finite")
    return JointRotation(name, tilt, parity, float(closing), float(opening))


def signed_joint_rotation_deg(scene, rotations, joint):
    """Signed relative rotation of ``joint`` measured from a result's node rotations (3x3 matrices): the
    magnitude of ``log(R_A^T R_B)`` (the solver's ``hinge_rotation_deg``), its sign from the rotation vector's
    component along plate A's normal. An independent check of :meth:`JointRotation.angle_deg`."""
    from metamaterial_wb.core.kinematics import rotation_log
    from metamaterial_wb.core.scene import joint_name, parse_joint

    topo = scene.topology
    k = topo.joint_index[joint_name(*parse_joint(joint))]
    a, b = topo.joint_pairs[k]
    R = np.asarray(rotations, dtype=float)
    w = rotation_log((R[a].T @ R[b])[None])[0]
    return math.copysign(math.degrees(float(np.linalg.norm(w))), float(w[2]) if w[2] != 0 else 1.0)
