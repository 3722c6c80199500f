"""Higher-fidelity lattice models (rigid plates + TPU beam hinges): "linear" and "nonlinear".

Importing this package only registers the two models; the numerical modules are imported when a
lattice model actually runs, so selecting the quadratic model never builds (or imports) them
(tests/fidelity/test_leave_out.py).

Options (``run_model(name, scene, **options)``; ``solve --model ... --option key=value``; types and ranges:
``LINEAR_OPTIONS`` / ``NONLINEAR_OPTIONS`` below, checked by ``core.models.check_options``):

* both: ``planar`` (bool, default: automatic = no tilted hinge in the scene; true on a scene with tilted
  hinges suppresses their folds, with a warning), ``contact`` (plate
  contact, true: one-sided constraints in the linear model, a penalty in the nonlinear one),
  ``contact_fraction`` (0.98 of the plate-contact rotation);
* linear: ``poses`` (``chain``, default: positions through the hinge chain from the plate rotations;
  ``linear``: the flat positions plus the solved displacements); ``about`` (``quadratic``, default:
  linearised about the quadratic model's predicted state, material tangent, one factorisation per call,
  about a third of the quadratic model's error at working amplitudes; ``flat``: linearised at the flat
  sheet, factorisation cached across actuator values, so a value-only change re-solves without a new
  factorisation, ~0.5-0.65 ms on 10 x 10 without plate contact, ~1.2-1.9 ms when the contact active set
  re-solves; valid up to amplitude ~0.4 there: beyond, hinges pass the scene's rotation limits, which
  ``_limit_check`` warns about for both models); ``line_search`` (with ``about=quadratic``: step length minimising
  the nonlinear energy along the solved step, true). Without CHOLMOD (scikit-sparse) the linear model
  factors its KKT matrix by SuperLU: same results, ~1.4 x the time;
* nonlinear: ``tol`` (relative residual, default 1e-8), ``max_iter`` (Newton iterations per load
  step, 40), ``load_steps`` (initial number of load steps, 1; halved adaptively down to
  ``min_step``), ``contact`` (plate-contact penalty, true), ``contact_fraction`` (0.98),
  ``contact_stiffness`` (1e4, times the hinge's soft bending stiffness), ``fallback`` (dynamic
  relaxation when Newton fails, true), ``dr_max_iter`` (5000), ``hinge_elements`` (corotational
  Timoshenko elements per hinge, 1; more resolve a hinge's deformed shape at large rotations:
  ``core/lattice/refine``, convergence study in docs/fidelity.md), ``predictor`` (false; only with one
  element per hinge, the scene's own ``planar`` and Newton: refused otherwise);
* both: ``hinge_law`` (``beam``, default: Timoshenko beam theory; ``fe``: its stiffness scaled per DOF to the
  CalculiX hinge study, ``core/data/fe_hinge_law.json``, hinges of length / width 1.25-7.5).
"""
import json
import time
from collections import OrderedDict

import numpy as np

from metamaterial_wb.core.models import ModelResult, Option, register_model

# every option of the two models: type, range, meaning (run_model parses and checks the values against these;
# "text" options are choices the model checks itself). Keep the module docstring and docs/fidelity-models.md
# in step.
_BOTH = {
    "planar": Option("bool", "solve in the sheet's plane; default: automatic, no tilted hinge", none_ok=True),
    "contact": Option("bool", "plate contact"),
    "contact_fraction": Option("float", "fraction of the plate-contact rotation where contact starts", 0.0, 1.0,
                               low_open=True),
    "hinge_law": Option("text", "beam or fe"),
}
LINEAR_OPTIONS = dict(_BOTH, **{
    "poses": Option("text", "chain or linear"),
    "about": Option("text", "quadratic or flat"),
    "line_search": Option("bool", "step length from the nonlinear energy (about=quadratic)"),
})
NONLINEAR_OPTIONS = dict(_BOTH, **{
    "tol": Option("float", "relative residual", 0.0, 1.0, low_open=True, high_open=True),
    "max_iter": Option("int", "Newton iterations per load step", 1, 100000),
    "load_steps": Option("int", "initial number of load steps", 1, 100000),
    "min_step": Option("float", "smallest load step, a fraction of the load", 0.0, 1.0, low_open=True),
    "contact_stiffness": Option("float", "contact penalty, times the hinge's soft bending stiffness", 0.0, 1e12,
                                low_open=True),
    "fallback": Option("bool", "dynamic relaxation when Newton fails"),
    "dr_max_iter": Option("int", "dynamic-relaxation iterations", 1, 10000000),
    "predictor": Option("bool", "start Newton from the linear model with contact"),
    "method": Option("text", "newton or dynamic_relaxation"),
    "hinge_elements": Option("text", "corotational elements per hinge"),
})
_LINEAR_OPTS = set(LINEAR_OPTIONS)
_NONLINEAR_OPTS = set(NONLINEAR_OPTIONS)


