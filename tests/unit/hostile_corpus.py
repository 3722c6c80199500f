"""Generator of hostile inputs (issue 19) and an in-process runner that puts each one through every command.

``cases()`` yields :class:`Case` objects: malformed scenes and sleeve specs (wrong types, NaN/Inf, huge and
deep values, unicode, truncated text, special files as input) and bad output paths. ``run_case`` calls the
CLI's ``main(argv)`` in this process for every command that takes the input, with an alarm as time limit
(the caller sets the memory limit on the whole process), and returns what went wrong: a traceback, a hang,
an exit status other than 0 / 2 (1 for "did not converge"), more than one stderr line on exit 2, or a file
left behind in the output folder, the input folder or the current directory.

Run as a script (``python3 tests/unit/hostile_corpus.py [--limit-mb N] [--only ID ...]``) it runs the
whole corpus and prints one JSON object per failing case; ``tests/unit/test_hostile_corpus.py`` does that
in a subprocess with a memory limit.
"""
import contextlib
import copy
import io
import json
import os
import signal
import sys
import traceback

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
EXAMPLES = os.path.join(REPO, "examples")

BASE_SCENE = {
    "format": "metamaterial-scene", "version": 1, "name": "hostile", "cell_size_mm": 20,
    "hinge": {"length_mm": 2, "width_mm": 0.8, "thickness_mm": 7},
    "layout": {"grid": [2, 3]},
    "joints": [{"joint": "H0,1", "k1": 0.9, "k2": 1.0}],
    "axes": [{"direction": "vertical", "line": 1, "fold_deg": 5, "name": "a"}],
    "actuators": [{"name": "m1", "joint": "V0,0", "value": 0.5,
                   "profile": {"shape": "sine", "amplitude": 0.3, "frequency_hz": 1, "phase_deg": 0}}],
    "constraints": [{"name": "c1", "joint": "V1,3", "value": -0.2}],
    "modules": [{"type": "servo_housing", "joint": "V0,0", "servo": "SG90"},
                {"type": "friction_pad", "node": "N0,0", "mu": 1.0, "side": "bottom"}],
    "material": {"hinge_strain_limit": 0.5},
    "dynamics": {"model": "sheet", "friction": 0.3, "damping_ratio": 0.05, "density_kg_m3": 1240,
                 "integrator": {"method": "implicit", "dt_s": 0.005}},
}

BASE_SLEEVE = {
    "format": "metamaterial-sleeve", "version": 1, "name": "hostile", "L_mm": 18, "c_mm": 4, "delta_mm": 0.5,
    "T_mm": 1.8, "shear_modulus_MPa": 28,
    "cell_types": [{"t_mm": 1.098, "h_mm": 7.092}, {"t_mm": 1.098, "h_mm": 7.488}],
    "ring": [0, 0, 1, 1],
    "actuator": {"core_diameter_mm": 24.6, "membrane_kPa_per_mL": 0},
}

# values that replace a field: wrong types, non-finite, huge, tiny, unicode
BAD_VALUES = [
    ("obj", "{}"), ("list", "[]"), ("str", '"x"'), ("null", "null"), ("true", "true"),
    ("nan", "NaN"), ("inf", "Infinity"), ("ninf", "-Infinity"), ("e309", "1e309"), ("big", "1e300"),
    ("int400", "1" + "0" * 400), ("int20", "-" + "9" * 20), ("int5000", "7" * 5000), ("neg", "-1"), ("tiny", "5e-324"),
    ("uni", '"\\u202e\\ud800x"'), ("deep", "[" * 900 + "]" * 900),
]

