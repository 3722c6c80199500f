"""Registry of simulation models (the fidelity ladder). One place to add a model.

A model is a function ``fn(scene, global_deformation=None, **options) -> ModelResult``; every model
returns the same fields so that the CLI, the GUI and the fidelity report treat them alike.
"""
import time
from dataclasses import dataclass, field

import numpy as np

from metamaterial_wb.core.errors import SceneError


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


def register_model(name, fn, description=""):
    """Add a model to the registry (or replace the one of that name).

    Parameters
    ----------
    name : str
        The name ``run_model`` and ``--model`` take.
    fn : callable
        ``fn(scene, global_deformation=None, **options) -> ModelResult``.
    description : str, optional
        One line for listings.
    """
    _MODELS[name] = (fn, description)


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
        Model-specific options; unknown ones are an error.

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
    return _MODELS[name][0](scene, global_deformation=global_deformation, **options)


_QUADRATIC_OPTS = {"backend", "model"}
_BACKENDS = ("auto", "superlu", "cholmod", "dense")


def _quadratic(scene, global_deformation=None, backend="auto", model=None, **unknown):
    from metamaterial_wb.core import kinematics
    from metamaterial_wb.core.solver import solve_scene

    for k in sorted(unknown):
        raise SceneError(f"--option {k}", f"unknown option of model 'quadratic'; allowed: {sorted(_QUADRATIC_OPTS)}")
    if backend not in _BACKENDS:
        raise SceneError("--option backend", f"{backend!r}; allowed: {list(_BACKENDS)}")

    D, _m, warnings, timings = solve_scene(scene, global_deformation=global_deformation, model=model,
                                           backend=backend)
    t = time.perf_counter()
    from metamaterial_wb.core.design import kinematics_for
    pos, R, _phi = kinematics.node_poses(scene, D, kin=kinematics_for(scene))
    timings = dict(timings)
    timings["kinematics_s"] = time.perf_counter() - t
    return ModelResult(D, pos, R, warnings, timings)


register_model("quadratic", _quadratic, "the seed's simplified energy (eq. 1-2), one sparse solve")

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
