"""``calibrate model|measured ...``: fit the quadratic model's (k1, k2) per hinge size (docs/calibration.md).

* ``calibrate model [--out TABLE.json] [--lengths ...] [--widths ...]``: fit to the nonlinear lattice
  model and write a calibration table (default: print a summary, write nothing unless ``--out``).
  ``--out metamaterial_wb/core/data/calibration.json`` regenerates the shipped table.
* ``calibrate measured PIECE.json ANGLES.csv [--table IN.json --out OUT.json]``: fit k1 (and a k2
  ratio for a piece with two hinge widths) to node angles measured on a printed test piece; with
  ``--out`` the fitted k1 (and width factor) is inserted into a copy of the table.
"""
import sys

NAME = "calibrate"
HELP = "fit the quadratic model's k1/k2 per hinge size to the nonlinear model or to measured node angles"


def _floats(text, field, allowed=""):
    """A comma-separated list of sizes in mm: numbers read strictly (:func:`metamaterial_wb.core.numbers.parse_float`:
    no ``1_0``, no non-ASCII digits, no inf/nan, no subnormals; the error names the flag and the item), strictly
    increasing (each size is range-checked by ``core.calibrate.check_sizes`` before any fit). ``allowed`` (such as
    ``allowed range [0.1, 10) mm``) is added to the error of an item that is not a number."""
    from metamaterial_wb.core.errors import SceneError
    from metamaterial_wb.core.numbers import parse_float

    items = text.split(",")
    if len(items) > 1 and any(not x.strip() for x in items):
        raise SceneError(field, f"{text!r}: an empty item; expected comma-separated numbers in mm")
    vals = []
    for k, x in enumerate(items, start=1):
        if not x.strip():
            continue
        try:
            vals.append(parse_float(field, x))
        except SceneError as e:
            raise SceneError(field, f"item {k} of {text!r}: {e.message}" + (f"; {allowed}" if allowed else "")) \
                from None
    if not vals:
        raise SceneError(field, f"{text!r}: expected comma-separated numbers in mm")
    if any(b <= a for a, b in zip(vals, vals[1:])):
        raise SceneError(field, f"{text!r}: expected strictly increasing numbers in mm")
    return vals


def _allowed(low, high, high_open):
    """``allowed range [0.1, 10) mm`` for a size flag's items."""
    return f"sizes in mm, allowed range [{low:g}, {high:.10g}{')' if high_open else ']'} mm"


def _check_flags(args):
    """Refuse flags the chosen source would ignore (before any work)."""
    from metamaterial_wb.core.errors import SceneError

    if args.source == "model":
        if args.table is not None:
            raise SceneError("--table", "is for 'calibrate measured' (the table to update); 'calibrate model' "
                                        "fits a whole new table")
        return
    for flag, val in (("--lengths", args.lengths), ("--widths", args.widths)):
        if val is not None:
            raise SceneError(flag, "is for 'calibrate model'; 'calibrate measured' takes the hinge sizes from "
                                   "PIECE.json")
    if args.table is not None and args.out is None:
        raise SceneError("--table", "needs --out: the updated table is only written with --out")


def _inputs(args):
    """``(what, path)`` of the files ``calibrate`` reads, which ``--out`` must not overwrite."""
    if args.source != "measured":
        return []
    from metamaterial_wb.core.calibration import _DEFAULT_PATH
    table = ("--table", args.table) if args.table is not None else ("shipped table (--table default)", _DEFAULT_PATH)
    return [("PIECE.json", args.piece), ("ANGLES.csv", args.angles), table]


def add_arguments(p):
    p.add_argument("source", choices=("model", "measured"), help="fit to the nonlinear model or to measurements")
    p.add_argument("piece", nargs="?", help="measured: the test piece's scene (JSON) with its constraint values")
    p.add_argument("angles", nargs="?", help="measured: CSV 'node,angle_deg' of measured plate rotations")
    p.add_argument("--out", default=None, help="write the calibration table (JSON) here")
    p.add_argument("--table", default=None, help="measured: table to update (default: the shipped table)")
    p.add_argument("--lengths", default=None, help="model: hinge lengths in mm (comma-separated)")
    p.add_argument("--widths", default=None, help="model: hinge widths in mm (comma-separated)")