SCENE_FIELDS = [  # JSON paths into BASE_SCENE (the sections that are kept-but-unchecked included)
    ("name",), ("cell_size_mm",), ("hinge",), ("hinge", "length_mm"), ("hinge", "width_mm"), ("layout",),
    ("layout", "grid"), ("layout", "grid", 0), ("joints",), ("joints", 0, "k1"), ("joints", 0, "k2"),
    ("joints", 0, "joint"), ("axes", 0, "line"), ("axes", 0, "fold_deg"), ("actuators", 0, "value"),
    ("actuators", 0, "joint"), ("actuators", 0, "profile"), ("actuators", 0, "profile", "frequency_hz"),
    ("constraints", 0, "value"), ("modules",), ("modules", 0), ("modules", 0, "type"), ("modules", 0, "joint"),
    ("modules", 1, "node"), ("modules", 1, "mu"), ("material",), ("material", "hinge_strain_limit"),
    ("dynamics",), ("dynamics", "friction"), ("dynamics", "density_kg_m3"), ("dynamics", "integrator", "dt_s"),
    ("global_deformation",), ("joint_config",), ("fabrication",), ("extra_key",),
]
SLEEVE_FIELDS = [("L_mm",), ("c_mm",), ("T_mm",), ("shear_modulus_MPa",), ("cell_types",), ("cell_types", 0),
                 ("cell_types", 0, "t_mm"), ("ring",), ("ring", 0), ("actuator",),
                 ("actuator", "core_diameter_mm")]

# every bound of every numeric sleeve field, hit from outside (issue 19): (id, {path: value}, field the error
# must name). The values sit just beyond the bound; integers get a fraction too. The base is BASE_SLEEVE
# (L = 18, c = 4, t = 1.098, 4 cells around, mid radius 14 mm).
SLEEVE_BOUNDS = [
    ("L-low", {("L_mm",): 1.99}, "L_mm"), ("L-high", {("L_mm",): 200.1}, "L_mm"),
    ("c-low", {("c_mm",): 0.39}, "c_mm"), ("c-high", {("c_mm",): 10.81}, "c_mm"),
    ("delta-low", {("delta_mm",): 0.19}, "delta_mm"), ("delta-high", {("delta_mm",): 18.01}, "delta_mm"),
    ("T-low", {("T_mm",): 0.39}, "T_mm"), ("T-high", {("T_mm",): 36.01}, "T_mm"),
    ("T-tube", {("T_mm",): 28.1}, "T_mm"),
    ("G-zero", {("shear_modulus_MPa",): 0}, "shear_modulus_MPa"),
    ("G-high", {("shear_modulus_MPa",): 5000.1}, "shear_modulus_MPa"),
    ("t-low", {("cell_types", 0, "t_mm"): 0.39}, "cell_types[0].t_mm"),
    ("t-high", {("cell_types", 0, "t_mm"): 4.51}, "cell_types[0].t_mm"),
    ("h-zero", {("cell_types", 1, "h_mm"): 0}, "cell_types[1].h_mm"),
    ("h-high", {("cell_types", 1, "h_mm"): 10.81}, "cell_types[1].h_mm"),
    ("rings-low", {("rings",): 0}, "rings"), ("rings-high", {("rings",): 13}, "rings"),
    ("rings-frac", {("rings",): 1.5}, "rings"),
    ("ring-short", {("ring",): [0]}, "ring"), ("ring-long", {("ring",): [0] * 33}, "ring"),
    ("ring-bed", {("L_mm",): 30, ("ring",): [0, 1] * 16}, "ring"),
    ("rings-height", {("L_mm",): 40, ("cell_types", 1, "h_mm"): 24, ("rings",): 12}, "rings"),
    ("elements_cell-low", {("model",): {"elements_cell": 1}}, "model.elements_cell"),
    ("elements_cell-high", {("model",): {"elements_cell": 81}}, "model.elements_cell"),
    ("elements_cell-frac", {("model",): {"elements_cell": 16.5}}, "model.elements_cell"),
    ("elements_ring-low", {("model",): {"elements_ring": 1}}, "model.elements_ring"),
    ("elements_ring-high", {("model",): {"elements_ring": 81}}, "model.elements_ring"),
    ("elements_ring-frac", {("model",): {"elements_ring": 2.5}}, "model.elements_ring"),
    ("steps-low", {("model",): {"steps": 19}}, "model.steps"),
    ("steps-high", {("model",): {"steps": 2001}}, "model.steps"),
    ("steps-frac", {("model",): {"steps": 100.5}}, "model.steps"),
    ("imperfection-low", {("model",): {"imperfection": -0.001}}, "model.imperfection"),
    ("imperfection-high", {("model",): {"imperfection": 0.11}}, "model.imperfection"),
    ("pillar_tip-low", {("model",): {"pillar_tip": 2.9}}, "model.pillar_tip"),
    ("pillar_tip-high", {("model",): {"pillar_tip": 12.1}}, "model.pillar_tip"),
    ("max_displacement-zero", {("model",): {"max_displacement_mm": 0}}, "model.max_displacement_mm"),
    ("max_displacement-high", {("model",): {"max_displacement_mm": 180.1}}, "model.max_displacement_mm"),
    ("core_diameter-zero", {("actuator", "core_diameter_mm"): 0}, "actuator.core_diameter_mm"),
    ("core_diameter-high", {("actuator", "core_diameter_mm"): 240.1}, "actuator.core_diameter_mm"),
    ("membrane-low", {("actuator", "membrane_kPa_per_mL"): -0.1}, "actuator.membrane_kPa_per_mL"),
    ("membrane-high", {("actuator", "membrane_kPa_per_mL"): 10000.1}, "actuator.membrane_kPa_per_mL"),
    ("t_over_L-zero", {("design_map",): {"t_over_L": [0, 0.07, 5]}}, "design_map.t_over_L[0]"),
    ("t_over_L-high", {("design_map",): {"t_over_L": [0.05, 0.26, 5]}}, "design_map.t_over_L[1]"),
    ("t_over_L-count0", {("design_map",): {"t_over_L": [0.05, 0.07, 0]}}, "design_map.t_over_L[2]"),
    ("t_over_L-count41", {("design_map",): {"t_over_L": [0.05, 0.07, 41]}}, "design_map.t_over_L[2]"),
    ("h_over_L-zero", {("design_map",): {"h_over_L": [0, 0.4, 5]}}, "design_map.h_over_L[0]"),
    ("h_over_L-high", {("design_map",): {"h_over_L": [0.3, 0.61, 5]}}, "design_map.h_over_L[1]"),
    ("map-elements-low", {("design_map",): {"elements": 1}}, "design_map.elements"),
    ("map-elements-high", {("design_map",): {"elements": 81}}, "design_map.elements"),
    ("map-elements-frac", {("design_map",): {"elements": 9.5}}, "design_map.elements"),
    ("foot-low", {("walker",): {"foot_length_mm": -0.1}}, "walker.foot_length_mm"),
    ("foot-high", {("walker",): {"foot_length_mm": 300.1}}, "walker.foot_length_mm"),
    ("body-zero", {("walker",): {"body_length_mm": 0}}, "walker.body_length_mm"),
    ("body-high", {("walker",): {"body_length_mm": 1000.1}}, "walker.body_length_mm"),
    ("band-zero", {("walker",): {"contact_band_mm": 0}}, "walker.contact_band_mm"),
    ("band-high", {("walker",): {"contact_band_mm": 100.1}}, "walker.contact_band_mm"),
]


