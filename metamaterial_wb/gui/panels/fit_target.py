""""Fit to target" task panel: inverse design in the GUI (core/inverse, docs/inverse.md).

Pick a target (a target / result JSON or a mesh file, or a mesh or shape object of the document), the
servo budget and forbidden joints (type them or click hinges), run the search in a background thread
with progress and Cancel, see the answer over the target (one sphere per node, coloured by its
distance: green 0 to red at the largest error; the target in orange), and OK applies it to the
structure as one undoable transaction (the structure's motors replaced by the fitted servos).
"""
import os
import threading
import time

import FreeCAD
import FreeCADGui
from PySide import QtCore, QtGui

from metamaterial_wb.core.errors import MetamaterialError
from metamaterial_wb.gui.panels import base
from metamaterial_wb.objects import structure

PREVIEW_LABEL = "FitTargetPreview"


class Cancelled(Exception):
    pass


def object_triangles(obj):
    """Triangles (t, 3, 3) of a Mesh or Part object of the document (its placement applied)."""
    import numpy as np
    if hasattr(obj, "Mesh"):
        m = obj.Mesh.copy()
        pts, faces = m.Topology
    elif hasattr(obj, "Shape") and not obj.Shape.isNull():
        pts, faces = obj.Shape.tessellate(0.1)
    else:
        raise MetamaterialError(f"target object {obj.Label}: neither a mesh nor a shape")
    if not faces:
        raise MetamaterialError(f"target object {obj.Label}: it has no faces")
    v = np.array([[p.x, p.y, p.z] for p in pts])
    return v[np.array(faces)]


