"""The scene: plain data that describes one metamaterial design (JSON round trip).

Naming follows the seed paper (000, section 3.2):

* cell ``(i, j)``: i = row (grows downwards), j = column. Its four corners are rigid nodes, its four
  edges are hinges (joints). ``R x C`` cells have ``(R+1) x (C+1)`` nodes.
* node ``N(i,j)`` is the top-left corner of cell ``(i, j)``.
* joint ``H(i,j)`` joins ``N(i,j)``-``N(i,j+1)`` (horizontal edge); ``V(i,j)`` joins
  ``N(i,j)``-``N(i+1,j)`` (vertical edge). Written as strings ``"H1,2"`` and ``"V0,3"``.

The format is documented in ``docs/scene-format.md``. Unknown top-level keys are kept (other tools
may add their own) and written back unchanged.
"""
import copy
import json
import math
import re
from dataclasses import dataclass, field

from metamaterial_wb.core.errors import SceneError, check_number

FORMAT = "metamaterial-scene"
VERSION = 1

DEFAULT_CELL_SIZE_MM = 20.0
DEFAULT_HINGE = {"length_mm": 2.0, "width_mm": 0.8, "thickness_mm": 7.0}

_JOINT_RE = re.compile(r"^\s*([HVhv])\s*\(?\s*(-?\d+)\s*,\s*(-?\d+)\s*\)?\s*$")
_NAME_RE = re.compile(r"^[A-Za-z_][A-Za-z0-9_.\-]{0,63}$")

KNOWN_KEYS = {"format", "version", "name", "description", "cell_size_mm", "hinge", "layout", "joints",
              "axes", "actuators", "constraints", "modules", "joint_config", "global_deformation",
              "material", "units"}


# ----------------------------------------------------------------------------------------------
# joint names
# ----------------------------------------------------------------------------------------------
def parse_joint(text, field_name="joint"):
    """``"H1,2"`` -> ``("H", 1, 2)``. Accepts ``"H(1,2)"`` and spaces too."""
    if isinstance(text, (tuple, list)) and len(text) == 3:
        kind, i, j = text
        text = f"{kind}{i},{j}"
    if not isinstance(text, str):
        raise SceneError(field_name, f"expected a joint name like \"H0,1\" or \"V2,3\", got {text!r}")
    m = _JOINT_RE.match(text)
    if not m:
        raise SceneError(field_name, f"{text!r} is not a joint name; write \"H<i>,<j>\" (joins N(i,j)-N(i,j+1)) "
                                     f"or \"V<i>,<j>\" (joins N(i,j)-N(i+1,j))")
    return m.group(1).upper(), int(m.group(2)), int(m.group(3))


def joint_name(kind, i, j):
    return f"{kind}{i},{j}"


def node_name(i, j):
    return f"N{i},{j}"


def joint_nodes(kind, i, j):
    """The two node keys ``(i, j)`` that a joint joins."""
    return ((i, j), (i, j + 1)) if kind == "H" else ((i, j), (i + 1, j))


