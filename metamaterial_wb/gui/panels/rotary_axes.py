"""Rotary axes: toggle grid lines (panel buttons or hinge clicks); rule violations listed."""
import FreeCAD
from PySide import QtGui

from metamaterial_wb.core.errors import MetamaterialError
from metamaterial_wb.objects import design_adapter, structure
from metamaterial_wb.gui.panels.base import BasePanel
from metamaterial_wb.gui.panels.overlays import AxisOverlay, axis_segment
from metamaterial_wb.gui.i18n import QT_TRANSLATE_NOOP, translate


BUTTONS_PER_ROW = 6       # grid-line buttons (30 px) per row: they fit a ~300 px task dock


class RotaryAxesPanel(BasePanel):
    VIEW_ATTRS = ("overlay",)
    TITLE = QT_TRANSLATE_NOOP("Metamaterial", "Rotary axes")
    ICON = "MM_RotaryAxes.svg"

    def __init__(self, scene_obj):
        super().__init__()
        self.obj = scene_obj
        self.scene = structure.compose_scene(scene_obj)
        self.old = {(a.direction, a.line): a.to_dict() for a in self.scene.axes}
        lines = design_adapter.candidate_lines(self.scene)
        self.buttons = {}
        intro = QtGui.QLabel(translate("Metamaterial", "Click grid lines here, or click a hinge in the 3D view.\n"
                                       "Vertical axes run down a cell column and cross its H joints;\n"
                                       "horizontal axes run along a cell row and cross its V joints."))
        intro.setWordWrap(True)                 # a narrow task dock (the combo view, ~300 px): the lines wrap
        self.layout.addWidget(intro)
        for d in ("vertical", "horizontal"):
            box = QtGui.QGroupBox(translate("Metamaterial", "Vertical axes (columns)") if d == "vertical" else
                                  translate("Metamaterial", "Horizontal axes (rows)"))
            lay = QtGui.QGridLayout(box)        # BUTTONS_PER_ROW a row: a wide sheet's buttons wrap, never widen
            for k, line in enumerate(lines[d]):
                b = QtGui.QPushButton(str(line))
                b.setCheckable(True)
                b.setFixedWidth(30)
                b.setStyleSheet("QPushButton:checked { background-color: #e07a00; }")
                b.setChecked((d, line) in self.old)
                b.toggled.connect(self._changed)
                lay.addWidget(b, k // BUTTONS_PER_ROW, k % BUTTONS_PER_ROW)
                self.buttons[(d, line)] = b
            lay.setColumnStretch(BUTTONS_PER_ROW, 1)
            self.layout.addWidget(box)
        self.violations = self.problem_label("axes")
        self.violations.setWordWrap(True)
        self.violations.setStyleSheet("color: #c00000;")
        self.layout.addWidget(self.violations)
        self.finish_layout()
        # the flat sheet (every D = 0) with the grid lines drawn over it while the panel is open
        self.overlay = None
        try:
            from metamaterial_wb.core.live import LiveSolver
            solver = LiveSolver(self.scene)
            self.preview_frame(scene_obj, solver, solver.frame(global_deformation=0.0))
            self.overlay = AxisOverlay(scene_obj.Document)
        except Exception as exc:  # pragma: no cover - display only
            FreeCAD.Console.PrintWarning(f"Metamaterial: no axis overlay ({exc})\n")
        self._changed()
        self.watch_selection(scene_obj, on_joint=self.pick_joint)

    def axes(self):
        out = []
        for (d, line), b in sorted(self.buttons.items()):
            if b.isChecked():
                a = dict(self.old.get((d, line), {"direction": d, "line": line, "fold_deg": 0.0}))
                out.append(a)
        return out

    def set_axis(self, direction, line, on=True):
        self.buttons[(direction, int(line))].setChecked(on)

    def pick_joint(self, joint):
        """A hinge clicked in the 3D view toggles the axis that crosses it."""
        kind, rest = joint[0], joint[1:]
        i, j = (int(x) for x in rest.split(","))
        key = ("vertical", j) if kind == "H" else ("horizontal", i)
        if key in self.buttons:
            b = self.buttons[key]
            b.setChecked(not b.isChecked())

    def current_violations(self):
        return design_adapter.axis_violations(self.scene, self.axes())

    def _changed(self, *_):
        v = self.current_violations()
        self.set_problem("axes", "\n".join(v))
        self.clear_error()
        if getattr(self, "overlay", None) is not None:
            z = 0.5 * self.scene.hinge["thickness_mm"] + 0.5
            cand = [axis_segment(self.scene, d, line, z) for (d, line) in sorted(self.buttons)]
            chosen = [axis_segment(self.scene, d, line, z) for (d, line), b in sorted(self.buttons.items())
                      if b.isChecked()]
            names = [f"{'col' if d == 'vertical' else 'row'} {line}" for (d, line) in sorted(self.buttons)]
            self.overlay.show(cand, chosen, names)

    def cleanup(self):
        if getattr(self, "overlay", None) is not None:
            self.overlay.remove()
            self.overlay = None
        super().cleanup()

    def apply(self):
        v = self.current_violations()
        if v:
            raise MetamaterialError(translate("Metamaterial", "the axes break the rules: {0}").format("; ".join(v)))
        doc = self.obj.Document

        def key(a):
            return (a.get("direction"), a.get("line"))
        if sorted(self.axes(), key=key) == sorted(structure.compose_scene(self.obj).to_dict().get("axes", []),
                                                  key=key):
            return                                    # the same axes in any order: the design (joint_config) kept
        # changing the axes invalidates a previous joint configuration
        self.commit(doc, "Rotary axes", lambda: structure.set_scene_fields(self.obj, axes=self.axes() or None,
                                                                           joint_config=None))


# ----------------------------------------------------------------------------------------------
