"""``solve SCENE.json --out RESULT.json [--set NAME=VALUE ...] [--global G] [--model M]
[--fields D,poses,joints] [--npz]``.

``--fields`` picks what is written per node / joint (default all three); ``--npz`` writes the
arrays to ``RESULT.npz`` beside a small ``RESULT.json`` that holds everything else
(``core/resultfile.py``, docs/scene-format.md "Result file").

``--option KEY=VALUE`` values are parsed and checked against the model's option table
(``core/models.py`` ``model_options``: quadratic in ``core/models.py``, linear / nonlinear in
``core/lattice/__init__.py``). Flags that would be ignored are refused: ``--backend`` with a lattice model or
contradicting ``--option backend``, one ``--option`` key given twice, ``--option`` or a ``--model`` other than
quadratic with ``--global`` (closed form, no model runs: the result is the quadratic model's closed form and says
``"model": "quadratic"``), ``--option``, ``--backend`` or such a ``--model`` when the scene's stored
``global_deformation`` is solved (the same closed form; ``check_scene_global``). With a global deformation the
listed actuator / constraint values were not applied: the result says ``"values_applied": false`` and a
``"values_note"``.

With ``--npz`` the ``.npz`` and the ``.json`` are written as one set (``fileio.OutputSet``: both or neither); a
run without ``--npz`` removes ``RESULT.npz`` only when the earlier ``RESULT.json`` (a result file) named it in its
``"arrays"`` entry, i.e. an earlier ``solve --npz`` wrote it; any other file of that name is left alone."""
import sys
import time

NAME = "solve"
HELP = "solve a scene: node deformations D and poses, written as JSON"


def add_arguments(p):
    from metamaterial_wb.cli import number

    p.add_argument("scene", help="scene file (JSON, docs/scene-format.md)")
    p.add_argument("--out", required=True, help="result file (JSON)")
    p.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                   help="change one actuator's or constraint's value (repeatable)")
    p.add_argument("--global", dest="global_g", type=number, default=None, metavar="G",
                   help="global deformation: every D = G in [-1, 1] (perfect propagation; closed form, so no "
                        "--option)")
    p.add_argument("--model", default=None,
                   help="simulation model (default quadratic; see docs/fidelity.md for the others; with a global "
                        "deformation only quadratic, the closed form)")
    p.add_argument("--backend", default=None, choices=("auto", "superlu", "cholmod", "dense"),
                   help="linear solver of the quadratic model only (default auto: CHOLMOD when installed, "
                        "else SuperLU)")
    p.add_argument("--option", action="append", default=[], metavar="KEY=VALUE",
                   help="model option, e.g. --model nonlinear --option tol=1e-10 (repeatable; checked, see "
                        "docs/fidelity-models.md). " + OPTIONS_HELP)
    p.add_argument("--fields", default="D,poses,joints", metavar="LIST",
                   help="what to write per node / joint: any of D, poses, joints, comma-separated (default all)")
    p.add_argument("--npz", action="store_true",
                   help="write the per-node / per-joint arrays to RESULT.npz (binary, numpy.load) beside a "
                        "small RESULT.json (--out must not end in .npz); much faster than JSON for large sheets")


# the option names per model, for --help (kept numpy-free: every command builds this parser); the tables with
# types and ranges are core/models.py QUADRATIC_OPTIONS and core/lattice/__init__.py LINEAR_OPTIONS /
# NONLINEAR_OPTIONS (tests/unit/test_solve_options.py checks this text names all of them)
OPTIONS_HELP = ("Options: quadratic: backend (auto, superlu, cholmod, dense). linear: planar, contact, "
                "contact_fraction (0, 1], poses (chain, linear), about (quadratic, flat), line_search, hinge_law "
                "(beam, fe). nonlinear: planar, contact, contact_fraction (0, 1], tol (0, 1), max_iter 1..100000, "
                "load_steps 1..100000, min_step (0, 1], contact_stiffness (0, 1e12], fallback, dr_max_iter "
                "1..10000000, predictor, method (newton, dynamic_relaxation), hinge_elements, hinge_law (beam, fe). "
                "Booleans: true/false/1/0/yes/no.")


def parse_sets(items):
    """``["m1=0.5", ...]`` -> ``[("m1", 0.5), ...]`` with clear errors; the value is read strictly
    (:func:`metamaterial_wb.core.numbers.parse_float`: no ``1_0``, non-ASCII digits, inf/nan or subnormals)."""
    from metamaterial_wb.core.errors import SceneError
    from metamaterial_wb.core.numbers import parse_float

    out = []
    for s in items:
        if "=" not in s:
            raise SceneError(f"--set {s}", "expected NAME=VALUE, e.g. --set m1=0.5")
        name, _, val = s.partition("=")
        v = parse_float(f"--set {name.strip()}", val)
        if any(n == name.strip() for n, _ in out):
            raise SceneError(f"--set {name.strip()}", "given twice; give each actuator or constraint once")
        out.append((name.strip(), v))
    return out


