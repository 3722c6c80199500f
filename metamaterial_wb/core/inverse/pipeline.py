"""One inverse-design run, as the CLI (``commands/inverse.py``) and the "Fit to target" panel both call it.

:func:`solve` takes a scene, a parsed target and the options, runs the values fit or the placement
search (candidates through the given *mapper*: serial, a process pool or a Dask cluster, see
``metamaterial_wb.parallel``), optionally the hinge sizes per region, the lattice polish, the
evaluation under every model and the fabrication checks (a callable given by the caller: core does not
build geometry), and returns an :class:`InverseRun`. :func:`report_dict` is ``report.json`` of it.

``progress(msg)`` is called at every stage; it may raise (the panel's Cancel does) to stop the run.
:func:`parse_joint_list` and :func:`parse_models` read the joint lists and model lists people type (CLI, panel).
"""
import re
import time
from dataclasses import dataclass, field

import numpy as np

from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.core.inverse import evaluate as ev


@dataclass
class InverseRun:
    problem: object
    scene: object                  # the answer (a normal scene)
    joints: tuple
    names: list
    values: np.ndarray             # (keyframes, servos)
    fit: object                    # FitResult (quadratic model)
    errors: dict                   # model -> evaluate_model() output
    hinges: list = None            # hinge report rows (None without hinge unknowns)
    fabrication: dict = None       # fab_check() output (None when not run)
    info: dict = field(default_factory=dict)
    lower_bound: float = None
    seconds: float = 0.0
    polish: dict = None            # --model linear|nonlinear: polish_report() (None: the values are the fit's)


SCREEN_RANGE = (0, 1000)
SCREEN_DEFAULT = 12                # placements fully fitted per search round when --screen is not given
_JOINT_TOKEN = re.compile(r"([HVhv])\s*\(?\s*(-?[0-9]{1,9})\s*,\s*(-?[0-9]{1,9})(?:\s*\))?")   # ASCII digits
_JOINT_SEP = re.compile(r"[\s,;]*")
_JOINT_LIST_ALLOWED = ("joint names H<i>,<j> or V<i>,<j>, several separated by spaces or semicolons "
                       "(e.g. \"V0,1 H2,3\" or \"V0,1; H2,3\")")


def _quiet(msg):
    pass


def parse_joint_list(items, field="--forbid", unique=False):
    """Joint names from the strings ``items`` (one per ``--forbid``), in order, repeats dropped (``unique``: a
    joint named twice, in any spelling, is refused, as the command line refuses repeated list items).

    A joint name holds a comma (``V0,1``), so a string may hold several names separated by spaces,
    semicolons or commas between whole names: ``"V0,1 H2,3"``, ``"V0,1; H2,3"``, ``"V0,1, H2,3"`` (the
    panel's way) and ``"V0,1,H2,3"`` all give ``["V0,1", "H2,3"]``. ``H(1,2)`` and lower case are accepted.
    Whether the joints exist is the search's check (it knows the scene).

    Raises
    ------
    SceneError
        At ``field`` for a string naming no joint or holding something that is not a joint name.
    """
    out = []
    for item in items:
        text = str(item)
        if _JOINT_SEP.fullmatch(text):
            raise SceneError(field, f"{text!r} names no joint; allowed: {_JOINT_LIST_ALLOWED}")
        pos = 0
        while True:
            pos = _JOINT_SEP.match(text, pos).end()
            if pos == len(text):
                break
            m = _JOINT_TOKEN.match(text, pos)
            if m is None or (m.end() < len(text) and text[m.end()] not in " \t\r\n,;"):
                bad = re.match(r"[^\s;]*", text[pos:]).group(0) or text[pos:]
                where = "" if bad == text else f"{text!r}: "
                raise SceneError(field, f"{where}{bad!r} is not a joint name; allowed: {_JOINT_LIST_ALLOWED}")
            name = f"{m.group(1).upper()}{int(m.group(2))},{int(m.group(3))}"
            if name not in out:
                out.append(name)
            elif unique:
                given = " ".join(repr(str(x)) for x in items)
                raise SceneError(field, f"{name} is given more than once (joints {out.index(name) + 1} and "
                                        f"{len(out) + 1} of {given}); give each joint once")
            pos = m.end()
    return out


