"""``bench fidelity [--out docs/fidelity.md] [--img docs/img/fidelity-work-precision.png]``.

Image defaults: without ``--out`` the plot is docs/img/fidelity-work-precision.png (the docs' picture); with
``--out`` and without ``--img`` it goes beside the report, ``<out stem>-work-precision.png`` (a redirected report
never overwrites the docs' picture); likewise ``--sleeves-img`` follows ``--sleeves-out``
(``<sleeves-out stem>-fe-check.png``, else docs/img/sleeve-fe-check.png). Every image name must end in .png.

Runs every model of the fidelity ladder on the standard scenes (chain, 10 x 10 and 30 x 30 grids,
bending strip, mixed hinge sizes; two actuator amplitudes) against the converged nonlinear reference (hinges
of 1, 2, 4, 8 elements, extrapolated) and writes the report and its work-precision plot; ``--fe`` adds the
CalculiX rung (metamaterial_wb/fe). Every option and output path is checked before any work (two outputs naming
the same file, or an output naming an input, are refused); the files are rendered in memory first and written
atomically: the report and plot first, then the side files (--json, --fe-json-out).
"""
import json
import os
import platform
import sys
import time

from metamaterial_wb.cli import integer

NAME = "bench"
STORED_FE = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))), "benchmarks",
                         "results", "fe-study.json")
FE_PARTS = {"hinge": "stiffness", "patch": "patch", "sleeve": "sleeve"}     # --fe-parts: the study's key in the JSON
REPEATS, REPEATS_RANGE = 3, (1, 20)     # --repeats: default and allowed range
OUT = os.path.join("docs", "fidelity.md")                           # --out's default
IMG = os.path.join("docs", "img", "fidelity-work-precision.png")    # --img's default without --out
IMG_SUFFIX = "-work-precision.png"                                  # --img's default with --out: <out stem> + this
SLEEVES_OUT = os.path.join("docs", "sleeves.md")
SLEEVES_IMG = os.path.join("docs", "img", "sleeve-fe-check.png")    # --sleeves-img's default without --sleeves-out
SLEEVES_IMG_SUFFIX = "-fe-check.png"                                # with --sleeves-out: <sleeves-out stem> + this
HELP = "benchmarks: 'bench fidelity' writes docs/fidelity.md and its work-precision plot (error vs run time)"


def add_arguments(p):
    p.add_argument("what", choices=("fidelity",), help="which benchmark")
    p.add_argument("--out", default=None, help=f"report (Markdown; default {OUT})")
    p.add_argument("--img", default=None,
                   help=f"work-precision plot (a name ending in .png; default: with --out, beside it as <out "
                        f"stem>{IMG_SUFFIX}; without --out, {IMG})")
    p.add_argument("--json", default=None,
                   help="also write the raw figures as JSON, with the date, machine and command of the run")
    p.add_argument("--scenes", default=None,
                   help="comma-separated subset of chain,grid10,grid30,bending,mixed (default: all)")
    p.add_argument("--amplitudes", default=None, help="comma-separated actuator amplitudes (default 0.05,0.5)")
    p.add_argument("--repeats", type=integer, default=None,
                   help=f"timing runs per model, {REPEATS_RANGE[0]} to {REPEATS_RANGE[1]} (best is reported; default "
                        f"{REPEATS}); not with --from-json, whose times were measured by the run that wrote it")
    p.add_argument("--quiet", action="store_true", help="no progress lines")
    p.add_argument("--fe", action="store_true",
                   help="also run the CalculiX rung (one hinge: stiffness and bending curves; the 3 x 3 patch "
                        "at amplitudes 0.05 and 0.5; mesh studies; 20-60 min on a shared machine); without ccx "
                        "the report says so and the rest still runs; a part whose ccx run fails is left out with "
                        "an 'FE rung failed' note in the report, the other parts kept")
    p.add_argument("--fe-json", default=None,
                   help="with --fe: reuse the FE study stored in this JSON file (written by --fe-json-out) "
                        "instead of running ccx again; without --fe: the FE study rendered into the report "
                        "(default: the stored one, benchmarks/results/fe-study.json, where it exists)")
    p.add_argument("--fe-json-out", default=None,
                   help="with --fe (refused without it): also write the FE study as JSON (figures not reached are "
                        "null, listed in 'nan_paths'; --fe-json reads them back)")
    p.add_argument("--fe-parts", default=None,
                   help="with --fe: which FE studies to run (one or more of hinge,patch,sleeve, comma-separated; every "
                        "study run or read from --fe-json is rendered into the report); "
                        "sleeve: the sleeve's unit cell and four-cell ring (2-D plane strain) against the beam model, "
                        "written into --sleeves-out")
    p.add_argument("--sleeves-out", default=None,
                   help="with --fe and the sleeve part: the document whose marked FE section is rewritten (default "
                        "docs/sleeves.md)")
    p.add_argument("--sleeves-img", default=None,
                   help=f"with --fe and the sleeve part: its plot (a name ending in .png; default: with --sleeves-out, "
                        f"beside it as <sleeves-out stem>{SLEEVES_IMG_SUFFIX}; without it, {SLEEVES_IMG})")
    p.add_argument("--from-json", default=None,
                   help="render the report and plot from the raw figures of a previous run (its --json file, "
                        "format metamaterial-fidelity: another format is refused) "
                        "instead of running the models again; --scenes / --amplitudes select among its results "
                        "(each must be in the file); the report keeps the run's recorded date and machine")


