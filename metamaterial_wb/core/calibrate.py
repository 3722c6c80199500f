"""Calibration of the quadratic model's (k1, k2) per hinge size (docs/calibration.md).

The seed (section 3.2) printed test pieces, fixed some joints with angular constraints and fitted
k1, k2 per hinge size to the measured deformation. This module does the same against two sources:

* the nonlinear lattice model (:func:`fit_table_to_model`, which regenerates
  ``core/data/calibration.json``), and
* node angles a user measured on a printed test piece (:func:`fit_measured`, CSV ``node,angle_deg``).

Fit measure: node angles in D units after removing the least-squares rigid rotation (the same
measure as docs/fidelity.md), over the nodes that are not held by a constraint. k1 is fitted on a
test piece with one hinge size; the k2 factor of a width is fitted on a test piece whose right half
has that width and whose left half has the reference width (only ratios of k2 matter).
"""
import csv
import math
import re

import numpy as np
from scipy.optimize import minimize_scalar

from metamaterial_wb.core.errors import MetamaterialError, SceneError, check_number, range_message
from metamaterial_wb.core.numbers import parse_float
from metamaterial_wb.core.scene import Scene, joint_nodes, parse_joint
from metamaterial_wb.core.scene.names import plate_side_mm

REFERENCE_WIDTH_MM = 0.8
REFERENCE_THICKNESS_MM = 7.0
DEFAULT_LENGTHS_MM = (0.25, 0.5, 1.0, 2.0, 3.0, 4.0, 6.0, 8.0, 9.5)
DEFAULT_WIDTHS_MM = (0.2, 0.4, 0.6, 0.8, 1.0, 1.2, 1.6, 2.0, 3.0, 4.0)
TEST_PIECE = {"rows": 5, "cols": 5, "joint": "H2,2", "value": 0.3}
# the set of printed layouts the k1 fit uses (a chain, two strips, a square), each with one clip
TEST_PIECES = ({"rows": 1, "cols": 8, "joint": "V0,1", "value": 0.3},
               {"rows": 2, "cols": 6, "joint": "H1,2", "value": 0.3},
               {"rows": 3, "cols": 6, "joint": "H1,2", "value": 0.3},
               {"rows": 5, "cols": 5, "joint": "H2,2", "value": 0.3})
MIXED_PIECE = {"rows": 5, "cols": 6, "joint": "H2,1", "value": 0.3}
CELL_SIZE_MM = 20.0          # the test pieces' cell pitch
WIDTH_FIT_LENGTH_MM = 2.0    # hinge length of the k2 (width) fit
# Sizes the model fit accepts. Lower bound: 0.1 mm, the finest nozzle core/fabrication accepts (a thinner gap or
# hinge cannot be printed; far below it the D scale underflows: the closing limit is 0 for a 1e-8 mm hinge and the
# fit is NaN, the lattice model stops converging for a 1e-6 mm width). Upper bounds: the scene's hinge checks
# (length < cell / 2, width <= plate side / 4 at the width fit's 2 mm length).
MIN_SIZE_MM = 0.1
MAX_LENGTH_MM = 0.5 * CELL_SIZE_MM
MAX_WIDTH_MM = 0.25 * plate_side_mm(CELL_SIZE_MM, WIDTH_FIT_LENGTH_MM)
# search ranges of the measured fit; a result within these tolerances of a bound is refused (not determined)
K1_BOUNDS = (0.0, 1.0)
LOG10_K2_RATIO_BOUNDS = (-4.0, 4.0)
_K1_BOUND_TOL = 1e-6
_LOG10_RATIO_BOUND_TOL = 1e-3