def parse_models(text, field="--evaluate"):
    """The model names of a comma-separated list; at least one, each of ``evaluate.MODELS``, each once.

    Raises
    ------
    SceneError
        At ``field`` for an empty list, an unknown model or a model given twice (as the command line refuses
        repeated list items).
    """
    allowed = ", ".join(ev.MODELS)
    models = []
    for m in str(text).split(","):
        m = m.strip()
        if m and m not in ev.MODELS:
            raise SceneError(field, f"{m!r}; allowed: {allowed} (comma-separated)")
        if m in models:
            raise SceneError(field, f"{m!r} is given more than once (items {models.index(m) + 1} and "
                                    f"{len(models) + 1} of {text!r}); give each model once")
        if m:
            models.append(m)
    if not models:
        raise SceneError(field, f"{text!r} names no model; allowed: one or more of {allowed} (comma-separated)")
    return models


def solve(scene, target, servos=None, values_only=False, forbidden=(), hinge_regions=None, model="quadratic",
          evaluate=ev.MODELS, screen=SCREEN_DEFAULT, mapper=None, workers=1, progress=None, fab_check=None, module_check=None):
    """The whole run (see the module doc). ``hinge_regions``: ``(rows, cols)`` or None; ``module_check(scene)``:
    a module problem (str) or None, used when servo housings move with the servos (``evaluate.move_housings``).
    ``screen`` None: :data:`SCREEN_DEFAULT`. The ``model`` model is always evaluated: when ``evaluate`` leaves it
    out it is added, with a line in the warnings."""
    from metamaterial_wb.core.inverse.fit import Problem
    from metamaterial_wb.core.inverse.search import search_placement

    progress = progress or _quiet
    t0 = time.perf_counter()
    for m in evaluate:
        if m not in ev.MODELS:
            raise SceneError("--evaluate", f"{m!r}; allowed: {', '.join(ev.MODELS)}")
    if not list(evaluate):
        raise SceneError("--evaluate", f"no model given; allowed: one or more of {', '.join(ev.MODELS)}")
    if model not in ev.MODELS:
        raise SceneError("--model", f"{model!r}; allowed: {', '.join(ev.MODELS)}")
    # the target's warnings (an old result) open the run's list; the caller says them when it reads the target
    told = list(getattr(target, "info", {}).get("warnings", []))
    evaluate, notes = list(evaluate), list(told)
    if model not in evaluate:
        evaluate.append(model)
        notes.append(f"--model {model} is not in --evaluate ({', '.join(evaluate[:-1])}): the answer is evaluated "
                     f"under the {model} model too (errors.{model}), the model whose error the values minimise")
    screen = SCREEN_DEFAULT if screen is None else screen
    if not SCREEN_RANGE[0] <= screen <= SCREEN_RANGE[1]:
        raise SceneError("--screen", f"{screen} is outside the allowed range [{SCREEN_RANGE[0]}, {SCREEN_RANGE[1]}] "
                                     f"(0: fit every candidate)")
    forbidden = list(forbidden or ())
    if values_only and forbidden:
        raise SceneError("--forbid", "has no effect with --values-only (the placement is the scene's)")
    pb = Problem(scene, target, keep_actuators=values_only)
    info = {"fits": 0, "screened": 0, "linearised": 0}
    lower = None
    if values_only:
        if servos is not None and servos != len(scene.actuators):
            raise SceneError("--servos", f"{servos} with --values-only: the scene has {len(scene.actuators)} "
                                         f"actuators (leave --servos out)")
        if not scene.actuators:
            raise SceneError("actuators", "--values-only needs a scene with actuators")
        joints = tuple(a.joint for a in scene.actuators)
        names = [a.name for a in scene.actuators]
        progress("fitting the values")
        fit = pb.fit(joints, starts=(0.5, -0.5))
        info["fits"] = 1
    else:
        if servos is None:
            raise SceneError("--servos", "give the servo budget N (or --values-only)")
        res = search_placement(pb, servos, forbidden=forbidden, mapper=mapper, workers=workers,
                               progress=progress, screen=screen)
        joints, fit, names = res.joints, res.fit, None
        info.update(fits=res.fits, screened=res.screened, linearised=res.info.get("linearised", 0))
        lower = res.info.get("lower_bound")
    fit, capped = converge(pb, joints, fit, info, progress, finalists=[] if values_only else res.finalists,
                           mapper=mapper, workers=workers)
    joints = tuple(fit.joints)
    values = fit.values
    hinge_report, overrides, warnings = None, None, notes + ([capped] if capped else [])
    if hinge_regions is not None:
        from metamaterial_wb.core.inverse.hinges import HingeRegions
        hr = HingeRegions(pb, *hinge_regions)
        progress(f"fitting {hr.n_unknowns} hinge size(s) of {len(hr.regions)} region(s) with the values")
        hfit, sizes = hr.fit(joints, v0=values)
        info["fits"] += 1
        kept = hinge_answer(pb, hr, joints, names, fit, hfit, sizes, warnings, progress, module_check)
        if kept is not None:
            pb, fit, sizes, overrides = kept
            values = fit.values
            info["fits"] += 1
        else:
            sizes = hr.start_sizes()
        hinge_report = hr.report(sizes)
    polish_costs = None
    if model != "quadratic":  # (the statics read no modules: the housings move once, in the answer below)
        polish_costs = []
        values = ev.polish_values(pb, ev.answer_scene(pb, joints, values, names, hinge_overrides=overrides),
                                  values, model, progress=progress, costs=polish_costs)
    moves = []
    out_scene = ev.answer_scene(pb, joints, values, names, hinge_overrides=overrides, warnings=warnings,
                                module_check=module_check, moves=moves)
    loadable_scene(out_scene)                     # the written scene loads and configures as solve reads it
    for w in warnings[len(told):] if warnings[:len(told)] == told else warnings:
        progress(f"warning: {w}")
    info["warnings"] = warnings
    info["module_moves"] = moves              # (module index, old joint, new joint or None): the GUI applies them
    errors = ev.evaluate_all(pb, out_scene, values, evaluate, progress=progress,
                             alignments=ev.fit_alignments(fit))   # a start: quadratic error <= fit.cost (unpolished)
    polish = None if polish_costs is None else polish_report(model, polish_costs, fit.values, out_scene)
    fab = None
    if fab_check is not None:
        progress("fabrication checks (the ones build runs)")
        fab = fab_check(out_scene)
    names = [a.name for a in out_scene.actuators]
    return InverseRun(pb, out_scene, tuple(joints), names, np.atleast_2d(values), fit, errors, hinge_report, fab,
                      info, lower, time.perf_counter() - t0, polish)


