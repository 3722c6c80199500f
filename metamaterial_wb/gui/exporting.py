"""Export a structure from the document: STEP and 3MF.

With the fabrication packages (``metamaterial_wb.geometry`` + ``metamaterial_wb.export``) the export
is the same as ``python -m metamaterial_wb build``: one named body per node and hinge, PLA / TPU
materials with per-part extruders, modules as separate files. The preferences (clearance, materials)
are passed as fabrication parameters. Without those packages a simpler export of the displayed
shapes is written (STEP through ImportGui with names and colours, 3MF through Mesh: one object).
"""
import os

import FreeCAD

from metamaterial_wb.core.errors import MetamaterialError
from metamaterial_wb.objects import structure


def fabrication_available():
    try:
        from metamaterial_wb.commands.build import export_result  # noqa: F401
        from metamaterial_wb.geometry.build import build_scene  # noqa: F401
        return True
    except ImportError:
        return False


def _stem(scene, scene_obj):
    text = scene.name or scene_obj.Label or "structure"
    keep = "".join(ch if ch.isalnum() or ch in "-_." else "_" for ch in text)
    return keep.strip("._") or "structure"


def export_structure(scene_obj, out_dir, step=True, threemf=True, modules=True, warnings=None, sockets=True):
    """Write the files into ``out_dir``; returns their paths. Problems that do not stop the export
    (modules the fabrication package cannot build yet) are appended to ``warnings``."""
    warnings = warnings if warnings is not None else []
    if not out_dir:
        raise MetamaterialError("export: give an output folder")
    if os.path.exists(out_dir) and not os.path.isdir(out_dir):
        raise MetamaterialError(f"export: {out_dir!r} exists and is not a folder")
    scene = structure.compose_scene(scene_obj)
    stem = _stem(scene, scene_obj)
    if fabrication_available():
        from metamaterial_wb.commands.build import export_result
        from metamaterial_wb.geometry.build import build_scene
        from metamaterial_wb.geometry.params import fabrication_params
        from metamaterial_wb.gui import preferences
        overrides = {"clearance_mm": float(preferences.get("PrinterClearance")),
                     "rigid_material": preferences.get("RigidMaterial"),
                     "flexible_material": preferences.get("FlexibleMaterial"),
                     "module_material": preferences.get("ModuleMaterial")}
        if not sockets:
            overrides["sockets"] = False
        params = fabrication_params(scene, **overrides)
        with_modules = bool(modules and scene.modules)
        if with_modules:
            from metamaterial_wb.geometry.modules import parse_modules
            try:
                parse_modules(scene, params)
            except (MetamaterialError, NotImplementedError) as exc:
                warnings.append(f"modules not exported: {exc}")
                with_modules = False
        result = build_scene(scene, modules=with_modules, progress=False, params=params)
        return export_result(result, out_dir, step=step, threemf=threemf, progress=False, stem=stem)
    return _fallback_export(scene_obj, out_dir, stem, step, threemf, modules)


def _fallback_export(scene_obj, out_dir, stem, step, threemf, modules):
    os.makedirs(out_dir, exist_ok=True)
    doc = scene_obj.Document
    parts = [o for o in (scene_obj.NodeArray, scene_obj.HingeArray) if o is not None]
    written = []
    if step:
        path = os.path.join(out_dir, stem + "_sheet.step")
        if FreeCAD.GuiUp:
            import ImportGui
            ImportGui.export(parts, path)
        else:
            import Import
            Import.export(parts, path)
        written.append(path)
    if threemf:
        import Mesh
        path = os.path.join(out_dir, stem + "_sheet.3mf")
        Mesh.export(parts, path, 0.05)
        written.append(path)
    if modules:
        for k, m in enumerate(scene_obj.Modules):
            path = os.path.join(out_dir, f"{stem}_{m.ModuleType}_{k + 1}.step")
            m.Shape.exportStep(path)
            written.append(path)
    doc.recompute()
    return written