# ----------------------------------------------------------------------------------------------------
# test pieces
# ----------------------------------------------------------------------------------------------------
def test_piece(length_mm, width_mm=REFERENCE_WIDTH_MM, thickness_mm=REFERENCE_THICKNESS_MM, right_width_mm=None,
               rows=None, cols=None, joint=None, value=None, cell_size_mm=CELL_SIZE_MM):
    """The k1 test piece: 5 x 5 cells with one angular constraint (D = 0.3) on the central joint H2,2.

    With ``right_width_mm``: the mixed piece, 5 x 6 cells whose right half (columns >= 3) has hinges of
    that width, constraint on H2,1 in the left half (used to check a k2 ratio on the D field).
    """
    spec = dict(MIXED_PIECE if right_width_mm is not None else TEST_PIECE)
    for k, v in (("rows", rows), ("cols", cols), ("joint", joint), ("value", value)):
        if v is not None:
            spec[k] = v
    rows, cols = spec["rows"], spec["cols"]
    d = {"format": "metamaterial-scene", "version": 1, "name": "calibration-test-piece",
         "cell_size_mm": cell_size_mm,
         "hinge": {"length_mm": length_mm, "width_mm": width_mm, "thickness_mm": thickness_mm},
         "layout": {"grid": [rows, cols]},
         "constraints": [{"name": "clip", "joint": spec["joint"], "value": spec["value"]}]}
    if right_width_mm is not None:
        half = cols // 2
        joints = []
        for r in range(rows + 1):
            for c in range(half, cols):
                joints.append({"joint": f"H{r},{c}", "width_mm": right_width_mm})
        for r in range(rows):
            for c in range(half + 1, cols + 1):
                joints.append({"joint": f"V{r},{c}", "width_mm": right_width_mm})
        d["joints"] = joints
    return Scene.from_dict(d)


def check_sizes(lengths, widths, length_field="lengths", width_field="widths"):
    """Check the model fit's hinge sizes before any work: every length in [MIN_SIZE_MM, MAX_LENGTH_MM), every
    width in [MIN_SIZE_MM, MAX_WIDTH_MM] (finite). Raises a SceneError naming the field, the value and the range."""
    cells = f"{CELL_SIZE_MM:g} mm cells"
    for field, vals, high, high_open, why in (
            (length_field, lengths, MAX_LENGTH_MM, True, f"hinge length below cell / 2 of {cells}"),
            (width_field, widths, MAX_WIDTH_MM, False, f"hinge width at most plate side / 4 of {cells} with the "
                                                       f"width fit's {WIDTH_FIT_LENGTH_MM:g} mm hinges")):
        for v in vals:
            try:
                check_number(field, v, MIN_SIZE_MM, high, "mm", high_open=high_open)
            except SceneError:
                raise SceneError(field, range_message(v, MIN_SIZE_MM, high, "mm", high_open=high_open) +
                                 f" ({why}; at least {MIN_SIZE_MM:g} mm, the finest nozzle, for a meaningful "
                                 f"fit)") from None


# ----------------------------------------------------------------------------------------------------
# fitting machinery
# ----------------------------------------------------------------------------------------------------
class _Fitter:
    """Quadratic-model node angles as a function of per-group (k1, k2) on one scene."""

    def __init__(self, scene, phi_ref, groups_of_joints=None):
        from metamaterial_wb.core.lattice.geometry import LatticeGeometry
        from metamaterial_wb.core.solver import scene_groups

        self.scene = scene
        self.geo = LatticeGeometry(scene)
        topo = scene.topology
        self.pairs = topo.joint_pairs
        self.groups = scene_groups(scene)
        self.values = np.array([it.value for _, it in scene.fixed_items()], float)
        fixed = set()
        for _, nodes in self.groups:
            fixed.update(int(n) for n in nodes)
        self.free = np.array([k for k in range(topo.n_nodes) if k not in fixed], dtype=np.int64)
        self.phi_ref = np.asarray(phi_ref, float)
        self.jg = np.zeros(topo.n_joints, dtype=np.int64) if groups_of_joints is None else groups_of_joints

    def D(self, k1, k2):
        from metamaterial_wb.core.solver import QuadraticModel

        k1 = np.asarray(k1, float)[self.jg]
        k2 = np.asarray(k2, float)[self.jg]
        m = QuadraticModel(self.scene.topology.n_nodes, self.pairs, k1, k2, self.groups)
        return m.solve(self.values)

    def residual(self, k1, k2):
        """D-unit residual over the free nodes after removing the rigid rotation; also its angle form."""
        geo = self.geo
        with np.errstate(invalid="ignore", divide="ignore"):     # a degenerate D scale: NaN, refused by callers
            phi_q = geo.phi_from_D(self.D(k1, k2))
            diff = (phi_q - self.phi_ref)[self.free]
            w = float(diff.mean()) if diff.size else 0.0
            Dref = geo.D_from_phi(self.phi_ref)[self.free]
            r = geo.parity[self.free] * (diff - w) / np.where(Dref >= 0, geo.closing_rad, geo.opening_rad)
        return r, diff - w

    def rms(self, k1, k2):
        r, _ = self.residual(k1, k2)
        return float(np.sqrt(np.mean(r ** 2))) if r.size else 0.0


