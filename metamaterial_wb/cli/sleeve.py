"""``sleeve SPEC.json --out DIR [--step] [--3mf] [--fe-check stiffness|converged|peak]``: metamaterial sleeve actuator
analysis.

Writes ``DIR/summary.json`` (unit cells, ring FD peaks/valleys, snapping sequence, PV, walker) and
plots ``DIR/fd_cells.png``, ``DIR/fd_ring.png``, ``DIR/pv.png`` (+ ``design_map.png``,
``walker.png`` when the spec asks for them); ``--step`` / ``--3mf`` export the sleeve's geometry
(FreeCAD needed); ``--fe-check`` compares the beam model with the curved CalculiX solid of every
cell type's uniform ring (``fe/sleeve_check.py``; needs ccx: refused before any work without it; a check whose
ccx run fails is recorded in the summary's notes with a warning, the rest written, exit 0). Everything is written
to a temporary folder first and moved into ``DIR`` at the end, so a failure leaves nothing half-written (and the
folders the run created, ``DIR`` and its parents, are removed again).
"""
import os
import shutil
import sys

NAME = "sleeve"
HELP = "metamaterial sleeve actuator: unit-cell and sleeve FD curves, PV curve, sequence, export"


def add_arguments(p):
    p.add_argument("spec", help="sleeve spec (JSON, docs/scene-format.md section 'Sleeve spec')")
    p.add_argument("--out", required=True, help="output folder (created; files in it are replaced)")
    p.add_argument("--step", action="store_true", help="also export the sleeve as STEP (needs FreeCAD)")
    p.add_argument("--3mf", dest="threemf", action="store_true",
                   help="also export a 3MF with TPU sleeve and PLA rings/caps laid out on the bundled printer's bed "
                        "(sleeve.3mf; sleeve_plate1.3mf, ... when the parts need more than one bed; needs FreeCAD)")
    p.add_argument("--render", action="store_true", help="also write sleeve.png, a picture of the geometry (needs FreeCAD)")
    p.add_argument("--no-plots", action="store_true", help="summary.json only (not with --render)")
    p.add_argument("--fe-check", choices=("stiffness", "converged", "peak"), default=None,
                   help="also run every cell type's uniform ring as a curved CalculiX solid (needs ccx) and compare the "
                        "beam model with it: 'stiffness' (10-30 s per type for four cells), 'converged' (the stiffness on three "
                        "finer meshes too, extrapolated, with its error: a few minutes per type), 'peak' (its first "
                        "peak too, minutes); refused without ccx; if ccx fails on it, the outputs are still written "
                        "with the failure in the summary's notes and a warning, exit 0")
    p.add_argument("--quiet", action="store_true", help="no progress on stderr")


def _progress(quiet):
    if quiet:
        return None, (lambda s: None)
    state = {"last": -1}

    def prog(i, n):
        pc = int(100 * i / n)
        if pc // 10 != state["last"]:
            state["last"] = pc // 10
            print(f"  {pc:3d} %", file=sys.stderr, flush=True)

    def log(s):
        state["last"] = -1
        print(s, file=sys.stderr, flush=True)
    return prog, log


