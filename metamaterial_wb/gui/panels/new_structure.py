"""New structure: rows / columns, toggle cells on a grid, presets, or a scene file.

The grid editor and a scene file never mix: while the file field holds a path the structure comes from the
file (its layout, cell size, motors), so the grid, its presets and the cell size are disabled (a note says
so) and their problems do not block OK; clearing the file field gives them back, with their problems. The
Name field names the structure either way: a loaded file fills it with the file's name unless the user
typed a name.
"""
import os

import FreeCAD
from PySide import QtCore, QtGui

import metamaterial_wb
from metamaterial_wb.core.errors import MetamaterialError
from metamaterial_wb.core.scene import MAX_CELLS, MAX_INDEX, Scene, validate_layout
from metamaterial_wb.objects import structure
from metamaterial_wb.gui.panels.base import GREEN, BasePanel, _fit
from metamaterial_wb.gui.panels.checks import design_problem
from metamaterial_wb.gui.panels import ranges
from metamaterial_wb.gui.i18n import QT_TRANSLATE_NOOP, translate


def _check_full_grid(rows, cols):
    """Check a full rows x cols grid as Scene.from_dict does, without building its cells when it passes: a
    full rectangle is one connected structure without holes, so only the size budget of ``layout.grid``
    can refuse it, and Scene.from_dict refuses that before it allocates anything (its own message). Within
    the budget nothing is built: a 1000 x 1000 grid cost seconds per keystroke; OK builds the scene."""
    if rows * cols > MAX_CELLS or max(rows, cols) > MAX_INDEX:
        Scene.from_dict({"format": "metamaterial-scene", "version": 1, "layout": {"grid": [rows, cols]}})