def polish_report(model, costs, fit_values, scene):
    """``report.json``'s ``polish``: the lattice ``model`` the written values were polished under, its cost
    (mm^2, summed over the keyframes, alignment refitted from the frame's own starts) of the fit's values
    (``start_cost_mm2``) and of the written ones (``cost_mm2``), and the fit's values before the polish
    (``fit_values``: the values ``fit_cost_mm2`` describes), per servo."""
    fv = np.atleast_2d(np.asarray(fit_values, dtype=float))
    return {"model": model, "start_cost_mm2": float(sum(c for c, _ in costs)),
            "cost_mm2": float(sum(c for _, c in costs)),
            "fit_values": [{"name": a.name, "joint": a.joint, "values": [float(v) for v in fv[:, k]]}
                           for k, a in enumerate(scene.actuators)]}


FINAL_MAX_NFEV = 1000   # the answer's own fit runs to convergence (the search's fits stop at 40-60 evaluations)


def converge(pb, joints, fit, info, progress, finalists=(), mapper=None, workers=1):
    """The answer's values fitted on from where the search (or the values-only fit) stopped, with up to
    ``FINAL_MAX_NFEV`` evaluations a frame: the search's fits are capped to keep screening cheap, and a capped fit
    can stop well short (the gripper on its cylinder, H4,2 + V3,6: 28.80 mm^2, converged 22.28). ``finalists``
    (``SearchResult.finalists``: ``[(joints, values)]``, other placements of the search) are fitted to convergence
    too, through ``mapper`` (``search.converge_batch``, one BLAS thread), and the lowest converged cost wins (the
    answer on a tie or a round-off difference): a capped cost ranks placements only roughly, and its last digits
    depend on the machine's BLAS (the gripper with OpenBLAS's AVX-512 kernels: H4,2 + V3,6 capped 29.09, converged
    22.28; V3,2 + V3,6 capped 34.82, converged 21.95; with its Haswell kernels the capped ranking was the other
    way). ``(fit, warning or None)``: the answer's fit (the lower of the search's and the converged one) or a
    finalist's converged fit; the warning when that fit still reached the limit."""
    import functools

    from metamaterial_wb.core.inverse.search import COST_FLOOR, _chunks, converge_batch, one_blas_thread, serial_map
    more = pb.fit(joints, v0=fit.values, max_nfev=FINAL_MAX_NFEV)
    info["fits"] = info.get("fits", 0) + 1
    stopped = any(f.nfev >= FINAL_MAX_NFEV for f in more.frames)
    if more.cost < fit.cost:
        if fit.cost - more.cost > 1e-6 * fit.cost + COST_FLOOR:     # (not a round-off gain)
            progress(f"the answer fitted to convergence: cost {fit.cost:.6g} -> {more.cost:.6g} mm^2")
        fit = more
    best = fit
    if finalists:
        tasks = [(tuple(j), np.asarray(v, dtype=float)) for j, v in finalists]
        progress(f"fitting {len(tasks)} other placement(s) of the search to convergence")
        parts = (mapper or serial_map)(functools.partial(one_blas_thread, converge_batch), pb,
                                       [(FINAL_MAX_NFEV, ch) for ch in _chunks(tasks, max(1, int(workers)))])
        done = [f for part in parts for f in part]
        info["fits"] += len(done)
        progress("converged: " + "; ".join(f"{', '.join(f.joints)} {f.cost:.6g}" for f in done) + " mm^2")
        k = min(range(len(done)), key=lambda i: (done[i].cost, i))
        if done[k].cost < fit.cost * (1.0 - 1e-6) - COST_FLOOR:
            best = done[k]
            stopped = any(f.nfev >= FINAL_MAX_NFEV for f in best.frames)
            progress(f"the lowest converged cost: {', '.join(best.joints)} ({best.cost:.6g} mm^2; the search's "
                     f"answer {', '.join(fit.joints)}: {fit.cost:.6g} mm^2)")
    capped = None
    if stopped:
        capped = (f"the answer's fit stopped at its evaluation limit ({FINAL_MAX_NFEV} a keyframe): the values may "
                  f"not be the best for this placement")
    return best, capped