FE_NAN_PATHS = "nan_paths"      # --fe-json-out: where the study held NaN (written as null; read back as NaN)
# --fe-json-out marks its file, as every JSON report written is marked (named if read as a scene, or as an FE study
# when it is another document); --fe-json reads a file with this marker or, written before it, none
FE_FORMAT, FE_VERSION = "metamaterial-fe-study", 1
RAW_FORMAT, RAW_VERSION = "metamaterial-fidelity", 1      # --json's raw figures, read back by --from-json


def _nan_to_null(obj, path=(), found=None):
    """``(copy, paths)``: ``obj`` with every NaN float (a figure not reached, e.g. a sleeve ring's valley) replaced
    by ``None``, and the paths (lists of keys and indices) where they were, so that :func:`_null_to_nan` restores
    exactly those (the study holds genuine ``None`` values elsewhere)."""
    found = [] if found is None else found
    if isinstance(obj, dict):
        # a key as JSON writes it (1 -> "1"), so that the path names it in the file
        return {k: _nan_to_null(v, path + (k if isinstance(k, str) else json.dumps(k),), found)[0]
                for k, v in obj.items()}, found
    if isinstance(obj, (list, tuple)):
        return [_nan_to_null(v, path + (i,), found)[0] for i, v in enumerate(obj)], found
    if isinstance(obj, float) and obj != obj:
        found.append(list(path))
        return None, found
    if hasattr(obj, "tolist") and not isinstance(obj, (str, bytes)):       # numpy scalars and arrays
        return _nan_to_null(obj.tolist(), path, found)
    return obj, found


def _null_to_nan(study, paths, where):
    """Put NaN back at ``paths`` (the file's ``nan_paths``) of ``study``; a path that names no null is refused."""
    from metamaterial_wb.core.errors import SceneError
    if not isinstance(paths, list):
        raise SceneError("--fe-json", f"{where}: {FE_NAN_PATHS!r} is {type(paths).__name__}, expected a list of paths")
    for p in paths:
        node = study
        try:
            if not isinstance(p, list) or not p:
                raise TypeError
            for k in p[:-1]:
                node = node[k]
            if node[p[-1]] is not None:
                raise TypeError
            node[p[-1]] = float("nan")
        except (KeyError, IndexError, TypeError):
            raise SceneError("--fe-json", f"{where}: {FE_NAN_PATHS!r} entry {p!r} names no null value of the "
                                          "study") from None


