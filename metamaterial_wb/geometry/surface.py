"""Target surfaces for inverse design read from files: STL / OBJ by the pure reader in core, STEP / IGES
through FreeCAD's Part (tessellated at 0.1 mm). Used by the ``inverse`` command and the Fit to target panel."""
import os


def load_surface_mesh(path):
    """(n, 3, 3) triangles (mm) of the surface in ``path``; raises TargetError naming the file."""
    from metamaterial_wb.core.inverse.surface import TargetError, load_mesh
    ext = os.path.splitext(path)[1].lower()
    if ext not in (".step", ".stp", ".iges", ".igs"):
        return load_mesh(path)
    import numpy as np
    from metamaterial_wb.geometry.fc import freecad
    _App, Part = freecad()
    shape = Part.read(path)
    pts, faces = shape.tessellate(0.1)
    if not faces:
        raise TargetError("surface.file", f"{path!r}: the STEP shape has no faces")
    v = np.array([[p.x, p.y, p.z] for p in pts])
    return v[np.array(faces)]
