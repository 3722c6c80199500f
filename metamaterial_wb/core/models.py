"""Registry of simulation models (the fidelity ladder). One place to add a model.

A model is a function ``fn(scene, global_deformation=None, **options) -> ModelResult``; every model
returns the same fields so that the CLI, the GUI and the fidelity report treat them alike.
"""
import time
from dataclasses import dataclass, field

import numpy as np

from metamaterial_wb.core.errors import SceneError, in_range
from metamaterial_wb.core.numbers import parse_float, parse_int


@dataclass
class ModelResult:
    D: np.ndarray                 # per node, seed units in [-1, 1] (derived from rotations for lattice models)
    positions_mm: np.ndarray      # (n, 3)
    rotations: np.ndarray         # (n, 3, 3)
    warnings: list = field(default_factory=list)
    timings: dict = field(default_factory=dict)
    converged: bool = True
    info: dict = field(default_factory=dict)


_MODELS = {}


@dataclass(frozen=True)
class Option:
    """One model option: ``kind`` "bool", "int", "float" (checked here, from a Python value or the text of
    ``--option KEY=VALUE``) or "text" (a choice the model checks itself, with its own message); ``low`` /
    ``high`` the allowed range (``low_open`` / ``high_open``: bound excluded); ``meaning`` one line for
    error messages and listings; ``none_ok``: None (the automatic default) is allowed."""
    kind: str
    meaning: str = ""
    low: float = None
    high: float = None
    low_open: bool = False
    high_open: bool = False
    none_ok: bool = False


_TRUE, _FALSE = ("true", "1", "yes"), ("false", "0", "no")


def allowed_text(opt):
    """What ``opt`` allows, for error messages: ``"an integer 1..100 (meaning)"``, ``"a number in (0, 1] ..."``.

    Parameters
    ----------
    opt : Option

    Returns
    -------
    str
    """
    if opt.kind == "bool":
        return "true/false/1/0/yes/no"
    lo = "(" if opt.low_open else "["
    hi = ")" if opt.high_open else "]"
    if opt.kind == "int":
        what = f"an integer {opt.low}..{opt.high}"
    else:
        what = f"a number in {lo}{opt.low:g}, {opt.high:g}{hi}"
    return what + (f" ({opt.meaning})" if opt.meaning else "")


def check_option(model, key, value, opt):
    """``value`` (Python value or the text of ``--option``) as the option's type, or a SceneError
    ``--option KEY: VALUE; allowed: ...``. "text" options are returned as they are (the model checks them).

    Parameters
    ----------
    model : str
        The model's name.
    key : str
        The option's name.
    value : object
        A Python value or the text given to ``--option``.
    opt : Option
        The option's type and range.

    Returns
    -------
    object
        The value as the option's type (bool, int, float; text and None as given).
    """
    import math

    if opt.kind == "text" or (value is None and opt.none_ok):
        return value
    bad = SceneError(f"--option {key}", f"{value!r}; allowed: {allowed_text(opt)}")
    if opt.kind == "bool":
        if isinstance(value, (bool, np.bool_)):
            return bool(value)
        if isinstance(value, str) and value.strip().lower() in _TRUE + _FALSE:
            return value.strip().lower() in _TRUE
        raise bad
    if isinstance(value, str):    # strict: no '1_0', no non-ASCII digits, no inf/nan (int() / float() take them)
        read = parse_int if opt.kind == "int" else parse_float
        try:
            value = read(f"--option {key}", value)
        except SceneError as exc:
            raise SceneError(exc.field, f"{exc.message}; allowed: {allowed_text(opt)}") from None
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise bad
    if opt.kind == "int":
        if not isinstance(value, (int, np.integer)) or not opt.low <= value <= opt.high:
            raise bad
        return int(value)
    v = float(value)
    if not math.isfinite(v) or not in_range(v, opt.low, opt.high, opt.low_open, opt.high_open):
        raise bad
    return v


