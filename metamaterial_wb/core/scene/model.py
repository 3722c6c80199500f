"""The :class:`Scene`: validated plain data of one design, with a JSON round trip."""
import copy
import json

from metamaterial_wb.core.errors import SceneError, check_number
from metamaterial_wb.core.scene.names import (DEFAULT_CELL_SIZE_MM, DEFAULT_HINGE, FORMAT, VERSION, _short,
                                                  joint_name, joint_nodes, node_name, parse_joint)
from metamaterial_wb.core.scene.names import plate_side_mm as _plate_side_mm
from metamaterial_wb.core.scene.topology import Topology


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
    def from_dict(cls, data, _fresh=False):
        """Validate ``data`` section by section (core/scene/sections.py) and build a Scene.

        ``data`` is checked by :func:`~metamaterial_wb.core.inputfile.check_tree` and copied first (the
        scene never shares lists or dicts with the caller).

        Parameters
        ----------
        data : dict
            A scene document (the JSON form described in docs/scene-format.md).

        Returns
        -------
        Scene

        Raises
        ------
        SceneError
            On the first invalid field, naming it, the value and the allowed range.
        """
        from metamaterial_wb.core.inputfile import check_tree
        from metamaterial_wb.core.scene.sections import PARSERS

        if not isinstance(data, dict):
            raise SceneError("", f"a scene is a JSON object, got {type(data).__name__}")
        if not _fresh:
            check_tree(data)
            data = copy.deepcopy(data)
        s = cls()
        for parse in PARSERS:
            parse(s, data)
        s.check_fixed_conflicts()
        return s

    @classmethod
    def from_json(cls, text):
        """Parse and validate a scene from JSON text.

        Parameters
        ----------
        text : str
            The scene document as JSON.

        Returns
        -------
        Scene

        Raises
        ------
        SceneError
            If the text is not JSON or the document is not a valid scene.
        """
        from metamaterial_wb.core.inputfile import parse_json

        return cls.from_dict(parse_json(text), _fresh=True)

    @classmethod
    def load(cls, path):
        """Read a scene file; every failure is one SceneError line naming PATH (mostly ending in ``(in PATH)``).

        Parameters
        ----------
        path : str or os.PathLike
            The scene file (``.json``).

        Returns
        -------
        Scene

        Raises
        ------
        SceneError
            If the file cannot be read, is not JSON, or is not a valid scene.
        """
        from metamaterial_wb.core.inputfile import read_json

        from metamaterial_wb.core.scene.sections import check_is_scene

        data = read_json(path, "scene")
        check_is_scene(data, path)          # names the file itself: no "(in PATH)" below
        try:
            return cls.from_dict(data, _fresh=True)
        except SceneError as exc:
            raise SceneError(exc.field, f"{exc.message} (in {path})") from None

    @classmethod
    def grid(cls, rows, cols, **kw):
        """A rectangular scene of ``rows`` x ``cols`` cells.

        Parameters
        ----------
        rows, cols : int
            The grid's size in cells.
        **kw
            Further top-level scene fields (``cell_size_mm``, ``hinge``, ``actuators``, ...).

        Returns
        -------
        Scene

        Raises
        ------
        SceneError
            If a field is invalid.
        """
        d = {"format": FORMAT, "version": VERSION, "layout": {"grid": [rows, cols]}}
        d.update(kw)
        return cls.from_dict(d)

    # -- output ----------------------------------------------------------------------------
    def to_dict(self):
        """The scene as a JSON-ready document (what :meth:`from_dict` reads back).

        Returns
        -------
        dict
        """
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
        """The scene as JSON text (see :meth:`to_dict`).

        Parameters
        ----------
        indent : int, optional
            JSON indentation.

        Returns
        -------
        str
        """
        return json.dumps(self.to_dict(), indent=indent, allow_nan=False) + "\n"

    def copy(self):
        """An independent copy (through the document form, so it is validated again).

        Returns
        -------
        Scene
        """
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

    def _node(self, text, field_name):
        """``"N1,2"`` (or ``"N(1,2)"``) -> ``(1, 2)`` of an existing node, else a SceneError."""
        import re

        m = re.match(r"^\s*[Nn]\s*\(?\s*([0-9]{1,9})\s*,\s*([0-9]{1,9})\s*\)?\s*\Z", text) if isinstance(text, str) else None
        if not m:
            raise SceneError(field_name, f"{_short(text)} is not a node name; write \"N<i>,<j>\"")
        i, j = int(m.group(1)), int(m.group(2))
        if self.topology.node_id(i, j) < 0:
            raise SceneError(field_name, f"node {node_name(i, j)} does not exist in this layout "
                                         f"({self.topology.n_nodes} nodes)")
        return i, j

    @property
    def plate_side_mm(self):
        """Side (mm) of every node plate: ``cell_size_mm - hinge.length_mm`` (the scene-wide gap; a shorter
        per-joint hinge keeps the plates and gets rigid stubs, docs/fabrication.md)."""
        return _plate_side_mm(self.cell_size_mm, self.hinge["length_mm"])

    def hinge_sizes(self, joint):
        """``{"length_mm", "width_mm", "thickness_mm"}`` (floats) of one joint, its overrides applied: what the
        solvers, the B-rep and the 3D view all use for that joint's hinge.

        Parameters
        ----------
        joint : str
            A joint name such as ``"H0,1"``.

        Returns
        -------
        dict
        """
        h = self.joint_hinge(joint)
        return {k: float(h[k]) for k in DEFAULT_HINGE}

    def joint_hinge(self, name):
        """Hinge sizes (mm) of one joint, with its overrides applied.

        Parameters
        ----------
        name : str
            A joint name such as ``"H0,1"``.

        Returns
        -------
        dict
            ``length_mm``, ``width_mm``, ``thickness_mm`` (as stored; :meth:`hinge_sizes` gives floats).
        """
        h = dict(self.hinge)
        ov = self.joint_overrides.get(name, {})
        for k in DEFAULT_HINGE:
            if k in ov:
                h[k] = ov[k]
        return h

    def joint_tilt_deg(self, name):
        """Hinge tilt of a joint (0 for contracting cells): per-joint override, else joint_config.

        Parameters
        ----------
        name : str
            A joint name.

        Returns
        -------
        float
            Degrees.
        """
        ov = self.joint_overrides.get(name, {})
        if "tilt_deg" in ov:
            return ov["tilt_deg"]
        return float(self.joint_config.get(name, {}).get("tilt_deg", 0.0))

    def fixed_items(self):
        """Actuators and constraints as ``(kind, item)`` in file order.

        Returns
        -------
        list of tuple
            ``("actuator" | "constraint", item)``.
        """
        return [("actuator", a) for a in self.actuators] + [("constraint", c) for c in self.constraints]

    def find_item(self, name):
        """The actuator or constraint called ``name``.

        Parameters
        ----------
        name : str
            The item's name.

        Returns
        -------
        tuple
            ``(kind, item)``, or ``(None, None)`` when no item has that name.
        """
        for kind, item in self.fixed_items():
            if item.name == name:
                return kind, item
        return None, None

    def set_value(self, name, value):
        """Change one actuator's or constraint's value by name (validated).

        Parameters
        ----------
        name : str
            The item's name.
        value : float
            The new value, in [-1, 1].

        Raises
        ------
        SceneError
            If no item has that name, the value is out of range, or it conflicts with another fixed value.
        """
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

        Returns
        -------
        dict
            Node -> ``(kind, item)`` that fixes it.

        Raises
        ------
        SceneError
            On two different fixed values on one node.
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


