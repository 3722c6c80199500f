"""The answer as a scene, its evaluation under every model, and the values polish under a lattice model.

Every answer is re-evaluated with the quadratic, the linear and the nonlinear lattice model
(``core/models.py``): each model's poses of every keyframe are rigidly re-aligned to the target (the
alignment is the only thing refitted; a lattice model's frame is not the kinematics' frame), and the
target error is reported per model, per keyframe and per node. Folds are measured from the model's
rotations (``kinematics.joint_angles``) for every model alike.
"""
import numpy as np

from metamaterial_wb.core import kinematics as _k
from metamaterial_wb.core.errors import MetamaterialError
from metamaterial_wb.core.inverse.fit import box_gauss_newton, combined_errors, frame_errors
from metamaterial_wb.core.scene import Scene, node_name

MODELS = ("quadratic", "linear", "nonlinear")


def servo_names(scene, n):
    used = {it.name for _, it in scene.fixed_items()}
    names, k = [], 1
    while len(names) < n:
        if f"s{k}" not in used:
            names.append(f"s{k}")
        k += 1
    return names


def answer_scene(problem, joints, values, names=None, hinge_overrides=None):
    """A normal scene: the problem's scene with servos on ``joints``; one keyframe: ``value``; several:
    a ``keyframes`` motion profile per servo (times of the target's keyframes, its period)."""
    base = problem.scene
    d = base.to_dict()
    values = np.atleast_2d(np.asarray(values, dtype=float))
    names = names or servo_names(Scene.from_dict(dict(d, actuators=[])), len(joints))
    frames = problem.target.frames
    acts = []
    for k, (name, j) in enumerate(zip(names, joints)):
        a = {"name": name, "joint": j, "value": round_value(values[0, k])}
        if len(frames) > 1:
            prof = {"shape": "keyframes", "times_s": [float(f.time_s) for f in frames],
                    "values": [round_value(v) for v in values[:, k]]}
            if problem.target.period_s is not None:
                prof["period_s"] = float(problem.target.period_s)
            a["profile"] = prof
        acts.append(a)
    d["actuators"] = acts
    if hinge_overrides:
        ov = {o["joint"]: o for o in d.get("joints", [])}
        for j, sizes in hinge_overrides.items():
            ov.setdefault(j, {"joint": j}).update(sizes)
        d["joints"] = [ov[k] for k in sorted(ov)]
    return Scene.from_dict(d)


def round_value(v):
    """Values as stored: clipped only against round-off (|excess| < 1e-12), never silently beyond."""
    v = float(v)
    if abs(v) > 1.0 and abs(v) - 1.0 < 1e-12:
        v = float(np.sign(v))
    return v


def frame_scene(scene, problem, fi, values_row):
    s = scene.copy()
    for a, v in zip(s.actuators, values_row):
        s.set_value(a.name, round_value(v))
    return s


def align_only(fr_res, pos, R, fold_deg=None):
    """Refit only the frame's alignment for given poses: ``(r, parts, transform)`` (the best of the
    frame's alignment starts)."""
    best = None
    for R0, xi0 in fr_res.initial_alignments(pos):
        out = _align_from(fr_res, pos, R, fold_deg, R0, xi0)
        if best is None or float(out[0] @ out[0]) < float(best[0] @ best[0]) - 1e-15:
            best = out
    return best


def _align_from(fr_res, pos, R, fold_deg, R0, xi0):
    if fr_res.n_xi == 0:
        r, _, _, parts = fr_res.evaluate(pos, R, xi0, R0, fold_deg=fold_deg, want_jac=False)
        return r, parts, fr_res.transform(xi0, R0)

    def fun(x, jac=True):
        r, _Jv, Jx, _ = fr_res.evaluate(pos, R, x, R0, fold_deg=fold_deg, want_jac=jac)
        return r, Jx

    inf = np.full(fr_res.n_xi, np.inf)
    x, _ = box_gauss_newton(fun, xi0, -inf, inf, max_nfev=40, tol=1e-14)
    r, _, _, parts = fr_res.evaluate(pos, R, x, R0, fold_deg=fold_deg, want_jac=False)
    return r, parts, fr_res.transform(x, R0)


