"""Folded shape: one fold per axis; Confirm runs the joint configuration."""
from PySide import QtGui

from metamaterial_wb.core.errors import MetamaterialError
from metamaterial_wb.core.scene import Scene
from metamaterial_wb.objects import design_adapter, structure
from metamaterial_wb.gui.panels.base import BasePanel, transaction, _slider


class FoldedShapePanel(BasePanel):
    TITLE = "Folded shape"
    ICON = "MM_FoldedShape.svg"

    def __init__(self, scene_obj):
        super().__init__()
        self.obj = scene_obj
        self.scene = structure.compose_scene(scene_obj)
        self.saved = structure.display_state(scene_obj)
        self.sliders = []
        if not self.scene.axes:
            self.layout.addWidget(QtGui.QLabel("No rotary axes yet: use 'Rotary axes' first."))
        for k, a in enumerate(self.scene.axes):
            mx = design_adapter.max_fold_deg(self.scene, k)
            lim = int(mx // 1) if mx is not None else 180
            row = QtGui.QHBoxLayout()
            lab = QtGui.QLabel(f"{a.direction} {a.line}")
            s = _slider(-lim, lim, int(round(max(-lim, min(lim, a.fold_deg)))))
            val = QtGui.QLabel("")
            maxlab = QtGui.QLabel(f"max {mx:.1f} deg" if mx is not None else "max: n/a")
            row.addWidget(lab)
            row.addWidget(s, 1)
            row.addWidget(val)
            row.addWidget(maxlab)
            self.layout.addLayout(row)
            s.valueChanged.connect(lambda v, lab=val: lab.setText(f"{v} deg"))
            val.setText(f"{s.value()} deg")
            self.sliders.append((s, mx))
        gl = QtGui.QHBoxLayout()
        gl.addWidget(QtGui.QLabel("Global deformation"))
        self.global_slider = _slider(-100, 100, 100)
        self.global_label = QtGui.QLabel("1.00")
        gl.addWidget(self.global_slider, 1)
        gl.addWidget(self.global_label)
        self.layout.addLayout(gl)
        self.preview_btn = QtGui.QPushButton("Preview")
        self.layout.addWidget(self.preview_btn)
        self.info = QtGui.QLabel("Confirm (OK) runs the joint configuration." if design_adapter.design_available()
                                 else "The joint configuration (core.design) is not installed in this checkout: "
                                      "OK stores the fold angles only.")
        self.info.setWordWrap(True)
        self.layout.addWidget(self.info)
        self.finish_layout()
        self.global_slider.valueChanged.connect(self.preview)
        self.preview_btn.clicked.connect(self.preview)
        self._solver = None

    def folds(self):
        return [float(s.value()) for s, _ in self.sliders]

    def set_fold(self, k, deg):
        self.sliders[k][0].setValue(int(round(deg)))

    def configured_scene(self):
        d = self.scene.to_dict()
        for a, f in zip(d.get("axes", []), self.folds()):
            a["fold_deg"] = f
        sc = Scene.from_dict(d)
        self.report = None
        if design_adapter.design_available() and sc.axes:
            sc, self.report = design_adapter.configure(sc)
        return sc

    def preview(self, *_):
        g = self.global_slider.value() / 100.0
        self.global_label.setText(f"{g:.2f}")
        try:
            from metamaterial_wb.objects.engine import LiveSolver
            sc = self.configured_scene()
            key = sc.to_json()
            if self._solver is None or self._solver[0] != key:
                self._solver = (key, LiveSolver(sc))
            solver = self._solver[1]
            frame = solver.frame(global_deformation=g)
            structure.apply_frame(self.obj, solver, frame, purge=True)
            self.error.setText("")
            if self.report:
                try:
                    from metamaterial_wb.core.design import format_report
                    self.info.setText("\n".join(format_report(self.report)))
                except Exception:
                    pass
        except MetamaterialError as exc:
            self.show_error(str(exc))

    def apply(self):
        sc = self.configured_scene()
        for (s, mx), f in zip(self.sliders, self.folds()):
            if mx is not None and abs(f) > mx + 1e-9:
                raise MetamaterialError(f"fold {f} deg exceeds the maximum {mx:.1f} deg")
        structure.restore_display(self.obj, self.saved)
        doc = self.obj.Document
        with transaction(doc, "Folded shape"):
            structure.set_scene_fields(self.obj, axes=[a.to_dict() for a in sc.axes] or None,
                                       joint_config=sc.joint_config or None)
            doc.recompute()

    def reject(self):
        structure.restore_display(self.obj, self.saved)
        return super().reject()


# ----------------------------------------------------------------------------------------------