# ----------------------------------------------------------------------------------------------
# topology
# ----------------------------------------------------------------------------------------------
class Topology:
    """Nodes and joints of a cell layout, with stable indices (vectorised; fine for 10^6 cells).

    ``nodes``: sorted list of ``(i, j)``; ``node_index[(i, j)]`` its index (``node_id(i, j)`` is the
    fast look-up). ``joints``: sorted list of ``(kind, i, j)`` ("H" block first, then "V");
    ``joint_index[name]`` its index (``joint_id(kind, i, j)`` is the fast look-up);
    ``joint_pairs``: int array (n_joints, 2) of node indices. List and dict views are built lazily.
    """

    def __init__(self, cells):
        import numpy as np

        arr = np.asarray(list(cells) if not hasattr(cells, "shape") else cells, dtype=np.int64).reshape(-1, 2)
        if len(arr):
            w = int(arr[:, 1].max()) + 1
            codes = np.unique(arr[:, 0] * w + arr[:, 1])
            arr = np.column_stack([codes // w, codes % w])
        self.cell_array = arr
        self._W = int(arr[:, 1].max()) + 3 if len(arr) else 3
        W = self._W
        enc = lambda i, j: i * W + j  # noqa: E731
        ci, cj = arr[:, 0], arr[:, 1]
        self._node_codes = np.unique(np.concatenate([enc(ci, cj), enc(ci, cj + 1), enc(ci + 1, cj),
                                                     enc(ci + 1, cj + 1)]))
        self._h_codes = np.unique(np.concatenate([enc(ci, cj), enc(ci + 1, cj)]))
        self._v_codes = np.unique(np.concatenate([enc(ci, cj), enc(ci, cj + 1)]))
        self.n_nodes = int(self._node_codes.size)
        self.n_joints = int(self._h_codes.size + self._v_codes.size)
        hi, hj = self._h_codes // W, self._h_codes % W
        vi, vj = self._v_codes // W, self._v_codes % W
        a = np.concatenate([np.searchsorted(self._node_codes, enc(hi, hj)),
                            np.searchsorted(self._node_codes, enc(vi, vj))])
        b = np.concatenate([np.searchsorted(self._node_codes, enc(hi, hj + 1)),
                            np.searchsorted(self._node_codes, enc(vi + 1, vj))])
        self.joint_pairs = np.column_stack([a, b]).astype(np.int64)
        self._joint_ij = np.column_stack([np.concatenate([hi, vi]), np.concatenate([hj, vj])])
        self.n_h = int(self._h_codes.size)
        self._lazy = {}

    # -- fast look-ups -----------------------------------------------------------------------
    def node_id(self, i, j):
        """Index of node (i, j), or -1."""
        import numpy as np
        code = i * self._W + j
        if j < 0 or j >= self._W or i < 0:
            return -1
        k = int(np.searchsorted(self._node_codes, code))
        return k if k < self.n_nodes and self._node_codes[k] == code else -1

    def joint_id(self, kind, i, j):
        """Index of joint (kind, i, j), or -1."""
        import numpy as np
        if j < 0 or j >= self._W or i < 0:
            return -1
        codes, off = (self._h_codes, 0) if kind == "H" else (self._v_codes, self.n_h)
        code = i * self._W + j
        k = int(np.searchsorted(codes, code))
        return off + k if k < codes.size and codes[k] == code else -1

    def has_joint(self, name):
        kind, i, j = parse_joint(name)
        return self.joint_id(kind, i, j) >= 0

    def node_ij(self):
        import numpy as np
        return np.column_stack([self._node_codes // self._W, self._node_codes % self._W])

    def joint_ij(self):
        """(n_joints, 2) array of the (i, j) of every joint (kinds: first ``n_h`` are H)."""
        return self._joint_ij

    def joint_kinds(self):
        import numpy as np
        return np.array(["H"] * self.n_h + ["V"] * (self.n_joints - self.n_h))

    # -- lazy list / dict views ----------------------------------------------------------------
    def _get(self, key, fn):
        if key not in self._lazy:
            self._lazy[key] = fn()
        return self._lazy[key]

    @property
    def cells(self):
        return self._get("cells", lambda: [tuple(map(int, c)) for c in self.cell_array])

    @property
    def cellset(self):
        return self._get("cellset", lambda: set(self.cells))

    @property
    def nodes(self):
        return self._get("nodes", lambda: [tuple(map(int, n)) for n in self.node_ij()])

    @property
    def node_index(self):
        return self._get("node_index", lambda: {n: k for k, n in enumerate(self.nodes)})

    @property
    def joints(self):
        def build():
            ij = self._joint_ij.tolist()
            return [("H" if k < self.n_h else "V", i, j) for k, (i, j) in enumerate(ij)]
        return self._get("joints", build)

    @property
    def joint_names(self):
        return self._get("joint_names", lambda: [joint_name(*t) for t in self.joints])

    @property
    def joint_index(self):
        return self._get("joint_index", lambda: {name: k for k, name in enumerate(self.joint_names)})

    def joint_cells(self, kind, i, j):
        """The (one or two) cells that a joint borders."""
        if kind == "H":
            cand = [(i - 1, j), (i, j)]
        else:
            cand = [(i, j - 1), (i, j)]
        return [c for c in cand if c in self.cellset]


def validate_layout(cells, field_name="layout"):
    """The seed's layout rules (section 4.1), each with its own error.

    * at least one cell, no duplicates, integer non-negative positions;
    * every cell shares an edge with another one (when there are several);
    * the cells form one connected structure;
    * no closed contour of cells encloses a hole (the empty cells all reach the outside; a contour
      closed through a shared corner node counts as closed).
    """
    import numpy as np
    from scipy import ndimage

    if cells is None or len(cells) == 0:
        raise SceneError(field_name, "the layout has no cells; give at least one cell")
    if not hasattr(cells, "shape"):
        for k, c in enumerate(cells):
            if (not isinstance(c, (list, tuple)) or len(c) != 2
                    or not all(isinstance(x, int) and not isinstance(x, bool) for x in c)):
                raise SceneError(f"{field_name}.cells[{k}]", f"expected [row, column] integers, got {c!r}")
    arr = np.asarray(cells, dtype=np.int64).reshape(-1, 2)
    neg = np.flatnonzero((arr < 0).any(axis=1))
    if neg.size:
        k = int(neg[0])
        raise SceneError(f"{field_name}.cells[{k}]", f"{arr[k].tolist()!r} has a negative index; rows and "
                                                     f"columns start at 0")
    w = int(arr[:, 1].max()) + 1
    uniq, counts = np.unique(arr[:, 0] * w + arr[:, 1], return_counts=True)
    if (counts > 1).any():
        code = uniq[counts > 1][0]
        dup = np.array([code // w, code % w])
        k = int(np.flatnonzero((arr == dup).all(axis=1))[1])
        raise SceneError(f"{field_name}.cells[{k}]", f"cell {dup.tolist()!r} is listed twice")
    if len(arr) == 1:
        return
    r0, c0 = arr.min(axis=0) - 1
    r1, c1 = arr.max(axis=0) + 1
    img = np.zeros((r1 - r0 + 1, c1 - c0 + 1), dtype=bool)
    img[arr[:, 0] - r0, arr[:, 1] - c0] = True
    nb = np.zeros_like(img)
    nb[1:, :] |= img[:-1, :]
    nb[:-1, :] |= img[1:, :]
    nb[:, 1:] |= img[:, :-1]
    nb[:, :-1] |= img[:, 1:]
    lonely = np.argwhere(img & ~nb)
    if len(lonely):
        c = (lonely[0] + (r0, c0)).tolist()
        raise SceneError(field_name, f"cell {c} shares no edge with another cell; every cell must have at least "
                                     f"one edge neighbour ({len(lonely)} such cell(s))")
    four = ndimage.generate_binary_structure(2, 1)
    labels, n = ndimage.label(img, structure=four)
    if n > 1:
        start = arr[np.lexsort((arr[:, 1], arr[:, 0]))[0]]
        lab0 = labels[start[0] - r0, start[1] - c0]
        other = np.argwhere(img & (labels != lab0))
        other = other[np.lexsort((other[:, 1], other[:, 0]))][0] + (r0, c0)
        raise SceneError(field_name, f"the layout is not connected: cell {other.tolist()} cannot be reached from "
                                     f"cell {start.tolist()} through shared edges")
    elabels, en = ndimage.label(~img, structure=four)
    outside = elabels[0, 0]
    holes = np.argwhere((~img) & (elabels != outside))
    if len(holes):
        h = (holes[0] + (r0, c0)).tolist()
        raise SceneError(field_name, f"the cells form a closed contour around the empty cell {h}; a layout may not "
                                     f"enclose a hole ({len(holes)} enclosed empty cell(s))")


def cells_from_layout(layout, field_name="layout"):
    """Expand the ``layout`` object to a list of ``(i, j)`` cells (not yet validated)."""
    if not isinstance(layout, dict):
        raise SceneError(field_name, f"expected an object with \"grid\", \"chain\" or \"cells\", got {layout!r}")
    keys = [k for k in ("grid", "chain", "cells", "rows") if k in layout]
    if len(keys) != 1:
        raise SceneError(field_name, f"give exactly one of \"grid\": [rows, columns], \"chain\": n, \"cells\": "
                                     f"[[i, j], ...] or \"rows\": [\"##.\", ...]; got keys {sorted(layout)}")
    key = keys[0]
    val = layout[key]
    if key == "grid":
        if (not isinstance(val, (list, tuple)) or len(val) != 2
                or not all(isinstance(x, int) and not isinstance(x, bool) for x in val)):
            raise SceneError(f"{field_name}.grid", f"expected [rows, columns] (cell counts), got {val!r}")
        r, c = val
        if r < 1 or c < 1:
            raise SceneError(f"{field_name}.grid", f"{list(val)!r}: both cell counts must be >= 1")
        if r * c > 4_000_000:
            raise SceneError(f"{field_name}.grid", f"{list(val)!r} has {r * c} cells; at most 4000000 are allowed")
        import numpy as np
        ii, jj = np.meshgrid(np.arange(r), np.arange(c), indexing="ij")
        return np.column_stack([ii.ravel(), jj.ravel()])
    if key == "chain":
        if not isinstance(val, int) or isinstance(val, bool) or val < 1:
            raise SceneError(f"{field_name}.chain", f"expected a cell count >= 1, got {val!r}")
        import numpy as np
        return np.column_stack([np.zeros(val, dtype=np.int64), np.arange(val)])
    if key == "rows":
        if not isinstance(val, list) or not all(isinstance(s, str) for s in val):
            raise SceneError(f"{field_name}.rows", "expected a list of strings, '#' for a cell and '.' for none")
        cells = []
        for i, s in enumerate(val):
            for j, ch in enumerate(s):
                if ch in "#Xx1":
                    cells.append((i, j))
                elif ch not in ". 0-":
                    raise SceneError(f"{field_name}.rows[{i}]", f"character {ch!r} at column {j}; use '#' for a cell "
                                                               f"and '.' for an empty place")
        return cells
    if not isinstance(val, list):
        raise SceneError(f"{field_name}.cells", f"expected a list of [row, column] pairs, got {val!r}")
    return [tuple(c) if isinstance(c, (list, tuple)) else c for c in val]


# ----------------------------------------------------------------------------------------------
# scene items
# ----------------------------------------------------------------------------------------------
@dataclass
class Actuator:
    """A servo across a joint: fixes D of both nodes of the joint to ``value`` in [-1, 1]."""
    name: str
    joint: str
    value: float = 0.0
    profile: dict = None
    extra: dict = field(default_factory=dict)

    def to_dict(self):
        d = {"name": self.name, "joint": self.joint, "value": self.value}
        if self.profile is not None:
            d["profile"] = copy.deepcopy(self.profile)
        d.update(copy.deepcopy(self.extra))
        return d


@dataclass
class Constraint:
    """An angular constraint (clip) on a joint: fixes D of both nodes of the joint to ``value``."""
    name: str
    joint: str
    value: float = 0.0
    extra: dict = field(default_factory=dict)

    def to_dict(self):
        d = {"name": self.name, "joint": self.joint, "value": self.value}
        d.update(copy.deepcopy(self.extra))
        return d


@dataclass
class Axis:
    """A rotary axis: a straight grid line through the whole structure (design stage, seed 4.1).

    ``direction`` "vertical": runs down cell column ``line`` and crosses every joint ``H(i, line)``;
    "horizontal": runs along cell row ``line`` and crosses every joint ``V(line, j)``.
    ``fold_deg``: the fold about this axis in the fully deformed state (every D = 1).
    """
    direction: str
    line: int
    fold_deg: float = 0.0
    name: str = ""
    extra: dict = field(default_factory=dict)

    def to_dict(self):
        d = {"direction": self.direction, "line": self.line, "fold_deg": self.fold_deg}
        if self.name:
            d["name"] = self.name
        d.update(copy.deepcopy(self.extra))
        return d


JOINT_OVERRIDE_KEYS = {"joint", "k1", "k2", "length_mm", "width_mm", "thickness_mm", "tilt_deg"}


class Scene:
    """A validated scene. Build it with :meth:`from_dict`, :meth:`load` or :meth:`from_json`."""

    def __init__(self):
        self.name = ""
        self.description = ""
        self.cell_size_mm = DEFAULT_CELL_SIZE_MM
        self.hinge = dict(DEFAULT_HINGE)
        self.layout = {"grid": [1, 1]}
        self._cells = None
        self.joint_overrides = {}      # joint name -> dict of override fields (without "joint")
        self.axes = []
        self.actuators = []
        self.constraints = []
        self.modules = []
        self.joint_config = {}         # joint name -> {"tilt_deg": ...} (design stage output)
        self.global_deformation = None
        self.material = {}
        self.extra = {}
        self._topology = None

    # -- construction ----------------------------------------------------------------------
    @classmethod
    def from_dict(cls, data):
        if not isinstance(data, dict):
            raise SceneError("", f"a scene is a JSON object, got {type(data).__name__}")
        data = copy.deepcopy(data)
        s = cls()
        fmt = data.get("format", FORMAT)
        if fmt != FORMAT:
            raise SceneError("format", f"{fmt!r} is not a scene; expected \"{FORMAT}\"")
        ver = data.get("version", VERSION)
        if ver != VERSION:
            raise SceneError("version", f"{ver!r} is not supported; this program reads version {VERSION}")
        s.name = str(data.get("name", ""))
        s.description = str(data.get("description", ""))
        s.cell_size_mm = check_number("cell_size_mm", data.get("cell_size_mm", DEFAULT_CELL_SIZE_MM),
                                      1.0, 1000.0, "mm")
        hinge = data.get("hinge", {})
        if not isinstance(hinge, dict):
            raise SceneError("hinge", f"expected an object with length_mm, width_mm, thickness_mm; got {hinge!r}")
        for k in hinge:
            if k not in DEFAULT_HINGE:
                raise SceneError(f"hinge.{k}", f"unknown hinge field; allowed: {sorted(DEFAULT_HINGE)}")
        s.hinge = {k: float(hinge.get(k, v)) if isinstance(hinge.get(k, v), (int, float))
                   and not isinstance(hinge.get(k, v), bool) else hinge.get(k, v)
                   for k, v in DEFAULT_HINGE.items()}
        _check_hinge_sizes("hinge", s.hinge, s.cell_size_mm)
        s.layout = data.get("layout", {"grid": [1, 1]})
        cells = cells_from_layout(s.layout)
        validate_layout(cells if hasattr(cells, "shape") else [list(c) if isinstance(c, tuple) else c
                                                                for c in cells])
        s._topology = Topology(cells)
        s._cells = None

        # per-joint overrides
        joints = data.get("joints", [])
        if not isinstance(joints, list):
            raise SceneError("joints", f"expected a list of per-joint overrides, got {joints!r}")
        for k, item in enumerate(joints):
            f = f"joints[{k}]"
            if not isinstance(item, dict) or "joint" not in item:
                raise SceneError(f, f"expected an object with \"joint\" and override fields, got {item!r}")
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
                ov["k2"] = check_number(f"{f}.k2 ({name})", item["k2"], 0.0, None, low_open=True)
            sizes = {key: item[key] for key in ("length_mm", "width_mm", "thickness_mm") if key in item}
            if sizes:
                merged = dict(s.hinge)
                merged.update(sizes)
                _check_hinge_sizes(f"{f} ({name})", merged, s.cell_size_mm)
                ov.update({key: float(v) for key, v in sizes.items()})
            if "tilt_deg" in item:
                ov["tilt_deg"] = check_number(f"{f}.tilt_deg ({name})", item["tilt_deg"], -80.0, 80.0, "deg")
            s.joint_overrides[name] = ov

        # axes (checked geometrically by the design stage; here only their form)
        axes = data.get("axes", [])
        if not isinstance(axes, list):
            raise SceneError("axes", f"expected a list of axes, got {axes!r}")
        for k, a in enumerate(axes):
            f = f"axes[{k}]"
            if not isinstance(a, dict):
                raise SceneError(f, f"expected an object with direction, line, fold_deg; got {a!r}")
            direction = a.get("direction")
            if direction not in ("vertical", "horizontal"):
                raise SceneError(f"{f}.direction", f"{direction!r}; allowed: \"vertical\" or \"horizontal\"")
            line = a.get("line")
            if not isinstance(line, int) or isinstance(line, bool):
                raise SceneError(f"{f}.line", f"expected an integer grid line, got {line!r}")
            fold = check_number(f"{f}.fold_deg", a.get("fold_deg", 0.0), -180.0, 180.0, "deg")
            extra = {kk: vv for kk, vv in a.items() if kk not in ("direction", "line", "fold_deg", "name")}
            s.axes.append(Axis(direction, line, fold, str(a.get("name", "")), extra))

        # actuators and constraints
        used_names = {}
        for listname, klass in (("actuators", Actuator), ("constraints", Constraint)):
            items = data.get(listname, [])
            if not isinstance(items, list):
                raise SceneError(listname, f"expected a list, got {items!r}")
            for k, item in enumerate(items):
                f = f"{listname}[{k}]"
                if not isinstance(item, dict):
                    raise SceneError(f, f"expected an object with name, joint, value; got {item!r}")
                if "joint" not in item:
                    raise SceneError(f"{f}.joint", "missing: every actuator and constraint sits on a joint")
                joint = s._joint(item["joint"], f"{f}.joint")
                default_name = ("m" if listname == "actuators" else "c") + str(k + 1)
                name = item.get("name", default_name)
                if not isinstance(name, str) or not _NAME_RE.match(name):
                    raise SceneError(f"{f}.name", f"{name!r} is not a valid name (letters, digits, _ . -; "
                                                  f"starting with a letter or _)")
                if name in used_names:
                    raise SceneError(f"{f}.name", f"{name!r} is already used by {used_names[name]}")
                used_names[name] = f
                value = check_number(f"{f}.value ({name})", item.get("value", 0.0), -1.0, 1.0)
                if listname == "actuators":
                    profile = item.get("profile")
                    if profile is not None:
                        from metamaterial_wb.core.motion import validate_profile
                        validate_profile(profile, f"{f}.profile ({name})")
                    extra = {kk: vv for kk, vv in item.items() if kk not in ("name", "joint", "value", "profile")}
                    s.actuators.append(Actuator(name, joint, value, profile, extra))
                else:
                    extra = {kk: vv for kk, vv in item.items() if kk not in ("name", "joint", "value")}
                    s.constraints.append(Constraint(name, joint, value, extra))

        modules = data.get("modules", [])
        if not isinstance(modules, list):
            raise SceneError("modules", f"expected a list of modules, got {modules!r}")
        s.modules = modules

        jc = data.get("joint_config", {})
        if not isinstance(jc, dict):
            raise SceneError("joint_config", f"expected an object keyed by joint name, got {jc!r}")
        for name, cfg in jc.items():
            jn = s._joint(name, f"joint_config.{name}")
            if not isinstance(cfg, dict):
                raise SceneError(f"joint_config.{name}", f"expected an object like {{\"tilt_deg\": 20}}, got {cfg!r}")
            if "tilt_deg" in cfg:
                check_number(f"joint_config.{name}.tilt_deg", cfg["tilt_deg"], -80.0, 80.0, "deg")
            s.joint_config[jn] = dict(cfg)

        g = data.get("global_deformation")
        if g is not None:
            s.global_deformation = check_number("global_deformation", g, -1.0, 1.0)
        mat = data.get("material", {})
        if not isinstance(mat, dict):
            raise SceneError("material", f"expected an object, got {mat!r}")
        s.material = mat
        s.extra = {k: v for k, v in data.items() if k not in KNOWN_KEYS}
        s.check_fixed_conflicts()
        return s

    @classmethod
    def from_json(cls, text):
        try:
            data = json.loads(text)
        except json.JSONDecodeError as exc:
            raise SceneError("", f"not valid JSON: {exc.msg} at line {exc.lineno} column {exc.colno}") from None
        return cls.from_dict(data)

    @classmethod
    def load(cls, path):
        with open(path, encoding="utf-8") as f:
            text = f.read()
        try:
            return cls.from_json(text)
        except SceneError as exc:
            raise SceneError(exc.field, f"{exc.message} (in {path})") from None

    @classmethod
    def grid(cls, rows, cols, **kw):
        d = {"format": FORMAT, "version": VERSION, "layout": {"grid": [rows, cols]}}
        d.update(kw)
        return cls.from_dict(d)

    # -- output ----------------------------------------------------------------------------
    def to_dict(self):
        d = {"format": FORMAT, "version": VERSION}
        if self.name:
            d["name"] = self.name
        if self.description:
            d["description"] = self.description
        d["cell_size_mm"] = self.cell_size_mm
        d["hinge"] = dict(self.hinge)
        d["layout"] = copy.deepcopy(self.layout)
        if self.joint_overrides:
            d["joints"] = [dict({"joint": k}, **v) for k, v in sorted(self.joint_overrides.items())]
        if self.axes:
            d["axes"] = [a.to_dict() for a in self.axes]
        d["actuators"] = [a.to_dict() for a in self.actuators]
        d["constraints"] = [c.to_dict() for c in self.constraints]
        if self.modules:
            d["modules"] = copy.deepcopy(self.modules)
        if self.joint_config:
            d["joint_config"] = copy.deepcopy(self.joint_config)
        if self.global_deformation is not None:
            d["global_deformation"] = self.global_deformation
        if self.material:
            d["material"] = copy.deepcopy(self.material)
        d.update(copy.deepcopy(self.extra))
        return d

    def to_json(self, indent=1):
        return json.dumps(self.to_dict(), indent=indent, allow_nan=False) + "\n"

    def copy(self):
        return Scene.from_dict(self.to_dict())

    # -- derived ---------------------------------------------------------------------------
    @property
    def topology(self):
        if self._topology is None:
            self._topology = Topology([(0, 0)])
        return self._topology

    @property
    def cells(self):
        """Sorted list of ``(i, j)`` cells."""
        return self.topology.cells

    def _joint(self, text, field_name):
        kind, i, j = parse_joint(text, field_name)
        name = joint_name(kind, i, j)
        topo = self.topology
        if topo.joint_id(kind, i, j) < 0:
            ca = topo.cell_array
            raise SceneError(field_name, f"joint {name} does not exist in this layout "
                                         f"({len(ca)} cells, {topo.n_joints} joints; "
                                         f"cell rows {ca[:, 0].min()}..{ca[:, 0].max()}, "
                                         f"cell columns {ca[:, 1].min()}..{ca[:, 1].max()})")
        return name

    def joint_hinge(self, name):
        """Hinge sizes (mm) of one joint, with its overrides applied."""
        h = dict(self.hinge)
        ov = self.joint_overrides.get(name, {})
        for k in DEFAULT_HINGE:
            if k in ov:
                h[k] = ov[k]
        return h

    def joint_tilt_deg(self, name):
        """Hinge tilt of a joint (0 for contracting cells): per-joint override, else joint_config."""
        ov = self.joint_overrides.get(name, {})
        if "tilt_deg" in ov:
            return ov["tilt_deg"]
        return float(self.joint_config.get(name, {}).get("tilt_deg", 0.0))

    def fixed_items(self):
        """Actuators and constraints as ``(kind, item)`` in file order."""
        return [("actuator", a) for a in self.actuators] + [("constraint", c) for c in self.constraints]

    def find_item(self, name):
        for kind, item in self.fixed_items():
            if item.name == name:
                return kind, item
        return None, None

    def set_value(self, name, value):
        """Change one actuator's or constraint's value by name (validated)."""
        kind, item = self.find_item(name)
        if item is None:
            names = [it.name for _, it in self.fixed_items()]
            raise SceneError(f"--set {name}", f"no actuator or constraint is called {name!r}; "
                                              f"the scene has {names if names else 'none'}")
        item.value = check_number(f"--set {name}", value, -1.0, 1.0)
        self.check_fixed_conflicts()

    def check_fixed_conflicts(self):
        """Two fixed values on one node are an error that names both items and the node.

        Two items that share a node with the *same* value are allowed.
        """
        owner = {}
        for kind, item in self.fixed_items():
            kind_, i, j = parse_joint(item.joint)
            for n in joint_nodes(kind_, i, j):
                if n in owner:
                    other_kind, other = owner[n]
                    if other.value != item.value:
                        raise SceneError(
                            f"{kind}s.{item.name}",
                            f"{kind} {item.name!r} on joint {item.joint} sets node {node_name(*n)} to "
                            f"{item.value}, but {other_kind} {other.name!r} on joint {other.joint} sets it to "
                            f"{other.value}; a node can take only one fixed value")
                else:
                    owner[n] = (kind, item)
        return owner


def _check_hinge_sizes(field_name, h, cell_size_mm):
    for k in DEFAULT_HINGE:
        v = h.get(k)
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
            raise SceneError(f"{field_name}.{k}", f"expected a number in mm, got {v!r}")
    check_number(f"{field_name}.length_mm", h["length_mm"], 0.0, 0.5 * cell_size_mm, "mm", low_open=True,
                 high_open=True)
    check_number(f"{field_name}.width_mm", h["width_mm"], 0.0, 0.25 * (cell_size_mm - h["length_mm"]), "mm",
                 low_open=True)
    check_number(f"{field_name}.thickness_mm", h["thickness_mm"], 0.0, 100.0, "mm", low_open=True)