HINGE_STEPS = (1.0, 0.5, 0.25)     # fractions of the fitted size change tried when the full change breaks a rule


def loadable_scene(scene):
    """``scene`` as ``solve`` reads it: through its JSON text, then configured (``design.ensure_configured``: the
    joint configuration and rotation limits re-derived from the scene's own hinges; an axis fold beyond its
    maximum raises). Returns the configured Scene (a new object)."""
    from metamaterial_wb.core import design
    from metamaterial_wb.core.scene import Scene
    s = Scene.from_json(scene.to_json())
    design.ensure_configured(s)
    return s


def hinge_answer(pb, hr, joints, names, fit, hfit, sizes, warnings, progress=_quiet, module_check=None):
    """The hinge answer to keep, or None to keep the scene's own hinges (``fit``: the values fit without hinge
    unknowns). The fitted sizes (and, when they break a rule, sizes moved back towards the scene's by
    :data:`HINGE_STEPS`) are written into an answer scene that must load and configure as ``solve`` does
    (:func:`loadable_scene`: an axis whose fold the new hinges cannot reach is refused); the values are then refitted
    on that scene (its own rotation limits) and the answer is kept only if that cost is below ``fit.cost``.
    Returns ``(problem of the answer scene, FitResult, sizes, overrides)``; notes go to ``warnings``."""
    from metamaterial_wb.core.errors import MetamaterialError
    from metamaterial_wb.core.inverse.fit import Problem
    if not hfit.cost < fit.cost:                  # the hinge fit itself found nothing better
        return None
    p0 = hr.start_sizes()
    first_error = None
    for t in HINGE_STEPS:
        p = p0 + t * (np.asarray(sizes, dtype=float) - p0)
        ov = hr.overrides(p)
        if not ov:
            return None
        notes, v0 = [], (hfit.values if t == 1.0 else fit.values)
        cand = ev.answer_scene(pb, joints, v0, names, hinge_overrides=ov, warnings=notes, module_check=module_check)
        try:
            checked = loadable_scene(cand)
        except MetamaterialError as exc:
            first_error = first_error or str(exc)
            progress(f"hinge sizes at {t:g} of the fitted change refused: {exc}")
            continue
        pb2 = Problem(checked, pb.target, keep_actuators=True)
        fit2 = pb2.fit(joints, v0=np.atleast_2d(v0), starts=(0.5, -0.5))
        progress(f"hinge answer ({t:g} of the fitted size change) re-evaluated with its own rotation limits: cost "
                 f"{fit2.cost:.6g} mm^2 (scene's hinges: {fit.cost:.6g} mm^2; the hinge fit saw {hfit.cost:.6g})")
        if fit2.cost >= fit.cost:
            warnings.append(f"--hinges: the fitted hinge sizes do not lower the cost once the scene's rotation limits "
                            f"are re-derived from them ({fit2.cost:.6g} mm^2 against {fit.cost:.6g} mm^2 with the "
                            f"scene's hinges); the answer keeps the scene's hinges")
            return None
        costs = (f"{fit2.cost:.6g} mm^2 with their own rotation limits against {fit.cost:.6g} mm^2 with the scene's "
                 f"hinges")
        if first_error:
            warnings.append(f"--hinges: the fitted hinge sizes were refused ({first_error}); the answer moves the "
                            f"sizes {t:g} of the way from the scene's to the fitted ones ({costs})")
        else:
            warnings.append(f"--hinges: the fitted hinge sizes are kept ({costs}); the answer's joints hold them "
                            f"(the report's hinges)")
        warnings.extend(n for n in notes if n not in warnings)
        return pb2, fit2, p, ov
    warnings.append(f"--hinges: the fitted hinge sizes were refused ({first_error}), also moved back towards the "
                    f"scene's; the answer keeps the scene's hinges")
    return None