def check_global(g):
    """SceneError naming ``--global`` unless ``g`` is None or a number in [-1, 1]."""
    import math

    from metamaterial_wb.core.errors import SceneError
    if g is not None and not (math.isfinite(g) and -1.0 <= g <= 1.0):
        raise SceneError("--global", f"{g!r}; allowed: a number in [-1, 1] (every node's D, the scene's "
                                     "global_deformation)")


def chosen_global(global_g, sets, scene):
    """The global deformation a command draws or solves: ``--global``'s, else none where ``--set`` gives values
    (they are solved for), else the one the scene was saved with. ``--global`` with ``--set`` is refused: two
    different states (every D = G, or the actuators' values solved for), and one would be ignored."""
    from metamaterial_wb.core.errors import SceneError
    check_global(global_g)
    if global_g is not None and sets:
        raise SceneError("--global", f"{global_g:g} with --set {sets[0][0]}={sets[0][1]:g}: --global sets every D, "
                                     "--set solves for the actuators' values; give one of them")
    return global_g if global_g is not None else (None if sets else scene.global_deformation)


def parse_options(items, model=None):
    """``["tol=1e-10", "contact=false"]`` -> ``{"tol": 1e-10, "contact": False}``: with ``model``, every
    option of its table is parsed and checked by type and range (``core.models.check_options``: a bad value
    is a SceneError ``--option KEY: VALUE; allowed: ...``); other values become numbers, booleans or text
    for the model to check. Numbers are read strictly (:mod:`metamaterial_wb.core.numbers`): a text Python's
    ``int()`` / ``float()`` would take but a person does not mean as a number (``1_0``, non-ASCII digits, inf/nan,
    a subnormal) is a SceneError ``--option KEY``."""
    from metamaterial_wb.core.errors import SceneError
    from metamaterial_wb.core.numbers import parse_float, parse_int

    out = {}
    table = {}
    if model is not None:
        from metamaterial_wb.core.models import model_options
        table = model_options(model)
    for s in items:
        if "=" not in s:
            raise SceneError(f"--option {s}", "expected KEY=VALUE, e.g. --model nonlinear --option tol=1e-10")
        key, _, val = s.partition("=")
        if key.strip() in out:
            raise SceneError(f"--option {key.strip()}", "given twice; give each option once")
        opt = table.get(key.strip())
        if opt is not None and opt.kind in ("int", "float"):    # read strictly here, its range checked below
            read = parse_int if opt.kind == "int" else parse_float
            try:
                out[key.strip()] = read(f"--option {key.strip()}", val)
            except SceneError as exc:
                from metamaterial_wb.core.models import allowed_text
                raise SceneError(exc.field, f"{exc.message}; allowed: {allowed_text(opt)}") from None
            continue
        if opt is not None and opt.kind != "text":
            out[key.strip()] = val.strip()          # parsed and checked by the table below
            continue
        low = val.strip().lower()
        if low in ("true", "yes", "on"):
            v = True
        elif low in ("false", "no", "off"):
            v = False
        else:
            v = _option_number(f"--option {key.strip()}", val)
        out[key.strip()] = v
    if model is not None:
        from metamaterial_wb.core.models import check_options
        out = check_options(model, out)
    return out


def _option_number(field, val):
    """An ``--option`` value that is not in the model's table as a number: an int or float when it is one (read
    strictly), else the text; a text that Python's ``float()`` reads but :func:`core.numbers.parse_float` refuses
    (``1_0``, non-ASCII digits, inf/nan, a subnormal) is refused, naming ``field``."""
    from metamaterial_wb.core.errors import SceneError
    from metamaterial_wb.core.numbers import parse_float, parse_int

    try:
        return parse_int(field, val)
    except SceneError:
        pass
    try:
        return parse_float(field, val)
    except SceneError:
        try:
            float(val)
        except ValueError:
            return val                      # text for the model to check
        raise


def parse_fields(text):
    """``--fields``: :func:`core.resultfile.parse_fields` (unknown, empty and repeated names refused)."""
    from metamaterial_wb.core import resultfile

    return resultfile.parse_fields(text)


GLOBAL_MODEL = "quadratic"     # what a global deformation's closed form is reported as (the seed's slider)