def _check_options(model, options, allowed):
    from metamaterial_wb.core.errors import SceneError

    for k in options:
        if k not in allowed:
            raise SceneError(f"--option {k}", f"unknown option of model {model!r}; allowed: {sorted(allowed)}")


def _global(scene, g, t0):
    from metamaterial_wb.core import kinematics
    from metamaterial_wb.core.errors import check_number

    g = check_number("global_deformation", g, -1.0, 1.0)
    D = np.full(scene.topology.n_nodes, g)
    from metamaterial_wb.core.design import kinematics_for
    pos, R, _phi = kinematics.node_poses(scene, D, kin=kinematics_for(scene))
    return ModelResult(D, pos, R, [], {"total_s": time.perf_counter() - t0}, True,
                       {"method": "global deformation: closed-form kinematics, no solve"})


def _range_warnings(scene, D, warnings, past_limits=False):
    over = np.flatnonzero(np.abs(D) > 1.0 + 1e-9)
    if over.size:
        k = int(over[np.argmax(np.abs(D[over]))])
        i, j = scene.topology.nodes[k]
        why = ("hinges past the scene's rotation limits (warned above): not a physical amplification" if past_limits
               else "free-edge amplification: D beyond +-1 means the plate turns further than in the uniform "
                    "mechanism at its limit")
        warnings.append(f"{over.size} node(s) turn further than the actuators' range, e.g. N{i},{j} at D = "
                        f"{D[k]:.3f} ({why})")


# a hinge whose relative rotation passes the scene's limit by more than this fraction is flagged (the plate-contact
# penalty and the linear contact constraint start at contact_fraction = 0.98 of it, so a resolved contact stays
# inside); a total rotation from this angle on folds the plates back onto each other whatever the limits
_LIMIT_SLACK = 0.01
_FOLD_THROUGH_DEG = 170.0


def _limit_check(scene, geo, R, model):
    """Hinges turned past the scene's rotation limits: ``(warning or None, records)``.

    Per hinge the relative rotation of its two plates (``R_a^T R_b``) is split into its in-plane part, signed
    closing (+) / opening (-) like the D scale, and compared with the scene's limits for that sense: twice the
    plate rotation at D = +1 (closing) or D = -1 (opening) (``core.limits.rotation_limit_info``, the same rule as
    the quadratic model's D scale); a total rotation of ``_FOLD_THROUGH_DEG`` or more is flagged whatever the
    sense (the plates fold through each other). ``records``: the worst ten, each ``joint``, ``angle_deg``,
    ``sense``, ``limit_deg``."""
    from metamaterial_wb.core.rotations import rotation_log

    R = np.asarray(R, float)
    a, b = geo.a, geo.b
    if not len(a):
        return None, []
    v = rotation_log(np.swapaxes(R[a], 1, 2) @ R[b])
    total = np.degrees(np.linalg.norm(v, axis=1))
    inplane = np.degrees(-geo.parity[a] * v[:, 2])          # > 0 closing, < 0 opening (D's sign)
    closing = inplane >= 0
    limit = np.where(closing, 2.0 * np.degrees(geo.closing_rad), 2.0 * np.degrees(geo.opening_rad))
    ratio = np.maximum(np.abs(inplane) / limit, total / _FOLD_THROUGH_DEG)
    bad = np.flatnonzero((np.abs(inplane) > (1.0 + _LIMIT_SLACK) * limit) | (total >= _FOLD_THROUGH_DEG))
    if not bad.size:
        return None, []
    bad = bad[np.argsort(-ratio[bad])]
    names = scene.topology.joint_names
    records = [{"joint": names[k], "angle_deg": float(total[k]), "in_plane_deg": float(abs(inplane[k])),
                "sense": "closing" if closing[k] else "opening", "limit_deg": float(limit[k])} for k in bad[:10]]
    k = int(bad[0])
    from metamaterial_wb.core.limits import rotation_limit_info
    binding = rotation_limit_info(scene, geo.tilt)["closing_binding" if closing[k] else "opening_binding"]
    sense = "closing" if closing[k] else "opening"
    d = "+1" if closing[k] else "-1"
    text = (f"{bad.size} hinge(s) turn past the scene's rotation limits, e.g. {names[k]} turns {total[k]:.1f} deg "
            f"({abs(inplane[k]):.1f} deg {sense} in the plane), past the scene's {sense} limit {limit[k]:.1f} deg "
            f"(twice the plate rotation at D = {d}: {binding})"
            + (f" and folding through at {_FOLD_THROUGH_DEG:g} deg" if total[k] >= _FOLD_THROUGH_DEG else ""))
    if model == "linear":
        text += ("; the linear model's result is not a valid pose there (a linearisation far outside its range: "
                 "plates may pass through each other): use smaller actuator values or the nonlinear model "
                 "(docs/fidelity-models.md)")
    else:
        text += "; plates may touch or pass through each other and the hinge may be overstrained there"
    return text, records


