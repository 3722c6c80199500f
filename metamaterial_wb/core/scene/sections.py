"""One parser per section of a scene (``Scene.from_dict`` calls them in order).

Each ``parse_X(scene, data)`` reads ``data["X"]`` (the whole scene dict, already checked by
:func:`metamaterial_wb.core.inputfile.check_tree`: finite numbers, sane depth, valid unicode), validates
it and stores it on ``scene``; an error is a :class:`SceneError` naming the field.
"""
import difflib
import math

from metamaterial_wb.core.errors import SceneError, check_number
from metamaterial_wb.core.scene.items import Actuator, Axis, Constraint
from metamaterial_wb.core.scene.layout import cells_from_layout, validate_layout
from metamaterial_wb.core.scene.names import (_NAME_RE, DEFAULT_CELL_SIZE_MM, DEFAULT_HINGE, FORMAT,
                                                  JOINT_OVERRIDE_KEYS, KNOWN_KEYS, MAX_TILT_DEG, VERSION, _short,
                                                  plate_side_mm)
from metamaterial_wb.core.scene.topology import Topology

CELL_SIZE_RANGE = (1.0, 1000.0)      # mm, closed
FOLD_RANGE = (-180.0, 180.0)         # deg, an axis's fold_deg and joint_config.*.fold_deg (docs/scene-format.md)
# the naming rule of actuators, constraints, axes and modules (names.py's _NAME_RE), as the errors and the doc say it
NAME_RULE = "letters, digits, _ . -; starting with a letter or _; at most 64 characters"
VALUE_RANGE = (-1.0, 1.0)            # an actuator / constraint value
THICKNESS_MAX_MM = 100.0             # hinge thickness (0, 100]; length (0, 0.5 cell), width (0, (cell - length) / 4]
K2_RANGE = (1e-9, 1e9)  # relative stiffness: beyond this the solve loses every digit (issue 19)
MAX_TEXT = 100_000      # characters of name / description
# material.<key>: (default, low, high, low_open, high_open, unit); read by core.limits (the strain limit) and
# core.lattice.geometry (the lattice models), checked here when a scene loads
MATERIAL_FIELDS = {"hinge_strain_limit": (0.5, 0, 5, True, False, ""),
                   "hinge_modulus_MPa": (26.0, 0, 1_000_000, True, False, "MPa"),
                   "hinge_poisson_ratio": (0.45, 0, 0.5, False, True, "")}
# the fields an actuator / constraint / axis reads (docs/scene-format.md); any other field is the user's and kept, unless
# it is a near miss of one of these (NEAR_MISS_CUTOFF): "vlaue", "Value", "profil" silently became value 0 / no motion
ITEM_FIELDS = {"actuators": ("name", "joint", "value", "profile", "servo"),
               "constraints": ("name", "joint", "value"),
               "axes": ("direction", "line", "fold_deg", "name", "from", "to")}
NEAR_MISS_CUTOFF = 0.8    # difflib ratio: "vlaue", "jiont", "sevro" are 0.8; "servo_type", "value_deg", "scale" below
# the "format" of the other documents this program reads or writes: reading one as a scene says what it is
OTHER_DOCUMENTS = {"metamaterial-result": "a result of solve", "metamaterial-result-npz": "a result of solve --npz",
                   "metamaterial-stream-report": "a stream --report file",
                   "metamaterial-design-report": "a design --report file",
                   "metamaterial-inverse-report": "an inverse report (report.json)",
                   "metamaterial-target": "an inverse target", "metamaterial-simulation": "a simulate summary.json",
                   "metamaterial-trajectory": "a simulate trajectory.json",
                   "metamaterial-build-manifest": "a build manifest.json",
                   "metamaterial-sleeve": "a sleeve spec (read by the sleeve command)",
                   "metamaterial-sleeve-summary": "a sleeve summary.json",
                   "metamaterial-calibration": "a calibration table", "metamaterial-fidelity": "a bench fidelity file",
                   "metamaterial-fe-study": "a bench --fe-json-out FE study"}


def module_name_error(field, name):
    """The SceneError for a module name ``name`` that breaks :data:`NAME_RULE` (at load here, at build in
    geometry/modules.py: one message); None when it follows it. Module names name files (``NAME_<name>.step``)."""
    if isinstance(name, str) and _NAME_RE.fullmatch(name):
        return None
    return SceneError(field, f"{_short(name)} is not a valid module name ({NAME_RULE})")


