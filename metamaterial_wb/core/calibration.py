"""Hinge sizes -> joint stiffness (k1, k2) of the quadratic model (seed eq. 1).

k1 comes from the hinge's flexible length, k2 from its cross-section, through the table in
``core/data/calibration.json`` (its ``source`` and ``assumptions`` say where the numbers come from).
Interpolation: piecewise linear in k1 over length; log-log linear for the k2 width factor (a power
law between table points), times thickness / reference thickness. A length or width outside the
table is an error that gives the table's range (no extrapolation, no silent clamping) and how to set k1 / k2
directly; for a belt scene (``dynamics.model`` "belt", whose model never reads the hinge) it also points to
`simulate`.
Per-joint ``k1`` / ``k2`` overrides in the scene win over the table.
"""
import os

import numpy as np

from metamaterial_wb.core.errors import SceneError, check_number, range_message

_DEFAULT_PATH = os.path.join(os.path.dirname(__file__), "data", "calibration.json")


class Calibration:
    """A calibration table (the layout of ``core/data/calibration.json``), checked on construction.

    Every entry is a real number (a JSON ``true`` or a quoted ``"0.9"`` is refused, never converted), finite and in
    its range: lengths and widths > 0 mm and strictly increasing, k1 in [0, 1], k2 factors in [1e-6, 1e6], the
    reference thickness in [0.1, 100] mm; ``source`` is text or absent, ``assumptions`` a list of text or absent.
    Errors name the field with its index (``calibration.k1_vs_length.k1[0]``), the value and the range, and, with
    ``path``, the table file.
    """

    def __init__(self, table, path=None):
        try:
            self._check(table)
        except SceneError as exc:
            if path is None:
                raise
            raise SceneError(exc.field, f"{exc.message} (in {path})") from None
        self.table = table

    def _check(self, table):
        if not isinstance(table, dict):
            raise SceneError("calibration", f"expected a JSON object with \"k1_vs_length\" and \"k2_vs_width\", "
                                            f"got {type(table).__name__}")
        for key, what in (("source", "text"), ("assumptions", "a list of text")):
            if key not in table:
                continue
            v = table[key]
            ok = isinstance(v, str) if key == "source" else (isinstance(v, list) and
                                                             all(isinstance(x, str) for x in v))
            if not ok:
                raise SceneError(f"calibration.{key}", f"expected {what} (or no \"{key}\"), got {v!r}")
        cols = {}
        for sub, xkey, ykey in (("k1_vs_length", "length_mm", "k1"), ("k2_vs_width", "width_mm", "factor")):
            if sub not in table:
                raise SceneError(f"calibration.{sub}", f"missing; expected {{\"{xkey}\": [...], \"{ykey}\": [...]}} "
                                                       f"(numbers)")
            d = table[sub]
            if not isinstance(d, dict):
                raise SceneError(f"calibration.{sub}", f"expected {{\"{xkey}\": [...], \"{ykey}\": [...]}} "
                                                       f"(numbers), got {d!r}")
            for key in (xkey, ykey):
                v = d.get(key)
                if not isinstance(v, list) or not v:
                    raise SceneError(f"calibration.{sub}.{key}", f"expected a non-empty list of numbers, got {v!r}")
            if len(d[xkey]) != len(d[ykey]):
                raise SceneError(f"calibration.{sub}", f"\"{xkey}\" has {len(d[xkey])} entries and \"{ykey}\" "
                                                       f"{len(d[ykey])}; each abscissa needs one value")
            cols[sub] = d
        num = lambda sub, key, lo, hi, unit, lo_open=False: np.array(  # noqa: E731
            [check_number(f"calibration.{sub}.{key}[{i}]", v, lo, hi, unit, low_open=lo_open, exact=True)
             for i, v in enumerate(cols[sub][key])], dtype=float)
        self.len_mm = num("k1_vs_length", "length_mm", 0, None, "mm", True)
        self.k1_tab = num("k1_vs_length", "k1", 0, 1, "")
        self.w_mm = num("k2_vs_width", "width_mm", 0, None, "mm", True)
        # k2 itself is limited to [1e-9, 1e9]
        self.w_fac = num("k2_vs_width", "factor", 1e-6, 1e6, "")
        for sub, key, arr in (("k1_vs_length", "length_mm", self.len_mm), ("k2_vs_width", "width_mm", self.w_mm)):
            bad = np.flatnonzero(np.diff(arr) <= 0)
            if bad.size:
                i = int(bad[0]) + 1
                v, prev = cols[sub][key][i], cols[sub][key][i - 1]
                raise SceneError(f"calibration.{sub}.{key}[{i}]", f"{v!r} mm is not greater than the entry before "
                                                                  f"it ({prev!r} mm); the abscissae must increase "
                                                                  f"strictly")
        self.t_ref = check_number("calibration.k2_thickness_reference_mm", table.get("k2_thickness_reference_mm", 7.0),
                                  0.1, 100, "mm", exact=True)

    @classmethod
    def load(cls, path=None):
        from metamaterial_wb.core.inputfile import read_json

        path = path or _DEFAULT_PATH
        return cls(read_json(path, "calibration table"), path=path)

    def k1(self, length_mm, where="hinge", joint=None):
        """k1 of a hinge ``length_mm`` long; out of the table: SceneError at ``WHERE.length_mm`` (`` (JOINT)``)."""
        lo, hi = self.len_mm[0], self.len_mm[-1]
        if not (lo <= length_mm <= hi):
            raise SceneError(_field(where, "length_mm", joint), range_message(length_mm, lo, hi, "mm") +
                             " of the calibration table (set k1 directly for other lengths: "
                             "a \"k1\" per joint in \"joints\", docs/scene-format.md)")
        return float(np.interp(length_mm, self.len_mm, self.k1_tab))

    def k2(self, width_mm, thickness_mm, where="hinge", joint=None):
        lo, hi = self.w_mm[0], self.w_mm[-1]
        if not (lo <= width_mm <= hi):
            raise SceneError(_field(where, "width_mm", joint), range_message(width_mm, lo, hi, "mm") +
                             " of the calibration table (set k2 directly for other widths: "
                             "a \"k2\" per joint in \"joints\", docs/scene-format.md)")
        fac = np.exp(np.interp(np.log(width_mm), np.log(self.w_mm), np.log(self.w_fac)))
        return float(fac * thickness_mm / self.t_ref)