def _planar_warning(geo, planar_override, warnings):
    """``planar=true`` on a scene with tilted hinges: every plate stays in the sheet's plane, so no fold."""
    tilted = np.flatnonzero(np.asarray(geo.tilt) != 0.0)
    if planar_override and tilted.size:
        k = int(tilted[0])
        warnings.append(f"--option planar=true on a scene with {tilted.size} tilted hinge(s) (e.g. "
                        f"{geo.scene.topology.joint_names[k]} at {np.degrees(geo.tilt[k]):.1f} deg): the solve keeps "
                        "every plate in the sheet's plane, so the tilted hinges' folds are suppressed; omit planar "
                        "(automatic) to let them fold")


_LINEAR_CACHE = OrderedDict()
_LINEAR_CACHE_SIZE = 4


def _state_warnings(scene, geo, D, R, model, planar_override, info, warnings):
    """What both lattice models warn about a solved state: ``planar=true`` on tilted hinges, hinges past the
    scene's rotation limits (also recorded as ``info["hinge_limit_exceeded"]``) and the range warnings."""
    _planar_warning(geo, planar_override, warnings)
    text, records = _limit_check(scene, geo, R, model)
    info["hinge_limit_exceeded"] = records
    if text:
        warnings.append(text)
    _range_warnings(scene, D, warnings, past_limits=bool(records))


def _structure_key(scene, planar):
    """Everything but the actuator/constraint values: scenes with equal keys share a factorisation."""
    d = scene.to_dict()
    for k in ("actuators", "constraints"):
        d[k] = [{kk: vv for kk, vv in item.items() if kk not in ("value", "profile")} for item in d.get(k, [])]
    for k in ("name", "description", "global_deformation", "modules"):
        d.pop(k, None)
    return json.dumps(d, sort_keys=True, default=str) + f"|planar={planar}"


def clear_cache():
    """Forget the cached linear models (factorisations kept per scene structure).

    Returns
    -------
    None
    """
    _LINEAR_CACHE.clear()


