"""Preferences of the workbench (page: resources/ui/preferences.ui, group Mod/Metamaterial)."""
import FreeCAD

from metamaterial_wb import PREFS_PATH as PATH  # noqa: F401 - one definition (package root)
from metamaterial_wb.gui.i18n import QT_TRANSLATE_NOOP, translate

DEFAULTS = {"PrinterClearance": 0.2, "RigidMaterial": "PLA", "FlexibleMaterial": "TPU",
            "ModuleMaterial": "ABS", "DefaultServo": "SG90", "SerialPort": "/dev/ttyACM0", "AnimationFps": 30}

# the integer preferences' allowed range (the preference page's spin box: resources/ui/preferences.ui) and label
RANGES = {"AnimationFps": (1, 120)}
LABELS = {"AnimationFps": QT_TRANSLATE_NOOP("Metamaterial", "Animation frame rate (1/s)")}


def params():
    return FreeCAD.ParamGet(PATH)


def stored(name):
    """The value the user stored for ``name`` in the parameter group, or None when it is not set (never stored,
    removed, or a text field cleared to ''): only such values override a scene's own fabrication section."""
    p = params()
    d = DEFAULTS[name]
    if isinstance(d, float):
        return p.GetFloat(name) if name in p.GetFloats() else None
    if isinstance(d, int):
        return p.GetInt(name) if name in p.GetInts() else None
    text = p.GetString(name) if name in p.GetStrings() else ""
    return text.strip() or None


def get(name):
    """The stored value of ``name``, else its default (a cleared text field is not set: the default)."""
    v = stored(name)
    return DEFAULTS[name] if v is None else v


def all_values():
    return {k: get(k) for k in DEFAULTS}


def checked(name):
    """``get(name)`` within its range ``RANGES[name]`` (the preference page's spin box): a value stored outside it
    (by a macro, an edited user.cfg) is refused, naming the preference, the value and the range, not used or
    clamped.

    Raises
    ------
    MetamaterialError
        Outside the range.
    """
    from metamaterial_wb.core.errors import MetamaterialError
    v = get(name)
    lo, hi = RANGES[name]
    if not lo <= v <= hi:
        raise MetamaterialError(translate("Metamaterial", "Edit > Preferences > Metamaterial > {0} ({1}): {2} is "
                                          "outside the allowed range {3}..{4}; set it there").format(
            translate("Metamaterial", LABELS[name]), name, v, lo, hi))
    return v