def _fit_k1(fitter, k2=(1.0,)):
    """One k1 for every joint group (k2 per group held)."""
    ng = len(k2)
    f = lambda k: fitter.rms([k] * ng, k2)
    res = minimize_scalar(f, bounds=K1_BOUNDS, method="bounded", options={"xatol": 1e-7})
    k1 = float(res.x)
    # the bounded search never evaluates the end points: compare with them explicitly
    for edge in (K1_BOUNDS[0], K1_BOUNDS[1] - 1e-9):
        if f(edge) < f(k1):
            k1 = edge
    return k1


def _fit_k2_ratio(fitter, k1):
    f = lambda lr: fitter.rms([k1, k1], [1.0, 10.0 ** lr])
    res = minimize_scalar(f, bounds=LOG10_K2_RATIO_BOUNDS, method="bounded", options={"xatol": 1e-5})
    return float(10.0 ** res.x)


def reference_angles(scene, model="nonlinear", **options):
    """In-plane node rotations (radians) of a scene from a lattice model."""
    from metamaterial_wb.core.lattice.solve import node_twist
    from metamaterial_wb.core.models import run_model

    res = run_model(model, scene, **options)
    if not res.converged:
        raise MetamaterialError(f"calibration: the {model} model did not converge on the test piece "
                                f"({scene.hinge}); no fit made")
    return node_twist(res.rotations)


def fit_length(length_mm, model="nonlinear", pieces=None, **piece):
    """Fit one k1 for a hinge length (reference width and thickness) to a set of test pieces.

    The seed printed "a set of layouts"; one k1 cannot match a chain and a grid equally well (chains
    keep deformation local, grids are close to the rotating-squares mechanism), so k1 minimises the RMS
    residual over all of :data:`TEST_PIECES` together. With ``piece`` keywords (rows, cols, joint, value)
    only that one piece is used. Returns k1, the overall residuals and the per-piece k1 and residual.
    """
    if piece:
        specs = [dict(TEST_PIECE, **piece)]
    else:
        specs = list(pieces or TEST_PIECES)
    fitters = []
    for spec in specs:
        sc = test_piece(length_mm, **spec)
        fitters.append(_Fitter(sc, reference_angles(sc, model)))
    f = lambda k: float(np.sqrt(np.mean([fi.rms([k], [1.0]) ** 2 for fi in fitters])))
    res = minimize_scalar(f, bounds=(0.0, 1.0), method="bounded", options={"xatol": 1e-7})
    k1 = float(res.x)
    for edge in (0.0, 1.0 - 1e-9):
        if f(edge) < f(k1):
            k1 = edge
    rs, ds = [], []
    per = []
    for spec, fi in zip(specs, fitters):
        r, dphi = fi.residual([k1], [1.0])
        rs.append(r / abs(spec["value"]) * abs(TEST_PIECE["value"]))
        ds.append(dphi)
        per.append({"piece": f"{spec['rows']} x {spec['cols']}, clip on {spec['joint']}",
                    "k1_alone": _fit_k1(fi), "rms_D": float(np.sqrt(np.mean(r ** 2)))})
    r = np.concatenate(rs)
    dphi = np.concatenate(ds)
    out = {"length_mm": length_mm, "k1": k1, "rms_D": float(np.sqrt(np.mean(r ** 2))),
           "max_D": float(np.abs(r).max()), "rms_deg": float(np.degrees(np.sqrt(np.mean(dphi ** 2)))),
           "pieces": per}
    if not all(math.isfinite(out[k]) for k in ("k1", "rms_D", "max_D", "rms_deg")):
        raise MetamaterialError(f"calibration: the fit for hinge length {length_mm} mm is not finite (k1 = {k1:.6g}, "
                                f"RMS residual {out['rms_D']} D units): the test pieces' D scale is degenerate at "
                                f"this size; no fit made")
    return out