def _read_study(path, hint=""):
    """The FE study stored in the JSON file ``path`` (``--fe-json``), or a SceneError naming it (``hint`` added).

    A file written by ``--fe-json-out`` holds NaN figures as null, listed in ``nan_paths``: they are NaN again
    here, as the renderer expects. The study is rendered once (in memory) so that a malformed one is refused
    now, not after the models or CalculiX ran."""
    from metamaterial_wb.bench import fe_study as fe
    from metamaterial_wb.core.errors import SceneError
    try:
        with open(path, encoding="utf-8") as f:
            study = json.load(f)
    except (OSError, ValueError) as exc:
        raise SceneError("--fe-json", f"{path!r}: cannot read the FE study ({exc}){hint}") from None
    if not isinstance(study, dict):
        raise SceneError("--fe-json", f"{path!r}: the FE study is a JSON {type(study).__name__}, expected an object "
                                      f"(as written by --fe-json-out){hint}")
    if _check_marker(study, path, "--fe-json", FE_FORMAT, FE_VERSION, "an FE study", "--fe-json-out", hint):
        del study["format"], study["version"]
    if FE_NAN_PATHS in study:
        _null_to_nan(study, study.pop(FE_NAN_PATHS), repr(path))
    try:
        fe.markdown(study)
    except (KeyError, IndexError, TypeError, ValueError, AttributeError, ZeroDivisionError) as exc:
        raise SceneError("--fe-json", f"{path!r}: the FE study is incomplete or malformed "
                                      f"({type(exc).__name__}: {exc}){hint}") from None
    return study


def _check_marker(doc, path, option, fmt_wanted, version, what_wanted, writer, hint=""):
    """Check the marker of a file written by ``writer`` (``--fe-json-out``: ``"format": FE_FORMAT``, ``--json``:
    RAW_FORMAT; ``"version"``), read by ``option``; refuse another document's format, naming it, or another version
    (a SceneError under ``option``). A file without "format" (one written before the marker, like a stored study)
    is read as it is, as scenes and targets without one are. Returns True when the file carries the marker."""
    from metamaterial_wb.core.errors import SceneError
    from metamaterial_wb.core.scene.names import FORMAT as SCENE_FORMAT
    from metamaterial_wb.core.scene.sections import OTHER_DOCUMENTS
    if "format" not in doc:
        return False
    fmt = doc["format"]
    if fmt != fmt_wanted:
        what = {SCENE_FORMAT: "a scene", **OTHER_DOCUMENTS}.get(fmt) if isinstance(fmt, str) else None
        raise SceneError(option, f"{path!r}: its format is {fmt!r}" + (f" ({what})" if what else "")
                         + f", not {what_wanted}; expected {fmt_wanted!r} (a file written by {writer}){hint}")
    ver = doc.get("version")
    if type(ver) is not int or ver != version:          # type(): True and 1.0 are no version 1
        raise SceneError(option, f"{path!r}: version {ver!r} of {fmt_wanted!r} is not supported; this program "
                                 f"reads version {version} (the whole number){hint}")
    return True


def _read_results(path):
    """``(results, measured)`` of the raw-figures file ``path`` (``--from-json``): the shape checked."""
    from metamaterial_wb.core.errors import SceneError
    try:
        with open(path, encoding="utf-8") as f:
            data = json.load(f)
    except (OSError, ValueError) as exc:
        raise SceneError("--from-json", f"{path!r}: cannot read the raw figures ({exc})") from None
    if isinstance(data, dict):     # another document (an FE study, a scene) is named before its missing 'results'
        _check_marker(data, path, "--from-json", RAW_FORMAT, RAW_VERSION, "raw figures", "--json")
    if not isinstance(data, dict) or not isinstance(data.get("results"), list):
        got = (_what(data) if not isinstance(data, dict) else "an object without 'results'" if "results" not in data
               else f"an object whose 'results' is {_what(data['results'])}")
        raise SceneError("--from-json", f"{path!r}: expected a JSON object with a list 'results' (a file written by "
                                        f"--json), got {got}")
    for i, r in enumerate(data["results"]):
        if not isinstance(r, dict):
            raise SceneError("--from-json", f"{path!r}: results[{i}] is {_what(r)}, expected an object")
        for field, ok, want in (("key", lambda v: isinstance(v, str), "a scene name"),
                                ("amplitude", lambda v: isinstance(v, (int, float)) and not isinstance(v, bool)
                                 and 0 < v <= 1, "a number in (0, 1]"),
                                ("rows", lambda v: isinstance(v, list) and v and all(isinstance(x, dict) for x in v),
                                 "a non-empty list of objects")):
            if field not in r:
                raise SceneError("--from-json", f"{path!r}: results[{i}] has no {field!r} ({want})")
            if not ok(r[field]):
                raise SceneError("--from-json", f"{path!r}: results[{i}].{field} is {r[field]!r:.60}; expected {want}")
    if not data["results"]:
        raise SceneError("--from-json", f"{path!r} holds no results")
    measured = data.get("measured")
    if measured is not None:
        types = {"date": str, "cores": int, "python": str, "arch": str, "load_average": (int, float),
                 "repeats": int, "command": str}
        if not isinstance(measured, dict) or any(k in measured and measured[k] is not None
                                                 and not isinstance(measured[k], t) for k, t in types.items()):
            raise SceneError("--from-json", f"{path!r}: 'measured' is {measured!r:.100}; expected an object with "
                                            "date, cores, python, arch, load_average, repeats, command")
    return data["results"], measured