def _linear(scene, global_deformation=None, planar=None, contact=True, contact_fraction=0.98, poses="chain",
            about=None, line_search=True, hinge_law=None, **options):
    t0 = time.perf_counter()
    _check_options("linear", options, _LINEAR_OPTS)
    from metamaterial_wb.core.errors import SceneError
    if about not in (None, "flat", "quadratic"):
        raise SceneError("--option about", f"{about!r}; allowed: flat, quadratic")
    from metamaterial_wb.core.lattice.geometry import HINGE_LAWS
    if hinge_law not in (None,) + HINGE_LAWS:
        raise SceneError("--option hinge_law", f"{hinge_law!r}; allowed: {', '.join(HINGE_LAWS)}")
    if global_deformation is not None:
        return _global(scene, global_deformation, t0)
    fallback = None
    if about in (None, "quadratic"):
        try:
            return _linear_about_quadratic(scene, planar, contact, contact_fraction, poses, bool(line_search), t0,
                                           hinge_law)
        except _PredictorRefused as exc:
            # the default only: a scene the quadratic model refuses (e.g. hinges outside its calibration
            # table) is linearised at the flat sheet instead, with a warning
            if about == "quadratic":
                raise exc.error from None
            fallback = str(exc.error)
    from metamaterial_wb.core.lattice.geometry import fixed_items
    from metamaterial_wb.core.lattice.solve import LinearLattice, finish

    key = (_structure_key(scene, planar) + f"|contact={bool(contact)},{float(contact_fraction)!r}|poses={poses}"
           f"|law={hinge_law or 'beam'}")
    cached = _LINEAR_CACHE.get(key)
    reused = cached is not None
    if reused:                       # only actuator values changed: reuse geometry and factorisation
        lin = cached
        geo = lin.geo
        _LINEAR_CACHE.move_to_end(key)
    t1 = time.perf_counter()
    if not reused:
        geo = _geometry(scene, planar, hinge_law)
        t1 = time.perf_counter()
        lin = LinearLattice(scene, geo, contact=contact, contact_fraction=contact_fraction, poses=poses)
        _LINEAR_CACHE[key] = lin
        while len(_LINEAR_CACHE) > _LINEAR_CACHE_SIZE:
            _LINEAR_CACHE.popitem(last=False)
    t2 = time.perf_counter()
    psi = fixed_items(scene, geo)[2] if reused else lin.psi
    X, R, q, mu = lin.solve(psi)
    t3 = time.perf_counter()
    X, R, phi, D = finish(geo, X, R)
    warnings = []
    info = {"method": "linearised lattice, one sparse KKT solve" if lin.joints.size and np.any(psi)
            else "no load (nothing to solve)", "dofs": int(lin.na), "planar": bool(geo.planar),
            "constraints": int(lin.joints.size), "reused_factorisation": reused, "poses": lin.poses,
            "about": "flat"}
    if fallback:
        info["about_fallback"] = fallback
        warnings.append(f"the quadratic model cannot predict this scene ({fallback}); the linear model is "
                        "linearised at the flat sheet instead (about=flat)")
    return _linear_result(scene, lin, D, X, R, info, warnings, t0,
                          {"geometry_s": t1 - t0, "assemble_factor_s": t2 - t1, "solve_s": t3 - t2}, planar)


def _geometry(scene, planar, hinge_law=None):
    """The lattice geometry of a scene, with the caller's planar override (None: as the scene is) and hinge
    law (``beam``, default, or ``fe``: core/lattice/geometry.apply_hinge_law)."""
    from metamaterial_wb.core.lattice.geometry import LatticeGeometry, apply_hinge_law
    geo = apply_hinge_law(LatticeGeometry(scene), hinge_law)
    if planar is not None:
        geo.planar = bool(planar)
    return geo


def _linear_result(scene, lin, D, X, R, info, warnings, t0, timings, planar=None):
    """The linear model's result, either linearisation: contact report, hinges past the scene's rotation limits,
    range warnings, total time."""
    info.update(lin.contact_info)
    if lin.contact_info.get("active_set_iterations"):
        info["method"] += f" + plate contact ({lin.contact_info['active_set_iterations']} active-set re-solves)"
    if info.get("active_set_converged") is False:
        warnings.append("the linear model's contact active set did not settle in 100 iterations")
    _state_warnings(scene, lin.geo, D, R, "linear", planar, info, warnings)
    timings["total_s"] = time.perf_counter() - t0
    return ModelResult(D, X, R, warnings, timings, bool(info.get("active_set_converged", True)), info)


class _PredictorRefused(Exception):
    """The quadratic model refused the scene (``about=quadratic`` has no predictor); carries its error."""

    def __init__(self, error):
        super().__init__(str(error))
        self.error = error