def material_value(material, key):
    """``material[key]`` (its default when absent) checked against :data:`MATERIAL_FIELDS`, as a float."""
    default, lo, hi, lo_open, hi_open, unit = MATERIAL_FIELDS[key]
    return check_number(f"material.{key}", (material or {}).get(key, default), lo, hi, unit, lo_open, hi_open)


def _text(data, key):
    v = data.get(key, "")
    if not isinstance(v, str):
        raise SceneError(key, f"expected text, got {_short(v)}")
    if len(v) > MAX_TEXT:
        raise SceneError(key, f"{len(v)} characters; at most {MAX_TEXT} are allowed")
    return v


def _list(data, key, what):
    v = data.get(key, [])
    if not isinstance(v, list):
        raise SceneError(key, f"expected a list of {what}, got {_short(v)}")
    return v


# the top-level keys some stage reads: KNOWN_KEYS, the sections other stages read from ``scene.extra`` and the two
# refused at the top level (parse_rest); any other top-level key is the user's and kept, unless it is a near miss
TOP_LEVEL_READ = tuple(sorted(KNOWN_KEYS)) + ("fabrication", "dynamics", "belt", "gait")
_PLURALS = {"axis": "axes"}     # singular / plural pairs difflib does not see (ratio 0.75)


def top_level_near_miss(key):
    """The top-level key of :data:`TOP_LEVEL_READ` that ``key`` (not itself one) looks like: letter case, spaces,
    a small misspelling (:func:`near_miss`) or singular / plural; else None."""
    if not isinstance(key, str) or key in TOP_LEVEL_READ:
        return None
    like = near_miss(key, TOP_LEVEL_READ)
    if like is None:
        folded = key.strip().lower()
        like = _PLURALS.get(folded) or next((k for k in TOP_LEVEL_READ if folded in (k + "s", k + "es", k[:-1])),
                                            None)
    return like


def check_top_level(data):
    """Refuse a top-level key that looks like one a stage reads ("Layout", "cell_size", "actuator", "dynamic"):
    it was kept as the user's own key and the default used in its place (a 1 x 1 grid, no actuator, exit 0).
    Runs before every section (after the format: another document is named as such), so the error names the
    misspelling, not what it caused."""
    for key in data:
        like = top_level_near_miss(key)
        if like is None:
            continue
        shown = key if key.isprintable() and len(key) <= 40 else _short(key, 40)
        note = f" (it belongs inside 'dynamics': dynamics.{like})" if like in ("belt", "gait") else ""
        raise SceneError(shown, f"unknown top-level key; it looks like \"{like}\" (letter case, a misspelling or "
                                f"singular / plural){note}; kept as is it would be ignored and the default used; "
                                f"allowed: the scene's keys (docs/scene-format.md) and keys of your own that "
                                f"resemble none of them")


def check_is_scene(data, path):
    """A scene file names its format or at least its layout (docs/scene-format.md); any other JSON object (a
    ``--channels`` file, an older report without "format", ``{}``) was read as a 1 x 1 default scene."""
    if not isinstance(data, dict) or "format" in data or "layout" in data:
        return
    try:
        check_top_level(data)           # {"Layout": ...}: the misspelling, not "not a scene"
    except SceneError as exc:
        raise SceneError(exc.field, f"{exc.message} (in {path})") from None
    if data:
        keys = [_short(k, 40) for k in list(data)[:8]]
        what = f"a JSON object with the keys {', '.join(keys)}" + (f" and {len(data) - 8} more" if len(data) > 8
                                                                       else "")
    else:
        what = "an empty JSON object"
    raise SceneError("format", f"missing, and so is \"layout\": {path} is not a scene ({what}); a scene file has "
                               f"\"format\": \"{FORMAT}\" and a \"layout\" (docs/scene-format.md)")


