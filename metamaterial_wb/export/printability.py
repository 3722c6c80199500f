"""Is a scene printable? The checks ``build`` runs, without writing any file (the inverse design's report).

:func:`check_printable` runs, in build's order:

1. the parameter checks (``core.fabrication.fabrication_params``: printable hinge tilt inside its node plate,
   walls of at least two nozzle widths, hinge lengths / thickness / sockets that fit) and the modules'
   (``geometry.modules.parse_modules``); no FreeCAD needed;
2. the geometry checks of every build (``geometry.validity.check_build`` with ``DEFAULT_CHECKS``: unique
   solids, module/module and module/sheet collisions, the servo horn over its rotation) on the built
   sheet, in a subprocess by default (an OCC crash cannot take the caller with it; FreeCAD absent:
   reported as not run, never as passed), or in the calling process (``geometry="inprocess"``: the GUI).

Returns ``{"printable": True | False | None, "problems": [...], "checks_run": [...], "notes": [...]}``;
``None``: the parameters passed but the geometry checks could not run (said in ``notes``).
Command line (used for the subprocess): ``python3 -m metamaterial_wb.export.printability SCENE.json``
prints that dict as JSON.
"""
import json
import os
import subprocess
import sys
import tempfile


def _result(printable, problems, ran, notes):
    return {"printable": printable, "problems": list(problems), "checks_run": list(ran), "notes": list(notes)}


def first_module_problem(scene):
    """The first problem build's parameter checks find in ``scene`` (its modules and sheet), or None: where a servo
    housing may move with its servo in inverse design (``core/inverse/evaluate.move_housings``), for the command
    line and the Fit to target panel alike."""
    problems = parameter_checks(scene)[0]
    return problems[0] if problems else None


def parameter_checks(scene):
    """``(problems, ran, params)`` of the checks before any geometry."""
    from metamaterial_wb.core.errors import MetamaterialError
    from metamaterial_wb.core.design import effective_tilts_deg
    from metamaterial_wb.core.fabrication import fabrication_params
    try:
        params = fabrication_params(scene, effective_tilts_deg(scene))
    except MetamaterialError as exc:
        return [str(exc)], ["parameters"], None
    ran = ["parameters"]
    if scene.modules:
        from metamaterial_wb.geometry.modules import parse_modules
        try:
            parse_modules(scene, params)
        except MetamaterialError as exc:
            return [str(exc)], ran + ["modules (parameters)"], None
        ran.append("modules (parameters)")
    return [], ran, params


def geometry_checks_inprocess(scene, params):
    """``(problems, ran)`` of build's geometry checks on the built sheet (needs FreeCAD)."""
    from metamaterial_wb.geometry.build import build_scene
    from metamaterial_wb.geometry.validity import DEFAULT_CHECKS, check_build
    result = build_scene(scene, modules=bool(scene.modules), progress=False, params=params)
    return check_build(result, DEFAULT_CHECKS)


def check_printable(scene, geometry="subprocess", timeout_s=600, python=None, pythonpath=()):
    """See the module doc. ``geometry``: ``"subprocess"`` (default), ``"inprocess"`` or ``"off"``;
    ``python``: the child's interpreter (default this one), ``pythonpath``: more folders for it (FreeCAD's
    library when the caller runs inside FreeCAD)."""
    if geometry not in ("subprocess", "inprocess", "off"):
        raise ValueError(f"geometry={geometry!r}; allowed: subprocess, inprocess, off")
    problems, ran, params = parameter_checks(scene)
    if problems:
        return _result(False, problems, ran, [])
    if geometry == "off":
        return _result(None, [], ran, ["geometry checks not run (asked for)"])
    if geometry == "inprocess":
        from metamaterial_wb.core.errors import MetamaterialError
        try:
            gp, gran = geometry_checks_inprocess(scene, params)
        except MetamaterialError as exc:
            if "needs FreeCAD" in str(exc):
                return _result(None, [], ran, [f"geometry checks not run: {exc}"])
            return _result(False, [str(exc)], ran + ["geometry"], [])
        return _result(not gp, gp, ran + list(gran), [])
    with tempfile.TemporaryDirectory(prefix="mm_printable_") as tmp:
        path = os.path.join(tmp, "scene.json")
        with open(path, "w", encoding="utf-8") as fh:
            fh.write(scene.to_json())
        root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
        env = dict(os.environ, PYTHONPATH=os.pathsep.join([root, *pythonpath, os.environ.get("PYTHONPATH", "")]))
        try:
            p = subprocess.run([python or sys.executable, "-m", "metamaterial_wb.export.printability", path],
                               capture_output=True, text=True, env=env, timeout=timeout_s)
        except subprocess.TimeoutExpired:
            return _result(None, [], ran, [f"geometry checks not finished within {timeout_s:g} s"])
    if p.returncode != 0:
        tail = (p.stderr.strip().splitlines() or ["no message"])[-1]
        return _result(None, [], ran, [f"geometry checks did not run (exit {p.returncode}): {tail}"])
    sub = json.loads(p.stdout)
    sub["checks_run"] = ran + [c for c in sub["checks_run"] if c not in ran]
    return sub


def main(argv=None):
    from metamaterial_wb.core.scene import Scene
    argv = sys.argv[1:] if argv is None else argv
    scene = Scene.load(argv[0])
    print(json.dumps(check_printable(scene, geometry="inprocess")))
    return 0


if __name__ == "__main__":
    sys.exit(main())
