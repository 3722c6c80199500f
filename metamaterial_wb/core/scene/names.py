"""Constants of the scene format and the names of joints and nodes (seed 000, section 3.2)."""
import re

from metamaterial_wb.core.errors import SceneError

FORMAT = "metamaterial-scene"
VERSION = 1

DEFAULT_CELL_SIZE_MM = 20.0
DEFAULT_HINGE = {"length_mm": 2.0, "width_mm": 0.8, "thickness_mm": 7.0}
MAX_TILT_DEG = 80.0          # the scene format's hinge tilt range [-80, 80] deg (fabrication limit)


def plate_side_mm(cell_size_mm, hinge_length_mm):
    """Side of a node plate (mm): the cell pitch less the hinge gap between two plates.

    The one place this is computed (``Scene.plate_side_mm`` for a scene; the validators for a candidate).

    Parameters
    ----------
    cell_size_mm : float
        Cell pitch.
    hinge_length_mm : float
        Scene-wide hinge length (the gap between neighbouring plates).

    Returns
    -------
    float
    """
    return float(cell_size_mm) - float(hinge_length_mm)

_JOINT_RE = re.compile(r"^\s*([HVhv])\s*\(?\s*(-?[0-9]{1,9})\s*,\s*(-?[0-9]{1,9})\s*\)?\s*\Z")  # ASCII digits
_NAME_RE = re.compile(r"^[A-Za-z_][A-Za-z0-9_.\-]{0,63}\Z")   # \Z: $ also matches before a final newline

KNOWN_KEYS = {"format", "version", "name", "description", "cell_size_mm", "hinge", "layout", "joints",
              "axes", "actuators", "constraints", "modules", "joint_config", "global_deformation",
              "material", "units"}
JOINT_OVERRIDE_KEYS = {"joint", "k1", "k2", "length_mm", "width_mm", "thickness_mm", "tilt_deg"}


def parse_joint(text, field_name="joint"):
    """``"H1,2"`` -> ``("H", 1, 2)``. Accepts ``"H(1,2)"`` and spaces too.

    Parameters
    ----------
    text : str or tuple
        A joint name, or a ``(kind, i, j)`` triple.
    field_name : str, optional
        The field named in errors.

    Returns
    -------
    tuple
        ``(kind, i, j)`` with kind ``"H"`` or ``"V"``.

    Raises
    ------
    SceneError
        If ``text`` is not a joint name.
    """
    if isinstance(text, (tuple, list)) and len(text) == 3:
        kind, i, j = text
        text = f"{kind}{i},{j}"
    if not isinstance(text, str):
        raise SceneError(field_name, f"expected a joint name like \"H0,1\" or \"V2,3\", got {_short(text)}")
    m = _JOINT_RE.match(text)
    if not m:
        raise SceneError(field_name, f"{_short(text)} is not a joint name; write \"H<i>,<j>\" (joins N(i,j)-N(i,j+1)) "
                                     f"or \"V<i>,<j>\" (joins N(i,j)-N(i+1,j))")
    return m.group(1).upper(), int(m.group(2)), int(m.group(3))


def _short(value, n=80):
    """``repr`` of a value, cut to ``n`` characters (error lines stay one readable line)."""
    r = repr(value)
    return r if len(r) <= n else r[:n] + f"... ({len(r)} characters)"


def joint_name(kind, i, j):
    """``("H", 1, 2)`` -> ``"H1,2"``.

    Parameters
    ----------
    kind : str
        ``"H"`` or ``"V"``.
    i, j : int
        Grid indices.

    Returns
    -------
    str
    """
    return f"{kind}{i},{j}"


def node_name(i, j):
    """``(1, 2)`` -> ``"N1,2"``.

    Parameters
    ----------
    i, j : int
        Grid indices.

    Returns
    -------
    str
    """
    return f"N{i},{j}"


def joint_nodes(kind, i, j):
    """The two node keys ``(i, j)`` that a joint joins.

    Parameters
    ----------
    kind : str
        ``"H"`` or ``"V"``.
    i, j : int
        The joint's grid indices.

    Returns
    -------
    tuple of tuple
    """
    return ((i, j), (i, j + 1)) if kind == "H" else ((i, j), (i + 1, j))