def _what(v):
    return {dict: "an object", list: "a list", str: "a string", type(None): "null", bool: "a boolean"}.get(
        type(v), f"a number ({v!r})" if isinstance(v, (int, float)) else type(v).__name__)


def _machine_line(m, source=None):
    """The report's "Measured ..." line from ``m`` (:func:`_measured`, or a --from-json file's record; ``None``:
    an older file that recorded none, named by ``source``)."""
    if source is not None and (m is None or not m.get("date")):
        return (f"Measured: date and machine not recorded (figures read from `{source}`, written by an older "
                "`--json`); shared machine, treat times as upper bounds.")
    load, cores = m.get("load_average"), m.get("cores")
    line = (f"Measured {m['date']} on {cores if cores else 'an unrecorded number of'} cores, "
            f"Python {m.get('python') or 'version not recorded'} ({m.get('arch') or 'architecture not recorded'}); "
            "shared machine, treat times as upper bounds"
            + (f" (load average {load:.1f} at the end of the run)" if load is not None else "") + ".")
    if load is not None and cores and load > cores:
        line += (" The machine was oversubscribed (more runnable jobs than cores): absolute times are inflated "
                 f"up to about {load / cores:.0f}x against an idle machine; ratios within the run and every error "
                 "are unaffected.")
    if source is not None:
        line += (f" Figures read from `{source}`" + (f" (measured by `{m['command']}`)" if m.get("command") else "")
                 + ".")
    return line


def _measured(repeats, command):
    """What the raw-figures file records about this run (date, machine, load, repeats, command)."""
    return {"date": time.strftime("%Y-%m-%d", time.gmtime()), "cores": os.cpu_count(),
            "python": platform.python_version(), "arch": platform.machine(),
            "load_average": round(os.getloadavg()[0], 2), "repeats": repeats, "command": command}


def _list_option(flag, text, what, example):
    """The comma-separated items of ``text`` (``--scenes`` / ``--amplitudes``); none is refused."""
    from metamaterial_wb.core.errors import SceneError
    items = [x.strip() for x in text.split(",") if x.strip()]
    if not items:
        raise SceneError(flag, f"{text!r} names no {what}; give one or more, comma-separated, e.g. {example}")
    return items


def _no_repeats(flag, text, items, what, why="each is run, or read, once"):
    """Refuse an item of a comma-separated list given twice, as ``--amplitudes`` does (it would be run once)."""
    from metamaterial_wb.core.errors import SceneError
    for i, x in enumerate(items, 1):
        if x in items[:i - 1]:
            raise SceneError(flag, f"{x!r} is given more than once (items {items.index(x) + 1} and {i} of {text!r}); "
                                   f"give each {what} once ({why})")


def _command(args, amps, keys, parts):
    """The command line the report credits: every option that changes what it shows."""
    import shlex
    cmd = "python3 -m metamaterial_wb bench fidelity"
    if args.from_json:
        cmd += f" --from-json {shlex.quote(args.from_json)}"
    elif args.repeats != REPEATS:
        cmd += f" --repeats {args.repeats}"
    if keys is not None:
        cmd += f" --scenes {','.join(keys)}"
    if args.amplitudes is not None:
        cmd += f" --amplitudes {','.join(f'{a:g}' for a in amps)}"
    if args.fe:
        cmd += " --fe"
        if parts != list(FE_PARTS):
            cmd += f" --fe-parts {','.join(parts)}"
    if args.fe_json:
        cmd += f" --fe-json {shlex.quote(args.fe_json)}"
    return cmd


