"""Export STEP / 3MF from the panel."""
import os

import FreeCAD
from PySide import QtGui

from metamaterial_wb.core.errors import MetamaterialError
from metamaterial_wb.gui.panels.base import BasePanel


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