def run(args):
    from metamaterial_wb.core.fileio import (check_output, commit_set, earlier_outputs, make_dirs, make_temp_dir,
                                             missing_dirs, remove_new_dirs, remove_outputs, write_json)
    from metamaterial_wb.core.sleeve.pipeline import analyse
    from metamaterial_wb.core.sleeve.spec import SleeveSpec
    from metamaterial_wb.core.threads import blas_threads

    out = check_output(args.out, "dir", "--out")
    check_spec_not_output(args.spec, out)                  # before any work: the run would replace the spec
    if args.no_plots and args.render:
        from metamaterial_wb.core.errors import SceneError
        raise SceneError("--render", "writes sleeve.png, but --no-plots asks for summary.json only: give one of them")
    geometry = [f for f, on in (("--step", args.step), ("--3mf", args.threemf), ("--render", args.render)) if on]
    if geometry:                                           # refuse before the analysis, not after
        from metamaterial_wb.core.errors import MetamaterialError, SceneError
        from metamaterial_wb.geometry.fc import freecad
        try:
            freecad()
        except MetamaterialError as exc:
            raise SceneError(geometry[0], str(exc)) from None
    spec = SleeveSpec.load(args.spec)
    if geometry:
        spec.check_end_pieces()                            # the end pieces fit: before the analysis, not after
    fe_check = getattr(args, "fe_check", None)
    if fe_check:                                           # refuse before minutes of work, not after
        from metamaterial_wb.fe import ccx
        from metamaterial_wb.fe.sleeve_check import check_spec
        ok, why = ccx.available()
        if not ok:
            raise ccx.FEError(f"--fe-check: {why}")
        check_spec(spec)
    prog, log = _progress(args.quiet)
    with blas_threads(1):   # many small dense systems: threads only cost time (not for other commands)
        summary, curves = analyse(spec, progress=None, log=log)
        if fe_check:
            summary["accuracy"]["fe_check"], fe_notes = _fe_check(spec, fe_check, log)
            summary["accuracy"]["notes"] += fe_notes
    parent = os.path.dirname(out)
    made, tmp, done = missing_dirs(out), None, False      # the folders this run creates: removed if it fails
    try:
        make_dirs(parent)
        tmp = make_temp_dir(parent, "sleeve")
        files = []
        if not args.no_plots:
            files += write_plots(spec, summary, curves, tmp)
        if args.step or args.threemf or args.render:
            log("geometry")
            from metamaterial_wb.export.sleeve import export_sleeve
            files += export_sleeve(spec, tmp, step=args.step, threemf=args.threemf, render=args.render)
        summary["files"] = sorted(["summary.json"] + files)
        write_json(os.path.join(tmp, "summary.json"), summary)
        os.makedirs(out, exist_ok=True)
        stale = earlier_outputs(out, "summary.json", summary["format"], summary["files"])
        commit_set(tmp, out, sorted(os.listdir(tmp)))          # all together or none
        done = True
        gone = remove_outputs(out, stale)      # an earlier run's plots or geometry this one does not write
        if gone:
            log(f"removed {len(gone)} file(s) of the earlier run that this one does not write: {', '.join(gone)}")
    finally:
        if tmp is not None:
            shutil.rmtree(tmp, ignore_errors=True)
        if not done:                           # failed or stopped (SIGTERM): no empty folder of ours left
            remove_new_dirs(made)
    seq = summary["sequence"]
    log(f"ring peaks {['%.3g' % p for p in summary['ring']['peaks']]}, valleys "
        f"{['%.3g' % v for v in summary['ring']['valleys']]} (F/GL^2); sequence {seq['loading']}|{seq['unloading']} "
        f"({symmetry_word(seq)}); wrote {out}")
    for u in summary["unit_cells"] + summary["uniform_rings"]:
        if u.get("note"):
            log(f"note: {'unit cell' if 'peak_force' in u else 'uniform ring'} of type {u['type']}: {u['note']}")
    frame_note = seq.get("frame3d_nl", {}).get("note")         # the frame's cycle's own (model.frame_nonlinear)
    for note in (([seq["note"]] if seq.get("note") else [])
                 + ([f"sequence on the nonlinear frame: {frame_note}"] if frame_note else [])
                 + summary["pv"].get("notes", []) + summary.get("walker", {}).get("notes", [])
                 + summary.get("design_map", {}).get("notes", [])):
        log(f"note: {note}")
    for note in summary["accuracy"]["notes"]:
        log(f"accuracy: {note}")
    return 0


# every name a sleeve run writes into --out, with or without --no-plots, --step, --3mf, --render (a later run removes
# an earlier one's that it does not write, so the spec may be none of them); the 3MF plates: export.sleeve.PLATE_NAME
OUTPUT_FILES = ("summary.json", "fd_cells.png", "fd_ring.png", "pv.png", "design_map.png", "walker.png", "sleeve.png",
                "sleeve.step", "sleeve.3mf")


def check_spec_not_output(spec, out):
    """Refuse, before any work, a spec that is one of the files a sleeve run writes into (or removes from) ``out``
    (``DIR/summary.json`` given to ``sleeve --out DIR``; also through a link): it would be overwritten."""
    from metamaterial_wb.core.fileio import check_scene_not_output
    from metamaterial_wb.export.sleeve import PLATE_NAME
    base = os.path.basename(spec).lower()      # (in any letter case: one file on Windows and macOS)
    plates = [base] if PLATE_NAME.fullmatch(base) else []
    check_scene_not_output(out, list(OUTPUT_FILES) + plates, spec, writer="the sleeve run",
                           what_input="the sleeve spec")


def symmetry_word(seq):
    """``symmetric`` / ``asymmetric`` of a snapping sequence, or, ``symmetric`` null, ``nothing snapped`` or
    ``undetermined`` (an incomplete order: ``analysis.symmetry_word``)."""
    from metamaterial_wb.core.sleeve.analysis import symmetry_word as word
    return word(seq)


