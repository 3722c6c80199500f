"""``simulate SCENE.json --seconds S --out DIR [--frames] [--method M] [--dt DT] [--fps F] [--no-dt-check]``.

The summary's ``warnings`` (also printed on stderr) say when the energy ledger does not close or when the
dt study (the first 2 s again at dt / 2, skipped with ``--no-dt-check``) changes the motion.

Writes into DIR (created; files written atomically, nothing half-way):

* ``summary.json``: ``displacement_mm`` (centre-of-mass travel along x, positive towards increasing
  column / cell index), mean speed, energy bookkeeping, integrator statistics, model info;
* ``trajectory.json``: times and per-body poses (x, y in mm, angle in degrees) in the floor frame,
  plus which scene nodes / cells each body stands for (the animation panel plays it);
* with ``--frames``: ``frames/frame_0000.png ...`` and ``motion.gif`` (matplotlib + ImageMagick if
  available, otherwise PNG frames only).
"""
import os
import re
import shutil
import sys

from metamaterial_wb.cli import number
from metamaterial_wb.core.dynamics.simulate import (MAX_FRAMES, MAX_POSES, MAX_STEPS,  # noqa: F401
                                                     check_output_budget, check_step_budget)
from metamaterial_wb.core.results import trajectory_dict  # noqa: F401  (simulate --out writes it)

NAME = "simulate"
HELP = "simulate a scene's dynamics (contact, gravity, gaits) and write trajectory + summary"


def add_arguments(p):
    p.add_argument("scene", help="scene file (JSON, docs/scene-format.md, section Dynamics)")
    p.add_argument("--seconds", type=number, required=True, help="simulated time (s)")
    p.add_argument("--out", required=True, help="output directory")
    p.add_argument("--frames", action="store_true",
                   help="also write PNG frames and an animated GIF (the GIF needs ImageMagick's convert)")
    p.add_argument("--method", default=None, choices=("auto", "symplectic", "implicit"),
                   help="integrator (default: the scene's dynamics.integrator.method, else auto)")
    p.add_argument("--dt", type=number, default=None,
                   help="time step (s), at most --seconds; default: the scene's dynamics.integrator.dt_s, else "
                        "automatic (implicit: 2 ms for belts, 0.25 ms for sheets); the explicit integrator reduces a "
                        "step beyond its stability limit to its guard, and a default step longer than the run runs "
                        "as one step of --seconds, each with a note on stderr")
    p.add_argument("--fps", type=number, default=30.0,
                   help="trajectory / frame rate (default 30), at most one frame per time step (1 / --dt, else "
                        "1 / the scene's dt_s); each frame is the state at the step nearest its instant k / fps")
    p.add_argument("--incline", type=number, default=None, metavar="DEG",
                   help="override dynamics.incline_deg")
    p.add_argument("--no-dt-check", dest="dt_check", action="store_false",
                   help="skip the dt study (the first 2 s again at dt / 2; a warning when the motion changes)")