def evaluate_model(problem, scene, values, model, options=None):
    """Errors of ``scene`` (servos valued per keyframe by ``values``) under ``model``."""
    from metamaterial_wb.core.models import run_model
    values = np.atleast_2d(values)
    frames, parts_all, converged, warnings = [], [], True, []
    for fi, fr_res in enumerate(problem.frames):
        s = frame_scene(scene, problem, fi, values[fi])
        res = run_model(model, s, **(options or {}))
        converged &= bool(res.converged)
        warnings += [w for w in res.warnings if w not in warnings]
        fold = _k.joint_angles(s, res.rotations)[0] if fr_res.frame.folds is not None else None
        r, parts, (sc, Rm, t) = align_only(fr_res, res.positions_mm, res.rotations, fold)
        parts_all.append(parts)
        e = frame_errors(parts)
        e.update({"time_s": fr_res.frame.time_s, "cost_mm2": 0.5 * float(r @ r),
                  "alignment": {"scale": sc, "rotation": Rm.tolist(), "translation_mm": list(map(float, t))},
                  "positions_mm": res.positions_mm})
        frames.append(e)
    out = combined_errors(parts_all)
    out["converged"] = converged
    out["warnings"] = warnings
    out["per_frame"] = frames
    out["per_node"] = per_node(problem, parts_all)
    out["cost_mm2"] = float(sum(f["cost_mm2"] for f in frames))
    return out


def per_node(problem, parts_all):
    ij = problem.topo.node_ij()
    rows = []
    for fi, (fr, parts) in enumerate(zip(problem.target.frames, parts_all)):
        for term, key in ((fr.nodes, "node_dist_mm"), (fr.surface, "surface_dist_mm")):
            if term is None:
                continue
            for n, d in zip(term.idx, parts[key]):
                rows.append({"frame": fi, "node": node_name(int(ij[n, 0]), int(ij[n, 1])), "error_mm": float(d),
                             "kind": "surface" if key.startswith("surface") else "position"})
        if fr.folds is not None:
            for lab, e in zip(fr.folds.labels, parts["fold_err_deg"]):
                rows.append({"frame": fi, "fold": lab, "error_deg": float(e)})
    return rows


def evaluate_all(problem, scene, values, models=MODELS, progress=None):
    out = {}
    for m in models:
        if progress:
            progress(f"evaluating under the {m} model")
        try:
            out[m] = evaluate_model(problem, scene, values, m)
        except MetamaterialError as exc:
            out[m] = {"error": str(exc), "rms_mm": None, "max_mm": None}
    return out


def polish_values(problem, scene, values, model, max_nfev=30, progress=None):
    """Refine the values under a lattice model (finite-difference Jacobian; the model is a black box
    here), starting from the quadratic answer. Returns the new values (frames, servos)."""
    from scipy.optimize import least_squares

    from metamaterial_wb.core.models import run_model
    values = np.array(np.atleast_2d(values), dtype=float)
    for fi, fr_res in enumerate(problem.frames):
        def fun(v):
            s = frame_scene(scene, problem, fi, np.clip(v, -1, 1))
            res = run_model(model, s)
            fold = _k.joint_angles(s, res.rotations)[0] if fr_res.frame.folds is not None else None
            return align_only(fr_res, res.positions_mm, res.rotations, fold)[0]

        r0 = fun(values[fi])
        c0 = 0.5 * float(r0 @ r0)
        sol = least_squares(fun, values[fi], bounds=(-1.0, 1.0), method="trf", diff_step=1e-4, max_nfev=max_nfev,
                            xtol=1e-10, ftol=1e-10)
        if progress:
            progress(f"keyframe {fi}: {model} polish cost {c0:.6g} -> {sol.cost:.6g} mm^2 ({sol.nfev} model runs)")
        if sol.cost < c0:
            values[fi] = np.clip(sol.x, -1, 1)
    return values