def sleeve_with(changes):
    """A copy of BASE_SLEEVE with ``{path: value}`` set."""
    d = copy.deepcopy(BASE_SLEEVE)
    for path, value in changes.items():
        obj = d
        for p in path[:-1]:
            obj = obj[p]
        obj[path[-1]] = copy.deepcopy(value)
    return d


SCENE_COMMANDS = ["solve", "design", "render", "simulate", "build", "stream", "calibrate"]
# multi-megabyte resource bombs: every command reads scenes through the same Scene.load, so these
# run through two commands only (one file output, one folder output) to keep the corpus fast
BIG_COMMANDS = ["solve", "simulate"]
SLEEVE_COMMANDS = ["sleeve"]


class Case:
    """One hostile input. ``make(folder)`` writes it and returns the input path (or None for a literal)."""

    def __init__(self, cid, kind, make, commands=None, out=None, loads=False, names=None):
        self.id, self.kind, self.make, self.out, self.loads = cid, kind, make, out, loads
        self.names = names          # the field the error line must name (with "allowed"), if set
        self.commands = commands or (SCENE_COMMANDS if kind == "scene" else SLEEVE_COMMANDS)

    def __repr__(self):
        return f"Case({self.id})"


def _marker(i):
    return f"\u0000MARK{i}\u0000"