def _beside(doc, suffix):
    """The picture's default name beside the document ``doc``: its name without the extension, plus ``suffix``."""
    return os.path.splitext(doc)[0] + suffix


def _image_defaults(args):
    """Fill in --out / --img (the plot follows a given --out: a redirected report never writes the docs' picture)."""
    if args.img is None:
        args.img = IMG if args.out is None else _beside(args.out, IMG_SUFFIX)
    if args.out is None:
        args.out = OUT


def _fe_only_flags(args):
    """Refuse the flags of a --fe run given without --fe (and the sleeve outputs without the sleeve part): they
    would be ignored; then fill in their defaults."""
    from metamaterial_wb.core.errors import SceneError

    given = [(f, v) for f, v in (("--fe-parts", args.fe_parts), ("--sleeves-out", args.sleeves_out),
                                 ("--sleeves-img", args.sleeves_img)) if v is not None]
    if given and not args.fe:
        flag, v = given[0]
        raise SceneError(flag, f"{v} without --fe: only a --fe run uses it (without --fe the FE study is read, not "
                               "made); add --fe, or drop " + flag)
    args.fe_parts = args.fe_parts if args.fe_parts is not None else ",".join(FE_PARTS)
    if "sleeve" not in [x.strip() for x in args.fe_parts.split(",")]:
        for flag, v in given:
            if flag != "--fe-parts":
                raise SceneError(flag, f"{v} without the sleeve part of --fe-parts ({args.fe_parts!r}): only the "
                                       "sleeve study writes it; add sleeve to --fe-parts, or drop " + flag)
    if args.sleeves_img is None:
        args.sleeves_img = SLEEVES_IMG if args.sleeves_out is None else _beside(args.sleeves_out, SLEEVES_IMG_SUFFIX)
    args.sleeves_out = args.sleeves_out if args.sleeves_out is not None else SLEEVES_OUT