def fit_width(width_mm, k1, length_mm=2.0, model="nonlinear"):
    """The k2 factor of a hinge width relative to the reference width (0.8 mm).

    k2 is the quadratic model's energy scale: for a fixed D field its energy is proportional to k2. The
    factor is therefore fitted on the energy: the lattice model's elastic energy of the k1 test piece
    with hinges of this width, divided by the same piece with reference hinges (same clip value). The
    D field is insensitive to a common k2, so the factor is then checked on the mixed piece (right
    half of this width): ``rms_D`` is its D-field residual with the fitted factor, ``rms_D_equal`` the
    residual with equal k2 (both against the lattice model).
    """
    from metamaterial_wb.core.models import run_model

    energies = []
    for w in (REFERENCE_WIDTH_MM, width_mm):
        res = run_model(model, test_piece(length_mm, width_mm=w))
        if not res.converged:
            raise MetamaterialError(f"calibration: the {model} model did not converge for width {w} mm")
        energies.append(res.info["elastic_energy_Nmm"])
    factor = energies[1] / energies[0]
    if not (math.isfinite(factor) and factor > 0):
        raise MetamaterialError(f"calibration: the k2 factor for hinge width {width_mm} mm is {factor!r} (elastic "
                                f"energies {energies[0]!r} / {energies[1]!r} N mm); no fit made")
    sc = test_piece(length_mm, right_width_mm=width_mm)
    topo = sc.topology
    jg = np.array([1 if sc.joint_hinge(n)["width_mm"] == width_mm and width_mm != REFERENCE_WIDTH_MM else 0
                   for n in topo.joint_names], dtype=np.int64)
    fitter = _Fitter(sc, reference_angles(sc, model), jg)
    r, dphi = fitter.residual([k1, k1], [1.0, factor])
    out = {"width_mm": width_mm, "factor": factor, "energy_Nmm": energies[1],
           "rms_D": float(np.sqrt(np.mean(r ** 2))), "max_D": float(np.abs(r).max()),
           "rms_D_equal": fitter.rms([k1, k1], [1.0, 1.0]),
           "rms_deg": float(np.degrees(np.sqrt(np.mean(dphi ** 2))))}
    if not all(math.isfinite(out[k]) for k in ("rms_D", "max_D", "rms_D_equal", "rms_deg")):
        raise MetamaterialError(f"calibration: the mixed-piece check for hinge width {width_mm} mm is not finite "
                                f"(RMS residual {out['rms_D']} D units); no fit made")
    return out


def fit_table_to_model(lengths=DEFAULT_LENGTHS_MM, widths=DEFAULT_WIDTHS_MM, model="nonlinear", progress=None):
    """Regenerate the calibration table (same format as core/data/calibration.json) from a lattice model.

    The sizes are checked first (:func:`check_sizes`); a non-finite fit is an error, never a table entry.
    """
    check_sizes(lengths, widths)
    kl = []
    for L in lengths:
        if progress:
            progress(f"k1: hinge length {L} mm")
        kl.append(fit_length(L, model))
    k1_ref = float(np.interp(2.0, [r["length_mm"] for r in kl], [r["k1"] for r in kl]))
    kw = []
    for w in widths:
        if progress:
            progress(f"k2: hinge width {w} mm")
        kw.append(fit_width(w, k1_ref, model=model))
    p = TEST_PIECE
    table = {
        "format": "metamaterial-calibration", "version": 1,
        "source": (f"Fitted to the {model} lattice model by 'python3 -m metamaterial_wb calibrate model' "
                   f"(metamaterial_wb.core.calibrate.fit_table_to_model): four test pieces of 20 mm cells (1 x 8, "
                   f"2 x 6, 3 x 6, 5 x 5), each with one angular constraint D = {p['value']}; one k1 per hinge length "
                   f"(width {REFERENCE_WIDTH_MM} mm, thickness {REFERENCE_THICKNESS_MM} mm) by least squares on the "
                   f"node angles in D units after removing the rigid rotation; k2 factor per width (length 2 mm) from "
                   f"the lattice's elastic energy of the 5 x 5 piece relative to {REFERENCE_WIDTH_MM} mm hinges. "
                   f"See docs/calibration.md."),
        "assumptions": [
            "k1 depends only on the flexible length; k2 only on the cross-section (only ratios of k2 matter)",
            "TPU hinges (modulus 26 MPa, Poisson 0.45) between rigid plates, 20 mm cells, hinge thickness 7 mm",
            "k2 scales linearly with the hinge thickness (the table's reference thickness)",
            "the fit depends on the test piece's size and on the amplitude: the quadratic model cannot "
            "represent the lattice's free-edge amplification; fit residuals in docs/calibration.md",
        ],
        "k1_vs_length": {"length_mm": [float(r["length_mm"]) for r in kl], "k1": [round(r["k1"], 6) for r in kl]},
        "k2_vs_width": {"width_mm": [float(r["width_mm"]) for r in kw],
                        "factor": [float(f"{r['factor']:.6g}") for r in kw]},
        "k2_thickness_reference_mm": REFERENCE_THICKNESS_MM,
    }
    return table, kl, kw


