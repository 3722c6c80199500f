"""The answer as a scene, its evaluation under every model, and the values polish under a lattice model.

Every answer is re-evaluated with the quadratic, the linear and the nonlinear lattice model
(``core/models.py``): each model's poses of every keyframe are rigidly re-aligned to the target (the
alignment is the only thing refitted; a lattice model's frame is not the kinematics' frame) from the frame's
alignment starts and from the fit's final alignment, the best end kept (so the quadratic error is at most the
fit's cost), and the target error is reported per model, per keyframe and per node. Folds are measured from the model's
rotations (``kinematics.joint_angles``) for every model alike.
"""
import copy

import numpy as np

from metamaterial_wb.core import kinematics as _k
from metamaterial_wb.core.errors import MetamaterialError
from metamaterial_wb.core.inverse.fit import box_gauss_newton, combined_errors, frame_errors
from metamaterial_wb.core.scene import Scene, node_name, parse_joint

MODELS = ("quadratic", "linear", "nonlinear")
HOUSING_TYPES = ("servo_housing", "servo")          # "servo": the alias the scene format accepts


def servo_names(scene, n):
    used = {it.name for _, it in scene.fixed_items()}
    names, k = [], 1
    while len(names) < n:
        if f"s{k}" not in used:
            names.append(f"s{k}")
        k += 1
    return names


def answer_scene(problem, joints, values, names=None, hinge_overrides=None, warnings=None, module_check=None,
                 moves=None):
    """A normal scene: the problem's scene with servos on ``joints``; one keyframe: ``value``; several:
    a ``keyframes`` motion profile per servo (times of the target's keyframes, its period).

    An actuator the scene already has (same name and joint: ``--values-only``) is copied with every field it
    has (``servo`` channel, ``profile``, notes, ...); only its ``value`` (and, for a keyframe target, its
    ``profile``) is replaced. New servos replace the others; the ``servo_housing`` modules of the replaced
    actuators are moved onto the new servos' joints (:func:`move_housings`), messages about them are appended
    to ``warnings`` (a list) when given, the moves themselves to ``moves`` (see :func:`move_housings`);
    ``module_check(scene)`` (optional) returns a module problem or None.

    The answer has no ``global_deformation``: a stored one is what ``solve`` solves (every D = g) in place of the
    actuators, so the fitted servos would do nothing; a scene that had one gets a line in ``warnings`` saying it
    was dropped."""
    base = problem.scene
    d = base.to_dict()
    g = d.pop("global_deformation", None)
    if g is not None and warnings is not None:
        g = g + 0.0                                   # a stored -0.0 reads 0 in the note (no negative zero)
        note = (f"the scene's global deformation ({g:g}) was dropped from the answer so that the servos act: "
                f"solve solves a stored global deformation (every D = {g:g}) instead of the actuators' values")
        if note not in warnings:
            warnings.append(note)
    values = np.atleast_2d(np.asarray(values, dtype=float))
    names = names or servo_names(Scene.from_dict(dict(d, actuators=[])), len(joints))
    frames = problem.target.frames
    old = {(a.get("name"), a.get("joint")): a for a in d.get("actuators", [])}
    acts = []
    for k, (name, j) in enumerate(zip(names, joints)):
        a = copy.deepcopy(old.get((name, j), {"name": name, "joint": j}))
        a["value"] = round_value(values[0, k])
        if len(frames) > 1:
            prof = {"shape": "keyframes", "times_s": [float(f.time_s) + 0.0 for f in frames],
                    "values": [round_value(v) for v in values[:, k]]}
            if problem.target.period_s is not None:
                prof["period_s"] = float(problem.target.period_s)
            a["profile"] = prof
        acts.append(a)
    kept = set(zip(names, joints))
    gone = [a for a in d.get("actuators", []) if (a.get("name"), a.get("joint")) not in kept]
    replaced = [a.get("joint") for a in gone]
    _carry_servo_channels(acts, old, gone, warnings)
    d["actuators"] = acts
    if hinge_overrides:
        ov = {o["joint"]: o for o in d.get("joints", [])}
        for j, sizes in hinge_overrides.items():
            ov.setdefault(j, {"joint": j}).update(sizes)
        d["joints"] = [ov[k] for k in sorted(ov)]
    if replaced and d.get("modules"):
        d["modules"], notes = move_housings(d, replaced, list(joints), module_check, moves)
        if warnings is not None:
            warnings.extend(n for n in notes if n not in warnings)
    return Scene.from_dict(d)


