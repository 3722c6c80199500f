"""Numbers typed by people (command-line flags, CSV cells, ``--set key=value``), read strictly.

Python's ``float()`` and ``int()`` accept more than a person means by a number: ``1_0`` is 10, Arabic-Indic or
full-width digits are read as their ASCII values, ``inf`` / ``nan`` are numbers and ``5e-320`` is a subnormal the
solvers cannot compute with. A scene file refuses all of these (:mod:`metamaterial_wb.core.inputfile`); the functions
here refuse them in typed text too, naming what was typed and what is allowed. :func:`inward` and :func:`inward_g` write
the other way round: a bound a message prints, rounded so that typed back it is accepted.
"""
import math
import re

from metamaterial_wb.core.errors import SceneError

_FLOAT = re.compile(r"[+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?\Z")
_INT = re.compile(r"[+-]?[0-9]+\Z")
_TINY = 2.2250738585072014e-308            # the smallest normal double
_WHAT = "a decimal number such as 12, -0.5 or 1e-3 (ASCII digits, no '_', no inf/nan)"


def _text(field, text):
    if not isinstance(text, str):
        raise SceneError(field, f"expected text holding a number, got {text!r}")
    return text.strip(" \t\r\n")


def parse_float(field, text):
    """Return the finite, normal (or zero) float written in ``text``, or raise a SceneError naming ``field``.

    Parameters
    ----------
    field : str
        What the text is (a flag such as ``--dt``, a CSV cell such as ``angles.csv row 3 column 2``).
    text : str
        The typed text; surrounding ASCII blanks are ignored.

    Returns
    -------
    float
        ``-0`` reads as 0.0 (never a negative zero).
    """
    t = _text(field, text)
    if not _FLOAT.match(t):
        raise SceneError(field, f"{text!r} is not a number; expected {_WHAT}")
    v = float(t)
    if v == 0.0 and any(c in "123456789" for c in t.split("e")[0].split("E")[0]):   # 1e-400: a non-zero typed
        raise SceneError(field, f"{text!r} is too close to zero to compute with (below about 2.2e-308)")
    if v in (float("inf"), float("-inf")):
        raise SceneError(field, f"{text!r} is beyond the largest number (about 1.8e308)")
    if v != 0.0 and -_TINY < v < _TINY:
        raise SceneError(field, f"{text!r} is subnormal (too close to zero to compute with)")
    return v + 0.0                          # "-0" is zero: no negative zero written back into a scene


def parse_int(field, text):
    """Return the integer written in ``text`` (ASCII digits, optional sign), or raise a SceneError naming ``field``.

    Parameters
    ----------
    field : str
        What the text is.
    text : str
        The typed text; surrounding ASCII blanks are ignored.

    Returns
    -------
    int
    """
    t = _text(field, text)
    if not _INT.match(t) or len(t.lstrip("+-")) > 18:
        raise SceneError(field, f"{text!r} is not a whole number; expected ASCII digits such as 3 or -12 "
                                f"(no '_', no decimals, at most 18 digits)")
    return int(t)


# ----------------------------------------------------------------------------------------------
# numbers printed for people to type back: a bound in a refusal or an advice, rounded inwards
# ----------------------------------------------------------------------------------------------
def inward(x, decimals=2, up=False, slack=1e-9):
    """``x`` as text with ``decimals`` places, rounded inwards: a maximum down (``up``: a minimum, or a need, up),
    so that the printed value typed back lies on the allowed side of ``x`` (within ``slack``): a fold refused
    beyond a maximum of 97.628 deg says 97.62, never 97.63 (which it refuses).

    Parameters
    ----------
    x : float
    decimals : int
    up : bool
        Round up (a minimum) instead of down (a maximum).
    slack : float
        The tolerance of the check the bound is used in (0: a strict check).

    Returns
    -------
    str
    """
    if up:
        t = inward(-x, decimals, slack=slack)
        return t[1:] if t.startswith("-") else ("-" + t if float(t) != 0.0 else t)
    q = 10 ** decimals
    k = math.floor(x * q)
    while (k + 1) / q <= x + slack:      # x * q rounded below an integer it reaches
        k += 1
    while k / q > x + slack:             # ... or above one it does not
        k -= 1
    return f"{k / q:.{decimals}f}"


def inward_g(x, digits=3, up=False, slack=0.0):
    """``x`` as text with ``digits`` significant digits (as ``f"{x:.3g}"`` writes it, never in exponent form),
    rounded inwards like :func:`inward`: a hinge that fits up to a tilt of 32.456 deg says 32.4, never 32.5.

    Parameters
    ----------
    x : float
    digits : int
    up : bool
        Round up (a minimum) instead of down (a maximum).
    slack : float
        The tolerance of the check the bound is used in (0: a strict check).

    Returns
    -------
    str
    """
    if x == 0.0 or not math.isfinite(x):
        return f"{x:g}"
    t = inward(x, max(digits - 1 - math.floor(math.log10(abs(x))), 0), up=up, slack=slack)
    if "." in t:
        t = t.rstrip("0").rstrip(".")
    return "0" if t == "-0" else t
