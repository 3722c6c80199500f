"""Simulate: global deformation and one slider per motor and constraint, solved live."""
import time

from PySide import QtGui

from metamaterial_wb.core.errors import MetamaterialError
from metamaterial_wb.objects import structure
from metamaterial_wb.objects.common import assign
from metamaterial_wb.gui.panels.base import BasePanel, _slider
from metamaterial_wb.gui.panels.folded_shape import SLIDER_MIN_WIDTH
from metamaterial_wb.gui.panels.widgets import ElidedLabel, SliderKeys
from metamaterial_wb.gui.i18n import QT_TRANSLATE_NOOP, translate


class SimulatePanel(BasePanel):
    """Global-deformation slider and one slider per motor and constraint, solved live."""
    TITLE = QT_TRANSLATE_NOOP("Metamaterial", "Simulate")
    # the Model property's values (the combo's item data), shown translated
    MODELS = {"linear": QT_TRANSLATE_NOOP("Metamaterial", "linear"),
              "quadratic": QT_TRANSLATE_NOOP("Metamaterial", "quadratic"),
              "nonlinear": QT_TRANSLATE_NOOP("Metamaterial", "nonlinear")}
    ICON = "MM_Simulate.svg"
    ITEM_ROWS = True

    def __init__(self, scene_obj):
        super().__init__()
        self.obj = scene_obj
        self.scene = structure.compose_scene(scene_obj)
        from metamaterial_wb.gui.panels.stream import ServoAngles
        self.angles = ServoAngles(self.scene)     # the angle stream sends for a value, per motor
        self.initial = {}
        self._slider_keys = SliderKeys()   # a focused slider's Home / End / arrows / Page keys (not FreeCAD's view Home)
        # laid out for a narrow task dock (the combo view, ~300 px): the global deformation and every motor take two
        # lines (its name and value, then its slider across the panel), long names are elided (in full in their
        # tooltip) and the statistics wrap, so every slider keeps SLIDER_MIN_WIDTH and nothing runs off the right
        f = QtGui.QFormLayout()
        f.setRowWrapPolicy(QtGui.QFormLayout.RowWrapPolicy.WrapLongRows)
        self.model = QtGui.QComboBox()
        self.model.setSizeAdjustPolicy(QtGui.QComboBox.SizeAdjustPolicy.AdjustToMinimumContentsLengthWithIcon)
        self.model.setMinimumContentsLength(10)
        for m in scene_obj.getEnumerationsOfProperty("Model"):
            self.model.addItem(translate("Metamaterial", self.MODELS.get(m, m)), m)
        self.model.setCurrentIndex(max(0, self.model.findData(scene_obj.Model)))
        f.addRow(translate("Metamaterial", "Model"), self.model)
        self.layout.addLayout(f)
        gbox = QtGui.QGroupBox(translate("Metamaterial", "Global deformation"))     # a title never wraps: short
        gl = QtGui.QGridLayout(gbox)
        self.use_global = QtGui.QCheckBox(translate("Metamaterial", "Use global deformation"))
        self.use_global.setToolTip(translate("Metamaterial", "Perfect propagation: every joint follows the global "
                                             "deformation; the motors' sliders are off while it is ticked"))
        gbox.setToolTip(self.use_global.toolTip())
        self.use_global.setChecked(bool(scene_obj.UseGlobal))
        self.global_slider = _slider(-1000, 1000, int(round(1000 * scene_obj.GlobalDeformation)))
        self.global_slider.setMinimumWidth(SLIDER_MIN_WIDTH)
        self.global_slider.installEventFilter(self._slider_keys)
        self.initial_global = (self.global_slider.value(), float(scene_obj.GlobalDeformation))
        self.global_label = QtGui.QLabel("")
        gl.addWidget(self.use_global, 0, 0)
        gl.addWidget(self.global_label, 0, 1)
        gl.addWidget(self.global_slider, 1, 0, 1, 2)
        gl.setColumnStretch(0, 1)
        self.layout.addWidget(gbox)
        ibox = QtGui.QGroupBox(translate("Metamaterial", "Motors and constraints"))
        il = QtGui.QGridLayout(ibox)
        self.sliders = {}
        self.labels = {}
        self.kinds = {}
        for r, (kind, it) in enumerate(self.scene.fixed_items()):
            il.addWidget(ElidedLabel((translate("Metamaterial", "motor {0} ({1})") if kind == "actuator" else
                                      translate("Metamaterial", "clip {0} ({1})")).format(it.name, it.joint)),
                         2 * r, 0)
            s = _slider(-1000, 1000, int(round(1000 * it.value)))
            s.setMinimumWidth(SLIDER_MIN_WIDTH)
            s.installEventFilter(self._slider_keys)
            self.initial[it.name] = (s.value(), float(it.value))
            lab = QtGui.QLabel("")
            il.addWidget(lab, 2 * r, 1)
            il.addWidget(s, 2 * r + 1, 0, 1, 2)
            self.sliders[it.name] = s
            self.labels[it.name] = lab
            self.kinds[it.name] = kind
            self._label(it.name, float(it.value))
            s.valueChanged.connect(lambda v, n=it.name: self._item_moved(n))
        il.setColumnStretch(0, 1)
        if not self.sliders:
            none = QtGui.QLabel(translate("Metamaterial", "No motors yet: use 'Place motor'."))
            none.setWordWrap(True)
            il.addWidget(none, 0, 0)
        self.layout.addWidget(ibox)
        self.stats = QtGui.QLabel("")
        self.stats.setWordWrap(True)
        self.layout.addWidget(self.stats)
        self.warn = QtGui.QLabel("")
        self.warn.setWordWrap(True)
        self.warn.setStyleSheet("color: #a05a00;")
        self.layout.addWidget(self.warn)
        self.finish_layout()
        self.solver = None
        self.base_warnings = []
        self.frames = 0
        self.update_ms = None
        self.update_times = []
        self.model.currentIndexChanged.connect(lambda *_: self._model_changed(self.model.currentData()))
        self.global_slider.valueChanged.connect(self._global_moved)
        self.use_global.toggled.connect(self._global_toggled)
        self._global_toggled(self.use_global.isChecked(), update=False)
        self._model_changed(self.model.currentData())

    def _model_changed(self, name):
        if self.check_target():
            return
        try:
            if name == self.obj.Model:
                self.solver = structure.solver_for(self.obj, self.scene)   # the stored factorisation
            else:
                from metamaterial_wb.core.live import LiveSolver
                self.solver = LiveSolver(self.scene, model=name)
            self.error.setText("")
            self.base_warnings = list(self.obj.SolveWarnings) + [w for w in self.solver.warnings
                                                                 if w not in self.obj.SolveWarnings]
            self.warn.setText("\n".join(self.base_warnings))
            self.update()
        except MetamaterialError as exc:
            self.show_error(str(exc))

    def _label(self, name, v):
        if self.kinds.get(name) == "actuator":
            deg = self.angles.deg(name, v)
            self.labels[name].setText(translate("Metamaterial", "? deg ({0:+.3f})").format(v) if deg is None else
                                      translate("Metamaterial", "{0:+.1f} deg ({1:+.3f})").format(deg, v))
            self.labels[name].setToolTip("\n".join([translate(
                "Metamaterial", "The angle sent to the servo for this value (closing and opening differ); the "
                "firmware's invert and trim come after"), self.angles.tooltip([name])]))
        else:
            self.labels[name].setText(translate("Metamaterial", "D {0:+.3f}").format(v))

    def _global_toggled(self, on, update=True):
        """Global deformation overrides the motors: their sliders are disabled while it is on."""
        for s in self.sliders.values():
            s.setEnabled(not on)
            s.setToolTip(translate("Metamaterial", "overridden by Global deformation (untick it to use the motors)")
                         if on else "")
        if update:
            self.update()

    def _global_moved(self, *_):
        if not self.use_global.isChecked():
            self.use_global.setChecked(True)  # toggled -> update
        else:
            self.update()

    def _item_moved(self, name):
        self._label(name, self.sliders[name].value() / 1000.0)
        self.update()

    def values(self):
        """The values the sliders show; an untouched slider keeps the stored value exactly."""
        out = {}
        for n, s in self.sliders.items():
            v0, stored = self.initial[n]
            out[n] = stored if s.value() == v0 else s.value() / 1000.0
        return out

    def global_value(self):
        """The global deformation the slider shows; an untouched slider keeps the stored value exactly."""
        g0, stored = self.initial_global
        return stored if self.global_slider.value() == g0 else self.global_slider.value() / 1000.0

    def set_value(self, name, value):
        self.sliders[name].setValue(int(round(1000 * value)))

    def update(self):
        if self.solver is None or self.check_target():
            return
        t0 = time.perf_counter()
        g = self.global_value()
        self.global_label.setText(translate("Metamaterial", "{0:+.3f}").format(g))
        try:
            frame = (self.solver.frame(global_deformation=g) if self.use_global.isChecked()
                     else self.solver.frame(values=self.values()))
        except MetamaterialError as exc:
            self.show_error(str(exc))
            return
        t1 = time.perf_counter()
        self._show_frame_warnings(frame)
        try:
            self.preview_frame(self.obj, self.solver, frame)
        except (ReferenceError, RuntimeError) as exc:
            if self.lost_on(exc):                     # deleted between the check and the drawing
                return
            raise
        self.frames += 1
        self.last_frame = frame
        t2 = time.perf_counter()
        # the panel's own update timer (solve + poses + the preview's corners written; the view renders afterwards)
        self.update_ms = {"solve": 1000 * (t1 - t0), "placements": 1000 * (t2 - t1), "total": 1000 * (t2 - t0)}
        self.update_times.append(self.update_ms["total"])
        self.clear_error()
        self.stats.setText(translate("Metamaterial", "max |D| = {0:.3f}; update {1:.1f} ms (solve {2:.1f}, preview {3:.1f}; no recompute, nothing written)").format(abs(frame.D).max(), self.update_ms['total'], self.update_ms['solve'], self.update_ms['placements']))

    def _show_frame_warnings(self, frame):
        """The model's own warnings for the state shown (a lattice model's hinge past its limits), after the
        scene's; a solve that did not converge says so."""
        extra = [w for w in frame.warnings if w not in self.base_warnings]
        if not frame.converged:
            extra.append(translate("Metamaterial", "the {0} solve did not converge: the pose shown is its last "
                                                   "iterate").format(self.solver.model_name))
        text = "\n".join(self.base_warnings + extra)
        if text != self.warn.text():
            self.warn.setText(text)

    def apply(self):
        vals = self.values()
        doc = self.obj.Document

        def change():
            for it in self.obj.Items:                 # equal values write nothing: an untouched OK leaves no trace
                if it.ItemName in vals:
                    assign(it, "Value", vals[it.ItemName])
            assign(self.obj, "UseGlobal", self.use_global.isChecked())
            assign(self.obj, "GlobalDeformation", self.global_value())   # untouched: the stored value exactly
            assign(self.obj, "Model", self.model.currentData())
        self.commit(doc, "Simulate", change)


# ----------------------------------------------------------------------------------------------
