"""Add module: housings, hubs and clips on joints, hubs and pads on nodes."""
from PySide import QtGui

from metamaterial_wb.core.errors import MetamaterialError
from metamaterial_wb.objects import structure
from metamaterial_wb.gui.panels.base import BasePanel, transaction


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
