"""Preferences of the workbench (page: resources/ui/preferences.ui, group Mod/Metamaterial)."""
import FreeCAD

from metamaterial_wb import PREFS_PATH as PATH  # noqa: F401 - one definition (package root)

DEFAULTS = {"PrinterClearance": 0.2, "RigidMaterial": "PLA", "FlexibleMaterial": "TPU",
            "ModuleMaterial": "ABS", "DefaultServo": "SG90", "SerialPort": "/dev/ttyACM0", "AnimationFps": 30}


def params():
    return FreeCAD.ParamGet(PATH)


def get(name):
    p = params()
    d = DEFAULTS[name]
    if isinstance(d, float):
        return p.GetFloat(name, d)
    if isinstance(d, int):
        return p.GetInt(name, d)
    return p.GetString(name, d) or d


def all_values():
    return {k: get(k) for k in DEFAULTS}