def _substitute(base, path, raw):
    """JSON text of ``base`` with the value at ``path`` replaced by the raw JSON text ``raw``."""
    d = copy.deepcopy(base)
    obj = d
    for p in path[:-1]:
        obj = obj[p]
    key = path[-1]
    if isinstance(obj, list) and key >= len(obj):
        return None
    obj[key] = "@@RAW@@"
    return json.dumps(d).replace('"@@RAW@@"', raw, 1)


def _text_case(cid, kind, text, **kw):
    def make(folder):
        p = os.path.join(folder, "in.json")
        with open(p, "wb") as f:
            f.write(text if isinstance(text, bytes) else text.encode("utf-8", "surrogatepass"))
        return p
    return Case(cid, kind, make, **kw)


def _scene_text(**over):
    d = copy.deepcopy(BASE_SCENE)
    d.update(over)
    return json.dumps(d)


def cases():
    out = []
    # 1. every field of a scene and a sleeve spec replaced by every bad value
    for kind, base, fields in (("scene", BASE_SCENE, SCENE_FIELDS), ("sleeve", BASE_SLEEVE, SLEEVE_FIELDS)):
        for path in fields:
            for vid, raw in BAD_VALUES:
                text = _substitute(base, path, raw)
                if text is not None:
                    out.append(_text_case(f"{kind}-{'.'.join(map(str, path))}-{vid}", kind, text))
    # 1b. every bound of every numeric sleeve field, from outside: exit 2 naming the field and the range
    for cid, changes, field in SLEEVE_BOUNDS:
        out.append(_text_case(f"sleeve-bound-{cid}", "sleeve", json.dumps(sleeve_with(changes)), names=field))
    # 2. whole-text damage: truncated, non-UTF-8, BOM, NUL, empty, deep, huge
    for kind, base in (("scene", BASE_SCENE), ("sleeve", BASE_SLEEVE)):
        text = json.dumps(base)
        for frac in (0.0, 0.1, 0.33, 0.5, 0.77, 0.99):
            out.append(_text_case(f"{kind}-truncated-{frac}", kind, text[:int(frac * len(text))]))
        out.append(_text_case(f"{kind}-latin1", kind, text.replace('"hostile"', '"h\u00e9"').encode("latin-1")))
        out.append(_text_case(f"{kind}-bytes-ff", kind, b"\xff\xfe\x00{" + text.encode()))
        out.append(_text_case(f"{kind}-bom", kind, b"\xef\xbb\xbf" + text.encode()))
        out.append(_text_case(f"{kind}-nul", kind, text.encode() + b"\x00"))
        out.append(_text_case(f"{kind}-deep-list", kind, "[" * 100000 + "]" * 100000))
        out.append(_text_case(f"{kind}-deep-dict", kind, '{"a":' * 5000 + "1" + "}" * 5000))
        out.append(_text_case(f"{kind}-toplevel-int", kind, "9" * 5000))
        out.append(_text_case(f"{kind}-toplevel-nan", kind, "NaN"))
        out.append(_text_case(f"{kind}-binary", kind, bytes(range(256)) * 4))
        out.append(_text_case(f"{kind}-dup-keys", kind, text[:-1] + ', "format": "x"}'))
    # 3. resource bombs (issue 19: size budget before allocation)
    for cid, layout in (("chain-1e7", {"chain": 10 ** 7}), ("chain-1e18", {"chain": 10 ** 18}),
                        ("grid-huge", {"grid": [10 ** 9, 10 ** 9]}), ("rows-1e7", {"rows": ["#" * 10 ** 7]}),
                        ("rows-many", {"rows": ["#"] * 5 * 10 ** 6}),
                        ("cells-far", {"cells": [[0, 0], [0, 1], [10 ** 5, 10 ** 5], [10 ** 5, 10 ** 5 + 1]]}),
                        ("cells-far-connected", {"cells": [[0, 0], [0, 1], [0, 2], [1, 2]] + [[200000, 0]]}),
                        ("cells-1e18", {"cells": [[0, 10 ** 18], [0, 10 ** 18 + 1]]}),
                        ("cells-many", {"cells": [[0, j] for j in range(10 ** 6)] + [[5, 5]]})):
        out.append(_text_case(f"scene-{cid}", "scene", _scene_text(layout=layout, joints=[], axes=[], actuators=[],
                                                                       constraints=[], modules=[]),
                              commands=BIG_COMMANDS))
    out.append(_text_case("scene-k2-huge", "scene", _scene_text(joints=[{"joint": "H0,1", "k2": 1e308}])))
    out.append(_text_case("scene-k2-subnormal", "scene", _scene_text(joints=[{"joint": "H0,1", "k2": 5e-320}])))
    out.append(_text_case("scene-name-huge", "scene", _scene_text(name="x" * 10 ** 6)))
    out.append(_text_case("scene-many-actuators", "scene",
                          _scene_text(actuators=[{"joint": "V0,0", "value": 0.1}] * 200000), commands=BIG_COMMANDS))
    out.append(_text_case("scene-dt-tiny", "scene",
                          _scene_text(dynamics={"model": "sheet", "integrator": {"method": "implicit",
                                                                                 "dt_s": 1e-12}})))
    # 4. special files as input
    def special(cid, maker, kind="scene"):
        out.append(Case(f"{kind}-special-{cid}", kind, maker))

    def mk_dir(folder):
        p = os.path.join(folder, "in.json")
        os.mkdir(p)
        return p

    def mk_loop(folder):
        p = os.path.join(folder, "in.json")
        os.symlink(p, p)
        return p

    def mk_fifo(folder):
        p = os.path.join(folder, "in.json")
        os.mkfifo(p)
        return p

    def mk_missing(folder):
        return os.path.join(folder, "missing.json")

    def mk_dangling(folder):
        p = os.path.join(folder, "in.json")
        os.symlink(os.path.join(folder, "nowhere"), p)
        return p

    def mk_empty(folder):
        p = os.path.join(folder, "in.json")
        open(p, "w").close()
        return p

    for kind in ("scene", "sleeve"):
        for cid, maker in (("dir", mk_dir), ("loop", mk_loop), ("fifo", mk_fifo), ("missing", mk_missing),
                           ("dangling", mk_dangling), ("empty", mk_empty)):
            special(cid, maker, kind)
        special("devnull", lambda folder: "/dev/null", kind)
        special("proc", lambda folder: "/proc/self/status", kind)
        special("under-file", lambda folder: os.path.join(_write(folder, "f", "x"), "in.json"), kind)
    # 5. bad output paths with a valid input (checked before any work)
    for cid, make_out in OUT_CASES:
        for cmd in ("solve", "design", "render", "simulate", "build", "sleeve", "stream", "calibrate"):
            kind = "sleeve" if cmd == "sleeve" else "scene"
            out.append(Case(f"out-{cid}-{cmd}", kind, _valid_input(kind), commands=[cmd], out=make_out))
    return [c for c in out if c.id not in SLOW_VALID]


