"""Export a structure: STEP and 3MF, the same pipeline as ``python -m metamaterial_wb build``.

:func:`export_scene` does the work (no FreeCAD document, no Qt): one named body per node and hinge,
PLA / TPU materials with per-part extruders, modules as separate files. The Export panel runs it in a
child process (``python -m metamaterial_wb.gui.export_job``, see ``gui/panels/jobs.py``) so the GUI
stays live and Cancel can stop it; scripts call :func:`export_structure` in-process. The stored preferences
(clearance, materials) are passed as fabrication parameters. Its messages go through ``translate`` (in the child
process, which loads no translation, they stay English).
"""
import os

from metamaterial_wb.core.errors import MetamaterialError
from metamaterial_wb.gui.i18n import translate


def stem_of(name, label=""):
    text = name or label or "structure"
    keep = "".join(ch if ch.isalnum() or ch in "-_." else "_" for ch in text)
    return keep.strip("._") or "structure"


def preference_overrides():
    """The fabrication parameters the user chose in the workbench preferences (GUI side; see
    ``objects.module.fabrication_overrides``): they win over the scene's own ``fabrication`` section; a preference
    never set, cleared, or at the fabrication default leaves the scene's value, as ``build`` does."""
    from metamaterial_wb.objects.module import PREFERENCE_PARAMS, fabrication_overrides
    return fabrication_overrides(tuple(PREFERENCE_PARAMS))


def check_out_dir(out_dir):
    if not out_dir:
        raise MetamaterialError(translate("Metamaterial", "export: give an output folder"))
    if os.path.exists(out_dir) and not os.path.isdir(out_dir):
        raise MetamaterialError(translate("Metamaterial", "export: {0} exists and is not a folder").format(
            repr(out_dir)))


def export_scene(scene, out_dir, step=True, threemf=True, modules=True, sockets=True, overrides=None, stem=None,
                 warnings=None, progress=False):
    """Write the files of ``scene`` into ``out_dir`` (atomically as a set); returns their paths.

    ``overrides``: the fabrication parameters the workbench preferences supply (:func:`preference_overrides`, also
    the background job's): a clearance among them is named as the preference in the snap pins' errors
    (``objects.module.mark_preference_clearance``, as the modules' solids). A module the fabrication package cannot
    build (a conflict, an unknown servo) is an error naming it: nothing is written; export without modules to get
    the sheet alone.
    """
    from metamaterial_wb.export.package import export_result
    from metamaterial_wb.geometry.build import build_scene
    from metamaterial_wb.geometry.fc import freecad
    from metamaterial_wb.core.design import effective_tilts_deg
    from metamaterial_wb.core.fabrication import fabrication_params

    freecad()
    from metamaterial_wb.objects.module import mark_preference_clearance   # (imports FreeCAD: after freecad())
    warnings = warnings if warnings is not None else []
    check_out_dir(out_dir)
    over = dict(overrides or {})
    if not sockets:
        over["sockets"] = False
    params = mark_preference_clearance(fabrication_params(scene, effective_tilts_deg(scene), **over), overrides)
    with_modules = bool(modules and scene.modules)
    if with_modules:
        from metamaterial_wb.geometry.modules import parse_modules
        try:
            parse_modules(scene, params)
        except (MetamaterialError, NotImplementedError) as exc:
            raise MetamaterialError(translate("Metamaterial", "modules cannot be built ({0}); nothing written - fix "
                                              "them or export without modules").format(exc)) from None
    elif modules is False and scene.modules:
        warnings.append(translate("Metamaterial", "{0} module(s) not exported (Modules unchecked)").format(
            len(scene.modules)))
    result = build_scene(scene, modules=with_modules, progress=progress, params=params)
    return export_result(result, out_dir, step=step, threemf=threemf, progress=progress,
                         stem=stem or stem_of(scene.name))


def export_structure(scene_obj, out_dir, step=True, threemf=True, modules=True, warnings=None, sockets=True):
    """In-process export of a Scene object (scripts). The active document stays active."""
    import FreeCAD

    from metamaterial_wb.objects import structure
    active = FreeCAD.ActiveDocument
    scene = structure.compose_scene(scene_obj)
    try:
        return export_scene(scene, out_dir, step=step, threemf=threemf, modules=modules, sockets=sockets,
                            overrides=preference_overrides(), stem=stem_of(scene.name, scene_obj.Label),
                            warnings=warnings)
    finally:
        if active is not None and active.Name in FreeCAD.listDocuments():
            FreeCAD.setActiveDocument(active.Name)


class Staging:
    """The staging folder of a background export into ``target``: made inside ``target`` (``.KIND-<pid>-...``,
    so the final move is a rename on that folder's own file system, also a mount point or a link to another drive,
    and a killed FreeCAD's is swept by ``fileio.make_temp_dir`` next time), and the folders of ``target`` the
    export made, removed (innermost first, while empty) when it fails or is cancelled: nothing is left."""

    def __init__(self, target, kind):
        from metamaterial_wb.core.fileio import make_temp_dir
        from metamaterial_wb.core.outdir import missing_dirs
        self.target, self.path = target, None
        self.created = missing_dirs(target)
        try:
            os.makedirs(target, exist_ok=True)
            self.path = make_temp_dir(target, kind)
        except OSError:
            self.discard(created=True)
            raise

    def discard(self, created=False):
        """Remove the staging folder; with ``created``, also the folders the export made, if still empty."""
        import shutil
        if self.path:
            shutil.rmtree(self.path, ignore_errors=True)
        self.path = None
        for d in self.created if created else ():
            try:
                os.rmdir(d)
            except OSError:
                break
        self.created = []