class NewStructurePanel(BasePanel):
    """Rows / columns and the toggle-button grid (cells named [row, col], as the rule messages name
    them), presets, or a scene file (typed or browsed; checked as the structure would be built)."""
    TITLE = QT_TRANSLATE_NOOP("Metamaterial", "New metamaterial structure")
    ICON = "MM_NewStructure.svg"
    BUTTONS_MAX = 32          # beyond 32 x 32 the layout is the full grid (too many buttons to click)
    GRID_MAX = 2000           # the scene validator allows at most 1,000,000 cells (it says so in words)
    DEFAULT_NAME = "structure"

    def __init__(self, doc=None):
        super().__init__()
        self.doc = doc
        self.loaded_scene = None
        self.loaded_path = None
        self._auto_name = self.DEFAULT_NAME     # the name the panel put in the Name field (not the user)
        self._name_typed = False
        self._file_on = False                   # the grid editor is disabled for a scene file
        form = QtGui.QFormLayout()
        self.name = QtGui.QLineEdit(self.DEFAULT_NAME)
        self.rows = QtGui.QSpinBox()
        self.rows.setRange(1, self.GRID_MAX)
        ranges.ui_only(self.rows, "the grid editor (one button per cell); larger sheets come from a scene file")
        self.rows.setValue(2)
        self.cols = QtGui.QSpinBox()
        self.cols.setRange(1, self.GRID_MAX)
        ranges.ui_only(self.cols, "the grid editor (one button per cell); larger sheets come from a scene file")
        self.cols.setValue(6)
        for w in (self.rows, self.cols):
            w.setKeyboardTracking(False)
        self.cell = QtGui.QDoubleSpinBox()
        ranges.bind(self.cell, "cell_size_mm")
        self.cell.setValue(20.0)
        self.cell.setSuffix(" mm")
        self.cell.setKeyboardTracking(False)
        form.addRow(translate("Metamaterial", "Name"), self.name)
        form.addRow(translate("Metamaterial", "Rows"), self.rows)
        form.addRow(translate("Metamaterial", "Columns"), self.cols)
        form.addRow(self.problem_label("grid"))
        form.addRow(translate("Metamaterial", "Cell size"), self.cell)
        form.addRow(self.problem_label("cell"))
        self.layout.addLayout(form)
        presets = QtGui.QHBoxLayout()
        self.grid_btn = QtGui.QPushButton(translate("Metamaterial", "Grid"))
        self.chain_btn = QtGui.QPushButton(translate("Metamaterial", "Chain"))
        self.clear_btn = QtGui.QPushButton(translate("Metamaterial", "Clear"))
        for b in (self.grid_btn, self.chain_btn, self.clear_btn):
            presets.addWidget(b)
        self.layout.addLayout(presets)
        self.layout.addWidget(QtGui.QLabel(translate("Metamaterial", "Click cells [row, col] to add or remove them:")))
        self.grid_widget = QtGui.QWidget()
        self.grid = QtGui.QGridLayout(self.grid_widget)
        self.grid.setSpacing(2)
        self.layout.addWidget(self.grid_widget)
        self.grid_widget.setStyleSheet("QPushButton:checked { background-color: #3b7dd8; }")
        self.buttons = {}
        self.headers = []
        self._col_heads, self._row_heads = {}, {}
        self.status = QtGui.QLabel("")
        self.status.setWordWrap(True)
        self.layout.addWidget(self.status)
        self.file_note = QtGui.QLabel(translate(
            "Metamaterial", "The structure comes from the scene file (its cells, cell size and motors): the grid "
                            "and the cell size above are not used. Clear the file field to use them again."))
        self.file_note.setWordWrap(True)
        self.file_note.setVisible(False)
        self.layout.addWidget(self.file_note)
        fl = QtGui.QHBoxLayout()
        self.file = QtGui.QLineEdit()
        self.file.setClearButtonEnabled(True)
        self.file.setPlaceholderText(translate("Metamaterial", "or a scene file (.json): type its path"))
        self.browse = QtGui.QPushButton(translate("Metamaterial", "Load scene file..."))
        fl.addWidget(self.file)
        fl.addWidget(self.browse)
        self.layout.addLayout(fl)
        self.layout.addWidget(self.problem_label("file"))
        self.finish_layout()
        self.rows.valueChanged.connect(self._rebuild)
        self.cols.valueChanged.connect(self._rebuild)
        self.cell.valueChanged.connect(self._changed)
        self.grid_btn.clicked.connect(self.preset_grid)
        self.chain_btn.clicked.connect(self.preset_chain)
        self.clear_btn.clicked.connect(self.clear)
        self.browse.clicked.connect(self._browse)
        self.file.editingFinished.connect(self._file_entered)
        self.file.textChanged.connect(self._file_edited)
        self.name.textEdited.connect(self._name_edited)
        self._rebuild()
        self.preset_grid()

    def big(self):
        return self.rows.value() > self.BUTTONS_MAX or self.cols.value() > self.BUTTONS_MAX

    def _rebuild(self, *_):
        """Fit the toggle grid to rows x columns. Only the cells and headers that come or go are made or
        removed (the others keep their state), so one more row costs one row of buttons; a big layout (the
        full grid) has no buttons, and back below the limit it stays full."""
        rows, cols = self.rows.value(), self.cols.value()
        was_big, self._was_big = getattr(self, "_was_big", False), self.big()
        if self.big():
            rows = cols = 0                     # no buttons at all
        for key in [k for k in self.buttons if k[0] >= rows or k[1] >= cols]:
            self._drop(self.buttons.pop(key))
        for heads, n in ((self._col_heads, cols), (self._row_heads, rows)):
            for k in [k for k in heads if k >= n]:
                self._drop(heads.pop(k))
        for j in range(cols):
            if j not in self._col_heads:
                h = QtGui.QLabel(str(j))
                h.setAlignment(QtCore.Qt.AlignmentFlag.AlignCenter)
                self.grid.addWidget(h, 0, j + 1)
                self._col_heads[j] = h
        for i in range(rows):
            if i not in self._row_heads:
                h = QtGui.QLabel(str(i))
                self.grid.addWidget(h, i + 1, 0)
                self._row_heads[i] = h
            for j in range(cols):
                if (i, j) not in self.buttons:
                    b = QtGui.QPushButton("")
                    b.setCheckable(True)
                    b.setFixedSize(22, 22)
                    b.setToolTip(translate("Metamaterial", "cell [{0}, {1}]").format(i, j))
                    b.setAccessibleName(f"cell [{i}, {j}]")
                    b.setChecked(was_big)
                    b.toggled.connect(self._changed)
                    self.grid.addWidget(b, i + 1, j + 1)
                    self.buttons[(i, j)] = b
        self.headers = list(self._col_heads.values()) + list(self._row_heads.values())
        if not self.big():
            for c in range(self.BUTTONS_MAX + 2):   # keep the toggle buttons packed to the left
                self.grid.setColumnStretch(c, 1 if c == cols + 1 else 0)
        self.grid_widget.setVisible(not self.big())
        self._tab_order()
        self._changed()

    def _tab_order(self):
        """Tab follows the panel's visual order: the presets, the cell toggles row by row (they are made after
        the file field and would come last), then the file field and its button."""
        chain = [self.clear_btn] + [self.buttons[k] for k in sorted(self.buttons)] + [self.file, self.browse]
        for a, b in zip(chain, chain[1:]):
            QtGui.QWidget.setTabOrder(a, b)

    def _drop(self, w):
        self.grid.removeWidget(w)
        w.deleteLater()

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

    def n_cells(self):
        """len(cells()) without listing a big layout's cells."""
        if self.big():
            return self.rows.value() * self.cols.value()
        return sum(b.isChecked() for b in self.buttons.values())

    def cells(self):
        if self.big():
            return [(i, j) for i in range(self.rows.value()) for j in range(self.cols.value())]
        return sorted(k for k, b in self.buttons.items() if b.isChecked())

    def _layout_dict(self):
        if self.big():
            return {"grid": [self.rows.value(), self.cols.value()]}
        return {"rows": structure.layout_rows(self.cells())}

    def file_mode(self):
        """True while the file field holds a path: the structure comes from the file, not the grid."""
        return bool(self.file.text().strip())

    def _grid_widgets(self):
        return [self.rows, self.cols, self.cell, self.grid_btn, self.chain_btn, self.clear_btn, self.grid_widget]

    def _use_file(self, on):
        """Enable the grid editor or the scene file (one of them makes the structure)."""
        self._file_on = on
        for w in self._grid_widgets():
            w.setEnabled(not on)
        self.file_note.setVisible(on)
        if on:
            self.set_problem("grid", "")       # the unused grid's problems never block a file
            self.set_problem("cell", "")
            self._forget_refused()
        else:
            self.set_problem("file", "")
            if self.name.text() == self._auto_name and not self._name_typed:
                self._set_name(self.DEFAULT_NAME)
            self._changed()

    def _forget_refused(self):
        """A keystroke refused in a grid box does not block OK while the file (not the grid) is used."""
        for w in (self.rows, self.cols, self.cell):
            w.setProperty(ranges.REFUSED, "")

    def _name_edited(self, *_):
        self._name_typed = True

    def _set_name(self, text):
        self.name.setText(text)
        self._auto_name = text

    def _changed(self, *_):
        if self.file_mode():
            return                             # the grid is not used (and disabled) while a file is
        grid = cell = ""
        try:
            if self.big():
                _check_full_grid(self.rows.value(), self.cols.value())
            else:
                validate_layout([list(c) for c in self.cells()])
        except MetamaterialError as exc:
            grid = str(exc)
        try:
            Scene.from_dict({"format": "metamaterial-scene", "version": 1, "cell_size_mm": float(self.cell.value()),
                             "layout": {"grid": [1, 1]}})
        except MetamaterialError as exc:
            cell = str(exc)
        self.set_problem("grid", grid)
        self.set_problem("cell", cell)
        if grid or cell:
            self.status.setText("")
        else:
            self.status.setStyleSheet(GREEN)
            n = self.n_cells()
            self.status.setText((translate("Metamaterial", "{0} cells: a valid layout (the full grid)") if self.big() else
                                 translate("Metamaterial", "{0} cells: a valid layout")).format(n))

    def _file_entered(self):
        typed = self.file.text().strip()
        if typed and typed != self.loaded_path:
            self.load_file(typed)

    def _file_edited(self, text):
        if text.strip() != self.loaded_path:
            self.loaded_scene = self.loaded_path = None
            self.set_problem("file", "")      # checked again on Enter / OK
            self.status.setText("")
        if self.file_mode() != self._file_on:
            self._use_file(self.file_mode())

    def _browse(self):  # pragma: no cover - modal file dialog, tests type the path
        path, _ = QtGui.QFileDialog.getOpenFileName(self.form, translate("Metamaterial", "Scene file"),
                                                    metamaterial_wb.EXAMPLES_DIR,
                                                    translate("Metamaterial", "Scenes (*.json)"))
        if path:
            self.file.setText(path)
            self.load_file(path)

    def load_file(self, path):
        """Read and check a scene file (as the structure would be built); the problem is shown under the
        file field. Returns the Scene or None."""
        self.loaded_scene, self.loaded_path = None, path
        try:
            if not path:
                raise MetamaterialError(translate("Metamaterial", "type the path of a scene file"))
            scene = Scene.load(path)
            problem = design_problem(scene)
            if problem:
                raise MetamaterialError(problem)
        except (MetamaterialError, OSError) as exc:
            self.set_problem("file", translate("Metamaterial", "{0}: {1}").format(
                os.path.basename(path) or translate("Metamaterial", "scene file"), exc))
            self.status.setText("")
            return None
        self.loaded_scene = scene
        if self.file.text().strip() != path:
            self.file.blockSignals(True)
            self.file.setText(path)
            self.file.blockSignals(False)
            self._use_file(True)
        if self.name.text() == self._auto_name and not self._name_typed:
            self._set_name(scene.name or os.path.splitext(os.path.basename(path))[0])
        self.set_problem("file", "")
        self.status.setStyleSheet(GREEN)
        self.status.setText(translate("Metamaterial", "scene {0}: {1} cells, {2} motors").format(os.path.basename(path), len(scene.cells), len(scene.actuators)))
        return scene

    def scene(self):
        typed = self.file.text().strip()
        if typed and typed != self.loaded_path:
            if self.load_file(typed) is None:
                raise MetamaterialError(self.problems.get("file", f"cannot load {typed}"))
        if self.loaded_scene is not None:
            self.loaded_scene.name = self.name.text().strip()     # the Name field names it, as for a grid
            return self.loaded_scene
        if "file" in self.problems:
            raise MetamaterialError(self.problems["file"])
        return Scene.from_dict({"format": "metamaterial-scene", "version": 1, "name": self.name.text().strip(),
                                "cell_size_mm": float(self.cell.value()), "layout": self._layout_dict()})

    def accept(self):
        typed = self.file.text().strip()
        if typed and typed != self.loaded_path:
            self.load_file(typed)           # a typed path counts even without Enter
        if self._file_on:
            self._forget_refused()
        return super().accept()

    def apply(self):
        scene = self.scene()
        doc = self.doc or FreeCAD.ActiveDocument or FreeCAD.newDocument()
        self.commit(doc, "New metamaterial structure", lambda: setattr(self, "result",
                                                                         structure.make_structure(doc, scene)))
        _fit(doc)