def run(args):
    from metamaterial_wb.bench import fidelity
    from metamaterial_wb.core.errors import MetamaterialError, SceneError
    from metamaterial_wb.core.fileio import check_output, write_atomic, write_json
    from metamaterial_wb.core.numbers import parse_float

    # every option checked before any work
    amps = fidelity.AMPLITUDES
    if args.amplitudes is not None:
        items = _list_option("--amplitudes", args.amplitudes, "amplitude", "0.05,0.5")
        amps = tuple(parse_float(f"--amplitudes item {i}", x) for i, x in enumerate(items, 1))
        for i, a in enumerate(amps, 1):
            if not (0 < a <= 1):
                raise SceneError(f"--amplitudes item {i}", f"{items[i - 1]!r} is outside the allowed range (0, 1]")
            if a in amps[:i - 1]:
                raise SceneError("--amplitudes", f"{a:g} is given more than once (items {amps.index(a) + 1} and "
                                                 f"{i} of {args.amplitudes!r}); give each amplitude once (each is "
                                                 "run, or read, once)")
    if args.repeats is not None and args.from_json:
        raise SceneError("--repeats", f"{args.repeats} with --from-json: no model runs, the report shows the times "
                                      f"recorded in {args.from_json!r} (and how many runs they are the best of); "
                                      "drop --repeats, or drop --from-json to measure again")
    if args.repeats is None:
        args.repeats = REPEATS
    if not (REPEATS_RANGE[0] <= args.repeats <= REPEATS_RANGE[1]):
        raise SceneError("--repeats", f"{args.repeats} is outside the allowed range [{REPEATS_RANGE[0]}, "
                                      f"{REPEATS_RANGE[1]}]")
    if args.fe_json_out is not None and not args.fe:
        raise SceneError("--fe-json-out", f"{args.fe_json_out} without --fe: only a --fe run writes its FE study "
                                          "there (without --fe the study is read, not made); add --fe, or drop "
                                          "--fe-json-out")
    keys = None
    if args.scenes is not None:
        keys = _list_option("--scenes", args.scenes, "scene", "chain,grid10")
        known = [k for k, _, _ in fidelity.standard_scenes()]
        for k in keys:
            if k not in known:
                raise SceneError("--scenes", f"{k!r} is not a standard scene; known: {', '.join(known)}")
        _no_repeats("--scenes", args.scenes, keys, "scene")
    _image_defaults(args)
    _fe_only_flags(args)
    parts = [x.strip() for x in args.fe_parts.split(",") if x.strip()]
    if not parts:
        raise SceneError("--fe-parts", f"{args.fe_parts!r} names no FE study; allowed: one or more of hinge, patch, "
                                       "sleeve, comma-separated")
    for x in parts:
        if x not in FE_PARTS:
            raise SceneError("--fe-parts", f"{x!r} is not an FE study; allowed: one or more of hinge, patch, sleeve, "
                                           "comma-separated")
    _no_repeats("--fe-parts", args.fe_parts, parts, "FE study", "each is run once")
    fe_in = args.fe_json or (None if args.fe or not os.path.exists(STORED_FE) else STORED_FE)
    inputs = [("--from-json file", args.from_json), ("--fe-json file", fe_in)]
    outputs = [("--out", args.out), ("--img", args.img), ("--json", args.json)]
    if args.fe:
        outputs.append(("--fe-json-out", args.fe_json_out))
        if "sleeve" in parts:
            outputs += [("--sleeves-out", args.sleeves_out), ("--sleeves-img", args.sleeves_img)]
            if not os.path.isfile(args.sleeves_out):
                raise SceneError("--sleeves-out", f"{args.sleeves_out} is not an existing file; with --fe and the "
                                                  "sleeve part it names the document whose marked FE section is "
                                                  "rewritten (docs/sleeves.md)")
    outputs = [(flag, p) for flag, p in outputs if p is not None]
    seen = {}
    for flag, p in outputs:
        check_output(p, "file", flag, inputs=inputs)
        real = os.path.realpath(p)
        if real in seen:
            raise SceneError(flag, f"{p} is also the {seen[real]} file; each output needs its own file (one would "
                                   f"overwrite the other)")
        seen[real] = flag
    for flag, p in outputs:          # after the collisions: a plot named like the report is named as that
        if flag in ("--img", "--sleeves-img") and not p.lower().endswith(".png"):
            raise SceneError(flag, f"{p}: the plot is written as a PNG picture; give a name ending in .png")

    t0 = time.perf_counter()

    def progress(msg):
        if not args.quiet:
            print(f"[{time.perf_counter() - t0:6.1f} s] {msg}", file=sys.stderr, flush=True)

    # the inputs read (and checked) before anything runs
    results, measured = [], None
    if args.from_json:
        results, measured = _read_results(args.from_json)
        held_keys = sorted({r["key"] for r in results})
        held_amps = sorted({r["amplitude"] for r in results})
        asked_amps = amps if args.amplitudes is not None else None
        for flag, asked, held in (("--scenes", keys, held_keys), ("--amplitudes", asked_amps, held_amps)):
            missing = [x for x in (asked or ()) if x not in held]
            if missing:
                raise SceneError(flag, f"{', '.join(map(str, missing))}: not in {args.from_json!r}, which holds "
                                       f"{', '.join(map(str, held))}; choose from these")
        results = [r for r in results if (keys is None or r["key"] in keys)
                   and (args.amplitudes is None or r["amplitude"] in amps)]
        if not results:
            raise SceneError("--scenes", f"{args.scenes!r} with --amplitudes {args.amplitudes!r} selects no result "
                                         f"of {args.from_json!r}")
    fe_study, fe_note, fe_ran = None, None, False
    if args.fe:
        fe_study = _read_study(args.fe_json) if args.fe_json else {}
        if args.fe_json:
            fe_note = f"FE figures read from `{os.path.basename(args.fe_json)}` (a previous `--fe` run)."
    elif fe_in:
        # the stored CalculiX study goes into the report as it is, so regenerating it keeps its FE rung
        fe_study = _read_study(fe_in, "" if args.fe_json else "; without --fe-json the stored one is read, with --fe "
                                                             "CalculiX runs again")
        fe_note = (f"FE figures read from `{os.path.basename(fe_in)}` (a stored `--fe` run; `--fe` runs "
                   "CalculiX again).")

    if args.fe:
        from metamaterial_wb.bench import fe_study as study
        from metamaterial_wb.fe import ccx
        # run every requested part the JSON (if any) does not hold
        todo = [x for x in parts if FE_PARTS[x] not in fe_study]
        ok, why = ccx.available()
        if todo and not ok:
            fe_note = f"FE rung not run: {why}."
            progress(fe_note)
        failed = []
        for part in (todo if ok else []):     # each part on its own: one that fails keeps the others
            fe_ran = True
            try:
                if part == "hinge":
                    fe_study.update(study.run_hinge_study(progress=progress))
                    fe_study["aspect"] = study.run_aspect_study(progress=progress)
                elif part == "patch":
                    fe_study["patch"] = study.run_patch_study(progress=progress)
                else:
                    from metamaterial_wb.bench import fe_sleeve
                    fe_study["sleeve"] = fe_sleeve.run_sleeve_study(progress=progress)
            except MetamaterialError as exc:          # ccx failed, stopped or wrote no tables (ccx.FEError)
                failed.append(f"FE rung failed: {part} study: {' '.join(str(exc).split())}")
                progress(failed[-1])
        if failed:
            fe_note = " ".join(filter(None, [fe_note] + [f + ("" if f.endswith(".") else ".") for f in failed]))
        if not fe_study:
            fe_study = None
    for a in ([] if args.from_json else amps):
        scenes = [s for s in fidelity.standard_scenes(a) if keys is None or s[0] in keys]
        results += fidelity.run_ladder(scenes, progress=progress, repeats=args.repeats, amplitudes=(a,))

    def save_fe_json():
        # not-reached figures (NaN) as null, listed in nan_paths so that --fe-json reads them back as NaN
        if args.fe and fe_study is not None and args.fe_json_out:
            copy, nan_paths = _nan_to_null(fe_study)
            copy = {"format": FE_FORMAT, "version": FE_VERSION, **copy}     # named when read as something else
            if nan_paths:
                copy[FE_NAN_PATHS] = nan_paths
            try:
                write_json(args.fe_json_out, copy)
            except (TypeError, ValueError) as exc:       # e.g. an infinite figure: nothing is written
                raise SceneError("--fe-json-out", f"{args.fe_json_out}: the FE study cannot be written as JSON "
                                                  f"({exc})") from None

    command = _command(args, amps, keys, parts)
    try:
        text, png, sleeves, raw, lines, code = _render(args, fidelity, results, measured, command, fe_study, fe_note,
                                                       args.fe and "sleeve" in parts, fe_file=fe_in, fe_ran=fe_ran)
    except BaseException:
        if fe_ran:       # hours of CalculiX work are kept even when the report cannot be made
            save_fe_json()
        raise
    write_atomic(args.img, png, mode="wb")
    write_atomic(args.out, text)
    if sleeves:
        write_atomic(args.sleeves_img, sleeves[0], mode="wb")
        write_atomic(args.sleeves_out, sleeves[1])
    if raw is not None:
        write_atomic(args.json, raw)
    save_fe_json()
    for line in lines:
        print(line)
    wrote = [args.out, args.img] + ([args.sleeves_out, args.sleeves_img] if sleeves else []) + (
        [args.json] if raw is not None else [])
    print(f"wrote {', '.join(wrote[:-1])} and {wrote[-1]} ({time.perf_counter() - t0:.1f} s)")
    return code


