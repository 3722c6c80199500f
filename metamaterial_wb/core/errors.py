"""Error types shared by the whole project.

Every error that reaches a user names the object (scene field, joint, node, module), the value and
what is allowed, so that the CLI can print it as one line and the GUI can show it in a dialog.
"""


class MetamaterialError(ValueError):
    """Base class of every user-facing error (bad input, impossible request)."""


class SceneError(MetamaterialError):
    """A scene file (or scene object) is invalid. ``field`` names where, e.g. ``actuators[1].joint``."""

    def __init__(self, field, message):
        self.field = field
        self.message = message
        super().__init__(f"{field}: {message}" if field else message)


def range_message(value, low, high, unit="", low_open=False, high_open=False):
    """Standard wording: '1.5 is outside the allowed range [-1, 1]'."""
    lo = "(" if low_open else "["
    hi = ")" if high_open else "]"
    u = f" {unit}" if unit else ""
    return f"{value!r}{u} is outside the allowed range {lo}{_bound(low)}, {_bound(high)}{hi}"


def _bound(x):
    """A computed bound as people write it (0.6 * 18 is 10.8, not 10.799999999999999)."""
    if isinstance(x, float) and len(repr(x)) > 12:
        return f"{x:.10g}"
    return x


_ULPS = 4e-16 * 4


def in_range(v, low=None, high=None, low_open=False, high_open=False, exact=False):
    """Whether the finite number ``v`` lies within the bounds (None: unbounded on that side).

    A closed bound computed from other fields (0.6 * 18 = 10.799999999999999) admits the value people write for
    it (10.8): a margin of a few units in the last place, never more. Open bounds are strict.

    Parameters
    ----------
    v : float
        The value.
    low, high : float or None
        The bounds.
    low_open, high_open : bool
        Whether a bound is excluded.
    exact : bool
        A fixed bound (the [-1, 1] of a value): no margin.

    Returns
    -------
    bool
    """
    m = 0.0 if exact else _ULPS
    if low is not None and (v <= low if low_open else v < low - m * abs(low)):
        return False
    return high is None or not (v >= high if high_open else v > high + m * abs(high))


def check_number(field, value, low=None, high=None, unit="", low_open=False, high_open=False, exact=False):
    """Return ``value`` as a float or raise a SceneError naming the field, the value and the range (``exact``: a
    fixed bound, no margin for computed ones: :func:`in_range`)."""
    import math

    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise SceneError(field, f"expected a number, got {value!r}")
    v = float(value)
    if not math.isfinite(v):
        raise SceneError(field, f"{value!r} is not a finite number")
    if not in_range(v, low, high, low_open, high_open, exact):
        lo = "-inf" if low is None else low
        hi = "inf" if high is None else high
        raise SceneError(field, range_message(value, lo, hi, unit, low_open or low is None,
                                              high_open or high is None))
    return v


def check_integer(field, value, low, high, note=""):
    """Return ``value`` if it is an integer in [low, high], else raise a SceneError naming the field, the value and
    the range. Strict: a boolean (True == 1 in Python) and a float (2.0) are refused, never taken as a count."""
    if isinstance(value, bool) or not isinstance(value, int) or not low <= value <= high:
        raise SceneError(field, f"{value!r}; allowed: an integer {low}..{high}" + (f" ({note})" if note else ""))
    return value