def _carry_servo_channels(acts, old, gone, warnings):
    """The wiring (``servo``: channel, trim, invert, ...) of replaced motors goes by joint: a new servo (not in
    ``old``) without a ``servo`` object on the joint of a replaced motor keeps that motor's wiring (the cable is
    already there); the wiring of a replaced motor whose joint gets no new servo goes to the new servos still
    without one: motors in the scene's order, servos in the answer's order (s1, s2, ...), the rule the servo
    housings follow. A moved cable gets a warning to check its invert and trim at the new joint."""
    wired = [a for a in gone if isinstance(a.get("servo"), dict)]
    new = [a for a in acts if (a.get("name"), a.get("joint")) not in old and "servo" not in a]
    by_joint = {}
    for src in wired:
        by_joint.setdefault(_joint_key(src.get("joint")), src)
    used = set()
    for a in new:
        src = by_joint.get(_joint_key(a.get("joint")))
        if src is not None and id(src) not in used:
            used.add(id(src))
            a["servo"] = copy.deepcopy(src["servo"])
            _wiring_note(warnings, a, src, moved=False)
    servo_joints = {_joint_key(a.get("joint")) for a in acts}
    free = [src for src in wired if id(src) not in used and _joint_key(src.get("joint")) not in servo_joints]
    for a in new:
        if not free:
            return
        if "servo" in a:
            continue
        src = free.pop(0)
        a["servo"] = copy.deepcopy(src["servo"])
        _wiring_note(warnings, a, src, moved=True)


def _wiring_note(warnings, a, src, moved):
    if warnings is None:
        return
    ch = src["servo"].get("channel")
    chan = f" (channel {ch})" if ch is not None else ""
    if moved:
        warnings.append(f"actuator {a['name']!r} on {a['joint']} takes the servo wiring of the replaced "
                        f"{src.get('name')!r} on {src.get('joint')}{chan}: check its invert and trim_deg at the new "
                        f"joint")
    else:
        warnings.append(f"actuator {a['name']!r} on {a['joint']} keeps the servo wiring of the replaced "
                        f"{src.get('name')!r} on the same joint{chan}")


def _joint_key(text):
    try:
        kind, i, j = parse_joint(text)
    except (MetamaterialError, TypeError, ValueError):
        return None
    return f"{kind}{i},{j}"


def _is_housing(m):
    return isinstance(m, dict) and m.get("type") in HOUSING_TYPES


def move_housings(d, replaced, joints, module_check=None, moves=None):
    """``(modules, notes)``: the scene dict ``d``'s modules with the ``servo_housing`` of every replaced actuator
    (on a joint of ``replaced`` that gets no new servo) moved onto a new servo's joint (``joints``) that has no
    housing yet, in order; ``housing_node`` (a node of the old joint) is dropped. A joint where the housing is
    not valid is skipped: a tilted joint (Export refuses a housing there), another joint module on it, or a
    problem ``module_check`` reports that the scene without the move does not have. A housing that fits no new
    servo is dropped; every move and drop is a line of ``notes`` and, when ``moves`` (a list) is given, a tuple
    ``(index in d["modules"], old joint, new joint or None for a drop)`` appended to it (the GUI applies them to
    its module objects)."""
    from metamaterial_wb.core.design import effective_tilts_deg
    mods = [copy.deepcopy(m) for m in d["modules"]]
    keys = [_joint_key(m.get("joint")) if isinstance(m, dict) else None for m in mods]
    gone = {_joint_key(j) for j in replaced} - set(joints)
    orphans = [k for k, m in enumerate(mods) if _is_housing(m) and keys[k] in gone]
    if not orphans:
        return mods, []
    housed = {keys[k] for k, m in enumerate(mods) if _is_housing(m) and k not in orphans}
    taken = {keys[k] for k, m in enumerate(mods) if k not in orphans and keys[k] is not None}
    free = [j for j in joints if j not in housed]
    probe = Scene.from_dict(dict(d, modules=[m for k, m in enumerate(mods) if k not in orphans]))
    tilt = dict(zip(probe.topology.joint_names, effective_tilts_deg(probe)))
    baseline = module_check(probe) if module_check else None
    notes, drop, pending = [], [], set(orphans)
    for k in orphans:
        m, why = mods[k], []
        label = f"modules[{k}] ({m.get('name', m.get('type'))})"
        for j in list(free):
            if abs(tilt.get(j, 0.0)) > 1e-9:
                why.append(f"{j} has a tilted hinge ({tilt[j]:.4g} deg; a servo housing needs an untilted joint)")
                continue
            if j in taken:
                why.append(f"{j} already carries another joint module")
                continue
            trial = dict(m, joint=j)
            trial.pop("housing_node", None)
            if module_check:
                rest = [trial if i == k else x for i, x in enumerate(mods)
                        if i == k or (i not in pending and i not in drop)]
                problem = module_check(Scene.from_dict(dict(d, modules=rest)))
                if problem is not None and problem != baseline:
                    why.append(f"{j}: {problem}")
                    continue
            notes.append(f"{label}: servo housing moved from {m.get('joint')} to {j} (the servo there replaces "
                         f"the actuator on {m.get('joint')})")
            mods[k] = trial
            if moves is not None:
                moves.append((k, m.get("joint"), j))
            free.remove(j)
            taken.add(j)
            break
        else:
            drop.append(k)
            if moves is not None:
                moves.append((k, m.get("joint"), None))
            reason = "; ".join(why) if why else "no new servo is left without a housing"
            notes.append(f"{label}: servo housing on {m.get('joint')} dropped: no servo there any more and it fits "
                         f"no new servo's joint ({reason})")
        pending.discard(k)
    return [m for k, m in enumerate(mods) if k not in drop], notes