def parse_header(s, data):
    fmt = data.get("format", FORMAT)
    if fmt != FORMAT:   # first: another document (a sleeve spec's "actuator") is named as such, not a misspelt scene
        what = OTHER_DOCUMENTS.get(fmt) if isinstance(fmt, str) else None
        raise SceneError("format", f"{_short(fmt)} is not a scene" + (f" (it is {what})" if what else "")
                         + f"; expected \"{FORMAT}\"")
    check_top_level(data)
    ver = data.get("version", VERSION)
    if type(ver) is float and ver == VERSION:          # 1.0: the format's version is a whole number
        raise SceneError("version", f"{_short(ver)} is a decimal number; allowed: the whole number {VERSION} "
                                    f"(the version this program reads)")
    if type(ver) is not int or ver != VERSION:         # type(): True is an int too
        raise SceneError("version", f"{_short(ver)} is not supported; this program reads version {VERSION} "
                                    f"(the whole number {VERSION})")
    s.name = _text(data, "name")
    s.description = _text(data, "description")
    s.cell_size_mm = check_number("cell_size_mm", data.get("cell_size_mm", DEFAULT_CELL_SIZE_MM),
                                  *CELL_SIZE_RANGE, "mm")


def parse_hinge(s, data):
    hinge = data.get("hinge", {})
    if not isinstance(hinge, dict):
        raise SceneError("hinge", f"expected an object with length_mm, width_mm, thickness_mm; got {_short(hinge)}")
    for k in hinge:
        if k not in DEFAULT_HINGE:
            raise SceneError(f"hinge.{k}", f"unknown hinge field; allowed: {sorted(DEFAULT_HINGE)}")
    s.hinge = {}
    for k, v in DEFAULT_HINGE.items():
        s.hinge[k] = check_number(f"hinge.{k}", hinge.get(k, v), None, None, "mm")
    check_hinge_sizes("hinge", s.hinge, s.cell_size_mm)


def parse_layout(s, data):
    s.layout = data.get("layout", {"grid": [1, 1]})
    cells = cells_from_layout(s.layout)
    validate_layout(cells)
    s._topology = Topology(cells)
    s._cells = None


def parse_joints(s, data):
    """``joints[]``: per-joint overrides."""
    for k, item in enumerate(_list(data, "joints", "per-joint overrides")):
        f = f"joints[{k}]"
        if not isinstance(item, dict) or "joint" not in item:
            raise SceneError(f, f"expected an object with \"joint\" and override fields, got {_short(item)}")
        for key in item:
            if key not in JOINT_OVERRIDE_KEYS:
                raise SceneError(f"{f}.{key}", f"unknown field; allowed: {sorted(JOINT_OVERRIDE_KEYS)}")
        name = s._joint(item["joint"], f"{f}.joint")
        if name in s.joint_overrides:
            raise SceneError(f"{f}.joint", f"joint {name} has two override entries; merge them into one")
        ov = {}
        if "k1" in item:
            ov["k1"] = check_number(f"{f}.k1 ({name})", item["k1"], 0.0, 1.0)
        if "k2" in item:
            ov["k2"] = check_number(f"{f}.k2 ({name})", item["k2"], *K2_RANGE)
        sizes = {key: item[key] for key in ("length_mm", "width_mm", "thickness_mm") if key in item}
        if sizes:
            for key, v in sizes.items():
                check_number(f"{f}.{key} ({name})", v, None, None, "mm")
            merged = dict(s.hinge)
            merged.update(sizes)
            check_hinge_sizes(f"{f} ({name})", merged, s.cell_size_mm)
            ov.update({key: float(v) for key, v in sizes.items()})
        if "tilt_deg" in item:
            ov["tilt_deg"] = check_number(f"{f}.tilt_deg ({name})", item["tilt_deg"], -MAX_TILT_DEG, MAX_TILT_DEG,
                                          "deg")
        s.joint_overrides[name] = ov


def parse_axes(s, data):
    """``axes[]``: only their form here; the design stage checks them geometrically."""
    for k, a in enumerate(_list(data, "axes", "axes")):
        f = f"axes[{k}]"
        if not isinstance(a, dict):
            raise SceneError(f, f"expected an object with direction, line, fold_deg; got {_short(a)}")
        _check_near_misses(a, f, "axes")       # "fold_dge" was kept and the axis silently folded by 0
        direction = a.get("direction")
        if direction not in ("vertical", "horizontal"):
            raise SceneError(f"{f}.direction", f"{_short(direction)}; allowed: \"vertical\" or \"horizontal\"")
        line = a.get("line")
        if not isinstance(line, int) or isinstance(line, bool):
            raise SceneError(f"{f}.line", f"expected an integer grid line, got {_short(line)}")
        if not -1 <= line <= 4_000_001:
            raise SceneError(f"{f}.line", f"{line} is outside the allowed range [-1, 4000001]")
        for key in ("from", "to"):
            if key in a and (not isinstance(a[key], int) or isinstance(a[key], bool)):
                raise SceneError(f"{f}.{key}", f"expected an integer cell index, got {_short(a[key])}")
        fold = check_number(f"{f}.fold_deg", a.get("fold_deg", 0.0), *FOLD_RANGE, "deg")
        name = _axis_name(a, f)
        extra = {kk: vv for kk, vv in a.items() if kk not in ("direction", "line", "fold_deg", "name")}
        s.axes.append(Axis(direction, line, fold, name, extra))
    _check_axis_names(s.axes)