def _write(folder, name, text):
    p = os.path.join(folder, name)
    with open(p, "w") as f:
        f.write(text)
    return p


def _valid_input(kind):
    def make(folder):
        return _write(folder, "in.json", json.dumps(BASE_SCENE if kind == "scene" else BASE_SLEEVE))
    return make


def _out_existing_dir(folder):
    p = os.path.join(folder, "o")
    os.mkdir(p)
    return p, "dir"


def _out_existing_file(folder):
    return _write(folder, "o", "keep"), "file"


def _out_fifo(folder):
    p = os.path.join(folder, "o")
    os.mkfifo(p)
    return p, "fifo"


def _out_loop(folder):
    p = os.path.join(folder, "o")
    os.symlink(p, p)
    return p, "loop"


OUT_CASES = [
    ("empty", lambda folder: ("", None)),
    ("proc", lambda folder: ("/proc/self/hostile_out", None)),
    ("proc-dir", lambda folder: ("/proc/hostile_out_dir/x", None)),
    ("long-name", lambda folder: (os.path.join(folder, "x" * 300), None)),
    ("long-path", lambda folder: (os.path.join(folder, *(["y" * 200] * 25)), None)),
    ("under-file", lambda folder: (os.path.join(_write(folder, "f", "x"), "o"), "under")),
    ("existing-dir", _out_existing_dir),
    ("existing-file", _out_existing_file),
    ("fifo", _out_fifo),
    ("loop", _out_loop),
    ("nul", lambda folder: (os.path.join(folder, "a\x00b"), None)),
]