def _fe_check(spec, kind, log):
    """``(fe_check, notes)`` of ``--fe-check kind``: the check's result and its notes, or, when CalculiX fails on it
    (an error, its time limit, a result it did not write: ``ccx.FEError``), ``{"failed": why, "types": []}`` and a
    note saying so, with one warning line on stderr: the beam model's outputs are written all the same and the
    command exits 0 (docs/sleeves.md)."""
    from metamaterial_wb.fe import ccx
    from metamaterial_wb.fe.sleeve_check import check_sleeve, notes
    try:
        check = check_sleeve(spec, peak=kind == "peak", converged=kind == "converged", log=log)
    except ccx.FEError as exc:
        why = " ".join(str(exc).split())
        why = why if len(why) <= 500 else why[:500] + " ..."
        print(f"warning: fe check failed: {why}; the beam model's outputs are written without it", file=sys.stderr,
              flush=True)
        return ({"failed": why, "types": []},
                [f"fe check failed: {why} (--fe-check {kind}; the beam model's figures are unaffected)"])
    return check, notes(check)


# ------------------------------------------------------------------------------------------------
def write_plots(spec, summary, curves, folder):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    files = []
    # unit cells
    fig, ax = plt.subplots(figsize=(6, 4))
    for i, (up, down) in enumerate(curves["cells"]):
        g = spec.cells[i]
        ax.plot(up.d, up.F * 1e3, label=f"type {i}: t/L={g.t / g.L:.3f}, h/L={g.h / g.L:.3f}")
        u = summary["unit_cells"][i]
        if u["peak_force"] is not None:            # null: no peak (valley) within the stroke
            ax.plot([u["peak_displacement"]], [u["peak_force"] * 1e3], "^k")
        if u["valley_force"] is not None:
            ax.plot([u["valley_displacement"]], [u["valley_force"] * 1e3], "vk")
    ax.axhline(0, color="0.6", lw=0.8)
    ax.set_xlabel("displacement d/L [-]")
    ax.set_ylabel("force F/(G L$^2$) [x1e-3]")
    ax.set_title("unit cell FD (beam model)")
    ax.set_ylim(_ylim([c[0].F for c in curves["cells"]], 1e3))
    ax.legend(fontsize=8)
    fig.tight_layout(); fig.savefig(os.path.join(folder, "fd_cells.png"), dpi=110); plt.close(fig)
    files.append("fd_cells.png")
    # ring / sleeve
    model, up, down = curves["ring"]
    fig, (ax, ax2) = plt.subplots(2, 1, figsize=(6, 6), sharex=True, gridspec_kw={"height_ratios": [3, 1.4]})
    for i, u in curves["uniform"]:
        ax.plot(u.d, u.F * 1e3, lw=1, alpha=0.7, label=f"uniform ring, type {i}")
    ax.plot(up.d, up.F * 1e3, "k", lw=2, label=f"sleeve {spec.pattern} loading")
    ax.plot(down.d, down.F * 1e3, "k--", lw=1.5, label="unloading")
    pv = summary["ring"]
    ax.plot(pv["peak_displacements"], np.array(pv["peaks"]) * 1e3, "^r")
    ax.plot(pv["valley_displacements"], np.array(pv["valleys"]) * 1e3, "vb")
    ax.axhline(0, color="0.6", lw=0.8)
    ax.set_ylabel("force F/(G L$^2$) [x1e-3]")
    ax.set_ylim(_ylim([up.F] + [u.F for _, u in curves["uniform"]], 1e3))
    seq = summary["sequence"]
    ax.set_title(f"sleeve FD: sequence {seq['loading']}|{seq['unloading']} "
                 f"({symmetry_word(seq)})", fontsize=10)
    ax.legend(fontsize=7)
    from metamaterial_wb.core.sleeve.pipeline import design_axis
    axis = design_axis(model)
    if axis is None:                 # uniform ring: along the largest tilt
        lean_up = up.tilt @ _lean_axis(up.tilt)
        lean_dn = down.tilt @ _lean_axis(up.tilt)
        ax2.set_ylabel("tilt [deg]")
    else:                            # mixed ring: the lean's component along the design axis (signed)
        def along(tilt, a):
            return np.stack([tilt[:, 1], -tilt[:, 0]], axis=1) @ a
        lean_up, lean_dn = along(up.tilt, axis), along(down.tilt, axis)
        across = np.array([-axis[1], axis[0]])
        ax2.plot(up.d, np.degrees(along(up.tilt, across)), color="0.6", lw=1, label="across the axis, loading")
        ax2.plot(down.d, np.degrees(along(down.tilt, across)), "--", color="0.6", lw=1, label="across, unloading")
        ax2.set_ylabel("lean along the\ndesign axis [deg]", fontsize=9)
    ax2.plot(up.d, np.degrees(lean_up), "k", label="loading")
    ax2.plot(down.d, np.degrees(lean_dn), "k--", label="unloading")
    ax2.set_xlabel("displacement d/L [-]")
    ax2.legend(fontsize=7)
    fig.tight_layout(); fig.savefig(os.path.join(folder, "fd_ring.png"), dpi=110); plt.close(fig)
    files.append("fd_ring.png")
    # PV
    c = curves["pv"]
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.plot(*c["load"], "k", label="volume control, inflation")
    ax.plot(*c["unload"], "k--", label="volume control, deflation")
    ax.plot(*c["pc_load"], "r", lw=1, label="pressure control, inflation")
    ax.plot(*c["pc_unload"], "b", lw=1, label="pressure control, deflation")
    ax.axhline(0, color="0.6", lw=0.8)
    ax.set_xlabel("volume change [mL]"); ax.set_ylabel("pressure [kPa]")
    ax.set_ylim(_ylim([c["load"][1]], 1))
    ax.set_title(f"PV (cap area {summary['pv']['cap_area_mm2']:.0f} mm$^2$, G = {spec.G:g} MPa)", fontsize=10)
    ax.legend(fontsize=7)
    fig.tight_layout(); fig.savefig(os.path.join(folder, "pv.png"), dpi=110); plt.close(fig)
    files.append("pv.png")
    if "design_map" in summary:
        files.append(plot_design_map(summary["design_map"], os.path.join(folder, "design_map.png")))
    if "walker" in curves:
        files.append(plot_walker(curves["walker"], os.path.join(folder, "walker.png")))
    return files


