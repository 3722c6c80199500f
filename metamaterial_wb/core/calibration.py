"""Hinge sizes -> joint stiffness (k1, k2) of the quadratic model (seed eq. 1).

k1 comes from the hinge's flexible length, k2 from its cross-section, through the table in
``core/data/calibration.json`` (its ``source`` and ``assumptions`` say where the numbers come from).
Interpolation: piecewise linear in k1 over length; log-log linear for the k2 width factor (a power
law between table points), times thickness / reference thickness. A length or width outside the
table is an error that gives the table's range (no extrapolation, no silent clamping).
Per-joint ``k1`` / ``k2`` overrides in the scene win over the table.
"""
import os

import numpy as np

from metamaterial_wb.core.errors import SceneError, range_message

_DEFAULT_PATH = os.path.join(os.path.dirname(__file__), "data", "calibration.json")


class Calibration:
    def __init__(self, table):
        self.table = table
        try:
            self.len_mm = np.asarray(table["k1_vs_length"]["length_mm"], dtype=float)
            self.k1_tab = np.asarray(table["k1_vs_length"]["k1"], dtype=float)
            self.w_mm = np.asarray(table["k2_vs_width"]["width_mm"], dtype=float)
            self.w_fac = np.asarray(table["k2_vs_width"]["factor"], dtype=float)
            self.t_ref = float(table.get("k2_thickness_reference_mm", 7.0))
        except (KeyError, TypeError, ValueError, AttributeError, OverflowError):
            raise SceneError("calibration", "expected \"k1_vs_length\": {\"length_mm\": [...], \"k1\": [...]} and "
                                            "\"k2_vs_width\": {\"width_mm\": [...], \"factor\": [...]} (numbers)") from None
        if np.any(np.diff(self.len_mm) <= 0) or np.any(np.diff(self.w_mm) <= 0):
            raise SceneError("calibration", "table abscissae must increase strictly")
        for name, arr in (("k1_vs_length.length_mm", self.len_mm), ("k1_vs_length.k1", self.k1_tab),
                          ("k2_vs_width.width_mm", self.w_mm), ("k2_vs_width.factor", self.w_fac)):
            if arr.ndim != 1 or arr.size < 1 or not np.all(np.isfinite(arr)):
                raise SceneError(f"calibration.{name}", "expected a non-empty list of finite numbers")
        if self.len_mm.size != self.k1_tab.size or self.w_mm.size != self.w_fac.size:
            raise SceneError("calibration", "each table's abscissae and values must have the same length")
        if np.any(self.k1_tab < 0) or np.any(self.k1_tab > 1):
            raise SceneError("calibration.k1_vs_length.k1", "table values must satisfy 0 <= k1 <= 1")
        if np.any(self.w_fac < 1e-6) or np.any(self.w_fac > 1e6):
            raise SceneError("calibration.k2_vs_width.factor", "k2 factors must lie in [1e-06, 1e6] (k2 itself is "
                                                               "limited to [1e-9, 1e9])")
        if not (np.isfinite(self.t_ref) and 0.1 <= self.t_ref <= 100):
            raise SceneError("calibration.k2_thickness_reference_mm", range_message(self.t_ref, 0.1, 100, "mm"))

    @classmethod
    def load(cls, path=None):
        from metamaterial_wb.core.fileio import read_json

        return cls(read_json(path or _DEFAULT_PATH, "calibration table"))

    def k1(self, length_mm, where="hinge"):
        lo, hi = self.len_mm[0], self.len_mm[-1]
        if not (lo <= length_mm <= hi):
            raise SceneError(f"{where}.length_mm", range_message(length_mm, lo, hi, "mm") +
                             " of the calibration table (set k1 directly for other lengths)")
        return float(np.interp(length_mm, self.len_mm, self.k1_tab))

    def k2(self, width_mm, thickness_mm, where="hinge"):
        lo, hi = self.w_mm[0], self.w_mm[-1]
        if not (lo <= width_mm <= hi):
            raise SceneError(f"{where}.width_mm", range_message(width_mm, lo, hi, "mm") +
                             " of the calibration table (set k2 directly for other widths)")
        fac = np.exp(np.interp(np.log(width_mm), np.log(self.w_mm), np.log(self.w_fac)))
        return float(fac * thickness_mm / self.t_ref)


_DEFAULT = None


def default_calibration():
    global _DEFAULT
    if _DEFAULT is None:
        _DEFAULT = Calibration.load()
    return _DEFAULT


def joint_stiffness(scene, calibration=None):
    """Arrays ``(k1, k2)`` over ``scene.topology.joints`` (overrides win over the table).

    The default hinge is looked up in the table only for the values some joint still needs, so a
    scene whose every joint sets k1 (or k2) directly may use a base hinge outside the table.
    """
    from metamaterial_wb.core.scene import parse_joint

    cal = calibration or default_calibration()
    topo = scene.topology
    h = scene.hinge
    n = topo.n_joints
    ov_k1 = sum(1 for ov in scene.joint_overrides.values() if "k1" in ov)
    ov_k2 = sum(1 for ov in scene.joint_overrides.values() if "k2" in ov)
    k1 = np.full(n, cal.k1(h["length_mm"], "hinge") if ov_k1 < n else np.nan)
    k2 = np.full(n, cal.k2(h["width_mm"], h["thickness_mm"], "hinge") if ov_k2 < n else np.nan)
    for name, ov in scene.joint_overrides.items():
        idx = topo.joint_id(*parse_joint(name))
        hh = scene.joint_hinge(name)
        where = f"joints.{name}"
        k1[idx] = ov["k1"] if "k1" in ov else cal.k1(hh["length_mm"], where)
        k2[idx] = ov["k2"] if "k2" in ov else cal.k2(hh["width_mm"], hh["thickness_mm"], where)
    return k1, k2