# what each command's output path is: replacing an existing entry of that kind is normal
OUT_KIND = {"solve": "file", "design": "file", "render": "file", "simulate": "dir", "build": "dir",
            "sleeve": "dir", "stream": "file", "calibrate": "file"}
# valid inputs that take far too long for the corpus (a sleeve analysis is ~10 s of CPU)
SLOW_VALID = {"sleeve-actuator-obj", "sleeve-bom", "out-existing-dir-sleeve"}


# how each command is called: argv after the command name (IN = input, OUT = output path)
def argv_for(cmd, inp, outdir, out=None):
    o = out if out is not None else None
    if cmd == "solve":
        return ["solve", inp, "--out", o if o is not None else os.path.join(outdir, "r.json")]
    if cmd == "design":
        return ["design", inp, "--out", o if o is not None else os.path.join(outdir, "c.json"), "--quiet"]
    if cmd == "render":
        return ["render", inp, "--out", o if o is not None else os.path.join(outdir, "p.png"), "--size", "200x150"]
    if cmd == "simulate":
        return ["simulate", inp, "--seconds", "0.02", "--out", o if o is not None else os.path.join(outdir, "sim")]
    if cmd == "build":
        return ["build", inp, "--out", o if o is not None else os.path.join(outdir, "b"), "--3mf", "--quiet",
                "--layout", "prusa"]
    if cmd == "stream":
        return ["stream", inp, "--dry-run", "--seconds", "0.05",
                "--report", o if o is not None else os.path.join(outdir, "report.json")]
    if cmd == "calibrate":
        csv = os.path.join(outdir, "..", "angles.csv")
        return ["calibrate", "measured", inp, csv, "--out", o if o is not None else os.path.join(outdir, "t.json")]
    if cmd == "sleeve":
        return ["sleeve", inp, "--out", o if o is not None else os.path.join(outdir, "s"), "--no-plots", "--quiet"]
    raise ValueError(cmd)


class _Hang(BaseException):
    pass


def _alarm(signum, frame):
    raise _Hang()


def _listing(folder):
    out = []
    for root, dirs, files in os.walk(folder):
        for n in dirs + files:
            out.append(os.path.relpath(os.path.join(root, n), folder))
    return sorted(out)


