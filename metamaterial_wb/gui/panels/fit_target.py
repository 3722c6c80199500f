""""Fit to target" task panel: inverse design in the GUI (core/inverse, docs/inverse.md).

Pick a target (a target / result JSON or a mesh file, or a mesh or shape object of the document), the
servo budget and forbidden joints (type them or click hinges), the local worker processes or a Dask
scheduler, and run the same search as ``inverse`` (core/inverse/pipeline.py: placement search through a
process pool or Dask, the values fit, then the answer re-evaluated under the quadratic, linear and
nonlinear models and put through build's checks) in a background thread with progress and Cancel. The
errors of all three models and whether the answer is printable are shown; the answer is drawn over the
target (one sphere per node, coloured by its quadratic-model distance: green 0 to red at the largest
error; the target in orange), and OK applies it to the structure as one undoable transaction (the
structure's motors replaced by the fitted servos).
"""
import json
import os

import FreeCAD
import FreeCADGui
from PySide import QtCore, QtGui

from metamaterial_wb.core.errors import MetamaterialError
from metamaterial_wb.gui.i18n import QT_TRANSLATE_NOOP, translate
from metamaterial_wb.gui.panels import base, jobs, ranges
from metamaterial_wb.gui.panels.widgets import wrapped_check
from metamaterial_wb.objects import structure

PREVIEW_LABEL = "FitTargetPreview"


