"""Task panels of the workbench (built in code; every change the user commits is one undo step).

Rules kept by every panel:

* nothing is recomputed while a slider moves or the animation plays: placements are moved from the
  stored factorisation (:class:`~metamaterial_wb.objects.engine.LiveSolver`);
* the placements the panel moved are restored when it closes (OK writes the chosen values into the
  properties and recomputes once, inside one transaction);
* errors are shown in the panel in red, never as modal dialogs and never silently ignored.

``ACTIVE`` is the panel being shown (the GUI tests drive it through its widgets).
"""
import contextlib
import json
import math
import os
import time

import FreeCAD
import FreeCADGui
from PySide import QtCore, QtGui

import metamaterial_wb
from metamaterial_wb.core.errors import MetamaterialError
from metamaterial_wb.core.scene import Scene, validate_layout
from metamaterial_wb.objects import design_adapter, structure

ACTIVE = None


def np_zeros(n):
    import numpy as np
    return np.zeros(n)


@contextlib.contextmanager
def transaction(doc, name):
    """One undo step: everything inside is committed together, or aborted on an error."""
    doc.openTransaction(name)
    try:
        yield
    except Exception:
        doc.abortTransaction()
        raise
    doc.commitTransaction()


def show(panel):
    global ACTIVE
    if FreeCADGui.Control.activeDialog():
        FreeCADGui.Control.closeDialog()
        if ACTIVE is not None:
            ACTIVE.cleanup()
    ACTIVE = panel
    FreeCADGui.Control.showDialog(panel)
    return panel


def _close():
    global ACTIVE
    ACTIVE = None
    FreeCADGui.Control.closeDialog()


def _fit(doc):
    try:
        gd = FreeCADGui.getDocument(doc.Name)
        if gd is not None and gd.ActiveView is not None and hasattr(gd.ActiveView, "fitAll"):
            gd.ActiveView.fitAll()
    except Exception:  # pragma: no cover - display only
        pass


