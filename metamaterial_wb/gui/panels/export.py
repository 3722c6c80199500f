"""Export STEP / 3MF from the panel, in the background (progress + Cancel), ending with a summary.

The files are written by a child process into a staging folder inside the target folder (as the command
line's ``build``: the final move is a rename on one file system, also into a mount point or a link to another
drive) and moved into the target folder only when every file succeeded: Cancel (or an error) leaves nothing
behind, not even the folders the export made. The staging folder's name carries this process's id
(``.mm-export-<pid>-...``), so one left by a killed FreeCAD is removed by the next export into that folder
(``core.fileio.sweep_stale``). The document the structure lives in stays the active one (structure commands
stay enabled).
"""
import json
import os

import FreeCAD
from PySide import QtGui

from metamaterial_wb.core.errors import MetamaterialError
from metamaterial_wb.gui.panels.base import GREEN, BasePanel, _close
from metamaterial_wb.gui.panels.jobs import JobBox, ProcessJob
from metamaterial_wb.objects import structure
from metamaterial_wb.gui.i18n import QT_TRANSLATE_NOOP, translate


class ExportPanel(BasePanel):
    TITLE = QT_TRANSLATE_NOOP("Metamaterial", "Export")
    ICON = "MM_Export.svg"

    def __init__(self, scene_obj):
        super().__init__()
        self.obj = scene_obj
        self.doc = scene_obj.Document
        f = QtGui.QFormLayout()
        base = os.path.splitext(self.doc.FileName)[0] if self.doc.FileName else \
            os.path.join(os.path.expanduser("~"), scene_obj.SceneName or "metamaterial")
        self.path = QtGui.QLineEdit(base + "_export")
        self.step = QtGui.QCheckBox(translate("Metamaterial", "STEP (named bodies, assembly)"))
        self.step.setChecked(True)
        self.threemf = QtGui.QCheckBox(translate("Metamaterial", "3MF (PLA nodes / TPU hinges)"))
        self.threemf.setChecked(True)
        self.modules = QtGui.QCheckBox(translate("Metamaterial", "Modules as separate files"))
        self.modules.setChecked(True)
        self.sockets = QtGui.QCheckBox(translate("Metamaterial", "Snap-fit sockets on the nodes"))
        self.sockets.setChecked(True)
        f.addRow(translate("Metamaterial", "Folder"), self.path)
        f.addRow(self.problem_label("path"))
        f.addRow(self.sockets)
        f.addRow(self.step)
        f.addRow(self.threemf)
        f.addRow(self.problem_label("format"))
        f.addRow(self.modules)
        f.addRow(self.problem_label("modules"))         # modules without the sockets they plug into
        f.addRow(self.problem_label("preferences"))     # a material the fabrication does not know
        self.layout.addLayout(f)
        self.export_btn = QtGui.QPushButton(translate("Metamaterial", "Export"))
        self.export_btn.setToolTip(translate("Metamaterial", "Build the sheet (and modules) and write the files in the background"))
        self.layout.addWidget(self.export_btn)
        self.jobbox = JobBox()
        self.layout.addWidget(self.jobbox)
        self.result_label = self.jobbox.summary
        self.finish_layout()
        self.written = []
        self.warnings = []
        self.staging = None     # exporting.Staging while an export runs (with the folders it made)
        self.close_when_done = False
        self.job = ProcessJob(self.jobbox, self._done, self._failed, self._cancelled)
        self.export_btn.clicked.connect(self.start_export)
        for w in (self.step, self.threemf, self.modules, self.sockets):   # (sockets, modules: the clearance check)
            w.toggled.connect(self._check)
        self.path.textChanged.connect(self._check)
        self._check()

    def getStandardButtons(self):
        return QtGui.QDialogButtonBox.StandardButton.Close

    def _check(self, *_):
        self.set_problem("format", "" if (self.step.isChecked() or self.threemf.isChecked())
                         else translate("Metamaterial", "choose STEP, 3MF or both"))
        out = self.path.text().strip()
        msg = ""
        if not out:
            msg = translate("Metamaterial", "give an output folder")
        elif os.path.exists(out) and not os.path.isdir(out):
            msg = translate("Metamaterial", "{0} exists and is not a folder").format(repr(out))
        self.set_problem("path", msg)
        from metamaterial_wb.gui.panels.checks import preference_problem
        keys = ["RigidMaterial", "FlexibleMaterial"] + (["ModuleMaterial"] if self.modules.isChecked() else [])
        scene = self._scene()
        # the clearance meets the socket lip only in the modules' snap pins: none without sockets (this box or the
        # scene's fabrication.sockets) or without a module to export (the sheet alone builds with any clearance)
        pins = self.sockets.isChecked() and self.modules.isChecked() and (scene is None or bool(scene.modules))
        self.set_problem("modules", self._modules_problem(scene))
        self.set_problem("preferences", preference_problem(keys, scene, pins))   # its socket lip, as Add module
        self.export_btn.setEnabled(not self.problems and not self.job.running)

    def _modules_problem(self, scene):
        """Modules to export without the node sockets they plug into (the box unticked, or the scene's
        ``fabrication.sockets`` false): the background export refuses them (``geometry.modules.parse_modules``),
        so it is said here, naming both options, before anything starts; "" otherwise."""
        if scene is None or not scene.modules or not self.modules.isChecked():
            return ""
        given = scene.extra.get("fabrication") if isinstance(getattr(scene, "extra", None), dict) else None
        n = len(scene.modules)
        if isinstance(given, dict) and given.get("sockets") is False:
            return translate("Metamaterial", "the structure's {0} module(s) plug into the node sockets, but its "
                             "fabrication.sockets is false: untick '{1}' to export the sheet alone, or set "
                             "fabrication.sockets to true in the structure").format(n, self.modules.text())
        if not self.sockets.isChecked():
            return translate("Metamaterial", "the structure's {0} module(s) plug into the node sockets: tick '{1}', "
                             "or untick '{2}' to export the sheet alone").format(
                n, self.sockets.text(), self.modules.text())
        return ""

    def _scene(self):
        """The structure's scene as it is now (the clearance is checked against its own socket lip), or None when
        it cannot be composed or is gone (the default lip; Export then says why it cannot start)."""
        if self.target_gone():
            return None
        try:
            return structure.compose_scene(self.obj)
        except MetamaterialError:
            return None

    # the job ----------------------------------------------------------------------------
    def start_export(self):
        """Start the export in the background. Returns False (reason shown) if it cannot start."""
        from metamaterial_wb.gui import exporting
        self.clear_error()
        if self.problems:
            self.show_error(translate("Metamaterial", "not exported: {0}").format(self.problem_text()))
            return False
        if self.job.running:
            return False
        if self.target_gone():
            self.show_error(translate("Metamaterial", "not exported: the structure this panel exports was deleted "
                                                      "(press Cancel)"))
            return False
        try:
            scene = structure.compose_scene(self.obj)
        except MetamaterialError as exc:
            self.show_error(translate("Metamaterial", "not exported: {0}").format(exc))
            return False
        out = os.path.abspath(os.path.expanduser(self.path.text().strip()))   # ~ is the home folder
        job = {"scene": scene.to_dict(), "out_dir": None, "step": self.step.isChecked(),
               "threemf": self.threemf.isChecked(), "modules": self.modules.isChecked(),
               "sockets": self.sockets.isChecked(), "overrides": exporting.preference_overrides(),
               "stem": exporting.stem_of(scene.name, self.obj.Label)}
        self.written, self.warnings = [], []
        try:
            self.staging = exporting.Staging(out, "mm-export")    # inside out; sweeps a killed FreeCAD's first
            job["out_dir"] = self.staging.path
            jpath = os.path.join(self.staging.path, ".job.json")
            with open(jpath, "w", encoding="utf-8") as f:
                json.dump(job, f)
        except OSError as exc:
            self._discard_staging(created=True)
            self.show_error(translate("Metamaterial", "not exported: cannot write in {0}: {1}").format(out, exc))
            return False
        self.target = out
        self.export_btn.setEnabled(False)
        self.job.start("metamaterial_wb.gui.export_job", [jpath],
                       text=translate("Metamaterial", "building the sheet ..."))
        return True

    def _discard_staging(self, created=False):
        """Remove the staging folder; with ``created``, also the folders this export made, if still empty."""
        if self.staging is not None:
            self.staging.discard(created)
        self.staging = None

    def _done(self, result):
        try:
            from metamaterial_wb.core.errors import MetamaterialError
            from metamaterial_wb.core.fileio import commit_set
            os.makedirs(self.target, exist_ok=True)
            from metamaterial_wb.core.fileio import earlier_outputs, remove_outputs
            from metamaterial_wb.export.manifest import FORMAT
            files = list(result["files"])
            stale = earlier_outputs(self.target, "manifest.json", FORMAT, [os.path.basename(p) for p in files])
            for folder in sorted({os.path.dirname(p) for p in files}):   # all together or none (one staging folder)
                commit_set(folder, self.target, [os.path.basename(p) for p in files if os.path.dirname(p) == folder])
            written = [os.path.join(self.target, os.path.basename(p)) for p in files]
            gone = remove_outputs(self.target, stale)
        except (OSError, MetamaterialError) as exc:   # a user's folder where a file goes is refused
            self._failed(translate("Metamaterial", "cannot move the files into {0}: {1}").format(self.target, exc))
            return
        finally:
            self._discard_staging()     # after _failed (which also removed the folders it made): nothing left
        self.written, self.warnings = written, list(result.get("warnings", []))
        self._keep_active()
        lines = [translate("Metamaterial", "wrote {0} file(s) to {1} in {2:.1f} s:").format(
            len(written), self.target, result.get("seconds", 0.0))]
        lines += ["  " + os.path.basename(p) for p in written]
        if gone:
            lines.append(translate("Metamaterial", "removed {0} file(s) of the earlier export that this one does not "
                                                   "write: {1}").format(len(gone), ", ".join(gone)))
        lines += [translate("Metamaterial", "warning: {0}").format(w) for w in self.warnings]
        self.jobbox.summary.setStyleSheet(GREEN if not self.warnings else "color: #a05a00;")
        self.jobbox.summary.setText("\n".join(lines))
        FreeCAD.Console.PrintMessage("Metamaterial export: " + ", ".join(written) + "\n")
        self._check()
        if self.close_when_done:
            self.cleanup()
            _close()

    def _failed(self, message):
        self._discard_staging(created=True)
        self._keep_active()
        self.written = []
        self.show_error(translate("Metamaterial", "not exported: {0}").format(message))
        self._check()

    def _cancelled(self):
        self._discard_staging(created=True)
        self._keep_active()
        self.jobbox.summary.setStyleSheet("")
        self.jobbox.summary.setText(translate("Metamaterial", "export cancelled: nothing written"))
        self._check()

    def _keep_active(self):
        if self.doc.Name in FreeCAD.listDocuments() and FreeCAD.ActiveDocument is not self.doc:
            FreeCAD.setActiveDocument(self.doc.Name)

    def wait(self, timeout_s=300.0):
        return self.job.wait(timeout_s)

    # OK / Close -------------------------------------------------------------------------
    def accept(self):
        """Scripts: export, wait, close on success (the panel's own button is Export + Close)."""
        if not self.start_export():
            return False
        self.wait()
        if self.job.outcome != "done" or not self.written:   # the child succeeded but the files were not moved in
            return False
        self.cleanup()
        _close()
        return True

    def cleanup(self):
        self.job.stop()
        self._discard_staging(created=True)     # closed while it ran: as Cancel (nothing left after a success)
        super().cleanup()