def _axis_name(a, f):
    """``a["name"]`` (``""`` when absent: the default ``v<line>`` / ``h<line>``), checked by the naming rule of
    actuators and constraints (docs/scene-format.md). A written ``""`` or ``"2"`` is refused: the first silently
    became the default, the second reads as an index in ``--fold 2=...``."""
    if "name" not in a:
        return ""
    name = a["name"]
    if not isinstance(name, str):
        raise SceneError(f"{f}.name", f"expected text, got {_short(name)}")
    if not _NAME_RE.fullmatch(name):      # fullmatch: the pattern's $ also matches before a final newline
        raise SceneError(f"{f}.name", f"{_short(name)} is not a valid name ({NAME_RULE}; leave the name out for "
                                      f"the default v<line> / h<line>)")
    return name


def _check_axis_names(axes):
    """Every axis' name (its own, or its default ``v<line>`` / ``h<line>``) names one axis: ``--fold NAME=...``,
    the design report and inverse targets pick axes by it."""
    seen = {}
    for k, a in enumerate(axes):
        name = a.name or f"{a.direction[0]}{a.line}"
        if name in seen and (a.name or seen[name][1]):      # two unnamed axes on one line: plan_axes says so
            j, j_named = seen[name]
            k_, j_ = (k, j) if a.name else (j, k)      # blame the axis whose written name collides
            what = "the name" if a.name and j_named else "the default name"
            raise SceneError(f"axes[{k_}].name", f"{name!r} is already {what} of axes[{j_}]; allowed: a name no "
                                                 "other axis has (defaults: v<line> / h<line>)")
        seen[name] = (k, bool(a.name))


def parse_fixed(s, data):
    """``actuators[]`` and ``constraints[]`` (names unique across both)."""
    used_names, used_joints = {}, {}
    given = _given_names(data)
    n_max = max(s.topology.n_joints, 1)
    for listname, klass in (("actuators", Actuator), ("constraints", Constraint)):
        items = _list(data, listname, "objects")
        if len(items) + len(used_names) > n_max:
            raise SceneError(listname, f"{len(items) + len(used_names)} actuators and constraints on a layout of "
                                       f"{n_max} joints; at most one per joint is allowed")
        for k, item in enumerate(items):
            f = f"{listname}[{k}]"
            if not isinstance(item, dict):
                raise SceneError(f, f"expected an object with name, joint, value; got {_short(item)}")
            _check_near_misses(item, f, listname)
            if "joint" not in item:
                raise SceneError(f"{f}.joint", "missing: every actuator and constraint sits on a joint")
            joint = s._joint(item["joint"], f"{f}.joint")
            if joint in used_joints:
                raise SceneError(f"{f}.joint", f"{joint} already carries {used_joints[joint]}; at most one actuator or "
                                               "constraint per joint")
            name = item.get("name") if "name" in item else _default_name(given, listname, k, used_names)
            if not isinstance(name, str) or not _NAME_RE.fullmatch(name):
                raise SceneError(f"{f}.name", f"{_short(name)} is not a valid name ({NAME_RULE})")
            if name in used_names:
                raise SceneError(f"{f}.name", f"{name!r} is already used by {used_names[name]}")
            used_names[name] = f
            used_joints[joint] = f"{f} ({name!r})"
            value = check_number(f"{f}.value ({name})", item.get("value", 0.0), *VALUE_RANGE, exact=True)
            if listname == "constraints" and "profile" in item:
                raise SceneError(f"{f}.profile ({name})", "a constraint holds its one value; only actuators move "
                                                         "(give the profile to an actuator on this joint)")
            if listname == "actuators":
                profile = item.get("profile")
                if profile is not None:
                    from metamaterial_wb.core.motion import validate_profile
                    if not isinstance(profile, dict):
                        raise SceneError(f"{f}.profile ({name})", f"expected an object, got {_short(profile)}")
                    validate_profile(profile, f"{f}.profile ({name})")
                extra = {kk: vv for kk, vv in item.items() if kk not in ("name", "joint", "value", "profile")}
                s.actuators.append(Actuator(name, joint, value, profile, extra))
            else:
                extra = {kk: vv for kk, vv in item.items() if kk not in ("name", "joint", "value")}
                s.constraints.append(Constraint(name, joint, value, extra))