def _ignored_model(args):
    """The explicit ``--model`` a global deformation would ignore (any but :data:`GLOBAL_MODEL`), else None."""
    return args.model if args.model is not None and args.model != GLOBAL_MODEL else None


def check_model_name(model):
    """SceneError naming ``--model`` unless ``model`` is None or a registered model."""
    if model is None:
        return
    from metamaterial_wb.core.errors import SceneError
    from metamaterial_wb.core.models import model_names
    names = model_names()
    if model not in names:
        raise SceneError("--model", f"{model!r}; allowed: {', '.join(names)}")


def check_flags(args):
    """Refuse flags that would be ignored or contradict each other, before any work: ``--global`` out of
    [-1, 1] (named as the flag), ``--global`` with ``--option`` or with a ``--model`` other than quadratic (closed
    form: no model runs), ``--backend`` with a lattice model (``run`` refuses ``--backend`` with a different
    ``--option backend``)."""
    from metamaterial_wb.core.errors import SceneError

    check_model_name(args.model)
    g = args.global_g
    if g is not None:
        check_global(g)
        if args.option:
            raise SceneError("--global", f"{g:g} with --option {args.option[0]}: --global sets every D in closed "
                                         "form and runs no model, so model options would be ignored; give one "
                                         "of them")
        if _ignored_model(args):
            raise SceneError("--global", f"{g:g} with --model {args.model}: --global sets every D in closed "
                                         "form and runs no model, so --model would be ignored (the closed form is "
                                         f"reported as model {GLOBAL_MODEL}); give one of them")
    if args.backend is not None and (args.model or "quadratic") != "quadratic":
        raise SceneError("--backend", f"{args.backend} with --model {args.model}; allowed: only with --model "
                                      "quadratic (the lattice models choose their own linear solver)")


def check_scene_global(args, g):
    """Refuse ``--option``, ``--backend`` and a ``--model`` other than quadratic when the scene's stored
    ``global_deformation`` is what gets solved (no ``--global``, no ``--set``): the closed form runs and no model
    does, so they would be ignored, exactly as with ``--global`` (:func:`check_flags`)."""
    from metamaterial_wb.core.errors import SceneError

    if args.global_g is not None or g is None:
        return
    flag = f"--option {args.option[0]}" if args.option else (f"--backend {args.backend}" if args.backend else None)
    if flag is None and _ignored_model(args):
        flag = f"--model {args.model}"
    if flag is not None:
        raise SceneError("global_deformation", f"{g:g} stored in the scene with {flag}: the scene's global "
                                               "deformation sets every D in closed form and runs no model, so "
                                               f"{flag.split()[0]} would be ignored; allowed: remove the scene's "
                                               "global_deformation, or give actuator values with --set, or drop "
                                               f"{flag.split()[0]}")


def result_dict(scene, res, global_g=None, model="quadratic", fields=None, arrays=None):
    """The result document (shared by ``solve`` and the GUI's export of a solved state).
    ``fields``: any of ``core.resultfile.FIELDS`` (default all); ``arrays``: with ``--npz``, the
    per-node / per-joint arrays are not listed (they go to the ``.npz`` file)."""
    from metamaterial_wb.core import resultfile

    fields = resultfile.FIELDS if fields is None else tuple(fields)
    out = {"format": "metamaterial-result", "version": 1, "scene": scene.name,
           "cell_size_mm": float(scene.cell_size_mm),   # the sheet's pitch: its nodes' rest positions (inverse)
           "model": model, "converged": bool(res.converged), "global_deformation": global_g,
           "actuators": {a.name: a.value for a in scene.actuators},
           "constraints": {c.name: c.value for c in scene.constraints},
           "values_applied": global_g is None,
           "fields": list(fields), "warnings": list(res.warnings), "timings": dict(res.timings)}
    if global_g is not None:
        out["values_note"] = (f"not applied: the global deformation {global_g:g} set every D in closed form and "
                              "replaced the actuator and constraint values (listed as stored in the scene)")
    if arrays is None:
        a = resultfile.result_arrays(scene, res, fields)
        out["nodes"] = resultfile.node_list(a)
        if "joints" in fields:
            out["joints"] = resultfile.joint_list(a)
    if res.info:
        out["info"] = res.info
    elif global_g is not None:
        out["info"] = {"method": "global deformation: closed-form kinematics, no solve"}
    return out