def json_errors(e):
    if "per_frame" not in e:
        return dict(e)
    out = {k: v for k, v in e.items() if k not in ("per_frame",)}
    out["per_frame"] = [{k: v for k, v in f.items() if k != "positions_mm"} for f in e["per_frame"]]
    return out


def report_dict(run, **extra):
    """``report.json`` of a run (docs/inverse.md); ``extra`` fields (paths, workers, ...) are added."""
    rep = {
        "format": "metamaterial-inverse-report", "version": 1,
        "servos": len(run.joints),
        "placement": [{"name": a.name, "joint": a.joint, "values": [float(v) for v in run.values[:, k]]}
                      for k, a in enumerate(run.scene.actuators)],
        "keyframes": [{"time_s": f.time_s} for f in run.problem.target.frames],
        "hinges": run.hinges,
        "errors": {m: json_errors(e) for m, e in run.errors.items()},
        "fit_cost_mm2": float(run.fit.cost), "polish": run.polish, "free_field_bound_mm2": run.lower_bound,
        "candidates_evaluated": {k: v for k, v in run.info.items() if k not in ("warnings", "module_moves")},
        "fabrication": run.fabrication,
        "printable": None if run.fabrication is None else run.fabrication.get("printable"),
        "warnings": list(run.info.get("warnings", [])),
        "run_time_s": run.seconds,
    }
    rep.update(extra)
    return rep


def summary_lines(run):
    """Human lines: the errors under every model, the placement, printability."""
    lines = []
    if run.polish is not None:
        p = run.polish
        lines.append(f"values polished under the {p['model']} model: cost {p['start_cost_mm2']:.6g} -> "
                     f"{p['cost_mm2']:.6g} mm^2 (the quadratic fit's cost {run.fit.cost:.6g} mm^2 is of the values "
                     f"before the polish)")
    for m, e in run.errors.items():
        if e.get("rms_mm") is not None:
            lines.append(f"{m}: rms {e['rms_mm']:.4g} mm, max {e['max_mm']:.4g} mm")
        if e.get("rms_deg") is not None:
            lines.append(f"{m}: folds rms {e['rms_deg']:.4g} deg, max {e['max_deg']:.4g} deg")
        if "error" in e:
            lines.append(f"{m}: {e['error']}")
    if run.fabrication is not None:
        f = run.fabrication
        if f.get("printable"):
            lines.append(f"printable: yes ({', '.join(f.get('checks_run', []))})")
        elif f.get("printable") is False:
            lines.append("printable: NO: " + "; ".join(f.get("problems", [])[:3]))
        else:
            lines.append("printable: not fully checked: " + "; ".join(f.get("notes", [])[:2]))
    return lines