def _linear_about_quadratic(scene, planar, contact, contact_fraction, poses, line_search, t0, hinge_law=None):
    """The lattice linearised about the quadratic model's predicted state (``about=quadratic``): one R0 solve
    for D, plate rotations from D, positions through the hinge chain, then one lattice solve with the
    corotational strains and forces of that state and its material (Gauss-Newton) tangent; actuators as
    constraints linearised there, plate contact by the same active set. Not cached: the state depends on
    the actuator values."""
    from metamaterial_wb.core.errors import MetamaterialError
    from metamaterial_wb.core.lattice.solve import (ChainPositions, LinearLattice, finish, quadratic_D,
                                                    quadratic_state)

    tq = time.perf_counter()
    try:
        D0 = quadratic_D(scene)          # first: a scene the quadratic model refuses costs nothing more
    except MetamaterialError as exc:
        raise _PredictorRefused(exc) from exc
    tq = time.perf_counter() - tq
    geo = _geometry(scene, planar, hinge_law)
    chain = ChainPositions(geo)
    t1 = time.perf_counter()
    _D0, Xb, Rb = quadratic_state(scene, geo, chain, D=D0)
    t2 = time.perf_counter()
    lin = LinearLattice(scene, geo, contact=contact, contact_fraction=contact_fraction, poses=poses,
                        base=(Xb, Rb), tangent="material", chain=chain)
    t3 = time.perf_counter()
    X, R, q, mu = lin.solve()
    alpha = 1.0
    if line_search:
        alpha, X, R = lin.line_search(q, mu, X, R)
    t4 = time.perf_counter()
    X, R, phi, D = finish(geo, X, R)
    warnings = []
    loaded = bool(lin.joints.size and np.any(lin.psi))
    info = {"method": "lattice linearised about the quadratic model's state, one sparse KKT solve" if loaded
            else "no load (nothing to solve)", "dofs": int(lin.na), "planar": bool(geo.planar),
            "constraints": int(lin.joints.size), "reused_factorisation": False, "poses": lin.poses,
            "about": "quadratic", "step_length": alpha}
    return _linear_result(scene, lin, D, X, R, info, warnings, t0,
                          {"geometry_s": t1 - t0 - tq, "quadratic_state_s": t2 - t1 + tq,
                           "assemble_factor_s": t3 - t2, "solve_s": t4 - t3}, planar)


def _nonlinear(scene, global_deformation=None, **options):
    t0 = time.perf_counter()
    _check_options("nonlinear", options, _NONLINEAR_OPTS)
    if global_deformation is not None:
        return _global(scene, global_deformation, t0)
    from metamaterial_wb.core.lattice.geometry import LatticeGeometry, apply_hinge_law
    from metamaterial_wb.core.lattice.refine import chord_stretch, refine
    from metamaterial_wb.core.lattice.solve import NonlinearLattice, finish

    base = apply_hinge_law(LatticeGeometry(scene), options.pop("hinge_law", None))
    geo = refine(base, options.pop("hinge_elements", 1))
    t1 = time.perf_counter()
    model = NonlinearLattice(scene, geo, **options)
    X, R, ok = model.solve()
    t2 = time.perf_counter()
    st_end, total_energy = model._state(X, R, tangent=False)[:2]
    energy = float(st_end.energy.sum())
    chord = chord_stretch(base, X, R)
    if geo is not base:
        X, R = geo.plates(X, R)
    X, R, phi, D = finish(base, X, R)
    warnings = []
    info = dict(model.stats)
    info.update({"dofs": int(model.na), "planar": bool(model.planar), "constraints": int(model.joints.size),
                 "elastic_energy_Nmm": energy, "contact_energy_Nmm": float(total_energy) - energy,
                 "hinge_elements": getattr(geo, "hinge_elements", 1), "hinge_law": base.hinge_law})
    if chord is not None and chord.size:
        info["hinge_chord_stretch_range"] = [float(chord.min()), float(chord.max())]
    if hasattr(model, "last_residual"):
        info["residual_force_rel"], info["residual_constraint_rad"] = (float(x) for x in model.last_residual)
    if not ok:
        how = "Newton with load stepping" + (" and the dynamic-relaxation fallback" if model.fallback else "")
        warnings.append(f"the nonlinear model did NOT converge ({how} stopped at relative force residual "
                        f"{info.get('residual_force_rel', float('nan')):.2e} and constraint residual "
                        f"{info.get('residual_constraint_rad', float('nan')):.2e} rad; tolerance {model.tol:g}); "
                        "the result is the last iterate, not an equilibrium")
    _state_warnings(scene, base, D, R, "nonlinear", options.get("planar"), info, warnings)
    timings = {"geometry_s": t1 - t0, "solve_s": t2 - t1, "total_s": time.perf_counter() - t0}
    return ModelResult(D, X, R, warnings, timings, bool(ok), info)


register_model("linear", _linear, "linearised lattice: rigid plates, TPU beam hinges, one sparse solve",
               LINEAR_OPTIONS)
register_model("nonlinear", _nonlinear, "nonlinear corotational lattice: Newton + line search + load stepping, "
                                        "plate contact, dynamic-relaxation fallback", NONLINEAR_OPTIONS)