def _render(args, fidelity, results, measured, command, fe_study, fe_note, with_sleeves, fe_file=None, fe_ran=False):
    """Everything written, in memory: ``(report, png, (sleeve png, sleeve doc) or None, --json text or None,
    summary lines, exit code)``; the sleeve document only ``with_sleeves`` (--fe with the sleeve part). Figures
    read from --from-json / --fe-json (``fe_file``: that file, or the stored study read without it) that cannot be
    rendered are refused naming the option and the file at fault: when both were read, the raw figures are
    rendered again without the FE study to tell which (only then, on the error path)."""
    import tempfile

    from metamaterial_wb.core.errors import SceneError

    if args.from_json:
        machine = _machine_line(measured, os.path.basename(args.from_json))
        repeats = measured.get("repeats") if measured else None
    else:
        measured = _measured(args.repeats, command)
        machine = _machine_line(measured)
        repeats = args.repeats
    img_rel = os.path.relpath(os.path.abspath(args.img), os.path.dirname(os.path.abspath(args.out)))
    fe_md = None
    if args.fe or fe_study:
        from metamaterial_wb.bench import fe_study as study
        fe_md = study.markdown(fe_study) + (f"\n{fe_note}\n" if fe_note else "")
    bad = (KeyError, IndexError, TypeError, ValueError, AttributeError, ZeroDivisionError, StopIteration)

    def render(fe_md, fe_study):
        text = fidelity.report_markdown(results, img_rel.replace(os.sep, "/"), machine, command=command,
                                        repeats=repeats, fe_markdown=fe_md)
        lines = [f"{s['key']:8s} amp {s['amplitude']:<5g} quadratic {s['quadratic_ms']:7.2f} ms  linear "
                 f"{s['linear_ms']:7.2f} ms  nonlinear {s['nonlinear_ms']:8.1f} ms  RMS dD quadratic "
                 f"{s['quadratic_rms_D']:.3g} linear {s['linear_rms_D']:.3g} (ratio {s['ratio']:.2f})"
                 f"{'' if s['nonlinear_converged'] else '  NONLINEAR NOT CONVERGED'}"
                 for s in fidelity.summary(results)]
        code = 0 if all(r["reference_converged"] for r in results) else 1
        with tempfile.TemporaryDirectory() as tmp:
            tmp_png = os.path.join(tmp, "plot.png")
            fidelity.plot_work_precision(results, tmp_png, fe_study)
            with open(tmp_png, "rb") as f:
                return text, lines, code, f.read()

    try:
        text, lines, code, png = render(fe_md, fe_study)
    except bad as exc:
        fe_read = bool(fe_study) and fe_file is not None
        if not (args.from_json or fe_read):
            raise
        at_fault = "--from-json" if args.from_json else None
        if fe_study:                         # which input: do the raw figures render without the FE study?
            try:
                render(None, None)
                at_fault = "--fe-json" if fe_read else None
            except bad:
                pass
        if at_fault is None:                 # the figures this run made (models or CalculiX), not a file: a bug
            raise
        if at_fault == "--from-json":
            what = repr(args.from_json)
        else:
            what = repr(fe_file) + ("" if args.fe_json else " (the stored FE study, read without --fe-json)") + (
                " with the FE parts this --fe run added" if fe_ran else "")
        raise SceneError(at_fault, f"{what}: the figures are incomplete or malformed and cannot be rendered "
                                   f"({type(exc).__name__}: {exc})") from None
    sleeves = None
    if with_sleeves and fe_study and fe_study.get("sleeve"):
        from metamaterial_wb.bench import fe_sleeve
        sl = fe_sleeve.summarise(fe_study["sleeve"])
        sl_img = os.path.relpath(os.path.abspath(args.sleeves_img), os.path.dirname(os.path.abspath(args.sleeves_out)))
        with tempfile.TemporaryDirectory() as tmp:
            tmp_png = os.path.join(tmp, "sleeve.png")
            fe_sleeve.plot(sl, tmp_png)
            with open(tmp_png, "rb") as f:
                sl_png = f.read()
        section = fe_sleeve.markdown(sl, sl_img.replace(os.sep, "/"))
        sleeves = (sl_png, fe_sleeve.write_section(args.sleeves_out, section))
    raw = None
    if args.json:
        try:
            raw = json.dumps({"format": RAW_FORMAT, "version": RAW_VERSION, "measured": measured,
                              "results": results}, indent=1, allow_nan=False) + "\n"
        except ValueError as exc:
            raise SceneError("--json", f"{args.json}: the figures cannot be written as JSON ({exc}); nothing "
                                       "was written") from None
    return text, png, sleeves, raw, lines, code