def run_case(case, workdir, timeout_s=20.0, commands=None):
    """Run one case through its commands in this process; return a list of problem strings."""
    from metamaterial_wb.cli import main

    problems = []
    for cmd in commands or case.commands:
        folder = os.path.join(workdir, f"{case.id[:80]}-{cmd}".replace("/", "_"))
        os.makedirs(folder)
        indir = os.path.join(folder, "in")
        outdir = os.path.join(folder, "out")
        cwd = os.path.join(folder, "cwd")
        for d in (indir, outdir, cwd):
            os.mkdir(d)
        _write(folder, "angles.csv", "node,angle_deg\nN0,1,1.0\n")
        inp = case.make(indir)
        out_path, out_kind = (None, None)
        if case.out is not None:
            out_path, out_kind = case.out(outdir)
        before_in = _listing(indir)
        before_out = _listing(outdir)
        argv = argv_for(cmd, inp, outdir, out_path)
        err = io.StringIO()
        outs = io.StringIO()
        old = os.getcwd()
        os.chdir(cwd)
        signal.signal(signal.SIGALRM, _alarm)
        signal.setitimer(signal.ITIMER_REAL, timeout_s)
        rc = None
        try:
            with contextlib.redirect_stderr(err), contextlib.redirect_stdout(outs):
                try:
                    rc = main(argv)
                except SystemExit as exc:
                    rc = exc.code if isinstance(exc.code, int) else 2
        except _Hang:
            problems.append(f"{cmd}: hang (> {timeout_s} s)")
        except BaseException as exc:  # noqa: BLE001 - that is what the corpus looks for
            tb = traceback.format_exc()
            problems.append(f"{cmd}: traceback {type(exc).__name__}: {str(exc)[:200]} | {tb.splitlines()[-3][:200]}")
        finally:
            signal.setitimer(signal.ITIMER_REAL, 0)
            os.chdir(old)
        text = err.getvalue()
        if rc is not None:
            if rc not in (0, 1, 2):
                problems.append(f"{cmd}: exit {rc}: {text[-300:]}")
            if rc == 2:
                lines = [ln for ln in text.splitlines() if ln.strip()]
                if len(lines) != 1 or not lines[0].startswith("error: "):
                    problems.append(f"{cmd}: exit 2 without one error line: {text[-300:]!r}")
                elif "Traceback" in text or "out of memory" in text:
                    problems.append(f"{cmd}: {lines[0][:200]}")
                elif case.names and not (f" {case.names}: " in lines[0] or lines[0].startswith(f"error: {case.names}: ")
                                         ) or case.names and "allowed" not in lines[0]:
                    problems.append(f"{cmd}: the error does not name {case.names} and its range: {lines[0][:200]}")
        if case.names and rc != 2:
            problems.append(f"{cmd}: out-of-range {case.names} not refused (exit {rc})")
        if _listing(cwd):
            problems.append(f"{cmd}: stray files in the current directory: {_listing(cwd)[:5]}")
        if _listing(indir) != before_in:
            problems.append(f"{cmd}: input folder changed: {_listing(indir)[:5]}")
        after = _listing(outdir)
        stray = [n for n in after if os.path.basename(n).startswith((".tmp", ".build-", ".sleeve-", ".tmp-simulate"))]
        if stray:
            problems.append(f"{cmd}: temporary files left: {stray[:5]}")
        if rc == 2 and after != before_out:
            problems.append(f"{cmd}: exit 2 but the output folder changed: {after[:5]}")
        if case.out is not None and rc == 0 and out_kind != OUT_KIND[cmd]:
            problems.append(f"{cmd}: bad output path {out_kind or out_path!r} accepted")
        if rc == 0 and case.out is None and not case.loads and "out-" not in case.id:
            pass  # a hostile input may be valid (e.g. a unicode name); then the command must simply work
    return problems


def main_cli(argv=None):
    import argparse
    import resource
    import tempfile

    ap = argparse.ArgumentParser()
    ap.add_argument("--limit-mb", type=int, default=3000)
    ap.add_argument("--timeout", type=float, default=20.0)
    ap.add_argument("--only", nargs="*", default=None)
    ap.add_argument("--commands", default=None)
    ap.add_argument("--every", type=int, default=1, help="run every N-th case only")
    a = ap.parse_args(argv)
    if a.limit_mb:
        lim = a.limit_mb * 2 ** 20
        resource.setrlimit(resource.RLIMIT_AS, (lim, lim))
    sys.path.insert(0, REPO)
    all_cases = cases()
    sel = [c for c in all_cases if a.only is None or any(o in c.id for o in a.only)][::a.every]
    cmds = a.commands.split(",") if a.commands else None
    n_bad = 0
    import time
    t_start = time.process_time()
    slow = []
    with tempfile.TemporaryDirectory(prefix="hostile-") as work:
        for c in sel:
            t0 = time.perf_counter()
            probs = run_case(c, work, a.timeout, [x for x in c.commands if cmds is None or x in cmds])
            slow.append((time.perf_counter() - t0, c.id))
            if probs:
                n_bad += 1
                print(json.dumps({"case": c.id, "problems": probs}), flush=True)
    slow.sort(reverse=True)
    print(json.dumps({"cases": len(sel), "failing": n_bad, "cpu_s": round(time.process_time() - t_start, 1),
                      "slowest": [[round(t, 2), cid] for t, cid in slow[:8]]}), flush=True)
    return 1 if n_bad else 0


if __name__ == "__main__":
    FREECAD_LIB = "/usr/lib/freecad-python3/lib"
    if os.path.isdir(FREECAD_LIB):
        sys.path.append(FREECAD_LIB)
    sys.path.insert(0, REPO)
    sys.exit(main_cli())