def near_miss(key, known):
    """The field of ``known`` that ``key`` (not itself one) looks like: the same but for letter case or surrounding
    spaces, or a close difflib match (ratio >= NEAR_MISS_CUTOFF: one swapped, missing or extra letter); else None."""
    if not isinstance(key, str) or key in known:
        return None
    folded = key.strip().lower()
    if folded in known:
        return folded
    close = difflib.get_close_matches(folded, known, n=1, cutoff=NEAR_MISS_CUTOFF)
    return close[0] if close else None


def _check_near_misses(item, f, listname):
    """An actuator's / constraint's / axis' own fields are kept (user metadata, docs/scene-format.md), but one that
    looks like a field the item reads is a misspelling: kept, the item silently lost its value (0), its motion or
    its fold (0)."""
    allowed = ITEM_FIELDS[listname]
    # a constraint's "profil" is a near miss too (of a field constraints refuse: said so below)
    candidates = allowed + (("profile",) if listname == "constraints" else ())
    for key in item:
        like = near_miss(key, candidates)
        if like is None:
            continue
        note = (" (a constraint holds its one value: only actuators take a profile)"
                if listname == "constraints" and like == "profile" else "")
        shown = key if key.isprintable() and len(key) <= 40 else _short(key, 40)   # one line: "value\n" is one too
        raise SceneError(f"{f}.{shown}",
                         f"unknown field; it looks like \"{like}\" (letter case or a misspelling){note}; allowed: "
                         f"{', '.join(allowed)}, and fields of your own whose names resemble none of these")


def parse_modules(s, data):
    """``modules[]``: their form (an object with a text ``type`` on an existing node or joint); the
    fabrication package (geometry/modules.py) checks the rest when it builds them."""
    modules = _list(data, "modules", "modules")
    if len(modules) > 4 * max(s.topology.n_nodes, 1):
        raise SceneError("modules", f"{len(modules)} modules on {s.topology.n_nodes} nodes; at most "
                                    f"{4 * s.topology.n_nodes} are allowed")
    for k, m in enumerate(modules):
        f = f"modules[{k}]"
        if not isinstance(m, dict):
            raise SceneError(f, f"expected an object with \"type\" and \"node\" or \"joint\", got {_short(m)}")
        typ = m.get("type")
        if not isinstance(typ, str):
            raise SceneError(f"{f}.type", f"expected a module type (text), got {_short(typ)}")
        for key in ("name", "side", "material", "servo", "node", "joint", "housing_node"):
            if key in m and not isinstance(m[key], str):
                raise SceneError(f"{f}.{key}", f"expected text, got {_short(m[key])}")
        bad_name = module_name_error(f"{f}.name", m["name"]) if "name" in m else None
        if bad_name is not None:          # module names name files: checked here, not first at build
            raise bad_name
        if "joint" in m:
            s._joint(m["joint"], f"{f}.joint")
        for key in ("node", "housing_node"):
            if key in m:
                s._node(m[key], f"{f}.{key}")
    s.modules = modules


JOINT_CONFIG_KEYS = ("tilt_deg", "fold_deg", "axis")


