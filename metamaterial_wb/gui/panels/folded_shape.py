"""Folded shape: one fold per axis (spin box + slider, 0.1 deg steps); the view follows live.

Each axis shows its kinematic maximum (tilt limit, hinge strain, plate contact: ``core.design``) and its
printable maximum (the hinge tilt the printed hinge fits in its node plate) on the control. A fold is
never rounded (12.5 deg stays 12.5) nor clamped: a fold beyond the maximum in force (the kinematic
one, or the printable one with "Limit to printable") is shown in red next to its axis and OK is
refused. Every maximum is shown rounded toward zero (to the spin box's 3 decimals) and a slider ends on its
last 0.1 deg step within the maximum in force, so every value a slider or a stated range offers is allowed.
A fold beyond the slider's end (after ticking "Limit to printable") keeps its value in the spin box while the
slider sits at its end, until the user acts on that slider: End / Home, an arrow, PageUp / PageDown or the wheel
pushing toward that end, a click there or a drag of the handle to it put a refused fold on the slider's end (the
largest fold it offers), and a key pushing toward the end lifts a fold just short of it onto it; an allowed fold
typed past the last 0.1 deg step stays (a push forward never pulls it back). Keys away from the end step from it.
A focused slider keeps its keys from the main window's shortcuts (FreeCAD binds Home to its home view).
Each axis takes two lines (name and spin box, then the slider across the panel) so a slider keeps a width
a hand can drag (>= SLIDER_MIN_WIDTH) in a narrow task dock.
**OK = Confirm** runs the joint configuration and stores the folds and hinge tilts.
"""
import math

from PySide import QtCore, QtGui

from metamaterial_wb.core.errors import MetamaterialError
from metamaterial_wb.core.scene import Scene
from metamaterial_wb.gui.panels.base import BasePanel, _slider
from metamaterial_wb.gui.panels.widgets import ElidedLabel  # noqa: F401 - also imported from here
from metamaterial_wb.gui.panels.widgets import SliderKeys
from metamaterial_wb.gui.panels.checks import unconfigured
from metamaterial_wb.objects import design_adapter, structure
from metamaterial_wb.gui.panels import ranges
from metamaterial_wb.gui.i18n import QT_TRANSLATE_NOOP, translate

FOLD_RANGE = ranges.FIELDS["axes.fold_deg"][:2]     # the scene validator's range of axes[k].fold_deg
FOLD_DECIMALS = 3
STEP = 0.1                       # deg per slider step
STEPS_PER_DEG = int(round(1 / STEP))
TOL = 1e-9                       # deg: a fold this close to a maximum counts as on it (float noise)
SLIDER_MIN_WIDTH = 120           # px: a slider narrower than this cannot be dragged by hand
ROWS_PER_AXIS = 4                # name + fold box, slider, maxima, problem line


def toward_zero(lim, decimals=FOLD_DECIMALS):
    """``lim`` (>= 0) rounded toward zero to ``decimals`` places: a stated range [-x, x] holds allowed folds only
    (97.6281 -> 97.628, never 97.63, which is beyond the maximum); a maximum on a multiple keeps it (15.3)."""
    q = 10 ** decimals
    return math.floor((lim + TOL) * q) / q


def slider_span(lim):
    """The slider's end in steps for the maximum ``lim`` (deg): the last step within it (never beyond)."""
    return int(math.floor((lim + TOL) * STEPS_PER_DEG))


def axis_limits(scene):
    """Per axis ``(kinematic max, binding reason, printable max)`` in deg (None where unknown)."""
    try:
        from metamaterial_wb.core import design
        plans = design.plan_axes(scene)
        phi_c = design.planar_closing_rad(scene)
        out = []
        for p in plans:
            mx, why = design.axis_limits(scene, p, phi_c)
            out.append((mx, why, design.printable_fold_deg(scene, p, phi_c)[0]))
        return out
    except MetamaterialError:
        raise
    except Exception:  # pragma: no cover - design package missing
        return [(design_adapter.max_fold_deg(scene, k), "", None) for k in range(len(scene.axes))]