def _field(where, key, joint):
    """``hinge.length_mm``, or for an override ``joints[0].length_mm (H0,1)`` as the scene's own checks write it."""
    return f"{where}.{key}" + (f" ({joint})" if joint else "")


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
    cal = calibration or default_calibration()
    try:
        return _joint_stiffness(scene, cal)
    except SceneError as exc:
        hint = _belt_hint(scene) if (".length_mm" in exc.field or ".width_mm" in exc.field) else None
        if hint is None:
            raise
        raise SceneError(exc.field, f"{exc.message}; {hint}") from None


def _belt_hint(scene):
    """What to do with a belt scene (``dynamics.model`` "belt") whose hinge is outside the table, else None.

    The belt model never reads the hinge (its cells are ``dynamics.belt``), so such a scene is for `simulate`;
    the quadratic model (`solve`, `render`) sees only its hinge sheet.
    """
    dyn = getattr(scene, "extra", {}).get("dynamics")
    if not isinstance(dyn, dict):
        return None
    model = dyn.get("model")
    if not (model == "belt" or (model is None and dyn.get("belt") is not None)):
        return None
    name = getattr(scene, "name", "") or ""
    return (f"scene {name!r} is a belt (dynamics.model \"belt\"), whose model does not read the hinge: run it "
            f"with `simulate` (--frames draws it); `solve` and `render` model its hinge sheet and need hinges "
            f"in the table or k1 / k2 set on every joint")


def _joint_stiffness(scene, cal):
    from metamaterial_wb.core.scene import parse_joint

    topo = scene.topology
    h = scene.hinge
    n = topo.n_joints
    ov_k1 = sum(1 for ov in scene.joint_overrides.values() if "k1" in ov)
    ov_k2 = sum(1 for ov in scene.joint_overrides.values() if "k2" in ov)
    k1 = np.full(n, cal.k1(h["length_mm"], "hinge") if ov_k1 < n else np.nan)
    k2 = np.full(n, cal.k2(h["width_mm"], h["thickness_mm"], "hinge") if ov_k2 < n else np.nan)
    for k, (name, ov) in enumerate(scene.joint_overrides.items()):  # in the order of the scene's "joints"
        idx = topo.joint_id(*parse_joint(name))
        hh = scene.joint_hinge(name)
        where = f"joints[{k}]"
        k1[idx] = ov["k1"] if "k1" in ov else cal.k1(hh["length_mm"], where, name)
        k2[idx] = ov["k2"] if "k2" in ov else cal.k2(hh["width_mm"], hh["thickness_mm"], where, name)
    return k1, k2