class FitTargetPanel(base.BasePanel):
    TITLE = "Fit to target"
    ICON = "MM_FitTarget.svg"

    def __init__(self, scene_obj):
        super().__init__()
        self.obj = scene_obj
        self.doc = scene_obj.Document
        self.scene = structure.compose_scene(scene_obj)
        f = QtGui.QFormLayout()
        row = QtGui.QHBoxLayout()
        self.path = QtGui.QLineEdit("")
        self.path.setPlaceholderText("target JSON, solve result, .stl / .obj / .step")
        browse = QtGui.QPushButton("...")
        browse.clicked.connect(self.browse)
        row.addWidget(self.path)
        row.addWidget(browse)
        f.addRow("Target file", row)
        self.target_obj = QtGui.QComboBox()
        self.target_obj.addItem("(use the file)")
        own = {o.Name for o in [scene_obj] + list(getattr(scene_obj, "OutList", []))}
        for o in self.doc.Objects:
            if o.Name not in own and (hasattr(o, "Mesh") or (hasattr(o, "Shape") and o.TypeId.startswith("Part::")
                                                               and "Metamaterial" not in o.Label)):
                self.target_obj.addItem(o.Label, o.Name)
        f.addRow("or target object", self.target_obj)
        self.servos = QtGui.QSpinBox()
        self.servos.setRange(1, 16)
        self.servos.setValue(max(1, len(self.scene.actuators)) if self.scene.actuators else 2)
        f.addRow("Servo budget", self.servos)
        self.forbid = QtGui.QLineEdit("")
        self.forbid.setPlaceholderText("e.g. H0,0, V1,2 (or click hinges)")
        f.addRow("Forbidden joints", self.forbid)
        self.values_only = QtGui.QCheckBox("Keep the motors, fit their values only")
        f.addRow("", self.values_only)
        self.layout.addLayout(f)
        buttons = QtGui.QHBoxLayout()
        self.run_btn = QtGui.QPushButton("Run")
        self.run_btn.clicked.connect(self.run)
        self.cancel_btn = QtGui.QPushButton("Cancel run")
        self.cancel_btn.setEnabled(False)
        self.cancel_btn.clicked.connect(self.cancel)
        buttons.addWidget(self.run_btn)
        buttons.addWidget(self.cancel_btn)
        self.layout.addLayout(buttons)
        self.progress = QtGui.QProgressBar()
        self.progress.setRange(0, 0)
        self.progress.setVisible(False)
        self.layout.addWidget(self.progress)
        self.status = QtGui.QLabel("")
        self.status.setWordWrap(True)
        self.layout.addWidget(self.status)
        self.finish_layout()
        self.job = None
        self.result = None
        self.preview = None
        self.timer = QtCore.QTimer()
        self.timer.setInterval(100)
        self.timer.timeout.connect(self._poll)
        self.watch_selection(scene_obj, on_joint=self._add_forbidden)

    # -- inputs -------------------------------------------------------------------------------
    def browse(self):  # pragma: no cover - interactive
        fn, _ = QtGui.QFileDialog.getOpenFileName(self.form, "Target", "", "Targets (*.json *.stl *.obj *.step *.stp)")
        if fn:
            self.path.setText(fn)

    def _add_forbidden(self, joint):
        cur = [j.strip() for j in self.forbid.text().split(",") if j.strip()]
        if joint not in cur:
            cur.append(joint)
        self.forbid.setText(", ".join(cur))

    def _target(self):
        from metamaterial_wb.core.inverse.targets import load_target, parse_target
        name = self.target_obj.currentData() if self.target_obj.currentIndex() > 0 else None
        if name:
            tri = object_triangles(self.doc.getObject(name))
            return parse_target(self.scene, {"surface": {"triangles": tri.tolist()}})
        path = self.path.text().strip()
        if not path:
            raise MetamaterialError("give a target file or pick a target object")
        from metamaterial_wb.geometry.surface import load_surface_mesh
        return load_target(self.scene, path, mesh_loader=load_surface_mesh)

    # -- the background run -------------------------------------------------------------------
    def run(self):
        from metamaterial_wb.core.inverse.fit import Problem
        if self.job is not None:
            self.show_error("a fit is already running")
            return False
        self.show_error("")
        try:
            target = self._target()
            pb = Problem(self.scene, target, keep_actuators=self.values_only.isChecked())
        except MetamaterialError as exc:
            self.show_error(str(exc))
            return False
        job = {"msg": "starting", "result": None, "error": None, "done": False, "cancel": False}
        forbid = [j.strip() for j in self.forbid.text().split(",") if j.strip()]
        n = int(self.servos.value())
        values_only = self.values_only.isChecked()

        def mapper(fn, problem, batches):
            out = []
            for b in batches:
                if job["cancel"]:
                    raise Cancelled()
                out.append(fn(problem, b))
            return out

        def work():
            try:
                job["result"] = self._compute(pb, n, forbid, values_only, mapper,
                                              lambda m: job.__setitem__("msg", m))
            except Cancelled:
                job["error"] = "cancelled"
            except Exception as exc:  # noqa: BLE001 - reported in the panel
                job["error"] = str(exc)
            job["done"] = True

        self.job = job
        self.run_btn.setEnabled(False)
        self.cancel_btn.setEnabled(True)
        self.progress.setVisible(True)
        job["thread"] = threading.Thread(target=work, daemon=True)
        job["thread"].start()
        self.timer.start()
        return True

    @staticmethod
    def _compute(pb, n, forbid, values_only, mapper, progress):
        from metamaterial_wb.core.inverse import evaluate as ev
        from metamaterial_wb.core.inverse.search import search_placement
        t0 = time.perf_counter()
        if values_only:
            if not pb.scene.actuators:
                raise MetamaterialError("the structure has no motors to fit")
            joints = tuple(a.joint for a in pb.scene.actuators)
            names = [a.name for a in pb.scene.actuators]
            progress("fitting the values")
            fit = pb.fit(joints, starts=(0.5, -0.5))
        else:
            res = search_placement(pb, n, forbidden=forbid, mapper=mapper, workers=8, progress=progress)
            joints, fit, names = res.joints, res.fit, None
        scene = ev.answer_scene(pb, joints, fit.values, names)
        progress("evaluating")
        errors = ev.evaluate_model(pb, scene, fit.values, "quadratic")
        return {"scene": scene, "joints": joints, "values": fit.values, "errors": errors, "problem": pb,
                "seconds": time.perf_counter() - t0}

    def cancel(self):
        if self.job is not None:
            self.job["cancel"] = True

    def _poll(self):
        job = self.job
        if job is None:
            self.timer.stop()
            return
        self.status.setText(job["msg"])
        if not job["done"]:
            return
        self.timer.stop()
        self.job = None
        self.run_btn.setEnabled(True)
        self.cancel_btn.setEnabled(False)
        self.progress.setVisible(False)
        if job["error"]:
            self.status.setText("")
            self.show_error(f"fit {job['error']}")
            return
        self.result = job["result"]
        e = self.result["errors"]
        parts = [f"{a.name} on {a.joint}: {', '.join(f'{v:+.3f}' for v in self.result['values'][:, k])}"
                 for k, a in enumerate(self.result["scene"].actuators)]
        err = []
        if e.get("rms_mm") is not None:
            err.append(f"rms {e['rms_mm']:.3g} mm, max {e['max_mm']:.3g} mm")
        if e.get("rms_deg") is not None:
            err.append(f"folds rms {e['rms_deg']:.3g} deg")
        self.status.setText("; ".join(parts) + "\n" + "; ".join(err) +
                            f" (quadratic model, {self.result['seconds']:.1f} s). OK applies it.")
        self.show_preview()

    def wait(self, timeout_s=120.0):
        """Block (processing events) until the background fit is done (tests, scripts)."""
        end = time.perf_counter() + timeout_s
        while self.job is not None and time.perf_counter() < end:
            QtGui.QApplication.processEvents()
            time.sleep(0.02)
        QtGui.QApplication.processEvents()
        return self.job is None

    # -- preview: the answer over the target, coloured by distance ----------------------------
    def show_preview(self):
        import numpy as np
        import Part
        self.remove_preview()
        r = self.result
        e = r["errors"]["per_frame"][0]
        al = e["alignment"]
        pos = al["scale"] * e["positions_mm"] @ np.array(al["rotation"]).T + np.array(al["translation_mm"])
        dist = np.zeros(len(pos))
        for row in r["errors"]["per_node"]:
            if row["frame"] == 0 and "error_mm" in row:
                i, j = (int(x) for x in row["node"][1:].split(","))
                dist[r["problem"].topo.node_id(i, j)] = row["error_mm"]
        rad = 0.12 * self.scene.cell_size_mm
        spheres = [Part.makeSphere(rad, FreeCAD.Vector(*p)) for p in pos]
        self.preview = self.doc.addObject("Part::Feature", PREVIEW_LABEL)
        self.preview.Shape = Part.Compound(spheres)
        vmax = max(float(dist.max()), 1e-9)
        self.preview_colours = [(min(1.0, 2 * d / vmax), min(1.0, 2 * (1 - d / vmax)), 0.0) for d in dist]
        fr = r["problem"].target.frames[0]
        tgt = []
        if fr.nodes is not None:
            tgt = [Part.makeSphere(0.5 * rad, FreeCAD.Vector(*p)) for p in fr.nodes.pos]
        if tgt:
            self.preview_target = self.doc.addObject("Part::Feature", PREVIEW_LABEL + "Target")
            self.preview_target.Shape = Part.Compound(tgt)
        if fr.surface is not None:
            import Mesh
            self.preview_target = self.doc.addObject("Mesh::Feature", PREVIEW_LABEL + "Target")
            self.preview_target.Mesh = Mesh.Mesh([[list(v) for v in t] for t in fr.surface.surface.tri])
        if FreeCAD.GuiUp:
            vo = self.preview.ViewObject
            if vo is not None:
                vo.DiffuseColor = self.preview_colours
            tv = getattr(getattr(self, "preview_target", None), "ViewObject", None)
            if tv is not None:
                tv.ShapeColor = (1.0, 0.55, 0.1)
                if hasattr(tv, "Transparency"):
                    tv.Transparency = 60
        self.doc.recompute()

    def remove_preview(self):
        for attr in ("preview", "preview_target"):
            o = getattr(self, attr, None)
            if o is not None:
                try:
                    self.doc.removeObject(o.Name)
                except Exception:  # pragma: no cover - already gone
                    pass
                setattr(self, attr, None)

    # -- apply / close ------------------------------------------------------------------------
    def apply(self):
        if self.job is not None:
            raise MetamaterialError("the fit is still running: wait or cancel it")
        if self.result is None:
            raise MetamaterialError("run the fit first")
        self.remove_preview()
        scene = self.result["scene"]
        from metamaterial_wb.core.scene import Scene
        Scene.from_dict(scene.to_dict())
        with base.transaction(self.doc, self.TITLE):
            old = [it for it in self.obj.Items if getattr(getattr(it, "Proxy", None), "Type", "") ==
                   "MetamaterialItem" and it.Kind == "actuator"]
            self.obj.Items = [it for it in self.obj.Items if it not in old]
            for it in old:
                self.doc.removeObject(it.Name)
            for a in scene.actuators:
                structure.make_item(self.doc, self.obj, "actuator", a.name, a.joint, a.value, a.profile)
            self.doc.recompute()

    def cleanup(self):
        self.cancel()
        if self.job is not None and "thread" in self.job:
            self.job["thread"].join(timeout=30)
        self.job = None
        self.timer.stop()
        self.remove_preview()
        super().cleanup()