def write_frames(model, traj, folder, every=1):
    """PNG frames (matplotlib, Agg) + motion.gif when ImageMagick's convert is available."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    from metamaterial_wb.core.dynamics.system import _rot

    t, q = traj.arrays()
    sys_ = model.system
    os.makedirs(folder, exist_ok=True)
    pts_all = np.concatenate([sys_.contact_points(qq) for qq in q]) * 1e3
    xmin, xmax = pts_all[:, 0].min(), pts_all[:, 0].max()
    ymax = max(q[:, :, 1].max() * 1e3 * 2, 10)
    pad = 0.1 * (xmax - xmin) + 10
    names = []
    a, b = sys_.ha, sys_.hb
    for k in range(0, len(t), every):
        qq = q[k]
        fig, ax = plt.subplots(figsize=(6, 3), dpi=80)
        ax.axhline(0, color="0.3", lw=2)
        pa = (qq[a, :2] + _rot(qq[a, 2], sys_.ra)) * 1e3
        ca = qq[a, :2] * 1e3
        cbp = qq[b, :2] * 1e3
        for i in range(len(a)):
            ax.plot([ca[i, 0], pa[i, 0], cbp[i, 0]], [ca[i, 1], pa[i, 1], cbp[i, 1]], "-", color="tab:blue", lw=2)
        ax.plot(qq[:, 0] * 1e3, qq[:, 1] * 1e3, "o", ms=3, color="k")
        if model.kind == "belt" and traj.extra:
            p = traj.extra[k][model.seg_cell]
            on = p > 0.5 * max(model.cfg["belt"]["pressure_kpa"], 1e-9)
            ax.plot(qq[on, 0] * 1e3, qq[on, 1] * 1e3, "o", ms=6, color="tab:red")
        ax.set_xlim(xmin - pad, xmax + pad)
        ax.set_ylim(-5, ymax + 5)
        ax.set_aspect("equal")
        ax.set_title(f"t = {t[k]:.2f} s   incline {model.cfg['incline_deg']:g} deg", fontsize=9)
        ax.set_xlabel("x (mm)")
        fig.tight_layout()
        name = os.path.join(folder, f"frame_{k // every:04d}.png")
        fig.savefig(name)
        plt.close(fig)
        names.append(name)
    return names


# MAX_STEPS (time steps), MAX_FRAMES, MAX_POSES (recorded frames, frames x bodies): core.dynamics.simulate's, which
# the GUI's run (core.playback.run_dynamics) uses too
OUTPUT_FILES = ("summary.json", "trajectory.json", "motion.gif")   # what a run writes into --out (with frames/)
FRAME_RE = re.compile(r"^frame_\d{4,}\.png$")                      # the frame files a --frames run writes


def check_not_input(scene, out):
    """Refuse a scene that is one of the files the run writes into ``out`` (also through a link; ``motion.gif``
    also without ``--frames``: an earlier run's is removed) or that lies under ``out/frames/`` (replaced or removed
    with the folder): it would be overwritten or deleted."""
    from metamaterial_wb.core.errors import SceneError
    from metamaterial_wb.core.fileio import check_scene_not_output

    check_scene_not_output(out, OUTPUT_FILES, scene)
    folder = os.path.join(out, "frames")
    try:
        inside = os.path.realpath(scene).startswith(os.path.realpath(folder) + os.sep)
    except (OSError, ValueError):
        inside = False
    if inside:
        raise SceneError("--out", f"{scene} is the scene this command reads and lies in {folder}, which a run "
                                  f"replaces or removes as a whole: move the scene or choose another output folder")


def check_frames_folder(out, frames):
    """Before any work: ``out/frames`` is replaced (``--frames``) or removed (an earlier run's, without
    ``--frames``) as a whole, so it must hold nothing but frame files (``frame_NNNN.png``); anything else in it is
    the user's and the run is refused, naming it."""
    from metamaterial_wb.core.errors import SceneError
    from metamaterial_wb.core.fileio import earlier_outputs

    folder = os.path.join(out, "frames")
    if not os.path.lexists(folder):
        return
    if not frames and "frames" not in earlier_outputs(out, "summary.json", "metamaterial-simulation",
                                                      ["summary.json", "trajectory.json"]):
        return                         # neither replaced nor removed: the user's folder, left alone
    if os.path.islink(folder):
        if frames:                     # replacing it would drop the user's link (and not write where it points)
            raise SceneError("--out", f"{folder} is a symbolic link (to {os.readlink(folder)}); --frames replaces "
                                      f"that folder as a whole and does not write through a link: remove the link "
                                      f"or choose another output folder")
        return                         # without --frames: not removed (earlier_outputs skips links), left alone
    if not os.path.isdir(folder):
        return                         # a file, not a folder of frames: commit_set refuses it / it is not removed
    try:
        names = sorted(os.listdir(folder))
    except OSError as exc:
        raise SceneError("--out", f"{folder} cannot be read ({exc.strerror or exc}); it is not replaced") from None
    other = [n for n in names if not FRAME_RE.match(n) or os.path.islink(os.path.join(folder, n))
             or not os.path.isfile(os.path.join(folder, n))]
    if other:
        shown = ", ".join(other[:3]) + (f" and {len(other) - 3} more" if len(other) > 3 else "")
        how = "replaces that folder" if frames else "removes the earlier run's frames folder"
        what = "not a frame file" if len(other) == 1 else "not frame files"
        raise SceneError("--out", f"{folder} holds {shown} ({what} of a run, frame_NNNN.png); this run "
                                  f"{how} as a whole: move {'it' if len(other) == 1 else 'them'} out or choose "
                                  f"another output folder")


