"""Input checks of the FE rung's public entry points (decks, meshes, solvers): one wording for every refusal,
``"<field>: <value>[ unit]; allowed: <range>"``, raised as :class:`~metamaterial_wb.core.errors.SceneError` (a
``ValueError``, which the command line prints as one line). Nothing is clamped or rounded: a count must be an
integer (an integral float such as ``4.0`` is one; ``2.5`` and ``True`` are not), a size a finite number inside
its range.
"""
import math
import numbers

from metamaterial_wb.core.errors import SceneError, in_range

MAX_ELEMENTS = 100_000     # bricks of one FE deck: ~1.3 M DOFs as C3D20, hours of ccx and GBs of memory


def integer(field, value, low, high=None, note=""):
    """``value`` as an ``int`` if it is an integer from ``low`` to ``high`` (``None``: no upper bound), else a
    SceneError naming ``field``, the value and the range (``note`` added in brackets)."""
    ok = (not isinstance(value, bool) and isinstance(value, numbers.Real) and math.isfinite(value)
          and int(value) == value and low <= value and (high is None or value <= high))
    if not ok:
        rng = f"an integer from {low} to {high}" if high is not None else f"an integer >= {low}"
        raise SceneError(field, f"{value!r}; allowed: {rng}" + (f" ({note})" if note else ""))
    return int(value)


def number(field, value, low=None, high=None, unit="", low_open=False, high_open=False, note=""):
    """``value`` as a ``float`` if it is a finite number within the bounds (``None``: unbounded on that side;
    ``*_open``: the bound excluded), else a SceneError naming ``field``, the value (with ``unit``) and the range,
    e.g. ``"h: -0.4 mm; allowed: 0 < h <= 7 mm"``."""
    ok = not isinstance(value, bool) and isinstance(value, numbers.Real)
    v = float(value) if ok else math.nan
    if not (ok and math.isfinite(v) and in_range(v, low, high, low_open, high_open)):
        u = f" {unit}" if unit else ""
        name = field.rsplit(".", 1)[-1]
        if low is not None and high is not None:
            rng = f"{low:g} {'<' if low_open else '<='} {name} {'<' if high_open else '<='} {high:g}{u}"
        elif low is not None:
            rng = f"{name} {'>' if low_open else '>='} {low:g}{u}"
        elif high is not None:
            rng = f"{name} {'<' if high_open else '<='} {high:g}{u}"
        else:
            rng = "a finite number"
        raise SceneError(field, f"{value!r}{u}; allowed: {rng}" + (f" ({note})" if note else ""))
    return v


def poisson(field, value):
    """A Poisson ratio of the decks' materials: from 0 to 0.5, 0.5 excluded (the neo-Hooke bulk modulus
    ``E / (3 (1 - 2 nu))`` is infinite there)."""
    return number(field, value, 0.0, 0.5, high_open=True, note="0.5 would make the solid incompressible")


def element_count(field, value, count, unit="mm", limit=MAX_ELEMENTS):
    """Refuse a mesh setting ``value`` (``field``, e.g. the element size ``h``) that gives more than ``limit``
    elements (``count``, counted on the grid before meshing)."""
    if count > limit:
        raise SceneError(field, f"{value!r} {unit}; allowed: a value giving at most {limit} elements (this one gives "
                                f"{count:.3g}: ccx would need hours and more memory than a shared machine has)")
