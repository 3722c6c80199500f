"""FreeCAD access for the geometry and export layers (one place that knows the library path).

FreeCAD must be imported before Part (importing Part first makes Part.read segfault in 0.20).
"""
import os
import sys

FREECAD_LIB = "/usr/lib/freecad-python3/lib"


def freecad():
    """``(FreeCAD, Part)``; raises MetamaterialError with an install hint if FreeCAD is missing."""
    try:
        import FreeCAD  # noqa: F401
    except ImportError:
        if os.path.isdir(FREECAD_LIB) and FREECAD_LIB not in sys.path:
            sys.path.append(FREECAD_LIB)
        try:
            import FreeCAD  # noqa: F401
        except ImportError:
            from metamaterial_wb.core.errors import MetamaterialError
            raise MetamaterialError("building geometry needs FreeCAD (Debian: apt-get install freecad-python3); "
                                    f"its Python library was not found in {FREECAD_LIB}") from None
    import FreeCAD
    import Part
    return FreeCAD, Part


def kernel_error(exc):
    """The reason of a geometry-kernel failure (FreeCAD's ``Base.FreeCADError``, ``Part.OCCError`` and its kinds, or
    the ``RuntimeError`` carrying FreeCAD's exception dictionary, e.g. "Multi cut failed"), else None: any other
    exception is a programming error and must stay visible."""
    payload = exc.args[0] if getattr(exc, "args", None) else None
    fc_dict = isinstance(payload, dict) and ("sErrMsg" in payload or "sclassname" in payload)
    base = getattr(sys.modules.get("FreeCAD"), "Base", None)
    kinds = tuple(k for k in (getattr(base, "FreeCADError", None),
                              getattr(sys.modules.get("Part"), "OCCError", None)) if isinstance(k, type))
    if not ((type(exc) is RuntimeError and fc_dict) or (kinds and isinstance(exc, kinds))):
        return None
    if fc_dict:
        why = payload.get("sErrMsg") or payload.get("swhat") or payload.get("sclassname")
    else:
        why = str(exc)
    return " ".join(str(why).split()) or type(exc).__name__


def placement(x=0.0, y=0.0, z=0.0, angle_deg=0.0, axis=(0.0, 0.0, 1.0)):
    App, _ = freecad()
    return App.Placement(App.Vector(x, y, z), App.Rotation(App.Vector(*axis), angle_deg))


def matrix4(pl):
    """A FreeCAD Placement as a 4x4 numpy matrix."""
    import numpy as np

    m = pl.toMatrix()
    return np.array([[m.A11, m.A12, m.A13, m.A14], [m.A21, m.A22, m.A23, m.A24],
                     [m.A31, m.A32, m.A33, m.A34], [0.0, 0.0, 0.0, 1.0]])


def set_shape_colour(vobj, rgb):
    """Set a view object's shape colour: ``ShapeAppearance`` where FreeCAD has it (1.0 and later, where
    ``ShapeColor`` is a deprecated alias), else ``ShapeColor`` (0.20). ``rgb``: three floats in 0..1 or a
    ``#rrggbb`` string. Display only: a view object that refuses the colour is left as it is."""
    if isinstance(rgb, str):
        from metamaterial_wb.core.materials import hex_to_rgb
        rgb = hex_to_rgb(rgb)
    rgb = tuple(float(c) for c in rgb[:3])
    try:
        if hasattr(vobj, "ShapeAppearance"):
            mats = list(vobj.ShapeAppearance)
            for mat in mats:
                mat.DiffuseColor = rgb + (getattr(mat, "DiffuseColor", (0, 0, 0, 0))[3:4] or (0.0,))
            vobj.ShapeAppearance = mats
        else:
            vobj.ShapeColor = rgb
    except Exception:  # noqa: BLE001 - display only
        pass