# ----------------------------------------------------------------------------------------------------
# measured angles (CSV)
# ----------------------------------------------------------------------------------------------------
_NODE_RE = re.compile(r"^\s*N?\s*\(?\s*(\d+)\s*,\s*(\d+)\s*\)?\s*$", re.ASCII)   # ASCII digits only


def read_angles_csv(path, scene):
    """``node,angle_deg`` rows (header optional; node as ``N1,2``) -> (node indices, angles in rad).

    The angle is the plate's measured in-plane rotation from the printed (flat) state, degrees,
    counter-clockwise positive seen from the top.
    """
    topo = scene.topology
    idx, ang = [], []
    import io

    from metamaterial_wb.core.inputfile import read_text
    rows = list(csv.reader(io.StringIO(read_text(path, "ANGLES.csv"), newline="")))
    first = True                      # the header may follow comment and blank lines
    for ln, row in enumerate(rows, start=1):
        if not row or all(not c.strip() for c in row) or row[0].strip().startswith("#"):
            continue
        header_allowed, first = first, False
        col = len(row)                # the angle's column in the file (3 in the N,i,j form)
        if len(row) == 3 and "," in row[0]:     # a quoted "N0,0" (it keeps its comma), its angle and a third cell
            raise SceneError(f"{path}:{ln}", f"3 columns: the node {row[0]!r}, the angle {row[1]!r} and an extra "
                                             f"cell {row[2]!r}; expected 2 columns 'node,angle_deg' (\"N1,2\",0.4) "
                                             f"or 3 with the node unquoted (N1,2,0.4)")
        if len(row) == 3:             # N,i,j form: "N1,2" split by the CSV reader -> ["N1", "2", angle]
            row = [f"{row[0]},{row[1]}", row[2]]
        if len(row) != 2:
            raise SceneError(f"{path}:{ln}", f"expected 2 columns 'node,angle_deg', got {len(row)}: {row!r}")
        if header_allowed and row[1].strip().lower().startswith("angle"):
            continue
        m = _NODE_RE.match(row[0].replace('"', ""))
        if not m:
            raise SceneError(f"{path}:{ln}", f"{row[0]!r} is not a node name like N1,2")
        key = (int(m.group(1)), int(m.group(2)))
        if key not in topo.node_index:
            raise SceneError(f"{path}:{ln}", f"node N{key[0]},{key[1]} is not in the test piece's layout")
        field = f"{path}:{ln} column {col} (angle_deg)"
        a = parse_float(field, row[1])          # strict: no 1_0, no non-ASCII digits, no inf/nan, no subnormals
        if abs(a) > 90:
            raise SceneError(field, range_message(a, -90, 90, "deg"))
        if topo.node_index[key] in idx:
            raise SceneError(f"{path}:{ln}", f"node N{key[0]},{key[1]} is listed twice")
        idx.append(topo.node_index[key])
        ang.append(math.radians(a))
    if len(idx) < 2:
        raise SceneError(str(path), f"{len(idx)} measured node(s); at least 2 are needed for a fit")
    return np.array(idx, dtype=np.int64), np.array(ang)


def _sizes_by_joint(scene, key):
    """``{size: [joint names]}`` of one hinge size (``length_mm``, ``width_mm``, ``thickness_mm``) over the joints."""
    out = {}
    for n in scene.topology.joint_names:
        out.setdefault(float(scene.joint_hinge(n)[key]), []).append(n)
    return out


def _sizes_text(by_size, base):
    """``2 mm on 48 joints (the piece's hinge), 6 mm on 12 joints (H0,3, H0,4, H1,3, H1,4, ...)``."""
    parts = []
    for v in sorted(by_size, key=lambda v: (v != base, v)):
        names = by_size[v]
        which = "the piece's hinge" if v == base else ", ".join(names[:4]) + (", ..." if len(names) > 4 else "")
        parts.append(f"{v:g} mm on {len(names)} joint{'s' if len(names) != 1 else ''} ({which})")
    return ", ".join(parts)