def _slider(lo=-100, hi=100, value=0):
    s = QtGui.QSlider(QtCore.Qt.Horizontal)
    s.setRange(lo, hi)
    s.setValue(value)
    s.setTickPosition(QtGui.QSlider.TicksBelow)
    s.setTickInterval(max(1, (hi - lo) // 10))
    return s


class BasePanel:
    TITLE = "Metamaterial"
    ICON = "Metamaterial_Workbench.svg"

    def __init__(self):
        self.form = QtGui.QWidget()
        self.form.setWindowTitle(self.TITLE)
        self.form.setWindowIcon(QtGui.QIcon(metamaterial_wb.icon_path(self.ICON)))
        self.layout = QtGui.QVBoxLayout(self.form)
        self.error = QtGui.QLabel("")
        self.error.setWordWrap(True)
        self.error.setStyleSheet("color: #c00000;")
        self._observer = None

    def finish_layout(self):
        self.layout.addWidget(self.error)
        self.layout.addStretch(1)

    def show_error(self, text):
        self.error.setText(text)
        FreeCAD.Console.PrintWarning(f"Metamaterial: {text}\n")

    def getStandardButtons(self):
        return QtGui.QDialogButtonBox.Ok | QtGui.QDialogButtonBox.Cancel

    def apply(self):
        """Do the panel's work; raise MetamaterialError to stay open with the message shown."""

    def cleanup(self):
        if self._observer is not None:
            try:
                FreeCADGui.Selection.removeObserver(self._observer)
            except Exception:
                pass
            self._observer = None

    def accept(self):
        try:
            self.apply()
        except (MetamaterialError, ValueError) as exc:
            self.show_error(str(exc))
            return False
        self.cleanup()
        _close()
        return True

    def reject(self):
        self.cleanup()
        _close()
        return True

    # 3D-view picking --------------------------------------------------------------------
    def watch_selection(self, scene_obj, on_joint=None, on_node=None):
        panel = self

        class Obs:
            def addSelection(self, doc, obj, sub, pnt):
                try:
                    panel._picked(scene_obj, obj, sub, on_joint, on_node)
                except Exception as exc:  # pragma: no cover - interactive
                    panel.show_error(str(exc))

        self._observer = Obs()
        FreeCADGui.Selection.addObserver(self._observer, 0)   # 0: unresolved, keeps "Hinges" + "12.Face3"

    def _picked(self, scene_obj, obj_name, sub, on_joint, on_node):
        # a click in the 3D view arrives as (container, "Hinges.12.Face3") or (Hinges, "12.Face3")
        parts = str(sub or "").split(".")
        for k in range(len(parts) - 1):
            if parts[k] in (getattr(scene_obj.HingeArray, "Name", None), getattr(scene_obj.NodeArray, "Name", None)):
                obj_name, sub = parts[k], ".".join(parts[k + 1:])
                break
        idx = pick_index(sub)
        if idx is None:
            return
        if scene_obj.HingeArray is not None and obj_name == scene_obj.HingeArray.Name and on_joint:
            scene = structure.compose_scene(scene_obj)
            on_joint(scene.topology.joint_names[idx])
        elif scene_obj.NodeArray is not None and obj_name == scene_obj.NodeArray.Name and on_node:
            scene = structure.compose_scene(scene_obj)
            i, j = scene.topology.nodes[idx]
            on_node(f"N{i},{j}")


def pick_index(sub):
    """``"12.Face3"`` (a pick on a link array element) -> 12."""
    if not sub:
        return None
    head = str(sub).split(".", 1)[0]
    return int(head) if head.isdigit() else None


# ----------------------------------------------------------------------------------------------
# New structure and Open example
# ----------------------------------------------------------------------------------------------
class NewStructurePanel(BasePanel):
    TITLE = "New metamaterial structure"
    ICON = "MM_NewStructure.svg"
    MAX = 16

    def __init__(self, doc=None):
        super().__init__()
        self.doc = doc
        self.loaded_scene = None
        form = QtGui.QFormLayout()
        self.name = QtGui.QLineEdit("structure")
        self.rows = QtGui.QSpinBox()
        self.rows.setRange(1, self.MAX)
        self.rows.setValue(2)
        self.cols = QtGui.QSpinBox()
        self.cols.setRange(1, self.MAX)
        self.cols.setValue(6)
        self.cell = QtGui.QDoubleSpinBox()
        self.cell.setRange(5.0, 200.0)
        self.cell.setValue(20.0)
        self.cell.setSuffix(" mm")
        form.addRow("Name", self.name)
        form.addRow("Rows", self.rows)
        form.addRow("Columns", self.cols)
        form.addRow("Cell size", self.cell)
        self.layout.addLayout(form)
        presets = QtGui.QHBoxLayout()
        self.grid_btn = QtGui.QPushButton("Grid")
        self.chain_btn = QtGui.QPushButton("Chain")
        self.clear_btn = QtGui.QPushButton("Clear")
        for b in (self.grid_btn, self.chain_btn, self.clear_btn):
            presets.addWidget(b)
        self.layout.addLayout(presets)
        self.layout.addWidget(QtGui.QLabel("Click cells to add or remove them:"))
        self.grid_widget = QtGui.QWidget()
        self.grid = QtGui.QGridLayout(self.grid_widget)
        self.grid.setSpacing(2)
        self.layout.addWidget(self.grid_widget)
        self.buttons = {}
        self.status = QtGui.QLabel("")
        self.status.setWordWrap(True)
        self.layout.addWidget(self.status)
        fl = QtGui.QHBoxLayout()
        self.file = QtGui.QLineEdit()
        self.file.setPlaceholderText("or a scene file (.json)")
        self.browse = QtGui.QPushButton("Load scene file...")
        fl.addWidget(self.file)
        fl.addWidget(self.browse)
        self.layout.addLayout(fl)
        self.finish_layout()
        self.rows.valueChanged.connect(self._rebuild)
        self.cols.valueChanged.connect(self._rebuild)
        self.grid_btn.clicked.connect(self.preset_grid)
        self.chain_btn.clicked.connect(self.preset_chain)
        self.clear_btn.clicked.connect(self.clear)
        self.browse.clicked.connect(self._browse)
        self._rebuild()
        self.preset_grid()

    def _rebuild(self, *_):
        keep = {k for k, b in self.buttons.items() if b.isChecked()}
        for b in self.buttons.values():
            self.grid.removeWidget(b)
            b.deleteLater()
        self.buttons = {}
        for i in range(self.rows.value()):
            for j in range(self.cols.value()):
                b = QtGui.QPushButton("")
                b.setCheckable(True)
                b.setFixedSize(22, 22)
                b.setStyleSheet("QPushButton:checked { background-color: #3b7dd8; }")
                b.setChecked((i, j) in keep)
                b.toggled.connect(self._changed)
                self.grid.addWidget(b, i, j)
                self.buttons[(i, j)] = b
        for c in range(self.MAX + 1):   # keep the toggle buttons packed to the left
            self.grid.setColumnStretch(c, 1 if c == self.cols.value() else 0)
        self._changed()

    def preset_grid(self):
        for b in self.buttons.values():
            b.setChecked(True)
        self._changed()

    def preset_chain(self):
        for (i, j), b in self.buttons.items():
            b.setChecked(i == 0)
        self._changed()

    def clear(self):
        for b in self.buttons.values():
            b.setChecked(False)
        self._changed()

    def toggle(self, i, j):
        b = self.buttons[(i, j)]
        b.setChecked(not b.isChecked())

    def cells(self):
        return sorted(k for k, b in self.buttons.items() if b.isChecked())

    def _changed(self, *_):
        self.loaded_scene = None
        try:
            validate_layout([list(c) for c in self.cells()])
            self.status.setStyleSheet("color: #1a7f2a;")
            self.status.setText(f"{len(self.cells())} cells: a valid layout")
        except MetamaterialError as exc:
            self.status.setStyleSheet("color: #c00000;")
            self.status.setText(str(exc))

    def _browse(self):  # pragma: no cover - modal file dialog, tests call load_file
        path, _ = QtGui.QFileDialog.getOpenFileName(self.form, "Scene file", metamaterial_wb.EXAMPLES_DIR,
                                                    "Scenes (*.json)")
        if path:
            self.load_file(path)

    def load_file(self, path):
        try:
            self.loaded_scene = Scene.load(path)
        except (MetamaterialError, OSError) as exc:
            self.loaded_scene = None
            self.show_error(str(exc))
            return None
        self.file.setText(path)
        self.status.setStyleSheet("color: #1a7f2a;")
        self.status.setText(f"scene {os.path.basename(path)}: {len(self.loaded_scene.cells)} cells, "
                            f"{len(self.loaded_scene.actuators)} motors")
        return self.loaded_scene

    def scene(self):
        if self.loaded_scene is not None:
            return self.loaded_scene
        cells = self.cells()
        validate_layout([list(c) for c in cells])
        return Scene.from_dict({"format": "metamaterial-scene", "version": 1, "name": self.name.text().strip(),
                                "cell_size_mm": float(self.cell.value()),
                                "layout": {"rows": structure.layout_rows(cells)}})

    def apply(self):
        scene = self.scene()
        doc = self.doc or FreeCAD.ActiveDocument or FreeCAD.newDocument()
        with transaction(doc, "New metamaterial structure"):
            self.result = structure.make_structure(doc, scene)
        _fit(doc)


def example_files():
    """Bundled scene files (other JSON files in examples/, e.g. sleeve models, are left out)."""
    d = metamaterial_wb.EXAMPLES_DIR
    out = []
    for f in sorted(os.listdir(d)) if os.path.isdir(d) else []:
        if not f.endswith(".json"):
            continue
        try:
            with open(os.path.join(d, f), encoding="utf-8") as fh:
                if json.load(fh).get("format") == "metamaterial-scene":
                    out.append(f)
        except (OSError, ValueError, AttributeError):
            continue
    return out


class OpenExamplePanel(BasePanel):
    TITLE = "Open example"
    ICON = "MM_OpenExample.svg"

    def __init__(self, doc=None):
        super().__init__()
        self.doc = doc
        self.list = QtGui.QListWidget()
        for f in example_files():
            self.list.addItem(f[:-5])
        self.desc = QtGui.QLabel("")
        self.desc.setWordWrap(True)
        self.layout.addWidget(self.list)
        self.layout.addWidget(self.desc)
        self.finish_layout()
        self.list.currentTextChanged.connect(self._describe)
        if self.list.count():
            items = self.list.findItems("fish", QtCore.Qt.MatchExactly)
            self.list.setCurrentItem(items[0] if items else self.list.item(0))

    def _describe(self, name):
        try:
            with open(metamaterial_wb.example_path(name), encoding="utf-8") as f:
                self.desc.setText(json.load(f).get("description", ""))
        except Exception as exc:
            self.desc.setText(str(exc))

    def select(self, name):
        items = self.list.findItems(name, QtCore.Qt.MatchExactly)
        if not items:
            raise MetamaterialError(f"no example called {name!r}; have {example_files()}")
        self.list.setCurrentItem(items[0])

    def apply(self):
        item = self.list.currentItem()
        if item is None:
            raise MetamaterialError("choose an example")
        scene = Scene.load(metamaterial_wb.example_path(item.text()))
        doc = self.doc or FreeCAD.ActiveDocument or FreeCAD.newDocument(scene.name or "Metamaterial")
        with transaction(doc, "Open example"):
            self.result = structure.make_structure(doc, scene)
        _fit(doc)


# ----------------------------------------------------------------------------------------------
# Rotary axes
# ----------------------------------------------------------------------------------------------
class AxisOverlay:
    """Temporary Coin lines in the 3D view: candidate grid lines (grey) and chosen axes (orange)."""

    def __init__(self, doc):
        from pivy import coin
        self.coin = coin
        self.view = None
        gd = FreeCADGui.getDocument(doc.Name)
        if gd is not None and hasattr(gd.ActiveView, "getSceneGraph"):
            self.view = gd.ActiveView
        self.root = coin.SoSeparator()
        self.root.setName("MetamaterialAxes")
        if self.view is not None:
            self.view.getSceneGraph().addChild(self.root)

    def _group(self, segments, rgb, width, pattern):
        coin = self.coin
        sep = coin.SoSeparator()
        col = coin.SoBaseColor()
        col.rgb = rgb
        style = coin.SoDrawStyle()
        style.lineWidth = width
        style.linePattern = pattern
        pts = coin.SoCoordinate3()
        pts.point.setValues(0, len(segments) * 2, [p for seg in segments for p in seg])
        lines = coin.SoLineSet()
        lines.numVertices.setValues(0, len(segments), [2] * len(segments))
        for n in (col, style, pts, lines):
            sep.addChild(n)
        return sep

    def show(self, candidates, chosen):
        self.root.removeAllChildren()
        self.n_candidates, self.n_chosen = len(candidates), len(chosen)
        if candidates:
            self.root.addChild(self._group(candidates, (0.55, 0.55, 0.6), 1.0, 0x0F0F))
        if chosen:
            self.root.addChild(self._group(chosen, (1.0, 0.5, 0.0), 4.0, 0xFFFF))

    def remove(self):
        if self.view is not None:
            try:
                self.view.getSceneGraph().removeChild(self.root)
            except Exception:  # pragma: no cover - view already gone
                pass
        self.view = None


class FloorOverlay:
    """Temporary translucent floor (Coin) under a simulated trajectory, tilted by its incline."""

    def __init__(self, doc, corners):
        from pivy import coin
        self.view = None
        self.root = coin.SoSeparator()
        self.root.setName("MetamaterialFloor")
        mat = coin.SoMaterial()
        mat.diffuseColor = (0.45, 0.38, 0.3)
        mat.transparency = 0.5
        pts = coin.SoCoordinate3()
        pts.point.setValues(0, 4, [tuple(float(v) for v in c) for c in corners])
        face = coin.SoFaceSet()
        face.numVertices.setValues(0, 1, [4])
        hints = coin.SoShapeHints()
        hints.vertexOrdering = coin.SoShapeHints.COUNTERCLOCKWISE
        for n in (hints, mat, pts, face):
            self.root.addChild(n)
        gd = FreeCADGui.getDocument(doc.Name)
        if gd is not None and hasattr(gd.ActiveView, "getSceneGraph"):
            self.view = gd.ActiveView
            self.view.getSceneGraph().addChild(self.root)

    def remove(self):
        if self.view is not None:
            try:
                self.view.getSceneGraph().removeChild(self.root)
            except Exception:  # pragma: no cover - view already gone
                pass
        self.view = None


def axis_segment(scene, direction, line, z):
    """End points (flat sheet, mm) of an axis' grid line: across every joint it crosses, plus a margin.

    Node N(i,j) sits at (j p, -i p); a vertical axis on cell column k lies at x = (k + 1/2) p and crosses
    H(i,k) for the node rows i of its cells; a horizontal one on cell row k lies at y = -(k + 1/2) p.
    """
    p = scene.cell_size_mm
    m = 0.6
    if direction == "vertical":
        rows = [i for (i, j) in scene.cells if j == line]
        x = (line + 0.5) * p
        return ((x, -(min(rows) - m) * p, z), (x, -(max(rows) + 1 + m) * p, z))
    cols = [j for (i, j) in scene.cells if i == line]
    y = -(line + 0.5) * p
    return (((min(cols) - m) * p, y, z), ((max(cols) + 1 + m) * p, y, z))


class RotaryAxesPanel(BasePanel):
    TITLE = "Rotary axes"
    ICON = "MM_RotaryAxes.svg"

    def __init__(self, scene_obj):
        super().__init__()
        self.obj = scene_obj
        self.scene = structure.compose_scene(scene_obj)
        self.old = {(a.direction, a.line): a.to_dict() for a in self.scene.axes}
        lines = design_adapter.candidate_lines(self.scene)
        self.buttons = {}
        self.layout.addWidget(QtGui.QLabel("Click grid lines here, or click a hinge in the 3D view.\n"
                                           "Vertical axes run down a cell column and cross its H joints;\n"
                                           "horizontal axes run along a cell row and cross its V joints."))
        for d in ("vertical", "horizontal"):
            box = QtGui.QGroupBox(f"{d.capitalize()} axes ({'columns' if d == 'vertical' else 'rows'})")
            lay = QtGui.QHBoxLayout(box)
            for line in lines[d]:
                b = QtGui.QPushButton(str(line))
                b.setCheckable(True)
                b.setFixedWidth(30)
                b.setStyleSheet("QPushButton:checked { background-color: #e07a00; }")
                b.setChecked((d, line) in self.old)
                b.toggled.connect(self._changed)
                lay.addWidget(b)
                self.buttons[(d, line)] = b
            lay.addStretch(1)
            self.layout.addWidget(box)
        self.violations = QtGui.QLabel("")
        self.violations.setWordWrap(True)
        self.violations.setStyleSheet("color: #c00000;")
        self.layout.addWidget(self.violations)
        self.finish_layout()
        # the flat sheet (every D = 0) with the grid lines drawn over it while the panel is open
        self.saved = structure.display_state(scene_obj)
        self.overlay = None
        try:
            from metamaterial_wb.objects.engine import LiveSolver
            solver = LiveSolver(self.scene)
            structure.apply_frame(scene_obj, solver, solver.frame(global_deformation=0.0), purge=True)
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
        self.violations.setText("\n".join(v) if v else "")
        if getattr(self, "overlay", None) is not None:
            z = 0.5 * self.scene.hinge["thickness_mm"] + 0.5
            cand = [axis_segment(self.scene, d, line, z) for (d, line) in sorted(self.buttons)]
            chosen = [axis_segment(self.scene, d, line, z) for (d, line), b in sorted(self.buttons.items())
                      if b.isChecked()]
            self.overlay.show(cand, chosen)

    def cleanup(self):
        if getattr(self, "overlay", None) is not None:
            self.overlay.remove()
            self.overlay = None
        if getattr(self, "saved", None) is not None:
            structure.restore_display(self.obj, self.saved)
            self.saved = None
        super().cleanup()

    def apply(self):
        v = self.current_violations()
        if v:
            raise MetamaterialError("the axes break the rules: " + "; ".join(v))
        self.cleanup()
        doc = self.obj.Document
        with transaction(doc, "Rotary axes"):
            # changing the axes invalidates a previous joint configuration
            structure.set_scene_fields(self.obj, axes=self.axes() or None, joint_config=None)
            doc.recompute()


# ----------------------------------------------------------------------------------------------
# Folded shape
# ----------------------------------------------------------------------------------------------
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
# Flexibility
# ----------------------------------------------------------------------------------------------
class FlexibilityPanel(BasePanel):
    TITLE = "Flexibility"
    ICON = "MM_Flexibility.svg"

    def __init__(self, scene_obj):
        super().__init__()
        self.obj = scene_obj
        self.scene = structure.compose_scene(scene_obj)
        self.overrides = {k: dict(v) for k, v in self.scene.joint_overrides.items()}
        g = QtGui.QGroupBox("All hinges")
        f = QtGui.QFormLayout(g)
        self.length = self._spin(self.scene.hinge["length_mm"])
        self.width = self._spin(self.scene.hinge["width_mm"])
        self.thick = self._spin(self.scene.hinge["thickness_mm"], hi=100.0)
        f.addRow("Length", self.length)
        f.addRow("Width", self.width)
        f.addRow("Thickness", self.thick)
        self.k_label = QtGui.QLabel("")
        f.addRow("k1, k2", self.k_label)
        self.layout.addWidget(g)
        pj = QtGui.QGroupBox("One joint (click a hinge in the 3D view)")
        pf = QtGui.QFormLayout(pj)
        self.joint = QtGui.QComboBox()
        self.joint.addItems(self.scene.topology.joint_names)
        self.j_length = self._spin(self.scene.hinge["length_mm"])
        self.j_width = self._spin(self.scene.hinge["width_mm"])
        self.jk_label = QtGui.QLabel("")
        pf.addRow("Joint", self.joint)
        pf.addRow("Length", self.j_length)
        pf.addRow("Width", self.j_width)
        pf.addRow("k1, k2", self.jk_label)
        bl = QtGui.QHBoxLayout()
        self.set_btn = QtGui.QPushButton("Set for this joint")
        self.del_btn = QtGui.QPushButton("Use global size")
        bl.addWidget(self.set_btn)
        bl.addWidget(self.del_btn)
        pf.addRow(bl)
        self.ov_list = QtGui.QListWidget()
        pf.addRow(self.ov_list)
        self.layout.addWidget(pj)
        self.finish_layout()
        for w in (self.length, self.width, self.thick):
            w.valueChanged.connect(self._update_k)
        for w in (self.j_length, self.j_width):
            w.valueChanged.connect(self._update_jk)
        self.joint.currentTextChanged.connect(self._joint_changed)
        self.set_btn.clicked.connect(self.set_override)
        self.del_btn.clicked.connect(self.remove_override)
        self._update_k()
        self._joint_changed(self.joint.currentText())
        self._refresh_list()
        self.watch_selection(scene_obj, on_joint=lambda j: self.joint.setCurrentText(j))

    @staticmethod
    def _spin(v, hi=20.0):
        s = QtGui.QDoubleSpinBox()
        s.setDecimals(2)
        s.setRange(0.01, hi)
        s.setSingleStep(0.1)
        s.setSuffix(" mm")
        s.setValue(v)
        return s

    @staticmethod
    def k_values(length, width, thickness):
        from metamaterial_wb.core.calibration import default_calibration
        cal = default_calibration()
        return cal.k1(length), cal.k2(width, thickness)

    def _update_k(self, *_):
        try:
            k1, k2 = self.k_values(self.length.value(), self.width.value(), self.thick.value())
            self.k_label.setText(f"k1 = {k1:.3f}, k2 = {k2:.3f}")
            self.error.setText("")
        except MetamaterialError as exc:
            self.k_label.setText("out of the calibrated range")
            self.show_error(str(exc))
        self._update_jk()

    def _update_jk(self, *_):
        try:
            k1, k2 = self.k_values(self.j_length.value(), self.j_width.value(), self.thick.value())
            self.jk_label.setText(f"k1 = {k1:.3f}, k2 = {k2:.3f}")
        except MetamaterialError as exc:
            self.jk_label.setText(str(exc))

    def _joint_changed(self, name):
        ov = self.overrides.get(name, {})
        self.j_length.setValue(ov.get("length_mm", self.length.value()))
        self.j_width.setValue(ov.get("width_mm", self.width.value()))

    def set_override(self):
        name = self.joint.currentText()
        ov = self.overrides.setdefault(name, {})
        ov["length_mm"] = float(self.j_length.value())
        ov["width_mm"] = float(self.j_width.value())
        self._refresh_list()

    def remove_override(self):
        self.overrides.pop(self.joint.currentText(), None)
        self._refresh_list()

    def _refresh_list(self):
        self.ov_list.clear()
        for name, ov in sorted(self.overrides.items()):
            self.ov_list.addItem(f"{name}: " + ", ".join(f"{k} {v:g}" for k, v in sorted(ov.items())))

    def apply(self):
        joints = [dict({"joint": k}, **v) for k, v in sorted(self.overrides.items()) if v]
        d = structure.compose_scene(self.obj).to_dict()
        d["hinge"] = {"length_mm": float(self.length.value()), "width_mm": float(self.width.value()),
                      "thickness_mm": float(self.thick.value())}
        d["joints"] = joints
        Scene.from_dict(d)  # validates sizes against the cell before anything changes
        from metamaterial_wb.core.calibration import joint_stiffness
        joint_stiffness(Scene.from_dict(d))  # and against the calibration table
        doc = self.obj.Document
        with transaction(doc, "Flexibility"):
            self.obj.HingeLength = float(self.length.value())
            self.obj.HingeWidth = float(self.width.value())
            self.obj.HingeThickness = float(self.thick.value())
            structure.set_scene_fields(self.obj, joints=joints or None)
            doc.recompute()


# ----------------------------------------------------------------------------------------------
# Place motor / constraint, add module
# ----------------------------------------------------------------------------------------------
class PlaceItemPanel(BasePanel):
    def __init__(self, scene_obj, kind="actuator"):
        self.kind = kind
        self.TITLE = "Place motor" if kind == "actuator" else "Angular constraint"
        self.ICON = "MM_PlaceMotor.svg" if kind == "actuator" else "MM_PlaceConstraint.svg"
        super().__init__()
        self.obj = scene_obj
        self.scene = structure.compose_scene(scene_obj)
        used = {it.name for _, it in self.scene.fixed_items()}
        prefix = "m" if kind == "actuator" else "c"
        k = 1
        while f"{prefix}{k}" in used:
            k += 1
        f = QtGui.QFormLayout()
        self.name = QtGui.QLineEdit(f"{prefix}{k}")
        self.joint = QtGui.QComboBox()
        self.joint.addItems(self.scene.topology.joint_names)
        self.value = QtGui.QDoubleSpinBox()
        self.value.setRange(-1.0, 1.0)
        self.value.setSingleStep(0.05)
        f.addRow("Name", self.name)
        f.addRow("Joint (or click a hinge)", self.joint)
        f.addRow("Value D", self.value)
        if kind == "actuator":
            self.amp = QtGui.QDoubleSpinBox()
            self.amp.setRange(0.0, 1.0)
            self.amp.setSingleStep(0.05)
            self.amp.setValue(0.5)
            self.freq = QtGui.QDoubleSpinBox()
            self.freq.setRange(0.0, 50.0)
            self.freq.setValue(0.5)
            self.freq.setSuffix(" Hz")
            self.phase = QtGui.QDoubleSpinBox()
            self.phase.setRange(-360.0, 360.0)
            self.phase.setSuffix(" deg")
            f.addRow("Sine amplitude", self.amp)
            f.addRow("Frequency", self.freq)
            f.addRow("Phase offset", self.phase)
        self.layout.addLayout(f)
        self.finish_layout()
        self.watch_selection(scene_obj, on_joint=lambda j: self.joint.setCurrentText(j))

    def apply(self):
        name = self.name.text().strip()
        joint = self.joint.currentText()
        profile = None
        if self.kind == "actuator":
            profile = {"shape": "sine", "amplitude": float(self.amp.value()), "frequency_hz": float(self.freq.value()),
                       "phase_deg": float(self.phase.value())}
        # validate the whole scene with the new item before touching the document
        d = self.scene.to_dict()
        item = {"name": name, "joint": joint, "value": float(self.value.value())}
        if profile:
            item["profile"] = profile
        d["actuators" if self.kind == "actuator" else "constraints"].append(item)
        Scene.from_dict(d)
        doc = self.obj.Document
        with transaction(doc, self.TITLE):
            self.result = structure.make_item(doc, self.obj, self.kind, name, joint, float(self.value.value()),
                                              profile)
            doc.recompute()


class AddModulePanel(BasePanel):
    TITLE = "Add module"
    ICON = "MM_AddModule.svg"
    LABELS = {"servo_housing": "Servo housing (across a joint)", "connection_hub": "Connection hub (node)",
              "stable_hub": "Stable connection hub (across a joint)", "friction_pad": "Friction pad (node)",
              "constraint_clip": "Angular-constraint clip (joint)"}
    ON_JOINT = structure.JOINT_MODULES

    def __init__(self, scene_obj):
        super().__init__()
        self.obj = scene_obj
        self.scene = structure.compose_scene(scene_obj)
        f = QtGui.QFormLayout()
        self.type = QtGui.QComboBox()
        for t in structure.MODULE_TYPES:
            self.type.addItem(self.LABELS[t], t)
        self.target = QtGui.QComboBox()
        f.addRow("Module", self.type)
        f.addRow("On (or click in the 3D view)", self.target)
        self.layout.addLayout(f)
        self.finish_layout()
        self.type.currentIndexChanged.connect(self._targets)
        self._targets()
        self.watch_selection(scene_obj, on_joint=self._pick, on_node=self._pick)

    def module_type(self):
        return self.type.itemData(self.type.currentIndex())

    def set_type(self, t):
        self.type.setCurrentIndex(structure.MODULE_TYPES.index(t))

    def _targets(self, *_):
        self.target.clear()
        if self.module_type() in self.ON_JOINT:
            self.target.addItems(self.scene.topology.joint_names)
        else:
            self.target.addItems([f"N{i},{j}" for i, j in self.scene.topology.nodes])

    def _pick(self, name):
        i = self.target.findText(name)
        if i >= 0:
            self.target.setCurrentIndex(i)

    def apply(self):
        t = self.module_type()
        target = self.target.currentText()
        if not target:
            raise MetamaterialError("choose a node or joint for the module")
        doc = self.obj.Document
        with transaction(doc, "Add module"):
            data = {}
            if t == "servo_housing":
                from metamaterial_wb.gui import preferences
                data["servo"] = preferences.get("DefaultServo")
            self.result = structure.make_module(doc, self.obj, t, target, data)
            doc.recompute()


# ----------------------------------------------------------------------------------------------
# Simulate
# ----------------------------------------------------------------------------------------------
class SimulatePanel(BasePanel):
    """Global-deformation slider and one slider per motor and constraint, solved live."""
    TITLE = "Simulate"
    ICON = "MM_Simulate.svg"

    def __init__(self, scene_obj):
        super().__init__()
        self.obj = scene_obj
        self.saved = structure.display_state(scene_obj)
        self.scene = structure.compose_scene(scene_obj)
        f = QtGui.QFormLayout()
        self.model = QtGui.QComboBox()
        self.model.addItems(list(scene_obj.getEnumerationsOfProperty("Model")))
        self.model.setCurrentText(scene_obj.Model)
        f.addRow("Model", self.model)
        self.layout.addLayout(f)
        gbox = QtGui.QGroupBox("Global deformation (perfect propagation)")
        gl = QtGui.QHBoxLayout(gbox)
        self.use_global = QtGui.QCheckBox("")
        self.use_global.setChecked(bool(scene_obj.UseGlobal))
        self.global_slider = _slider(-100, 100, int(round(100 * scene_obj.GlobalDeformation)))
        self.global_label = QtGui.QLabel("")
        gl.addWidget(self.use_global)
        gl.addWidget(self.global_slider, 1)
        gl.addWidget(self.global_label)
        self.layout.addWidget(gbox)
        ibox = QtGui.QGroupBox("Motors and constraints")
        il = QtGui.QGridLayout(ibox)
        self.sliders = {}
        self.labels = {}
        for r, (kind, it) in enumerate(self.scene.fixed_items()):
            il.addWidget(QtGui.QLabel(("motor " if kind == "actuator" else "clip ") + f"{it.name} ({it.joint})"), r, 0)
            s = _slider(-100, 100, int(round(100 * it.value)))
            lab = QtGui.QLabel(f"{it.value:+.2f}")
            il.addWidget(s, r, 1)
            il.addWidget(lab, r, 2)
            self.sliders[it.name] = s
            self.labels[it.name] = lab
            s.valueChanged.connect(lambda v, n=it.name: self._item_moved(n))
        if not self.sliders:
            il.addWidget(QtGui.QLabel("No motors yet: use 'Place motor'."), 0, 0)
        self.layout.addWidget(ibox)
        self.stats = QtGui.QLabel("")
        self.layout.addWidget(self.stats)
        self.warn = QtGui.QLabel("")
        self.warn.setWordWrap(True)
        self.warn.setStyleSheet("color: #a05a00;")
        self.layout.addWidget(self.warn)
        self.finish_layout()
        self.solver = None
        self.frames = 0
        self.model.currentTextChanged.connect(self._model_changed)
        self.global_slider.valueChanged.connect(self._global_moved)
        self.use_global.toggled.connect(lambda _v: self.update())
        self._model_changed(self.model.currentText())

    def _model_changed(self, name):
        try:
            if name == self.obj.Model:
                self.solver = structure.solver_for(self.obj, self.scene)   # the stored factorisation
            else:
                from metamaterial_wb.objects.engine import LiveSolver
                self.solver = LiveSolver(self.scene, model=name)
            self.error.setText("")
            self.warn.setText("\n".join(list(self.obj.SolveWarnings) + [w for w in self.solver.warnings
                                                                          if w not in self.obj.SolveWarnings]))
            self.update()
        except MetamaterialError as exc:
            self.show_error(str(exc))

    def _global_moved(self, *_):
        if not self.use_global.isChecked():
            self.use_global.setChecked(True)  # toggled -> update
        else:
            self.update()

    def _item_moved(self, name):
        self.labels[name].setText(f"{self.sliders[name].value() / 100:+.2f}")
        if self.use_global.isChecked():
            self.use_global.setChecked(False)  # toggled -> update
        else:
            self.update()

    def values(self):
        return {n: s.value() / 100.0 for n, s in self.sliders.items()}

    def set_value(self, name, value):
        self.sliders[name].setValue(int(round(100 * value)))

    def update(self):
        if self.solver is None:
            return
        t0 = time.perf_counter()
        g = self.global_slider.value() / 100.0
        self.global_label.setText(f"{g:+.2f}")
        try:
            frame = (self.solver.frame(global_deformation=g) if self.use_global.isChecked()
                     else self.solver.frame(values=self.values()))
        except MetamaterialError as exc:
            self.show_error(str(exc))
            return
        structure.apply_frame(self.obj, self.solver, frame, purge=True)
        self.frames += 1
        self.last_frame = frame
        dt = (time.perf_counter() - t0) * 1000
        self.error.setText("")
        self.stats.setText(f"max |D| = {abs(frame.D).max():.3f}; update {dt:.1f} ms (no recompute)")

    def apply(self):
        structure.restore_display(self.obj, self.saved)
        vals = self.values()
        doc = self.obj.Document
        with transaction(doc, "Simulate"):
            for it in self.obj.Items:
                if it.ItemName in vals and abs(it.Value - vals[it.ItemName]) > 1e-12:
                    it.Value = vals[it.ItemName]
            self.obj.UseGlobal = self.use_global.isChecked()
            self.obj.GlobalDeformation = self.global_slider.value() / 100.0
            if self.obj.Model != self.model.currentText():
                self.obj.Model = self.model.currentText()
            doc.recompute()

    def reject(self):
        structure.restore_display(self.obj, self.saved)
        return super().reject()


# ----------------------------------------------------------------------------------------------
# Animate
# ----------------------------------------------------------------------------------------------
def hardware_available():
    """True when the hardware package (serial link + streamer) can be imported."""
    try:
        from metamaterial_wb.hardware import Link, Streamer, channel_map  # noqa: F401
        return True
    except ImportError:
        return False


class AnimatePanel(BasePanel):
    """Timeline from the motors' motion profiles: play / pause / loop / speed, optional streaming."""
    TITLE = "Animate"
    ICON = "MM_Animate.svg"

    def __init__(self, scene_obj):
        super().__init__()
        self.obj = scene_obj
        self.saved = structure.display_state(scene_obj)
        self.scene = structure.compose_scene(scene_obj)
        self.solver = structure.solver_for(scene_obj, self.scene)
        self.table = QtGui.QTableWidget(len(self.scene.actuators), 4)
        self.table.setHorizontalHeaderLabels(["motor", "amplitude", "freq (Hz)", "phase (deg)"])
        self.spins = {}
        for r, a in enumerate(self.scene.actuators):
            p = a.profile or {"shape": "sine", "amplitude": 0.0, "frequency_hz": 0.5, "phase_deg": 0.0}
            self.table.setItem(r, 0, QtGui.QTableWidgetItem(a.name))
            sp = []
            for c, (key, lo, hi, default) in enumerate((("amplitude", 0.0, 1.0, 0.5), ("frequency_hz", 0.0, 50.0, 0.5),
                                                         ("phase_deg", -360.0, 360.0, 0.0)), start=1):
                w = QtGui.QDoubleSpinBox()
                w.setRange(lo, hi)
                w.setSingleStep(0.05 if key != "phase_deg" else 15.0)
                w.setValue(float(p.get(key, default)) if p.get("shape", "sine") == "sine" else default)
                w.setEnabled(p.get("shape", "sine") == "sine")
                w.valueChanged.connect(self._profiles_changed)
                self.table.setCellWidget(r, c, w)
                sp.append(w)
            self.spins[a.name] = sp
        self.table.setMaximumHeight(40 + 30 * max(1, len(self.scene.actuators)))
        self.table.horizontalHeader().setStretchLastSection(True)
        self.layout.addWidget(self.table)
        tl = QtGui.QHBoxLayout()
        self.play_btn = QtGui.QPushButton("Play")
        self.play_btn.setCheckable(True)
        self.loop = QtGui.QCheckBox("Loop")
        self.loop.setChecked(True)
        self.speed = QtGui.QDoubleSpinBox()
        self.speed.setRange(0.05, 10.0)
        self.speed.setValue(1.0)
        self.speed.setSuffix(" x")
        self.duration = QtGui.QDoubleSpinBox()
        self.duration.setRange(0.1, 600.0)
        self.duration.setValue(self.default_duration())
        self.duration.setSuffix(" s")
        tl.addWidget(self.play_btn)
        tl.addWidget(self.loop)
        tl.addWidget(QtGui.QLabel("speed"))
        tl.addWidget(self.speed)
        tl.addWidget(QtGui.QLabel("length"))
        tl.addWidget(self.duration)
        self.layout.addLayout(tl)
        self.timeline = _slider(0, 1000, 0)
        self.time_label = QtGui.QLabel("t = 0.00 s")
        self.layout.addWidget(self.timeline)
        self.layout.addWidget(self.time_label)
        hl = QtGui.QHBoxLayout()
        self.connect_btn = QtGui.QPushButton("Connect")
        self.connect_btn.setCheckable(True)
        from metamaterial_wb.gui import preferences
        self.port = QtGui.QLineEdit(preferences.get("SerialPort"))
        hl.addWidget(QtGui.QLabel("Port"))
        hl.addWidget(self.port)
        hl.addWidget(self.connect_btn)
        self.layout.addLayout(hl)
        if not hardware_available():
            self.connect_btn.setEnabled(False)
            self.connect_btn.setToolTip("the hardware package (metamaterial_wb.hardware) is not available")
        else:
            self.connect_btn.setToolTip("Stream the values shown to the servo firmware at 50 Hz "
                                        "(port loop:// = dry run without hardware)")
        # simulated trajectory (core.dynamics): load DIR/trajectory.json or simulate in the background
        tg = QtGui.QGroupBox("Simulated trajectory (dynamics: gravity, floor contact, friction)")
        tv = QtGui.QVBoxLayout(tg)
        th = QtGui.QHBoxLayout()
        self.traj_load_btn = QtGui.QPushButton("Load...")
        self.traj_load_btn.setToolTip("Play DIR/trajectory.json written by "
                                      "'python3 -m metamaterial_wb simulate SCENE --seconds S --out DIR'")
        self.traj_seconds = QtGui.QDoubleSpinBox()
        self.traj_seconds.setRange(0.05, 600.0)
        self.traj_seconds.setValue(4.0)
        self.traj_seconds.setSuffix(" s")
        self.traj_sim_btn = QtGui.QPushButton("Simulate")
        self.traj_sim_btn.setToolTip("Run the dynamics model on this structure in the background, then play it")
        self.traj_off_btn = QtGui.QPushButton("Motors")
        self.traj_off_btn.setToolTip("Back to the motion profiles (quadratic model)")
        self.traj_off_btn.setEnabled(False)
        th.addWidget(self.traj_load_btn)
        th.addWidget(self.traj_seconds)
        th.addWidget(self.traj_sim_btn)
        th.addWidget(self.traj_off_btn)
        tv.addLayout(th)
        self.traj_progress = QtGui.QProgressBar()
        self.traj_progress.setRange(0, 1000)
        self.traj_progress.setValue(0)
        self.traj_progress.setVisible(False)
        tv.addWidget(self.traj_progress)
        self.traj_label = QtGui.QLabel("playing: the motors' profiles")
        self.traj_label.setWordWrap(True)
        tv.addWidget(self.traj_label)
        self.layout.addWidget(tg)
        self.stats = QtGui.QLabel("")
        self.layout.addWidget(self.stats)
        self.finish_layout()
        self.trajectory = None
        self.trajectory_data = None
        self.floor = None
        self.sim_job = None
        self.sim_timer = QtCore.QTimer()
        self.sim_timer.setInterval(100)
        self.sim_timer.timeout.connect(self._poll_simulation)
        self.traj_load_btn.clicked.connect(self._browse_trajectory)
        self.traj_sim_btn.clicked.connect(lambda: self.simulate_trajectory(self.traj_seconds.value()))
        self.traj_off_btn.clicked.connect(self.clear_trajectory)
        self.t = 0.0
        self.frames = 0
        self.streamer = None
        self.link = None
        self.stream_error = None
        self.shown_values = {}
        self.preview_scene = self.scene
        fps = max(1, int(preferences.get("AnimationFps")))
        self.dt = 1.0 / fps
        self.timer = QtCore.QTimer()
        self.timer.setInterval(int(1000 / fps))
        self.timer.timeout.connect(self.tick)
        self.play_btn.toggled.connect(self._play_toggled)
        self.timeline.sliderMoved.connect(self._scrub)
        self.connect_btn.toggled.connect(self._connect_toggled)
        self._profiles_changed()
        self.show_time(0.0)

    def default_duration(self):
        freqs = [a.profile.get("frequency_hz", 0) for a in self.scene.actuators
                 if a.profile and a.profile.get("shape", "sine") == "sine" and a.profile.get("frequency_hz", 0) > 0]
        if freqs:
            return round(max(1.0 / min(freqs), 0.5), 3)
        periods = [a.profile.get("period_s") for a in self.scene.actuators if a.profile and a.profile.get("period_s")]
        return float(max(periods)) if periods else 4.0

    def profiles(self):
        out = {}
        for a in self.scene.actuators:
            if a.profile is not None and a.profile.get("shape", "sine") != "sine":
                out[a.name] = dict(a.profile)
                continue
            amp, f, ph = (w.value() for w in self.spins[a.name])
            p = {"shape": "sine", "amplitude": float(amp), "frequency_hz": float(f), "phase_deg": float(ph)}
            if a.profile and a.profile.get("offset"):
                p["offset"] = a.profile["offset"]
            out[a.name] = p
        return out

    def set_profile(self, name, amplitude=None, frequency_hz=None, phase_deg=None):
        w = self.spins[name]
        for spin, v in zip(w, (amplitude, frequency_hz, phase_deg)):
            if v is not None:
                spin.setValue(v)

    def _profiles_changed(self, *_):
        d = self.scene.to_dict()
        prof = self.profiles()
        for a in d["actuators"]:
            a["profile"] = prof[a["name"]]
        try:
            self.preview_scene = Scene.from_dict(d)
            self.error.setText("")
        except MetamaterialError as exc:
            self.show_error(str(exc))

    def values_at(self, t):
        from metamaterial_wb.core.motion import scene_values_at
        return self.solver.values_with(scene_values_at(self.preview_scene, t))

    # simulated trajectory ---------------------------------------------------------------------
    def _browse_trajectory(self):  # pragma: no cover - modal file dialog, tests call load_trajectory
        path, _ = QtGui.QFileDialog.getOpenFileName(self.form, "Trajectory", "", "Trajectory (*.json)")
        if path:
            self.load_trajectory(path)

    def load_trajectory(self, source):
        """Play a trajectory: a path to ``trajectory.json`` (or the ``simulate --out`` folder holding it) or
        its parsed dict. Returns True on success (False with the reason shown in the panel)."""
        from metamaterial_wb.objects.engine import TrajectoryPlayer
        try:
            if isinstance(source, dict):
                data, label = source, "simulated here"
            else:
                if os.path.isdir(source):                  # the simulate --out folder
                    source = os.path.join(source, "trajectory.json")
                try:
                    with open(source) as f:
                        data = json.load(f)
                except (OSError, ValueError) as exc:
                    raise MetamaterialError(f"trajectory {source}: cannot read it ({exc})") from None
                label = os.path.basename(os.path.dirname(os.path.abspath(source))) + "/" + os.path.basename(source)
            flat, _R = self.solver.poses(np_zeros(self.scene.topology.n_nodes))
            player = TrajectoryPlayer(data, self.scene, flat)
        except MetamaterialError as exc:
            self.show_error(str(exc))
            return False
        self.pause()
        self._remove_floor()
        self.trajectory, self.trajectory_data = player, data
        try:
            self.floor = FloorOverlay(self.obj.Document, player.floor_corners(float(self.scene.cell_size_mm)))
        except Exception as exc:  # pragma: no cover - display only (no 3D view)
            FreeCAD.Console.PrintWarning(f"Metamaterial: no floor shown ({exc})\n")
        self.duration.setValue(max(0.1, round(player.duration, 3)))
        self.table.setEnabled(False)
        self.traj_off_btn.setEnabled(True)
        self.traj_label.setText(f"playing: {label}, {player.times.size} frames, {player.duration:.2f} s, "
                                f"incline {math.degrees(player.incline):g} deg (side view mapped onto the "
                                "x-z plane: one rigid body per column)")
        self.error.setText("")
        self.show_time(0.0)
        return True

    def _remove_floor(self):
        if getattr(self, "floor", None) is not None:
            self.floor.remove()
        self.floor = None

    def clear_trajectory(self):
        self.pause()
        self._remove_floor()
        self.trajectory = self.trajectory_data = None
        self.table.setEnabled(True)
        self.traj_off_btn.setEnabled(False)
        self.traj_label.setText("playing: the motors' profiles")
        self.duration.setValue(self.default_duration())
        self.solver._last = None
        self.show_time(0.0)

    def simulate_trajectory(self, seconds):
        """Run core.dynamics on this structure in a background thread (progress bar); plays it when done."""
        import threading

        from metamaterial_wb.objects.engine import run_dynamics
        if self.sim_job is not None:
            self.show_error("a simulation is already running")
            return False
        scene = structure.compose_scene(self.obj)
        d = scene.to_dict()
        prof = self.profiles()
        for a in d["actuators"]:
            a["profile"] = prof[a["name"]]
        scene = Scene.from_dict(d)
        job = {"progress": 0.0, "result": None, "error": None, "done": False, "seconds": float(seconds),
               "fps": 1.0 / self.dt}

        def work():
            try:
                job["result"] = run_dynamics(scene, job["seconds"], fps=job["fps"],
                                             progress=lambda f: job.__setitem__("progress", f))
            except Exception as exc:  # noqa: BLE001 - reported in the panel
                job["error"] = str(exc)
            job["done"] = True

        self.sim_job = job
        self.traj_sim_btn.setEnabled(False)
        self.traj_progress.setValue(0)
        self.traj_progress.setVisible(True)
        self.traj_label.setText(f"simulating {seconds:g} s ...")
        job["thread"] = threading.Thread(target=work, daemon=True)
        job["thread"].start()
        self.sim_timer.start()
        return True

    def _poll_simulation(self):
        job = self.sim_job
        if job is None:
            self.sim_timer.stop()
            return
        self.traj_progress.setValue(int(1000 * min(1.0, job["progress"])))
        if not job["done"]:
            return
        self.sim_timer.stop()
        self.sim_job = None
        self.traj_sim_btn.setEnabled(True)
        self.traj_progress.setVisible(False)
        if job["error"]:
            self.show_error(f"simulation failed: {job['error']}")
            self.traj_label.setText("playing: the motors' profiles")
            return
        data, summary = job["result"]
        self.last_simulation = summary
        if self.load_trajectory(data):
            self.traj_label.setText(self.traj_label.text() + f"; centre of mass moved "
                                    f"{summary['displacement_mm']:+.2f} mm")

    def wait_simulation(self, timeout_s=60.0):
        """Block (processing events) until the background simulation is done (tests, scripts)."""
        end = time.perf_counter() + timeout_s
        while self.sim_job is not None and time.perf_counter() < end:
            QtGui.QApplication.processEvents()
            time.sleep(0.01)
        return self.sim_job is None

    def show_time(self, t):
        t0 = time.perf_counter()
        self.t = t
        vals = self.values_at(t)
        try:
            if self.trajectory is not None:
                frame = self.trajectory.frame(self.solver, min(t, self.trajectory.duration))
            else:
                frame = self.solver.frame(values=vals)
        except MetamaterialError as exc:
            self.show_error(str(exc))
            self.pause()
            return
        structure.apply_frame(self.obj, self.solver, frame, purge=True)
        self.frames += 1
        self.last_values = vals
        dur = self.duration.value()
        self.timeline.blockSignals(True)
        self.timeline.setValue(int(round(1000 * min(t, dur) / dur)))
        self.timeline.blockSignals(False)
        self.time_label.setText(f"t = {t:.2f} s")
        # what is shown is what the streamer sends (its thread reads this dict at 50 Hz)
        self.shown_values = {a.name: float(vals[a.name]) for a in self.scene.actuators}
        if self.stream_error:
            self.show_error(f"streaming stopped: {self.stream_error}")
            self.stream_error = None
            self.connect_btn.setChecked(False)
        self.stats.setText(f"frame {self.frames}: {1000 * (time.perf_counter() - t0):.1f} ms (no recompute)")

    def step(self, n=1):
        """Advance ``n`` frames as the timer would (tests and scripted playback)."""
        for _ in range(n):
            self.tick()

    def tick(self):
        t = self.t + self.dt * self.speed.value()
        dur = self.duration.value()
        if t > dur:
            if self.loop.isChecked():
                t = t - dur
            else:
                t = dur
                self.pause()
        self.show_time(t)

    def play(self):
        self.play_btn.setChecked(True)

    def pause(self):
        self.play_btn.setChecked(False)

    def _play_toggled(self, on):
        if on:
            self.play_btn.setText("Pause")
            self.timer.start()
        else:
            self.play_btn.setText("Play")
            self.timer.stop()

    def _scrub(self, v):
        self.show_time(v / 1000.0 * self.duration.value())

    # hardware ---------------------------------------------------------------------------
    def _connect_toggled(self, on):
        if on:
            self.connect(self.port.text().strip())
        else:
            self.disconnect()

    def connect(self, port):
        """Open the serial link, hand-shake, ARM and stream what the panel shows (50 Hz thread)."""
        from metamaterial_wb.hardware import Link, Streamer, channel_map
        link = None
        try:
            dry = port.startswith("loop://")
            link = Link.open(port, dry_run=dry)
            streamer = Streamer(link, channel_map(self.preview_scene))
            streamer.prepare()
            streamer.on_error = self._stream_failed
            if not self.shown_values:
                self.show_time(self.t)
            streamer.start(lambda _t: dict(self.shown_values))
        except Exception as exc:
            if link is not None:
                try:
                    link.close()
                except Exception:
                    pass
            self.show_error(f"cannot stream to {port}: {exc}")
            self.connect_btn.blockSignals(True)
            self.connect_btn.setChecked(False)
            self.connect_btn.blockSignals(False)
            return False
        self.link, self.streamer = link, streamer
        self.connect_btn.blockSignals(True)
        self.connect_btn.setChecked(True)
        self.connect_btn.blockSignals(False)
        self.connect_btn.setText("Disconnect")
        return True

    def _stream_failed(self, message):  # called from the streaming thread
        self.stream_error = message

    def disconnect(self):
        stats = None
        if self.streamer is not None:
            try:
                stats = self.streamer.stop(disarm=False)
            except Exception:
                pass
        if self.link is not None:
            try:
                self.link.close()
            except Exception:
                pass
        self.streamer = self.link = None
        self.connect_btn.blockSignals(True)
        self.connect_btn.setChecked(False)
        self.connect_btn.blockSignals(False)
        self.connect_btn.setText("Connect")
        if stats is not None:
            self.stats.setText(f"streamed {stats.frames} frames, {stats.acked} acknowledged")
        return stats

    def cleanup(self):
        self.timer.stop()
        self.sim_timer.stop()
        self._remove_floor()
        if self.sim_job is not None:
            self.sim_job = None       # the daemon thread finishes on its own; its result is dropped
        self.disconnect()
        super().cleanup()

    def apply(self):
        self.timer.stop()
        structure.restore_display(self.obj, self.saved)
        prof = self.profiles()
        doc = self.obj.Document
        with transaction(doc, "Animate: motion profiles"):
            for it in self.obj.Items:
                p = prof.get(it.ItemName)
                if it.Kind != "actuator" or p is None or p.get("shape") != "sine":
                    continue
                if it.ProfileShape != "sine":
                    it.ProfileShape = "sine"
                for prop, key in (("Amplitude", "amplitude"), ("FrequencyHz", "frequency_hz"),
                                  ("PhaseDeg", "phase_deg")):
                    if abs(getattr(it, prop) - p[key]) > 1e-12:
                        setattr(it, prop, p[key])
            doc.recompute()

    def reject(self):
        self.timer.stop()
        structure.restore_display(self.obj, self.saved)
        return super().reject()


# ----------------------------------------------------------------------------------------------
# Sleeve actuator (issue 9): spec file or parameters -> geometry in the document, prediction
# ----------------------------------------------------------------------------------------------
def sleeve_summary_text(summary):
    """The panel's short report of a ``core.sleeve.pipeline.analyse`` summary (plain text lines)."""
    lines = []
    for uc in summary["unit_cells"]:
        lines.append(f"cell type {uc['type']}: peak {uc['peak_force']:.4g}, valley {uc['valley_force']:.4g} "
                     f"(F / G L^2)")
    ring = summary["ring"]
    fmt = lambda xs: ", ".join(f"{x:.4g}" for x in xs) or "none"  # noqa: E731
    lines.append(f"sleeve ({ring['rings']} x {ring['cells']} cells): peaks {fmt(ring['peaks'])}; "
                 f"valleys {fmt(ring['valleys'])}")
    seq = summary["sequence"]
    lines.append(f"sequence: loading {seq['loading']}, unloading {seq['unloading']} -> "
                 f"{'symmetric' if seq['symmetric'] else 'asymmetric'}")
    pv = summary.get("pv", {})
    if pv.get("peaks_kPa"):
        lines.append(f"pressure peaks {fmt(pv['peaks_kPa'])} kPa")
    return lines


class SleevePanel(BasePanel):
    """Open a ``metamaterial-sleeve`` spec, edit its main parameters, build the sleeve (OK, one undo
    step) and optionally run the prediction (core.sleeve.pipeline.analyse) in the background."""
    TITLE = "Sleeve actuator"
    ICON = "MM_Sleeve.svg"
    DEFAULT = os.path.join(metamaterial_wb.EXAMPLES_DIR, "sleeve.json")

    def __init__(self, doc=None):
        super().__init__()
        self.doc = doc
        self.raw = {}
        fl = QtGui.QHBoxLayout()
        self.path = QtGui.QLineEdit("")
        self.open_btn = QtGui.QPushButton("Open...")
        fl.addWidget(QtGui.QLabel("Spec"))
        fl.addWidget(self.path)
        fl.addWidget(self.open_btn)
        self.layout.addLayout(fl)
        f = QtGui.QFormLayout()
        self.name = QtGui.QLineEdit("sleeve")
        f.addRow("Name", self.name)
        self.dims = {}
        for key, label, lo, hi in (("L_mm", "L (beam span)", 1.0, 500.0), ("c_mm", "c (pillar width)", 0.1, 100.0),
                                   ("delta_mm", "delta (gap)", 0.01, 50.0), ("T_mm", "T (wall thickness)", 0.1, 50.0),
                                   ("shear_modulus_MPa", "G (shear modulus)", 0.01, 1e4)):
            w = QtGui.QDoubleSpinBox()
            w.setDecimals(3)
            w.setRange(lo, hi)
            w.setSingleStep(0.1)
            w.setSuffix(" MPa" if key.endswith("MPa") else " mm")
            f.addRow(label, w)
            self.dims[key] = w
        self.layout.addLayout(f)
        self.types = QtGui.QTableWidget(0, 2)
        self.types.setHorizontalHeaderLabels(["t (mm)", "h (mm)"])
        self.types.setMaximumHeight(130)
        self.layout.addWidget(QtGui.QLabel("Cell types (row = type index)"))
        self.layout.addWidget(self.types)
        bl = QtGui.QHBoxLayout()
        add, rem = QtGui.QPushButton("Add type"), QtGui.QPushButton("Remove last")
        add.clicked.connect(lambda: self.add_type(1.0, 7.0))
        rem.clicked.connect(self.remove_type)
        bl.addWidget(add)
        bl.addWidget(rem)
        self.layout.addLayout(bl)
        f2 = QtGui.QFormLayout()
        self.ring = QtGui.QLineEdit("0, 0, 1, 1")
        self.ring.setToolTip("cell type index of each cell around the circumference")
        self.rings = QtGui.QSpinBox()
        self.rings.setRange(1, 12)
        f2.addRow("Ring pattern", self.ring)
        f2.addRow("Rings", self.rings)
        self.layout.addLayout(f2)
        pl = QtGui.QHBoxLayout()
        self.predict_btn = QtGui.QPushButton("Predict")
        self.predict_btn.setToolTip("Unit-cell and sleeve force-displacement curves, snapping sequence "
                                    "(core.sleeve, about a second per curve)")
        self.progress = QtGui.QProgressBar()
        self.progress.setRange(0, 0)
        self.progress.setVisible(False)
        pl.addWidget(self.predict_btn)
        pl.addWidget(self.progress)
        self.layout.addLayout(pl)
        self.result = QtGui.QLabel("")
        self.result.setWordWrap(True)
        self.result.setTextInteractionFlags(QtCore.Qt.TextSelectableByMouse)
        self.layout.addWidget(self.result)
        el = QtGui.QHBoxLayout()
        self.export_dir = QtGui.QLineEdit(os.path.join(os.path.expanduser("~"), "sleeve_export"))
        self.export_btn = QtGui.QPushButton("Export STEP + 3MF")
        self.export_btn.setToolTip("sleeve.step (named bodies) and sleeve.3mf (TPU sleeve, PLA rings and caps, "
                                   "per-part extruders), as 'sleeve SPEC --step --3mf'")
        self.export_btn.clicked.connect(lambda: self.export(self.export_dir.text().strip()))
        el.addWidget(self.export_dir)
        el.addWidget(self.export_btn)
        self.layout.addLayout(el)
        self.finish_layout()
        self.summary = None
        self.job = None
        self.created = []
        self.timer = QtCore.QTimer()
        self.timer.setInterval(100)
        self.timer.timeout.connect(self._poll)
        self.open_btn.clicked.connect(self._browse)
        self.predict_btn.clicked.connect(self.predict)
        if os.path.exists(self.DEFAULT):
            self.load_spec(self.DEFAULT)

    def _browse(self):  # pragma: no cover - modal file dialog, tests call load_spec
        path, _ = QtGui.QFileDialog.getOpenFileName(self.form, "Sleeve spec", "", "Sleeve spec (*.json)")
        if path:
            self.load_spec(path)

    def add_type(self, t, h):
        r = self.types.rowCount()
        self.types.insertRow(r)
        for c, v in enumerate((t, h)):
            w = QtGui.QDoubleSpinBox()
            w.setDecimals(3)
            w.setRange(0.001, 300.0)
            w.setSingleStep(0.05)
            w.setValue(float(v))
            self.types.setCellWidget(r, c, w)

    def remove_type(self):
        if self.types.rowCount() > 1:
            self.types.removeRow(self.types.rowCount() - 1)

    def load_spec(self, path):
        """Fill the widgets from a spec file (validated by core.sleeve.spec). Returns True on success."""
        from metamaterial_wb.core.sleeve.spec import SleeveSpec
        try:
            spec = SleeveSpec.load(path)
        except (OSError, MetamaterialError) as exc:
            self.show_error(f"{path}: {exc}")
            return False
        self.path.setText(str(path))
        self.set_spec(spec)
        return True

    def set_spec(self, spec):
        self.raw = dict(spec.raw)
        self.name.setText(spec.name)
        for key, attr in (("L_mm", "L"), ("c_mm", "c"), ("delta_mm", "delta"), ("T_mm", "T"),
                          ("shear_modulus_MPa", "G")):
            self.dims[key].setValue(getattr(spec, attr))
        self.types.setRowCount(0)
        for g in spec.cells:
            self.add_type(g.t, g.h)
        uniform = all(row == spec.pattern[0] for row in spec.pattern)
        self.ring.setText(", ".join(str(v) for v in spec.pattern[0]))
        self.rings.setValue(spec.M)
        self.ring.setEnabled(uniform)
        self.rings.setEnabled(uniform)
        self.summary = None
        self.result.setText("")
        self.error.setText("")
        if not uniform:
            self.result.setText("this spec has a per-ring pattern; it is kept as in the file")

    def spec_dict(self):
        """The spec the widgets describe: the loaded file's other fields (model, actuator, ...) kept."""
        d = {k: v for k, v in self.raw.items() if k not in ("cell_types",)}
        d["format"] = "metamaterial-sleeve"
        d.setdefault("version", 1)
        d["name"] = self.name.text().strip() or "sleeve"
        for key, w in self.dims.items():
            d[key] = round(w.value(), 6)
        d["cell_types"] = [{"t_mm": round(self.types.cellWidget(r, 0).value(), 6),
                            "h_mm": round(self.types.cellWidget(r, 1).value(), 6)} for r in range(self.types.rowCount())]
        if self.ring.isEnabled():
            try:
                d["ring"] = [int(x) for x in self.ring.text().replace(";", ",").split(",") if x.strip()]
            except ValueError:
                raise MetamaterialError(f"ring pattern {self.ring.text()!r}: expected cell type indices "
                                        "separated by commas, e.g. 0, 0, 1, 1") from None
            d["rings"] = int(self.rings.value())
            d.pop("pattern", None)
        return d

    def spec(self):
        from metamaterial_wb.core.sleeve.spec import SleeveSpec
        return SleeveSpec(self.spec_dict(), "panel")

    # prediction (background thread) -------------------------------------------------------
    def predict(self):
        import threading

        from metamaterial_wb.core.sleeve.pipeline import analyse
        if self.job is not None:
            return False
        try:
            spec = self.spec()
        except MetamaterialError as exc:
            self.show_error(str(exc))
            return False
        self.error.setText("")
        job = {"done": False, "summary": None, "error": None, "stage": "", "spec": spec}

        def work():
            try:
                job["summary"], _curves = analyse(spec, log=lambda s: job.__setitem__("stage", s))
            except Exception as exc:  # noqa: BLE001 - reported in the panel
                job["error"] = str(exc)
            job["done"] = True

        self.job = job
        self.predict_btn.setEnabled(False)
        self.progress.setVisible(True)
        self.result.setText("predicting ...")
        threading.Thread(target=work, daemon=True).start()
        self.timer.start()
        return True

    def _poll(self):
        job = self.job
        if job is None:
            self.timer.stop()
            return
        if not job["done"]:
            if job["stage"]:
                self.result.setText("predicting: " + job["stage"])
            return
        self.timer.stop()
        self.job = None
        self.predict_btn.setEnabled(True)
        self.progress.setVisible(False)
        if job["error"]:
            self.result.setText("")
            self.show_error(f"prediction failed: {job['error']}")
            return
        self.summary = job["summary"]
        self.result.setText("\n".join(sleeve_summary_text(self.summary)))

    def wait_prediction(self, timeout_s=120.0):
        end = time.perf_counter() + timeout_s
        while self.job is not None and time.perf_counter() < end:
            QtGui.QApplication.processEvents()
            time.sleep(0.01)
        return self.job is None

    def export(self, folder):
        """Write sleeve.step and sleeve.3mf into ``folder`` (via a temporary folder: nothing half-written).
        Returns the paths written, or [] with the error shown."""
        import shutil
        import tempfile

        from metamaterial_wb.geometry.sleeve import export_sleeve
        if not folder:
            self.show_error("export: choose a folder")
            return []
        folder = os.path.abspath(folder)
        QtGui.QApplication.setOverrideCursor(QtCore.Qt.WaitCursor)
        tmp = None
        try:
            spec = self.spec()
            os.makedirs(os.path.dirname(folder), exist_ok=True)
            tmp = tempfile.mkdtemp(prefix=".sleeve-export-", dir=os.path.dirname(folder))
            names = export_sleeve(spec, tmp, step=True, threemf=True)
            os.makedirs(folder, exist_ok=True)
            for n in names:
                os.replace(os.path.join(tmp, n), os.path.join(folder, n))
        except (MetamaterialError, OSError) as exc:
            self.show_error(f"export: {exc}")
            return []
        finally:
            QtGui.QApplication.restoreOverrideCursor()
            if tmp:
                shutil.rmtree(tmp, ignore_errors=True)
        self.error.setText("")
        paths = [os.path.join(folder, n) for n in names]
        FreeCAD.Console.PrintMessage("Metamaterial sleeve export: " + ", ".join(paths) + "\n")
        self.result.setText((self.result.text() + "\n" if self.result.text() else "") + "wrote " + ", ".join(names))
        return paths

    def cleanup(self):
        self.timer.stop()
        self.job = None
        super().cleanup()

    def apply(self):
        from metamaterial_wb.geometry import sleeve as geo
        spec = self.spec()
        doc = self.doc or FreeCAD.ActiveDocument or FreeCAD.newDocument("Sleeve")
        self.doc = doc
        with transaction(doc, "Sleeve actuator"):
            part = doc.addObject("App::Part", "Sleeve")
            part.Label = spec.name
            part.addProperty("App::PropertyString", "SleeveSpec", "Metamaterial",
                             "the sleeve spec (metamaterial-sleeve JSON) the parts were built from")
            part.SleeveSpec = json.dumps(self.spec_dict(), indent=1)
            objs = geo.add_to_document(spec, doc)
            for o in objs:
                part.addObject(o)
            doc.recompute()
        self.created = [part] + list(objs)
        _fit(doc)


# ----------------------------------------------------------------------------------------------
# Export
# ----------------------------------------------------------------------------------------------
class ExportPanel(BasePanel):
    TITLE = "Export"
    ICON = "MM_Export.svg"

    def __init__(self, scene_obj):
        super().__init__()
        self.obj = scene_obj
        f = QtGui.QFormLayout()
        base = os.path.splitext(scene_obj.Document.FileName)[0] if scene_obj.Document.FileName else \
            os.path.join(os.path.expanduser("~"), scene_obj.SceneName or "metamaterial")
        self.path = QtGui.QLineEdit(base + "_export")
        self.step = QtGui.QCheckBox("STEP (named bodies, assembly)")
        self.step.setChecked(True)
        self.threemf = QtGui.QCheckBox("3MF (PLA nodes / TPU hinges)")
        self.threemf.setChecked(True)
        self.modules = QtGui.QCheckBox("Modules as separate files")
        self.modules.setChecked(True)
        self.sockets = QtGui.QCheckBox("Snap-fit sockets on the nodes")
        self.sockets.setChecked(True)
        f.addRow("Folder", self.path)
        f.addRow(self.sockets)
        f.addRow(self.step)
        f.addRow(self.threemf)
        f.addRow(self.modules)
        self.layout.addLayout(f)
        self.result_label = QtGui.QLabel("")
        self.result_label.setWordWrap(True)
        self.layout.addWidget(self.result_label)
        self.finish_layout()
        self.written = []

    def apply(self):
        from metamaterial_wb.gui import exporting
        if not (self.step.isChecked() or self.threemf.isChecked()):
            raise MetamaterialError("choose STEP, 3MF or both")
        self.warnings = []
        self.written = exporting.export_structure(self.obj, self.path.text().strip(), step=self.step.isChecked(),
                                                  threemf=self.threemf.isChecked(), modules=self.modules.isChecked(),
                                                  warnings=self.warnings, sockets=self.sockets.isChecked())
        for w in self.warnings:
            FreeCAD.Console.PrintWarning(f"Metamaterial export: {w}\n")
        FreeCAD.Console.PrintMessage("Metamaterial export: " + ", ".join(self.written) + "\n")