def joint_results(scene, rotations):
    """Per joint: its nodes, signed fold (deg, between the plate normals), hinge rotation (deg) and
    hinge tilt (deg) - measured from the node rotations, so the same for every model."""
    from metamaterial_wb.core import design, kinematics

    topo = scene.topology
    fold, psi = kinematics.joint_angles(scene, rotations)
    tilt = design.effective_tilts_deg(scene)
    nodes = topo.node_ij()
    out = []
    for k, name in enumerate(topo.joint_names):
        a, b = topo.joint_pairs[k]
        out.append({"name": name, "nodes": [f"N{nodes[a][0]},{nodes[a][1]}", f"N{nodes[b][0]},{nodes[b][1]}"],
                    "fold_deg": float(fold[k]), "hinge_rotation_deg": float(psi[k]), "tilt_deg": float(tilt[k])})
    return out


def _our_earlier_npz(out_path, npz_name):
    """``npz_name`` when the earlier result at ``out_path`` (a ``metamaterial-result`` JSON) named it in its
    ``"arrays"`` entry - written by an earlier ``solve --npz`` - and it is a plain file beside it; else None.
    Read before the new result replaces that JSON."""
    import json
    import os

    folder = os.path.dirname(os.path.abspath(out_path))
    p = os.path.join(folder, npz_name)
    if not os.path.isfile(p) or os.path.islink(p):
        return None             # nothing to remove (checked first: a large JSON result is not read for nothing)
    try:
        with open(out_path, encoding="utf-8") as f:
            old = json.load(f)
    except (OSError, ValueError):
        return None
    ref = old.get("arrays") if isinstance(old, dict) and old.get("format") == "metamaterial-result" else None
    return npz_name if isinstance(ref, dict) and ref.get("file") == npz_name else None


def run(args):
    import os

    from metamaterial_wb.core.fileio import OutputSet, remove_outputs, write_json
    from metamaterial_wb.core.models import run_model
    from metamaterial_wb.core.scene import Scene

    from metamaterial_wb.core import resultfile
    from metamaterial_wb.core.errors import SceneError
    from metamaterial_wb.core.fileio import check_output
    out_abs = check_output(args.out, "file", "--out", inputs=[("scene", args.scene)])
    npz_path = None
    if args.npz:
        npz_path = resultfile.npz_path_for(args.out)
        check_output(npz_path, "file", "--npz", inputs=[("scene", args.scene)])
    check_flags(args)
    fields = parse_fields(args.fields)          # before any work
    model = args.model or "quadratic"
    opts = parse_options(args.option, model)
    if args.backend is not None:
        if opts.get("backend", args.backend) != args.backend:
            raise SceneError("--option backend", f"{opts['backend']} contradicts --backend {args.backend}; "
                                                 "allowed: one of them, or the same value")
        opts["backend"] = args.backend
    t0 = time.perf_counter()
    scene = Scene.load(args.scene)
    sets = parse_sets(args.set)
    for name, v in sets:
        scene.set_value(name, v)
    g = chosen_global(args.global_g, sets, scene)
    check_scene_global(args, g)
    from metamaterial_wb.core.design import ensure_configured
    for w in (ensure_configured(scene) or {}).get("warnings", []):  # axes without joint_config: configure
        print(f"warning: {w}", file=sys.stderr)
    res = run_model(model, scene, global_deformation=g, **opts)
    folder = os.path.dirname(out_abs)
    if args.npz:
        arrays = resultfile.result_arrays(scene, res, fields)
        out = result_dict(scene, res, g, model, fields, arrays=arrays)
        npz_name = os.path.basename(npz_path)
        out["arrays"] = {"file": npz_name, "keys": sorted(arrays)}
        out["timings"]["total_s"] = time.perf_counter() - t0
        with OutputSet(folder, "tmp-solve") as tmp:      # the .npz and the .json land together, or neither
            resultfile.write_npz(os.path.join(tmp, npz_name), arrays, out)
            write_json(os.path.join(tmp, os.path.basename(out_abs)), out)
    else:
        out = result_dict(scene, res, g, model, fields)
        out["timings"]["total_s"] = time.perf_counter() - t0
        stale = _our_earlier_npz(out_abs, os.path.basename(resultfile.npz_path_for(out_abs))) \
            if not out_abs.lower().endswith(".npz") else None
        write_json(args.out, out)
        if stale:       # an earlier `solve --npz` wrote it: beside this result it would name none of its arrays
            remove_outputs(folder, [stale])
    for w in res.warnings:
        print(f"warning: {w}", file=sys.stderr)
    if not res.converged:   # the file is written (marked "converged": false) but the exit status says so
        print(f"error: model {model!r} did not converge; {args.out} holds the last iterate", file=sys.stderr)
        return 1
    return 0