def _lean_axis(tilt):
    import numpy as np
    k = int(np.argmax(np.linalg.norm(tilt, axis=1)))
    v = tilt[k]
    n = np.linalg.norm(v)
    return v / n if n > 0 else np.array([1.0, 0.0])


def _ylim(Fs, scale):
    """A y range that shows peaks and valleys (the stretching branch is clipped)."""
    import numpy as np
    lo = min(float(np.min(F)) for F in Fs) * scale
    # highest value before the final stiffening: the maximum over the first 75 % of the path
    hi = max(float(np.max(F[: max(3, int(0.75 * len(F)))])) for F in Fs) * scale
    span = hi - lo
    return lo - 0.15 * span, hi + 0.35 * span


def plot_design_map(dm, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np
    keys = [("peak", "unit cell peak $F_p$"), ("valley", "unit cell valley $F_v$")]
    if "P1" in dm:
        keys += [("P1", "ring first peak $P_1$"), ("V2", "ring second valley $V_2$")]
    fig, axes = plt.subplots(1, len(keys), figsize=(3.3 * len(keys), 3.2))
    t, h = np.array(dm["t_over_L"]), np.array(dm["h_over_L"])
    for ax, (k, title) in zip(np.atleast_1d(axes), keys):
        Z = np.array(dm[k], dtype=float) * 1e3         # null (a skipped cell, no peak): not drawn
        im = ax.pcolormesh(t, h, Z, shading="nearest", cmap="viridis")
        fig.colorbar(im, ax=ax, label="F/(G L$^2$) x1e-3")
        if k in ("P1", "V2") and "peaks_count" in dm:
            one = np.array(dm["peaks_count"], dtype=float) < 2
            for (i, j) in zip(*np.nonzero(one)):
                ax.plot(t[j], h[i], "wx", ms=5)
        ax.set_xlabel("t/L"); ax.set_ylabel("h/L"); ax.set_title(title, fontsize=9)
    fig.tight_layout(); fig.savefig(path, dpi=110); plt.close(fig)
    return os.path.basename(path)


def plot_walker(cyc, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    tip = cyc["tip"]
    n = len(tip) // 2
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(9, 4))
    ax.plot(tip[:n, 0], -tip[:n, 1], "r", label="inflation")
    ax.plot(tip[n:, 0], -tip[n:, 1], "b", label="deflation")
    ax.fill(tip[:, 0], -tip[:, 1], color="0.85", zorder=0)
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("lateral [mm]"); ax.set_ylabel("height [mm] (leg hangs down)")
    ax.set_title(f"leg tip loop, area {cyc['area_mm2']:.1f} mm$^2$", fontsize=10)
    ax.legend(fontsize=8)
    ph = cyc["phase"]
    for leg, tr in cyc["legs"].items():
        ax2.plot(ph, tr[:, 0], label=f"leg {leg}", ls="-" if leg in (1, 3) else "--")
    ax2.set_xlabel("cycle phase"); ax2.set_ylabel("tip lateral [mm]")
    ax2.set_title("diagonal pairs 1-3 / 2-4 in antiphase", fontsize=10)
    ax2.legend(fontsize=8)
    fig.tight_layout(); fig.savefig(path, dpi=110); plt.close(fig)
    return os.path.basename(path)