def parse_joint_config(s, data):
    jc = data.get("joint_config", {})
    if not isinstance(jc, dict):
        raise SceneError("joint_config", f"expected an object keyed by joint name, got {_short(jc)}")
    written = {}
    for name, cfg in jc.items():
        jn = s._joint(name, f"joint_config.{_short(name, 40)}")
        if jn in written:
            raise SceneError(f"joint_config.{jn}", f"{_short(written[jn], 40)!s} and {_short(name, 40)!s} name the "
                                                   "same joint; give one entry per joint")
        written[jn] = name
        if not isinstance(cfg, dict):
            raise SceneError(f"joint_config.{jn}", f"expected an object like {{\"tilt_deg\": 20}}, got {_short(cfg)}")
        for key in cfg:
            if key not in JOINT_CONFIG_KEYS:
                raise SceneError(f"joint_config.{jn}.{key[:40]}", f"unknown field; allowed: "
                                                                         f"{list(JOINT_CONFIG_KEYS)}")
        if "axis" in cfg and not isinstance(cfg["axis"], str):
            raise SceneError(f"joint_config.{jn}.axis", f"expected text (the axis' name), got {_short(cfg['axis'])}")
        for key in ("tilt_deg", "fold_deg"):
            if key in cfg:
                lo, hi = (-MAX_TILT_DEG, MAX_TILT_DEG) if key == "tilt_deg" else FOLD_RANGE
                check_number(f"joint_config.{jn}.{key}", cfg[key], lo, hi, "deg")
        s.joint_config[jn] = dict(cfg)


def _given_names(data):
    """The names the file gives its actuators and constraints (lists of objects only: the rest is refused later)."""
    return {it.get("name") for key in ("actuators", "constraints") if isinstance(data.get(key), list)
            for it in data[key] if isinstance(it, dict) and isinstance(it.get("name"), str)}


def _default_name(given, listname, k, used):
    """``m<k+1>`` / ``c<k+1>``, or the next number that no item of either list is given (``given``) or has taken
    (``used``): an unnamed item after one named ``m2`` was refused as "'m2' is already used", a name nobody wrote."""
    prefix, n = ("m" if listname == "actuators" else "c"), k + 1
    while f"{prefix}{n}" in given or f"{prefix}{n}" in used:
        n += 1
    return f"{prefix}{n}"


def parse_rest(s, data):
    """``global_deformation``, ``material``, the objects other stages read, and unknown keys (kept)."""
    g = data.get("global_deformation")
    if g is not None:
        s.global_deformation = check_number("global_deformation", g, *VALUE_RANGE, exact=True)
    for key in ("material", "fabrication", "dynamics"):
        if key in data and not isinstance(data[key], dict):
            raise SceneError(key, f"expected an object, got {_short(data[key])}")
    for key in ("belt", "gait"):   # read inside `dynamics` only: at the top level they would be ignored
        if key in data:
            raise SceneError(key, f"belongs inside 'dynamics' (dynamics.{key}); at the top level it would be ignored")
    mat = data.get("material", {})
    for key in mat:
        if key not in MATERIAL_FIELDS:
            raise SceneError(f"material.{key[:40]}", f"unknown field; allowed: {list(MATERIAL_FIELDS)}")
        material_value(mat, key)
    s.material = mat
    s.extra = {k: v for k, v in data.items() if k not in KNOWN_KEYS}
    if "units" in data:
        if data["units"] != "mm":
            raise SceneError("units", f"{_short(data['units'])}; allowed: 'mm' (every length in a scene is in "
                                      "millimetres)")
        s.extra["units"] = data["units"]


PARSERS = (parse_header, parse_hinge, parse_layout, parse_joints, parse_axes, parse_fixed, parse_modules,
           parse_joint_config, parse_rest)


def check_hinge_sizes(field_name, h, cell_size_mm):
    """Check hinge sizes against the cell: 0 < length < cell / 2, 0 < width <= plate side / 4,
    0 < thickness <= THICKNESS_MAX_MM.

    Parameters
    ----------
    field_name : str
        The field named in errors (``"hinge"`` or ``"joints[k] (H0,1)"``).
    h : dict
        ``length_mm``, ``width_mm``, ``thickness_mm``.
    cell_size_mm : float

    Raises
    ------
    SceneError
        Naming the size, its value and the allowed range.
    """
    for k in DEFAULT_HINGE:
        v = h.get(k)
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
            raise SceneError(f"{field_name}.{k}", f"expected a number in mm, got {_short(v)}")
    check_number(f"{field_name}.length_mm", h["length_mm"], 0.0, 0.5 * cell_size_mm, "mm", low_open=True,
                 high_open=True)
    check_number(f"{field_name}.width_mm", h["width_mm"], 0.0, 0.25 * plate_side_mm(cell_size_mm, h["length_mm"]), "mm",
                 low_open=True)
    check_number(f"{field_name}.thickness_mm", h["thickness_mm"], 0.0, THICKNESS_MAX_MM, "mm", low_open=True)