def run(args):
    from metamaterial_wb.core import calibrate as C
    from metamaterial_wb.core.errors import SceneError
    from metamaterial_wb.core.fileio import check_output, write_atomic
    from metamaterial_wb.core.inputfile import read_json

    if args.source == "model" and (args.piece or args.angles):
        raise SceneError("calibrate model", "takes no positional files (did you mean 'calibrate measured'?)")
    _check_flags(args)
    if args.out is not None:
        check_output(args.out, "file", "--out", inputs=_inputs(args))
    if args.source == "model":
        lengths = (_floats(args.lengths, "--lengths", _allowed(C.MIN_SIZE_MM, C.MAX_LENGTH_MM, True))
                   if args.lengths is not None else C.DEFAULT_LENGTHS_MM)
        widths = (_floats(args.widths, "--widths", _allowed(C.MIN_SIZE_MM, C.MAX_WIDTH_MM, False))
                  if args.widths is not None else C.DEFAULT_WIDTHS_MM)
        C.check_sizes(lengths, widths, "--lengths", "--widths")
        if C.REFERENCE_WIDTH_MM not in widths:
            raise SceneError("--widths", f"must include the reference width {C.REFERENCE_WIDTH_MM} mm (factor 1)")
        table, kl, kw = C.fit_table_to_model(lengths, widths,
                                              progress=lambda m: print(m, file=sys.stderr, flush=True))
        print("length_mm  k1        rms_D   max_D   (fit residual, D units)")
        for r in kl:
            print(f"{r['length_mm']:8g}  {r['k1']:.6f}  {r['rms_D']:.4f}  {r['max_D']:.4f}")
        print("width_mm  k2 factor  rms_D mixed piece (equal k2)")
        for r in kw:
            print(f"{r['width_mm']:8g}  {r['factor']:9.4g}  {r['rms_D']:.4f} ({r['rms_D_equal']:.4f})")
        if args.out:
            write_atomic(args.out, C.table_json(table))
            print(f"wrote {args.out}")
        return 0

    if not args.piece or not args.angles:
        raise SceneError("calibrate measured", "needs PIECE.json and ANGLES.csv")
    from metamaterial_wb.core.calibration import _DEFAULT_PATH, Calibration, default_calibration
    from metamaterial_wb.core.scene import Scene

    table = cal = None
    if args.out:                        # the table to update is read and checked before any work
        table_path = args.table or _DEFAULT_PATH
        table = read_json(table_path, "--table")
        try:
            cal = Calibration(table)
        except SceneError as exc:
            raise SceneError("--table", f"{table_path}: {exc}") from None
    scene = Scene.load(args.piece)
    if not scene.constraints and not scene.actuators:
        raise SceneError("constraints", "the test piece has no angular constraint or actuator; the fit needs the "
                                        "deformation you imposed")
    idx, ang = C.read_angles_csv(args.angles, scene)
    fit = C.fit_measured(scene, idx, ang, source=args.angles)
    ratio = fit["k2_ratio"]
    print(f"k1 = {fit['k1']:.6f}" + (f", k2 ratio (width {fit['other_width_mm']} / {fit['base_width_mm']} mm) = "
                                      f"{ratio:.4g}" if ratio is not None else ""))
    print(f"residual: RMS {fit['rms_D']:.4f} / max {fit['max_D']:.4f} D units, RMS {fit['rms_deg']:.3f} deg "
          f"over {len(fit['nodes'])} measured free nodes")
    for n, r in zip(fit["nodes"], fit["residual_deg"]):
        print(f"  {n}: {r:+.3f} deg")
    # the table the note compares with: the one read (--table, or the shipped one with --out), else the shipped one
    t_ref = (cal or default_calibration()).t_ref
    which = f"--table {args.table}" if args.table is not None else f"the shipped table, {_DEFAULT_PATH}"
    if fit["thickness_mm"] != t_ref:
        print(f"note: the piece's hinge thickness {fit['thickness_mm']:g} mm differs from the table's reference "
              f"thickness {t_ref:g} mm ({which}); the table takes k1 as independent of the thickness (its "
              f"assumptions), so k1 is filed under the hinge length {fit['length_mm']:g} mm alone")
    if args.out:
        width = factor = None
        if ratio is not None and fit["other_width_mm"] is not None:
            width, factor = C.measured_width_factor(cal, fit["base_width_mm"], fit["other_width_mm"], ratio)
        table = C.update_table(table, fit["length_mm"], round(fit["k1"], 6), width, factor)
        before = table.get("source", "")          # text or absent (checked by Calibration)
        table["source"] = ((before + " " if before else "") + f"Updated from measured angles: {args.angles} on "
                           f"{args.piece} (k1 = {fit['k1']:.4f} at {fit['length_mm']} mm"
                           + (f", k2 factor {factor:.4g} at {width} mm" if factor is not None else "")
                           + f", RMS residual {fit['rms_deg']:.3f} deg).")
        write_atomic(args.out, C.table_json(table))
        print(f"wrote {args.out}")
    return 0
