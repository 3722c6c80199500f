"""Target surfaces for inverse design read from files: STL / OBJ by the pure reader in core, STEP / IGES
through FreeCAD's Part (tessellated at 0.1 mm). Used by the ``inverse`` command and the Fit to target panel."""
import os

STEP_ALLOWED = "a STEP (.step/.stp) or IGES (.iges/.igs) file with at least one face, or an .stl / .obj mesh"


def _reason(exc):
    return " ".join(str(exc).split())[:300] or type(exc).__name__


def load_surface_mesh(path):
    """(n, 3, 3) triangles (mm) of the surface in ``path``; raises TargetError naming the file.

    A file FreeCAD cannot read or tessellate (FreeCAD raises a bare ``RuntimeError`` / ``Part.OCCError``) is a
    TargetError too, as is a missing FreeCAD."""
    from metamaterial_wb.core.errors import MetamaterialError
    from metamaterial_wb.core.inverse.surface import TargetError, load_mesh
    ext = os.path.splitext(path)[1].lower()
    if ext not in (".step", ".stp", ".iges", ".igs"):
        return load_mesh(path)
    import numpy as np
    from metamaterial_wb.geometry.fc import freecad
    try:
        _App, Part = freecad()
    except MetamaterialError as exc:
        raise TargetError("surface.file", f"{path!r}: reading {ext} files needs FreeCAD ({exc})") from None
    try:
        shape = Part.read(path)
    except Exception as exc:  # noqa: BLE001 - FreeCAD's exceptions are RuntimeError / Part.OCCError / Base.*
        raise TargetError("surface.file", f"{path!r}: FreeCAD cannot read this {ext} file ({_reason(exc)}); "
                                          f"allowed: {STEP_ALLOWED}") from None
    try:
        pts, faces = shape.tessellate(0.1)
    except Exception as exc:  # noqa: BLE001 - as above
        raise TargetError("surface.file", f"{path!r}: FreeCAD cannot tessellate the shape ({_reason(exc)}); "
                                          f"allowed: {STEP_ALLOWED}") from None
    if not faces:
        raise TargetError("surface.file", f"{path!r}: the STEP shape has no faces; allowed: {STEP_ALLOWED}")
    v = np.array([[p.x, p.y, p.z] for p in pts])
    return v[np.array(faces)]