def check_piece_stiffness(scene):
    """Refuse a measured test piece whose joints set ``k1`` / ``k2`` directly (per-joint overrides): the fit computes
    k1 and k2 from the hinge sizes, so a pinned value could be neither honoured nor fitted; it was silently ignored.
    The error names every such joint and its pinned values (docs/calibration.md, section 2)."""
    pinned = []
    for name in sorted(scene.joint_overrides):
        ov = scene.joint_overrides[name]
        keys = [k for k in ("k1", "k2") if k in ov]
        if keys:
            pinned.append(f"{name} (" + ", ".join(f"{k} {ov[k]:g}" for k in keys) + ")")
    if pinned:
        n = len(pinned)
        raise SceneError("joints", f"{n} joint{'s' if n != 1 else ''} of the test piece set k1 / k2 directly: "
                                   f"{', '.join(pinned[:6])}{', ...' if n > 6 else ''}; the fit computes k1 and k2 "
                                   f"from the hinge sizes and cannot honour a pinned value; remove k1 / k2 from these "
                                   f"joints (describe them by their hinge sizes); nothing fitted")


def check_piece_sizes(scene):
    """Refuse a measured test piece whose hinges the fit cannot represent: more than one hinge length (k1 is filed
    under one length), more than one thickness (k2 scales with it; the fit groups joints by width only), more than
    two widths. The error names the sizes and the joints that have them (docs/calibration.md, section 2)."""
    base = scene.hinge
    for key, what, most, use in (
            ("length_mm", "hinge lengths", 1, "k1 is fitted for one hinge length: give every joint the same "
                                              "length_mm"),
            ("thickness_mm", "hinge thicknesses", 1, "the fit assumes one thickness: give every joint the same "
                                                     "thickness_mm"),
            ("width_mm", "hinge widths", 2, "use one (k1 fit) or two (k1 and k2 ratio fit)")):
        by = _sizes_by_joint(scene, key)
        if len(by) > most:
            raise SceneError("joints", f"the test piece has {len(by)} {what}: {_sizes_text(by, float(base[key]))}; "
                                       f"{use}")


