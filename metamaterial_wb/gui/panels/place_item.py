"""Place motor / angular constraint on a joint."""
from PySide import QtGui

from metamaterial_wb.core.scene import Scene
from metamaterial_wb.objects import structure
from metamaterial_wb.gui.panels.base import BasePanel, transaction


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
