"""New structure: rows / columns, toggle cells on a grid, presets, or a scene file."""
import os

import FreeCAD
from PySide import QtGui

import metamaterial_wb
from metamaterial_wb.core.errors import MetamaterialError
from metamaterial_wb.core.scene import Scene, validate_layout
from metamaterial_wb.objects import structure
from metamaterial_wb.gui.panels.base import BasePanel, transaction, _fit


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