def fit_measured(scene, node_idx, angles_rad, fit_k2=None, source="angles"):
    """Fit k1 (and, for a piece with two hinge widths, the k2 ratio) to measured node angles.

    Only the measured nodes enter the residual. Returns a dict with k1, the k2 ratio
    ``k2(other_width_mm) / k2(base_width_mm)`` (the base width is the piece's default ``hinge.width_mm``),
    the joints' hinge ``length_mm`` and ``thickness_mm`` (one each: :func:`check_piece_sizes`, checked first; no
    joint may set k1 / k2 directly: :func:`check_piece_stiffness`),
    residuals (D units and degrees) and per-node residuals.

    Raises a SceneError when the fit is not finite or ends on its search bound (k1 in [0, 1], log10 of the k2
    ratio in [-4, 4]): the measured angles then do not determine the value, and it must not enter a table; and,
    at ``source`` (the CSV's name), when fewer than 2 measured nodes are left after dropping those a constraint
    holds (naming them and the constraint), as :func:`read_angles_csv` refuses fewer than 2 measured nodes.
    """
    topo = scene.topology
    check_piece_stiffness(scene)
    check_piece_sizes(scene)
    widths = sorted({scene.joint_hinge(n)["width_mm"] for n in topo.joint_names})
    base_w = scene.hinge["width_mm"]
    jg = np.array([0 if scene.joint_hinge(n)["width_mm"] == base_w else 1 for n in topo.joint_names], dtype=np.int64)
    two = len(widths) == 2 if fit_k2 is None else bool(fit_k2)
    phi_ref = np.zeros(topo.n_nodes)
    phi_ref[node_idx] = angles_rad
    fitter = _Fitter(scene, phi_ref, jg)
    fixed_nodes = set(range(topo.n_nodes)) - set(int(k) for k in fitter.free)
    use = np.array([k for k in node_idx if int(k) not in fixed_nodes], dtype=np.int64)
    if use.size < 2:                # one free node is fitted exactly by the rigid rotation: no information on k1
        holder = {}
        for (kind, it), (_, nodes) in zip(scene.fixed_items(), fitter.groups):
            for n in nodes:
                holder.setdefault(int(n), f"the {kind} {it.name!r} on {it.joint}")
        held = [f"N{topo.nodes[k][0]},{topo.nodes[k][1]} held by {holder.get(int(k), 'a constraint')}"
                for k in node_idx if int(k) in fixed_nodes]
        if not held:
            raise SceneError(str(source), f"{use.size} measured node(s); at least 2 are needed for a fit")
        raise SceneError(str(source), f"{use.size} measured node(s) left after dropping {'; '.join(held)} (a plate "
                                      f"held by a constraint or actuator does not follow k1 and is not used); at "
                                      f"least 2 are needed for a fit: measure free plates")
    fitter.free = use
    if two:
        best = None
        for _ in range(3):          # alternate k1 and the k2 ratio (each a 1-D fit)
            ratio = 1.0 if best is None else best[1]
            k1 = _fit_k1(fitter, [1.0, ratio])
            ratio = _fit_k2_ratio(fitter, k1)
            best = (k1, ratio)
        from scipy.optimize import least_squares
        sol = least_squares(lambda x: fitter.residual([x[0], x[0]], [1.0, 10.0 ** x[1]])[0],
                            [best[0], math.log10(best[1])],
                            bounds=([K1_BOUNDS[0], LOG10_K2_RATIO_BOUNDS[0]], [K1_BOUNDS[1], LOG10_K2_RATIO_BOUNDS[1]]),
                            x_scale=[1e-2, 0.1], xtol=1e-12, ftol=1e-12)
        k1, ratio = float(sol.x[0]), float(10.0 ** sol.x[1])
        k2 = [1.0, ratio]
    else:
        k1 = _fit_k1(fitter, [1.0, 1.0])
        ratio = None
        k2 = [1.0, 1.0]
    r, dphi = fitter.residual([k1, k1], k2)
    nodes = [f"N{topo.nodes[k][0]},{topo.nodes[k][1]}" for k in use]
    other = [w for w in widths if w != base_w]
    fit = {"k1": k1, "k2_ratio": ratio, "widths_mm": widths, "base_width_mm": base_w,
           "length_mm": float(scene.joint_hinge(topo.joint_names[0])["length_mm"]),
           "thickness_mm": float(scene.joint_hinge(topo.joint_names[0])["thickness_mm"]),
           "other_width_mm": other[0] if other else None, "rms_D": float(np.sqrt(np.mean(r ** 2))),
           "max_D": float(np.abs(r).max()), "rms_deg": float(np.degrees(np.sqrt(np.mean(dphi ** 2)))),
           "nodes": nodes, "residual_deg": [float(x) for x in np.degrees(dphi)]}
    _check_measured_fit(fit)
    return fit


def _check_measured_fit(fit):
    """Refuse a measured fit that is not finite or ends on its search bound (the data do not determine it)."""
    res = f"RMS residual {fit['rms_D']:.4g} D units, {fit['rms_deg']:.3g} deg"
    vals = [fit["k1"], fit["rms_D"], fit["max_D"], fit["rms_deg"]] + ([fit["k2_ratio"]] if fit["k2_ratio"] else [])
    if not all(math.isfinite(v) for v in vals):
        raise SceneError("k1", f"the fit is not finite (k1 = {fit['k1']!r}, {res}): the test piece's D scale is "
                               f"degenerate; no fit made")
    advice = "check the clip values in the piece, the angle signs and units, and the node names; nothing written"
    k1 = fit["k1"]
    for b in K1_BOUNDS:
        if abs(k1 - b) <= _K1_BOUND_TOL:
            raise SceneError("k1", f"the fit ended on its search bound {b:g} of [{K1_BOUNDS[0]:g}, {K1_BOUNDS[1]:g}] "
                                   f"(k1 = {k1:.6g}, {res}): the measured angles do not determine k1; {advice}")
    if fit["k2_ratio"] is not None:
        lr = math.log10(fit["k2_ratio"])
        for b in LOG10_K2_RATIO_BOUNDS:
            if abs(lr - b) <= _LOG10_RATIO_BOUND_TOL:
                lo, hi = (10.0 ** x for x in LOG10_K2_RATIO_BOUNDS)
                raise SceneError("k2 ratio", f"the fit ended on its search bound {10.0 ** b:g} of [{lo:g}, {hi:g}] "
                                             f"(k2({fit['other_width_mm']} mm) / k2({fit['base_width_mm']} mm) = "
                                             f"{fit['k2_ratio']:.6g}, {res}): the measured angles do not determine "
                                             f"the ratio; {advice}")