def check_frame_rate(fps, dt, what):
    """Refuse, before any work, more than one frame per time step: a frame is a state the integrator reaches, so
    ``fps`` above ``1 / dt`` could only be recorded at a lower rate. ``what`` names where ``dt`` comes from."""
    from metamaterial_wb.core.errors import SceneError
    from metamaterial_wb.core.numbers import inward_g

    if 1.0 / fps < dt * (1.0 - 1e-9):
        raise SceneError("--fps", f"{fps:g} frames/s is more than one frame per time step ({what}: {dt:g} s); "
                                  f"allowed (0, {inward_g(1.0 / dt, 5)}] frames/s (at most 1 / dt, each frame a state "
                                  f"at a step): give a lower --fps or a smaller --dt")


def run(args):
    import numpy as np  # noqa: F401

    from metamaterial_wb.core.dynamics.builders import INCLINE_RANGE_DEG, build, dynamics_config
    from metamaterial_wb.core.dynamics.simulate import simulate
    from metamaterial_wb.core.errors import SceneError, check_number
    from metamaterial_wb.core.fileio import OutputSet, check_output, earlier_outputs, remove_outputs, write_json
    from metamaterial_wb.core.scene import Scene

    out = check_output(args.out, "dir", "--out")
    check_not_input(args.scene, out)
    check_frames_folder(out, args.frames)
    seconds = check_number("--seconds", args.seconds, 0.0, 1e5, "s", low_open=True)
    fps = check_number("--fps", args.fps, 0.0, 1000.0, "Hz", low_open=True)
    if args.dt is not None:
        check_number("--dt", args.dt, 0.0, 1.0, "s", low_open=True)
        if args.dt > seconds:       # the integrator would shorten it to the run: one step, not the step asked for
            raise SceneError("--dt", f"{args.dt:g} s is longer than --seconds {seconds:g} s (the run would be one "
                                     f"step of {seconds:g} s); give --dt at most {seconds:g} s, or a longer --seconds")
    how = f"--seconds {seconds:g} x --fps {fps:g}"
    check_output_budget(seconds, fps, field="--fps", how=how)
    if args.dt is not None:
        check_step_budget(seconds, args.dt, field="--dt", how=f"--seconds {seconds:g} / --dt {args.dt:g}")
    scene = Scene.load(args.scene)
    if args.incline is not None:
        check_number("--incline", args.incline, *INCLINE_RANGE_DEG, "deg")
        dyn = dict(scene.extra.get("dynamics", {}))
        dyn["incline_deg"] = args.incline
        scene.extra["dynamics"] = dyn
    cfg = dynamics_config(scene)
    dt_scene = ((scene.extra.get("dynamics") or {}).get("integrator") or {}).get("dt_s")
    if args.dt is None and isinstance(dt_scene, (int, float)) and dt_scene > 0:
        check_step_budget(seconds, dt_scene, field="dynamics.integrator.dt_s",
                          how=f"--seconds {seconds:g} / dt_s {dt_scene:g}")
    if args.dt is not None:
        check_frame_rate(fps, args.dt, "--dt")
    elif isinstance(dt_scene, (int, float)) and dt_scene > 0:
        check_frame_rate(fps, dt_scene, f"dynamics.integrator.dt_s of {args.scene}")
    model = build(scene, cfg)
    bodies = int(model.system.n)
    check_output_budget(seconds, fps, bodies, field="--fps", how=how)    # simulate() checks it too (the GUI's run)
    if model.kind == "sheet":
        model.scene_nodes = scene.topology.nodes
    from metamaterial_wb.core.dynamics.integrators import StepBudgetError
    from metamaterial_wb.core.dynamics.system import DynamicsError
    try:
        summary, traj, model, sim = simulate(scene, seconds, method=args.method, dt=args.dt, record_dt=1.0 / fps,
                                             cfg=cfg, model=model, dt_check=args.dt_check, max_steps=MAX_STEPS)
    except StepBudgetError as exc:      # the step the integrator chose (automatic, or the symplectic guard)
        raise SceneError("--seconds", f"{exc} (the size budget): shorten --seconds or give a larger --dt "
                                      f"with --method implicit") from None
    except DynamicsError as exc:       # the settling on a slope: name the incline the user gave
        incline = cfg.get("incline_deg") or 0.0
        if not str(exc).startswith("no static equilibrium") or not incline:     # level ground: no slope to blame
            raise
        lo, hi = INCLINE_RANGE_DEG
        flag, where = (("--incline", "") if args.incline is not None else
                       ("dynamics.incline_deg", f" (in {args.scene})"))
        raise SceneError(flag, f"{incline:g} deg (allowed [{lo:g}, {hi:g}] deg): {exc}, or give a gentler "
                               f"{flag}{where}") from None
    rec = summary["recording"] = summary["integrator"].pop("recording")    # what the frames are (frames.py)
    doc = trajectory_dict(model, traj)
    doc["recording"] = rec
    with OutputSet(args.out, "tmp-simulate") as tmp:
        write_json(os.path.join(tmp, "trajectory.json"), doc, indent=None)
        if args.frames:
            names = write_frames(model, traj, os.path.join(tmp, "frames"))
            conv = shutil.which("convert")
            if conv and names:
                import subprocess
                # the rate the frames were recorded at (every step where the step is longer than 1 / fps)
                shown = fps if "every_step_from_s" not in rec else 1.0 / rec["step_s"]
                delay = max(1, int(round(100.0 / shown)))
                r = subprocess.run([conv, "-delay", str(delay), "-loop", "0"] + names
                                   + [os.path.join(tmp, "motion.gif")], capture_output=True, text=True)
                summary["frames"] = {"count": len(names), "gif": r.returncode == 0}
                if r.returncode:
                    summary["frames"]["note"] = (f"ImageMagick's convert failed ({r.stderr.strip()[:200]}): "
                                                 "PNG frames only, no motion.gif")
            else:
                summary["frames"] = {"count": len(names), "gif": False,
                                     "note": "no ImageMagick (its convert command makes the GIF; Debian: "
                                             "imagemagick): PNG frames only, no motion.gif"}
        summary["files"] = sorted(set(os.listdir(tmp)) | {"summary.json"})
        write_json(os.path.join(tmp, "summary.json"), summary)
        stale = earlier_outputs(args.out, "summary.json", summary["format"], summary["files"])
    gone = remove_outputs(args.out, stale)     # an earlier run's frames or GIF this one does not write
    if gone:
        print(f"note: removed {len(gone)} file(s) of the earlier run that this one does not write: "
              f"{', '.join(gone)}", file=sys.stderr)
    it = summary["integrator"]
    print(f"{scene.name or args.scene}: {summary['displacement_mm']:+.2f} mm in {seconds:g} s "
          f"({it['method']}, {it['steps']} steps, {it['wall_s']:.2f} s wall, "
          f"{it['realtime_factor']:.1f}x real time)")
    for fb in it.get("fallbacks", []):
        print(f"warning: at t = {fb['at_s']} s {fb['reason']}; {fb['action']}", file=sys.stderr)
    if it.get("note"):
        print(f"note: {it['note']}", file=sys.stderr)
    if rec.get("note"):
        print(f"note: {rec['note']}", file=sys.stderr)
    if summary.get("frames", {}).get("note"):
        print(f"note: {summary['frames']['note']}", file=sys.stderr)
    for w in summary.get("warnings", []):
        print(f"warning: {w}", file=sys.stderr)
    return 0