class FitOverlay:
    """Spheres and a surface drawn over the 3D view of ``doc`` (a Coin separator named ``PREVIEW_LABEL``): no
    document object. ``count``: the spheres of the first call (the answer's nodes); ``colours``: theirs."""

    def __init__(self, doc):
        from pivy import coin
        self.coin, self.view, self.count, self.colours = coin, None, 0, []
        gd = FreeCADGui.getDocument(doc.Name) if FreeCAD.GuiUp else None
        if gd is not None and hasattr(gd.ActiveView, "getSceneGraph"):
            self.view = gd.ActiveView
        self.root = coin.SoSeparator()
        self.root.setName(PREVIEW_LABEL)
        if self.view is not None:
            self.view.getSceneGraph().addChild(self.root)

    def _material(self, rgb, transparency):
        m = self.coin.SoMaterial()
        m.diffuseColor.setValue(*rgb)
        m.transparency.setValue(transparency)
        return m

    def spheres(self, points, radius, colours, transparency=0.0):
        for p, c in zip(points, colours):
            sep = self.coin.SoSeparator()
            sep.addChild(self._material(c, transparency))
            t = self.coin.SoTranslation()
            t.translation.setValue(*(float(x) for x in p))
            sep.addChild(t)
            sph = self.coin.SoSphere()
            sph.radius.setValue(float(radius))
            sep.addChild(sph)
            self.root.addChild(sep)
        if not self.count:
            self.count, self.colours = len(colours), list(colours)

    def surface(self, triangles, rgb, transparency=0.0):
        sep = self.coin.SoSeparator()
        sep.addChild(self._material(rgb, transparency))
        coords = self.coin.SoCoordinate3()
        pts = [tuple(float(x) for x in v) for t in triangles for v in t]
        coords.point.setValues(0, len(pts), pts)
        faces = self.coin.SoFaceSet()
        faces.numVertices.setValues(0, len(pts) // 3, [3] * (len(pts) // 3))
        sep.addChild(coords)
        sep.addChild(faces)
        self.root.addChild(sep)

    def remove(self):
        if self.view is not None:
            try:
                self.view.getSceneGraph().removeChild(self.root)
            except Exception:  # pragma: no cover - the view is gone
                pass
        self.view = None


Cancelled = jobs.Cancelled


def cancellable(inner, report, counter):
    """A mapper that hands ``inner`` (None: serial) a few batches at a time and calls ``report`` between
    them (which raises :class:`Cancelled` once Cancel was pressed): a cancel stops the search within one
    slice of batches. Results equal ``inner``'s (the batches themselves are not changed)."""
    def mapper(fn, problem, batches):
        step = max(1, 2 * getattr(inner, "workers", 1)) if inner is not None else 1
        out = []
        for i in range(0, len(batches), step):
            report(None)
            part = batches[i:i + step]
            out += inner(fn, problem, part) if inner is not None else [fn(problem, b) for b in part]
            counter[0] += len(part)
        report(None)
        return out
    return mapper


def object_triangles(obj):
    """Triangles (t, 3, 3) of a Mesh or Part object of the document (its placement applied)."""
    import numpy as np
    if hasattr(obj, "Mesh"):
        m = obj.Mesh.copy()
        pts, faces = m.Topology
    elif hasattr(obj, "Shape") and not obj.Shape.isNull():
        pts, faces = obj.Shape.tessellate(0.1)
    else:
        raise MetamaterialError(translate("Metamaterial", "target object {0}: neither a mesh nor a shape").format(
            obj.Label))
    if not faces:
        raise MetamaterialError(translate("Metamaterial", "target object {0}: it has no faces").format(obj.Label))
    v = np.array([[p.x, p.y, p.z] for p in pts])
    return v[np.array(faces)]


class FitTargetPanel(base.BasePanel):
    VIEW_ATTRS = ("preview",)
    TITLE = QT_TRANSLATE_NOOP("Metamaterial", "Fit to target")
    ICON = "MM_FitTarget.svg"

    def __init__(self, scene_obj):
        super().__init__()
        self.obj = scene_obj
        self.doc = scene_obj.Document
        self.scene = structure.compose_scene(scene_obj)
        # a narrow task dock (the combo view, ~300 px): a field that does not fit beside its label goes below it,
        # the check boxes' texts wrap, the object list takes the width it gets (long names in its popup)
        f = QtGui.QFormLayout()
        f.setRowWrapPolicy(QtGui.QFormLayout.RowWrapPolicy.WrapLongRows)
        row = QtGui.QHBoxLayout()
        self.path = QtGui.QLineEdit("")
        self.path.setPlaceholderText(translate("Metamaterial", "target JSON, solve result, .stl / .obj / .step"))
        self.browse_btn = browse = QtGui.QPushButton(translate("Metamaterial", "..."))
        browse.clicked.connect(self.browse)
        row.addWidget(self.path)
        row.addWidget(browse)
        f.addRow(translate("Metamaterial", "Target file"), row)
        self.target_obj = QtGui.QComboBox()
        self.target_obj.setSizeAdjustPolicy(QtGui.QComboBox.SizeAdjustPolicy.AdjustToMinimumContentsLengthWithIcon)
        self.target_obj.setMinimumContentsLength(12)
        self.target_obj.addItem(translate("Metamaterial", "(use the file)"))
        own = {o.Name for o in [scene_obj] + list(getattr(scene_obj, "OutList", []))}
        for o in self.doc.Objects:
            if o.Name not in own and (hasattr(o, "Mesh") or (hasattr(o, "Shape") and o.TypeId.startswith("Part::")
                                                               and "Metamaterial" not in o.Label)):
                self.target_obj.addItem(o.Label, o.Name)
        f.addRow(translate("Metamaterial", "or target object"), self.target_obj)
        self.servos = QtGui.QSpinBox()
        # the search's own bound: one servo per joint at most (it says in words when fewer fit)
        self.servos.setRange(1, max(1, len(self.scene.topology.joint_names)))
        ranges.ui_only(self.servos, "bounded by the sheet's joint count, as the search checks it")
        self.servos.setValue(max(1, len(self.scene.actuators)) if self.scene.actuators else 2)
        f.addRow(translate("Metamaterial", "Servo budget"), self.servos)
        self.forbid = QtGui.QLineEdit("")
        self.forbid.setPlaceholderText(translate("Metamaterial", "e.g. H0,0, V1,2 (or click hinges)"))
        f.addRow(translate("Metamaterial", "Forbidden joints"), self.forbid)
        self.values_only, row = wrapped_check(translate("Metamaterial", "Keep the motors, fit their values only"))
        f.addRow(row)
        self.values_only_hint = QtGui.QLabel(translate(
            "Metamaterial", "Servo budget, Forbidden joints, Workers and Dask scheduler are not used: the fit keeps the "
                            "structure's {0} motors on their joints and runs in this process (untick to use them "
                            "again)").format(len(self.scene.actuators)))
        self.values_only_hint.setWordWrap(True)
        self.values_only_hint.hide()
        f.addRow(self.values_only_hint)
        self.workers = QtGui.QSpinBox()
        from metamaterial_wb.core.inverse import WORKERS_RANGE
        self.workers.setRange(*WORKERS_RANGE)       # the command line's inverse --workers bound
        ranges.ui_only(self.workers, "a run setting (local worker processes), not a scene quantity")
        self.workers.setValue(min(2, os.cpu_count() or 1))
        self.workers.setToolTip(translate("Metamaterial", "local worker processes for the candidate evaluations (inverse --workers)"))
        f.addRow(translate("Metamaterial", "Workers"), self.workers)
        self.scheduler = QtGui.QLineEdit("")
        self.scheduler.setPlaceholderText(translate("Metamaterial", "optional: tcp://HOST:PORT of a Dask scheduler"))
        f.addRow(translate("Metamaterial", "Dask scheduler"), self.scheduler)
        self.geometry_checks, row = wrapped_check(translate("Metamaterial", "Run build's geometry checks on the answer (a child process)"))
        self.geometry_checks.setChecked(True)
        f.addRow(row)
        self.layout.addLayout(f)
        self.form_layout = f
        # the fields a values-only fit does not use (the command line's "not with --values-only"): greyed while the
        # box is ticked, showing what the fit uses; what was typed is kept aside and given back when it is unticked
        self.tips = {w: w.toolTip() for w in (self.servos, self.forbid, self.workers, self.scheduler, self.path)}
        self.forbid_hint, self.sched_hint = self.forbid.placeholderText(), self.scheduler.placeholderText()
        self.typed = None
        self.values_only.toggled.connect(self._values_only_toggled)
        self.scheduler.textChanged.connect(self._sync_fields)
        self.target_obj.currentIndexChanged.connect(self._sync_fields)
        self.run_btn = QtGui.QPushButton(translate("Metamaterial", "Run"))
        self.run_btn.clicked.connect(self.run)
        self.layout.addWidget(self.run_btn)
        self.box = jobs.JobBox()
        self.cancel_btn = self.box.cancel_btn
        self.progress = self.box.progress
        self.layout.addWidget(self.box)
        self.status = QtGui.QLabel("")
        self.status.setWordWrap(True)
        self.status.setTextInteractionFlags(QtCore.Qt.TextInteractionFlag.TextSelectableByMouse)
        self.layout.addWidget(self.status)
        self.finish_layout()
        self.job = jobs.ThreadJob(self.box, self._done, self._failed, self._cancelled)
        self.result = None
        self.preview = None
        self.watch_selection(scene_obj, on_joint=self._add_forbidden)
        self._sync_fields()

    # -- inputs -------------------------------------------------------------------------------
    def browse(self):  # pragma: no cover - interactive
        fn, _ = QtGui.QFileDialog.getOpenFileName(self.form, translate("Metamaterial", "Target"), "",
                                                  translate("Metamaterial", "Targets (*.json *.stl *.obj *.step *.stp)"))
        if fn:
            self.path.setText(fn)

    def _forbidden(self):
        """The joints in the forbid field (a joint name holds a comma: ``pipeline.parse_joint_list``)."""
        from metamaterial_wb.core.inverse.pipeline import parse_joint_list
        return parse_joint_list([self.forbid.text()], "forbidden joints") if self.forbid.text().strip() else []

    def _add_forbidden(self, joint):
        if self.values_only.isChecked():   # the field is greyed (the placement is the structure's): a click adds nothing
            return
        try:
            cur = self._forbidden()
        except MetamaterialError:          # the user's half-typed text stays; the clicked joint goes after it
            self.forbid.setText("; ".join((self.forbid.text().rstrip(), joint)))
            return
        if joint not in cur:
            cur.append(joint)
        self.forbid.setText(", ".join(cur))

    # -- the fields a values-only fit or a Dask scheduler does not use --------------------------
    def _box(self):
        return translate("Metamaterial", "Keep the motors, fit their values only")

    def _values_only_toggled(self, on):
        """Ticked: the servo budget, forbidden joints, workers and scheduler show what a values-only fit uses (the
        structure's motors, no forbidden joint, this process) and are greyed; unticked: they get back what was typed."""
        fields = (self.servos, self.forbid, self.workers, self.scheduler)
        if on and self.typed is None:
            self.typed = (self.servos.value(), self.forbid.text(), self.workers.value(), self.scheduler.text())
            n = len(self.scene.actuators)
            if self.servos.minimum() <= n <= self.servos.maximum():
                self.servos.setValue(n)
            self.forbid.setText("")
            self.workers.setValue(1)
            self.scheduler.setText("")
        elif not on and self.typed is not None:
            for w, v in zip(fields, self.typed):
                if isinstance(w, QtGui.QSpinBox):
                    w.setValue(v)
                else:
                    w.setText(v)
            self.typed = None
        self._sync_fields()

    def _values_only_why(self):
        """Per greyed field: why a values-only fit does not use it."""
        box = self._box()
        here = translate("Metamaterial", "not used while '{0}' is ticked: a values-only fit runs in this process (only "
                                         "the placement search runs in parallel)").format(box)
        return {self.servos: translate("Metamaterial", "not used while '{0}' is ticked: the fit keeps the structure's "
                                                       "{1} motors").format(box, len(self.scene.actuators)),
                self.forbid: translate("Metamaterial", "not used while '{0}' is ticked: the placement is the "
                                                       "structure's").format(box),
                self.workers: here, self.scheduler: here}

    def _enable(self, w, on, tip):
        w.setEnabled(on)
        w.setToolTip(tip)
        label = self.form_layout.labelForField(w)
        if label is not None:
            label.setEnabled(on)

    def _sync_fields(self, *_):
        """Grey the fields that are not used and say why in their tooltips: those of a values-only fit, the worker
        count while a Dask scheduler is given (the command line: --workers or --scheduler), the target file while a
        target object is picked."""
        vo = self.values_only.isChecked()
        why = self._values_only_why() if vo else {}
        for w in (self.servos, self.forbid, self.scheduler):
            self._enable(w, not vo, why.get(w, self.tips[w]))
        self.forbid.setPlaceholderText(translate("Metamaterial", "none: the structure's placement") if vo
                                       else self.forbid_hint)
        self.scheduler.setPlaceholderText(translate("Metamaterial", "none: this process") if vo else self.sched_hint)
        self.values_only_hint.setVisible(vo)
        if vo:
            self._enable(self.workers, False, why[self.workers])
        elif self.scheduler.text().strip():
            self._enable(self.workers, False, translate(
                "Metamaterial", "not used while a Dask scheduler is given: its workers run the search (clear the Dask "
                                "scheduler to use local workers)"))
        else:
            self._enable(self.workers, True, self.tips[self.workers])
        obj = self.target_obj.currentIndex() > 0
        self._enable(self.path, not obj, translate(
            "Metamaterial", "not used while a target object is picked: pick '{0}' to use the file").format(
                self.target_obj.itemText(0)) if obj else self.tips[self.path])
        self.browse_btn.setEnabled(not obj)

    def _combined(self):
        """The command line's "not with --values-only" in the panel's words: with the box ticked, each field that
        holds something else than what a values-only fit uses (a script, a restored state wrote it) as
        ``field value (why)``; [] when there is none."""
        if not self.values_only.isChecked():
            return []
        n, out = len(self.scene.actuators), []
        if n and self.servos.minimum() <= n <= self.servos.maximum() and self.servos.value() != n:
            out.append(translate("Metamaterial", "Servo budget {0} (the fit keeps the structure's {1} motors)").format(
                self.servos.value(), n))
        if self.forbid.text().strip():
            out.append(translate("Metamaterial", "Forbidden joints {0} (the placement is the structure's)").format(
                self.forbid.text().strip()))
        if self.workers.value() != 1:
            out.append(translate("Metamaterial", "Workers {0} (a values-only fit runs in this process)").format(
                self.workers.value()))
        if self.scheduler.text().strip():
            out.append(translate("Metamaterial", "Dask scheduler {0} (a values-only fit runs in this process)").format(
                self.scheduler.text().strip()))
        return out

    def _target(self):
        from metamaterial_wb.core.inverse.targets import load_target, parse_target
        name = self.target_obj.currentData() if self.target_obj.currentIndex() > 0 else None
        if name:
            tri = object_triangles(self.doc.getObject(name))
            return parse_target(self.scene, {"surface": {"triangles": tri.tolist()}})
        path = self.path.text().strip()
        if not path:
            raise MetamaterialError(translate("Metamaterial", "give a target file or pick a target object"))
        from metamaterial_wb.geometry.surface import load_surface_mesh
        return load_target(self.scene, path, mesh_loader=load_surface_mesh)

    # -- the background run -------------------------------------------------------------------
    def run(self):
        if self.job.running:
            self.show_error(translate("Metamaterial", "a fit is already running"))
            return False
        self.show_error("")
        combined = self._combined()
        if combined:         # refused as the command line does, before any work: nothing is dropped without a word
            self.show_error(translate("Metamaterial", "{0} with '{1}'; allowed: only without it (untick it to use "
                                                      "them; ticked, it sets them itself)").format(
                "; ".join(combined), self._box()))
            return False
        try:
            target = self._target()
            from metamaterial_wb.core.inverse.fit import Problem
            Problem(self.scene, target, keep_actuators=self.values_only.isChecked())   # bad targets: now
            forbidden = [] if self.values_only.isChecked() else self._forbidden()
        except MetamaterialError as exc:
            self.show_error(self.in_panel_words(str(exc)))
            return False
        opts = {"servos": None if self.values_only.isChecked() else int(self.servos.value()),
                "values_only": self.values_only.isChecked(),
                "forbidden": forbidden}
        workers, sched = int(self.workers.value()), self.scheduler.text().strip() or None
        if sched is not None:
            from metamaterial_wb.parallel import check_scheduler_address
            try:
                check_scheduler_address(sched, translate("Metamaterial", "Dask scheduler"))
            except MetamaterialError as exc:
                self.show_error(str(exc))
                return False
        geometry = "subprocess" if self.geometry_checks.isChecked() else "off"
        scene = self.scene
        self.result = None
        self.status.setText("")
        self.remove_preview()
        self.run_btn.setEnabled(False)
        return self.job.start(lambda report: self._compute(scene, target, opts, workers, sched, geometry, report),
                              translate("Metamaterial", "starting the fit"))

    @staticmethod
    def _compute(scene, target, opts, workers, sched, geometry, report):
        """The work of the background thread: the CLI's pipeline with a cancellable mapper."""
        from metamaterial_wb.core.inverse import pipeline
        from metamaterial_wb.export.printability import check_printable, first_module_problem
        from metamaterial_wb.parallel import make_mapper
        counter = [0]
        stage = {"f": 0.0}

        def progress(msg):
            if msg.startswith("evaluating under the"):
                stage["f"] = max(stage["f"], 0.7 + 0.08 * ["quadratic", "linear", "nonlinear"].index(msg.split()[3]))
            elif msg.startswith("fabrication"):
                stage["f"] = max(stage["f"], 0.95)
            report(stage["f"], msg)

        def ticking(_):
            if stage["f"] < 0.7:
                stage["f"] = max(stage["f"], 0.7 * (1.0 - 1.0 / (1.0 + counter[0] / 40.0)))
            report(stage["f"])

        inner, n = (None, 1) if opts["values_only"] else make_mapper(workers, sched)
        py, paths = jobs.child_python(), []
        try:
            paths = [os.path.join(FreeCAD.getHomePath(), "lib")]
        except Exception:  # pragma: no cover
            pass
        try:
            # serial runs are still cut into 4 slices per round, so that Cancel acts within a round
            return pipeline.solve(scene, target, mapper=cancellable(inner, ticking, counter),
                                  workers=n if inner is not None else 4,
                                  progress=progress,
                                  fab_check=lambda s: check_printable(s, geometry=geometry, python=py,
                                                                      pythonpath=paths),
                                  module_check=first_module_problem, **opts)
        finally:
            if inner is not None:
                inner.close()

    def cancel(self):
        self.job.cancel()

    def _failed(self, msg):
        self.run_btn.setEnabled(True)
        self.status.setText("")
        self.show_error(translate("Metamaterial", "fit: {0}").format(self.in_panel_words(msg)))

    @staticmethod
    def in_panel_words(msg):
        """A message of the fit (worded for the command line) with its flags as this panel's fields."""
        for flag, field in (("--values-only", translate("Metamaterial", "Keep the motors, fit their values only")),
                            ("--servos", translate("Metamaterial", "Servo budget")),
                            ("--forbid", translate("Metamaterial", "Forbidden joints")),
                            ("--scheduler", translate("Metamaterial", "Dask scheduler"))):
            msg = msg.replace(flag, f"'{field}'")
        return msg

    def _cancelled(self):
        self.run_btn.setEnabled(True)
        self.status.setText("")
        self.show_error(translate("Metamaterial", "fit cancelled: nothing changed"))

    def _done(self, run):
        self.run_btn.setEnabled(True)
        self.result = run
        from metamaterial_wb.core.inverse.pipeline import summary_lines
        # per motor: its name, its joint, its values (one per target frame)
        parts = [translate("Metamaterial", "{0} on {1}: {2}").format(a.name, a.joint,
                                                                     ", ".join(f"{v:+.3f}" for v in run.values[:, k]))
                 for k, a in enumerate(run.scene.actuators)]
        notes = [translate("Metamaterial", "warning: {0}").format(w) for w in run.info.get("warnings", [])]
        self.status.setText("; ".join(parts) + "\n" + "\n".join(summary_lines(run) + notes) + "\n" +
                            translate("Metamaterial", "({0:.1f} s, {1} fits). OK applies it.").format(
                                run.seconds, run.info.get("fits", 0)))
        self.show_preview()

    def wait(self, timeout_s=120.0):
        """Block (processing events) until the background fit is done (tests, scripts)."""
        return self.job.wait(timeout_s)

    # -- preview: the answer over the target, coloured by distance ----------------------------
    def show_preview(self):
        """The answer's nodes as spheres coloured by their distance to the target (green to red), the target as
        small orange spheres or its surface: a Coin overlay in the 3D view, never a document object (Cancel leaves
        the document as it was; a save while the preview shows stores nothing of it)."""
        import numpy as np
        self.remove_preview()
        r = self.result
        e = r.errors["quadratic"]["per_frame"][0]
        al = e["alignment"]
        pos = al["scale"] * e["positions_mm"] @ np.array(al["rotation"]).T + np.array(al["translation_mm"])
        dist = np.zeros(len(pos))
        for row in r.errors["quadratic"]["per_node"]:
            if row["frame"] == 0 and "error_mm" in row:
                i, j = (int(x) for x in row["node"][1:].split(","))
                dist[r.problem.topo.node_id(i, j)] = row["error_mm"]
        rad = 0.12 * self.scene.cell_size_mm
        vmax = max(float(dist.max()), 1e-9)
        colours = [(min(1.0, 2 * d / vmax), min(1.0, 2 * (1 - d / vmax)), 0.0) for d in dist]
        fr = r.problem.target.frames[0]
        self.preview = FitOverlay(self.doc)
        self.preview.spheres(pos, rad, colours)
        if fr.nodes is not None:
            self.preview.spheres(fr.nodes.pos, 0.5 * rad, [(1.0, 0.55, 0.1)] * len(fr.nodes.pos), transparency=0.6)
        if fr.surface is not None:
            self.preview.surface(fr.surface.surface.tri, (1.0, 0.55, 0.1), transparency=0.6)

    def remove_preview(self):
        if getattr(self, "preview", None) is not None:
            self.preview.remove()
            self.preview = None


    # -- apply / close ------------------------------------------------------------------------
    def apply(self):
        if self.job.running:
            raise MetamaterialError(translate("Metamaterial", "the fit is still running: wait or cancel it"))
        if self.result is None:
            raise MetamaterialError(translate("Metamaterial", "run the fit first"))
        self.remove_preview()
        scene = self.result.scene
        from metamaterial_wb.core.scene import Scene
        Scene.from_dict(scene.to_dict())

        def change():
            old = [it for it in self.obj.Items if getattr(getattr(it, "Proxy", None), "Type", "") ==
                   "MetamaterialItem" and it.Kind == "actuator"]
            self.obj.Items = [it for it in self.obj.Items if it not in old]
            for it in old:
                self.doc.removeObject(it.Name)
            for a in scene.actuators:     # with every field the answer kept (a servo channel, notes)
                structure.make_item(self.doc, self.obj, "actuator", a.name, a.joint, a.value, a.profile,
                                    extra=a.extra or None)
            self._move_modules(self.result.info.get("module_moves", ()))
            if self.obj.UseGlobal and scene.global_deformation is None:
                self.obj.UseGlobal = False    # the answer's servos act (a global deformation replaces them)
        self.commit(self.doc, self.TITLE, change)     # one undo step; an invalid result is undone, its error shown

    def _move_modules(self, moves):
        """The servo housings of replaced motors, moved onto the new servos' joints or removed, as the answer
        says (``(module index, old joint, new joint or None)``, indices in the Scene's module order)."""
        mods = [m for m in self.obj.Modules if getattr(getattr(m, "Proxy", None), "Type", "") == "MetamaterialModule"]
        gone = []
        for k, _old, new in moves:
            m = mods[k]
            if new is None:
                gone.append(m)
                continue
            m.Target = new
            data = json.loads(m.ModuleData or "{}")
            if data.pop("housing_node", None) is not None:
                m.ModuleData = json.dumps(data)
        if gone:
            self.obj.Modules = [m for m in self.obj.Modules if m not in gone]
            for m in gone:
                self.doc.removeObject(m.Name)

    def cleanup(self):
        self.job.cancel()
        self.remove_preview()
        super().cleanup()