class FoldedShapePanel(BasePanel):
    TITLE = QT_TRANSLATE_NOOP("Metamaterial", "Folded shape")
    ICON = "MM_FoldedShape.svg"

    def __init__(self, scene_obj):
        super().__init__()
        self.obj = scene_obj
        self._closed = False              # set by cleanup(): late signals (editingFinished as the form closes) do nothing
        self.scene = structure.compose_scene(scene_obj)
        self.limits = axis_limits(unconfigured(self.scene)) if self.scene.axes else []
        self.spins, self.sliders, self.limit_labels = [], [], []
        self._slider_keys = SliderKeys()
        if not self.scene.axes:
            self.layout.addWidget(QtGui.QLabel(translate("Metamaterial", "No rotary axes yet: use 'Rotary axes' first.")))
        self.printable = QtGui.QCheckBox(translate("Metamaterial", "Limit to printable folds"))
        self.printable.setToolTip(translate("Metamaterial", "Hold every fold within what the printed hinges fit in their node plates "
                                  "(otherwise the kinematic maximum applies and Export may refuse the design)"))
        grid = QtGui.QGridLayout()
        # two lines per axis so a narrow task dock (the combo view, ~300 px) leaves the slider a usable width:
        # the axis name (elided, in full in its tooltip) with the fold box, then the slider across the whole width.
        # The tab order follows the lines: fold box, then its slider, axis by axis.
        for k, a in enumerate(self.scene.axes):
            mx, why, pmx = self.limits[k]
            name = getattr(a, "name", "")
            spin = QtGui.QDoubleSpinBox()
            spin.setDecimals(FOLD_DECIMALS)     # what is typed is kept (12.25 stays 12.25); steps of 0.1 deg
            spin.setSingleStep(STEP)
            ranges.bind(spin, "axes.fold_deg")
            spin.setSuffix(" deg")
            spin.setKeyboardTracking(False)
            spin.setValue(float(a.fold_deg))
            s = _slider(-1000, 1000, 0)
            s.setSingleStep(1)
            s.setPageStep(10)
            s.setMinimumWidth(SLIDER_MIN_WIDTH)
            lim = QtGui.QLabel("")
            lim.setWordWrap(True)
            lim.setToolTip(translate("Metamaterial", "kinematic maximum bound by {0}").format(why) if why else "")
            r = ROWS_PER_AXIS * k
            line = (translate("Metamaterial", "vertical {0}") if a.direction == "vertical" else
                    translate("Metamaterial", "horizontal {0}")).format(a.line)
            text = translate("Metamaterial", "{0}: {1}").format(name, line) if name else line
            spin.setAccessibleName(translate("Metamaterial", "Fold of {0}").format(text))    # (named so when refused)
            grid.addWidget(ElidedLabel(text), r, 0)
            grid.addWidget(spin, r, 1)
            grid.addWidget(s, r + 1, 0, 1, 2)
            grid.addWidget(lim, r + 2, 0, 1, 2)
            grid.addWidget(self.problem_label(f"axis{k}"), r + 3, 0, 1, 2)
            self.spins.append(spin)
            self.sliders.append((s, mx))
            self.limit_labels.append(lim)
            s.valueChanged.connect(lambda v, k=k: self._slider_moved(k, v))
            s.actionTriggered.connect(lambda _a, k=k: self._slider_action(k))
            s.sliderReleased.connect(lambda k=k: self._slider_released(k))
            s.installEventFilter(self._slider_keys)
            spin.valueChanged.connect(lambda v, k=k: self._spin_changed(k, v))
            spin.editingFinished.connect(lambda k=k: self._spin_changed(k, self.spins[k].value()))
        grid.setColumnStretch(0, 1)
        self.layout.addLayout(grid)
        self.layout.addWidget(self.printable)
        gl = QtGui.QGridLayout()                       # the same two lines: name and value, then the slider
        self.global_slider = _slider(-100, 100, 100)
        self.global_slider.setMinimumWidth(SLIDER_MIN_WIDTH)
        self.global_slider.installEventFilter(self._slider_keys)
        self.global_label = QtGui.QLabel(translate("Metamaterial", "1.00"))
        gl.addWidget(ElidedLabel(translate("Metamaterial", "Global deformation")), 0, 0)
        gl.addWidget(self.global_label, 0, 1)
        gl.addWidget(self.global_slider, 1, 0, 1, 2)
        gl.setColumnStretch(0, 1)
        self.layout.addLayout(gl)
        self.info = QtGui.QLabel(translate("Metamaterial", "The view follows the folds live; Confirm (OK) stores them with the joint "
                                 "configuration."))
        self.info.setWordWrap(True)
        self.layout.addWidget(self.info)
        self.finish_layout()
        self.report = None
        self._solver = None
        self.previews = 0
        self._preview_timer = QtCore.QTimer()
        self._preview_timer.setSingleShot(True)
        self._preview_timer.setInterval(0)
        self._preview_timer.timeout.connect(self.preview)
        self.global_slider.valueChanged.connect(lambda *_: None if self._closed else self._preview_timer.start())
        self.printable.toggled.connect(self._limits_changed)
        self._limits_changed()

    # limits -----------------------------------------------------------------------------
    def limit_deg(self, k):
        """The maximum in force for axis ``k`` (printable with the toggle on, else kinematic)."""
        mx, _why, pmx = self.limits[k]
        if self.printable.isChecked() and pmx is not None:
            return pmx
        return mx

    def _limits_changed(self, *_):
        if self._closed:
            return
        for k, (s, _mx) in enumerate(self.sliders):
            mx, _why, pmx = self.limits[k]
            lim = self.limit_deg(k)
            span = slider_span(lim if lim is not None else FOLD_RANGE[1])
            s.blockSignals(True)
            s.setRange(-span, span)
            s.setTickInterval(max(1, span // 5))
            s.setValue(int(round(self.spins[k].value() / STEP)))
            s.blockSignals(False)
            kin = translate("Metamaterial", "kinematic +-{0:.3f} deg").format(toward_zero(mx)) if mx is not None else \
                translate("Metamaterial", "kinematic: n/a")
            pr = translate("Metamaterial", "printable +-{0:.3f} deg").format(toward_zero(pmx)) if pmx is not None else \
                translate("Metamaterial", "printable: n/a")
            text = translate("Metamaterial", "{0}, {1}").format(kin, pr)
            if lim is not None:
                text = translate("Metamaterial", "{0} (slider +-{1:.1f})").format(text, span / STEPS_PER_DEG)
            self.limit_labels[k].setText(text)
        self._validate()
        self._preview_timer.start()

    def _validate(self):
        for k, spin in enumerate(self.spins):
            f = spin.value()
            lim = self.limit_deg(k)
            msg = ""
            if lim is not None and abs(f) > lim + TOL:
                b = f"{toward_zero(lim):.{FOLD_DECIMALS}f}"
                msg = (translate("Metamaterial", "{0:g} deg is beyond the printable maximum of this axis: "
                                                 "allowed range [-{1}, {1}] deg")
                       if self.printable.isChecked() and self.limits[k][2] is not None else
                       translate("Metamaterial", "{0:g} deg is beyond the kinematic maximum of this axis: "
                                                 "allowed range [-{1}, {1}] deg")).format(f, b)
            self.set_problem(f"axis{k}", msg)

    # edits ------------------------------------------------------------------------------
    def _slider_moved(self, k, v):
        if self._closed:
            return
        spin = self.spins[k]
        spin.blockSignals(True)
        spin.setValue(v * STEP)
        spin.blockSignals(False)
        self._validate()
        self._preview_timer.start()

    def _at_end(self, k, pos):
        """+1 / -1 when slider ``k``'s position ``pos`` is its right / left end, else 0."""
        s = self.sliders[k][0]
        return 1 if pos == s.maximum() else -1 if pos == s.minimum() else 0

    def _slider_action(self, k):
        """A key, a click on the groove or the wheel on slider ``k`` (Qt has moved its position, not yet its value).
        When the slider stays at an end (it was there: no valueChanged follows) the push went toward that end: a fold
        beyond the maximum in force, or one short of the end (the slider shows it there), goes to the end; an allowed
        fold already past the end stays."""
        if self._closed:
            return
        s = self.sliders[k][0]
        pos = s.sliderPosition()
        side = self._at_end(k, pos)
        if not side or pos != s.value():
            return                                  # the slider moves: valueChanged sets the fold
        f, end, lim = self.spins[k].value(), pos * STEP, self.limit_deg(k)
        refused = lim is not None and abs(f) > lim + TOL
        if refused or side * (end - f) > TOL:
            self._slider_moved(k, pos)          # the fold to the slider's end

    def _slider_released(self, k):
        """The handle of slider ``k`` let go (a drag, or a click on it): at an end with a refused fold beyond that end
        (the handle could not move further), the fold is the slider's end."""
        if self._closed:
            return
        s = self.sliders[k][0]
        pos = s.value()
        side = self._at_end(k, pos)
        f, lim = self.spins[k].value(), self.limit_deg(k)
        if side and lim is not None and abs(f) > lim + TOL and side * (f - pos * STEP) > TOL:
            self._slider_moved(k, pos)          # the fold to the slider's end

    def _spin_changed(self, k, v):
        if self._closed:                    # the closing form's spin box emits editingFinished after cleanup()
            return
        s = self.sliders[k][0]
        s.blockSignals(True)
        s.setValue(int(round(v / STEP)))     # the slider shows it; the spin box keeps the exact value
        s.blockSignals(False)
        self._validate()
        self._preview_timer.start()

    def folds(self):
        """The folds shown; an axis whose spin box still shows its stored fold keeps that fold exactly (a stored
        fold of 5.2504 is shown as 5.250, and an OK that changed nothing writes nothing)."""
        out = []
        for spin, a in zip(self.spins, self.scene.axes):
            v = spin.value()
            out.append(float(a.fold_deg) if v == round(float(a.fold_deg), FOLD_DECIMALS) else float(round(v, 6)))
        return out

    def set_fold(self, k, deg):
        self.spins[k].setValue(float(deg))

    def configured_scene(self):
        d = unconfigured(self.scene).to_dict()
        for a, f in zip(d.get("axes", []), self.folds()):
            a["fold_deg"] = f
        sc = Scene.from_dict(d)
        self.report = None
        if sc.axes:
            sc, self.report = design_adapter.configure(sc)
        return sc

    def preview(self, *_):
        """Show the folds in the 3D view now (called after every edit; nothing is recomputed)."""
        if self._closed:
            return
        g = self.global_slider.value() / 100.0
        self.global_label.setText(translate("Metamaterial", "{0:.2f}").format(g))
        if self.problems:
            return
        try:
            from metamaterial_wb.core.live import LiveSolver
            sc = self.configured_scene()
            key = sc.to_json()
            if self._solver is None or self._solver[0] != key:
                self._solver = (key, LiveSolver(sc))
            solver = self._solver[1]
            self.preview_frame(self.obj, solver, solver.frame(global_deformation=g))
            self.previews += 1
            self.clear_error()
            if self.report:
                try:
                    from metamaterial_wb.core.design import format_report
                    self.info.setText("\n".join(format_report(self.report)))
                except Exception:  # pragma: no cover
                    pass
        except MetamaterialError as exc:
            self.show_error(str(exc))

    def apply(self):
        self._preview_timer.stop()
        sc = self.configured_scene()
        doc = self.obj.Document

        def change():                                 # equal fields write nothing: an untouched OK leaves no trace
            structure.set_scene_fields(self.obj, axes=[a.to_dict() for a in sc.axes] or None,
                                       joint_config=sc.joint_config or None)
        self.commit(doc, "Folded shape", change)

    def cleanup(self):
        self._closed = True
        self._preview_timer.stop()
        super().cleanup()

    def reject(self):
        self._preview_timer.stop()
        return super().reject()