def round_value(v):
    """Values as stored: clipped only against round-off (|excess| < 1e-12), never silently beyond."""
    v = float(v)
    if abs(v) > 1.0 and abs(v) - 1.0 < 1e-12:
        v = float(np.sign(v))
    return v + 0.0                     # -0.0 is stored as 0.0 (no negative zero in the answer scene)


def frame_scene(scene, problem, fi, values_row):
    s = scene.copy()
    for a, v in zip(s.actuators, values_row):
        s.set_value(a.name, round_value(v))
    return s


def align_only(fr_res, pos, R, fold_deg=None, starts=()):
    """Refit only the frame's alignment for given poses: ``(r, parts, transform)``, the best end of the
    frame's own alignment starts (``initial_alignments``) and of ``starts`` (more ``(R0, xi0)`` pairs: the
    fit's final alignment, so a model with the fit's poses ends no worse than the fit)."""
    best = None
    for R0, xi0 in list(fr_res.initial_alignments(pos)) + list(starts or ()):
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


def evaluate_model(problem, scene, values, model, options=None, alignments=None):
    """Errors of ``scene`` (servos valued per keyframe by ``values``) under ``model``. ``alignments``: per
    keyframe, extra alignment starts ``[(R0, xi0), ...]`` (:func:`fit_alignments`: the fit's final ones) tried
    besides the frame's own; the best end is kept."""
    from metamaterial_wb.core.models import run_model
    values = np.atleast_2d(values)
    frames, parts_all, converged, warnings = [], [], True, []
    for fi, fr_res in enumerate(problem.frames):
        s = frame_scene(scene, problem, fi, values[fi])
        res = run_model(model, s, **(options or {}))
        converged &= bool(res.converged)
        warnings += [w for w in res.warnings if w not in warnings]
        fold = _k.joint_angles(s, res.rotations)[0] if fr_res.frame.folds is not None else None
        extra = alignments[fi] if alignments is not None else ()
        r, parts, (sc, Rm, t) = align_only(fr_res, res.positions_mm, res.rotations, fold, extra)
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


def fit_alignments(fit):
    """Per keyframe, ``[(R0, xi)]``: the final alignment of a ``FitResult`` as a start of :func:`align_only`
    (empty for a frame without one)."""
    return [[] if f.R0 is None else [(f.R0, f.xi)] for f in fit.frames]


def evaluate_all(problem, scene, values, models=MODELS, progress=None, alignments=None):
    """``{model: evaluate_model() output or {"error": ...}}``; ``alignments`` as in :func:`evaluate_model`."""
    out = {}
    for m in models:
        if progress:
            progress(f"evaluating under the {m} model")
        try:
            out[m] = evaluate_model(problem, scene, values, m, alignments=alignments)
        except MetamaterialError as exc:
            out[m] = {"error": str(exc), "rms_mm": None, "max_mm": None}
    return out


def polish_values(problem, scene, values, model, max_nfev=30, progress=None, costs=None):
    """Refine the values under a lattice model (finite-difference Jacobian; the model is a black box
    here), starting from the quadratic answer. Returns the new values (frames, servos); a keyframe keeps its
    values when the polish does not lower its cost. ``costs`` (a list), when given, gets one
    ``(cost before, cost of the values returned)`` pair (mm^2, under ``model``) per keyframe."""
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
        if costs is not None:
            costs.append((c0, min(c0, float(sol.cost))))
    return values