def model_options(name):
    """The option table of a model: ``{key: Option}`` (empty for a model registered without one).

    Parameters
    ----------
    name : str
        The model's name.

    Returns
    -------
    dict of str to Option
    """
    _load_builtin()
    if name not in _MODELS:
        raise SceneError("--model", f"{name!r}; allowed: {', '.join(_MODELS)}")
    return dict(_MODELS[name][2] or {})


def check_options(name, options):
    """``options`` with every value of the model's table parsed and checked (:func:`check_option`); keys
    the table does not know are left for the model, which refuses them naming the allowed ones.

    Parameters
    ----------
    name : str
        The model's name.
    options : dict
        ``{key: value}`` (Python values or ``--option`` text).

    Returns
    -------
    dict
        The options with every known value parsed and checked.
    """
    table = model_options(name)
    return {k: (check_option(name, k, v, table[k]) if k in table else v) for k, v in options.items()}


def register_model(name, fn, description="", options=None):
    """Add a model to the registry (or replace the one of that name).

    Parameters
    ----------
    name : str
        The name ``run_model`` and ``--model`` take.
    fn : callable
        ``fn(scene, global_deformation=None, **options) -> ModelResult``.
    description : str, optional
        One line for listings.
    options : dict of str to Option, optional
        The model's options (type, range, meaning): ``run_model`` checks every value against it.
    """
    _MODELS[name] = (fn, description, options)


def model_names():
    """The registered model names (built-in ones loaded first).

    Returns
    -------
    list of str
    """
    _load_builtin()
    return list(_MODELS)


def run_model(name, scene, global_deformation=None, **options):
    """Run the model called ``name`` on a scene.

    Parameters
    ----------
    name : str
        A registered model (see :func:`model_names`).
    scene : Scene
    global_deformation : float, optional
        The seed's global deformation (D = g), for models that honour it.
    **options
        Model-specific options (the model's table: :func:`model_options`); Python values or the text of
        ``--option`` ("1e-8", "true"); unknown ones and values of the wrong type or range are an error.

    Returns
    -------
    ModelResult

    Raises
    ------
    SceneError
        If the model name or an option is unknown or invalid.
    """
    _load_builtin()
    if name not in _MODELS:
        raise SceneError("--model", f"{name!r}; allowed: {', '.join(_MODELS)}")
    options = check_options(name, options)
    return _MODELS[name][0](scene, global_deformation=global_deformation, **options)


_BACKENDS = ("auto", "superlu", "cholmod", "dense")
QUADRATIC_OPTIONS = {"backend": Option("text", "linear solver: " + ", ".join(_BACKENDS))}
_QUADRATIC_OPTS = set(QUADRATIC_OPTIONS)


def _quadratic(scene, global_deformation=None, backend="auto", **unknown):
    from metamaterial_wb.core import kinematics
    from metamaterial_wb.core.solver import solve_scene

    for k in sorted(unknown):
        raise SceneError(f"--option {k}", f"unknown option of model 'quadratic'; allowed: {sorted(_QUADRATIC_OPTS)}")
    if backend not in _BACKENDS:
        raise SceneError("--option backend", f"{backend!r}; allowed: {list(_BACKENDS)}")

    D, _m, warnings, timings = solve_scene(scene, global_deformation=global_deformation, backend=backend)
    t = time.perf_counter()
    from metamaterial_wb.core.design import kinematics_for
    pos, R, _phi = kinematics.node_poses(scene, D, kin=kinematics_for(scene))
    timings = dict(timings)
    timings["kinematics_s"] = time.perf_counter() - t
    return ModelResult(D, pos, R, warnings, timings)


register_model("quadratic", _quadratic, "the seed's simplified energy (eq. 1-2), one sparse solve",
               QUADRATIC_OPTIONS)

_BUILTIN_LOADED = False


def _load_builtin():
    """Import optional model modules that register themselves (higher-fidelity models)."""
    global _BUILTIN_LOADED
    if _BUILTIN_LOADED:
        return
    _BUILTIN_LOADED = True
    import importlib
    for mod in ("metamaterial_wb.core.lattice",):
        try:
            importlib.import_module(mod)
        except ModuleNotFoundError as exc:
            if exc.name != mod:
                raise