def table_json(table):
    """The table as JSON text in the shipped file's layout (one line per list of numbers)."""
    import json

    lines = ["{"]
    items = list(table.items())
    for k, (key, val) in enumerate(items):
        end = "," if k < len(items) - 1 else ""
        if isinstance(val, dict):
            inner = ", ".join(f"{json.dumps(a)}: {json.dumps(b)}" for a, b in val.items())
            lines.append(f" {json.dumps(key)}: {{{inner}}}{end}")
        elif isinstance(val, list) and all(isinstance(x, str) for x in val):
            lines.append(f" {json.dumps(key)}: [")
            lines += [f"  {json.dumps(x)}{',' if i < len(val) - 1 else ''}" for i, x in enumerate(val)]
            lines.append(f" ]{end}")
        else:
            lines.append(f" {json.dumps(key)}: {json.dumps(val, allow_nan=False)}{end}")
    lines.append("}")
    text = "\n".join(lines) + "\n"
    assert json.loads(text) == json.loads(json.dumps(table))
    return text



def _set_point(xs, ys, x, y):
    """Table columns ``(xs, ys)`` with ``y`` at abscissa ``x``: replaced if present, else inserted in order."""
    xs, ys = list(xs), list(ys)
    if x in xs:
        ys[xs.index(x)] = y
        return xs, ys
    xs.append(x)
    ys.append(y)
    order = np.argsort(xs)
    return [xs[i] for i in order], [ys[i] for i in order]


def measured_width_factor(cal, base_width_mm, other_width_mm, ratio):
    """``(width_mm, factor)`` to enter in a table for a fitted ratio ``k2(other) / k2(base)``.

    The table's factors are relative to the reference width (0.8 mm = factor 1): when the piece's other width is
    the reference, the base width gets ``factor(reference) / ratio``; otherwise the other width gets
    ``factor(base) * ratio`` (the base width's factor taken from the table ``cal``).
    """
    anchor, target = ((other_width_mm, base_width_mm) if other_width_mm == REFERENCE_WIDTH_MM
                      else (base_width_mm, other_width_mm))
    lo, hi = float(cal.w_mm[0]), float(cal.w_mm[-1])
    if not lo <= anchor <= hi:
        raise SceneError("k2 ratio", f"the piece's width {anchor} mm, relative to which the fitted ratio is entered, "
                                     f"is outside the table's widths [{lo:g}, {hi:g}] mm; nothing written")
    f_anchor = cal.k2(anchor, cal.t_ref)
    return target, (f_anchor / ratio if target == base_width_mm else f_anchor * ratio)


def update_table(table, length_mm, k1, width_mm=None, factor=None):
    """A copy of a calibration table with one k1 (and optionally one width factor) inserted/replaced.

    A width factor that would make the table's k2 factors not increase strictly with the width (a wider hinge
    softer than a narrower one) is refused: it comes from a measurement that cannot be trusted.
    """
    import copy

    t = copy.deepcopy(table)
    L, K = _set_point(t["k1_vs_length"]["length_mm"], t["k1_vs_length"]["k1"], length_mm, k1)
    t["k1_vs_length"] = {"length_mm": L, "k1": K}
    if width_mm is not None and factor is not None:
        W, F = _set_point(t["k2_vs_width"]["width_mm"], t["k2_vs_width"]["factor"], width_mm, factor)
        t["k2_vs_width"] = {"width_mm": W, "factor": F}
        k = W.index(width_mm)
        near = [(W[i], F[i]) for i in (k - 1, k + 1) if 0 <= i < len(W)]
        if any((w < width_mm) != (f < factor) or f == factor for w, f in near):
            shown = ", ".join(f"{f:.4g} at {w:g} mm" for w, f in near)
            raise SceneError("k2 ratio", f"the fitted k2 factor {factor:.4g} at width {width_mm:g} mm does not lie "
                                         f"between its neighbours in the table ({shown}): a wider hinge would be "
                                         f"softer; check the measurement; nothing written")
    from metamaterial_wb.core.calibration import Calibration
    Calibration(t)        # validates (monotone abscissae, ranges)
    return t
