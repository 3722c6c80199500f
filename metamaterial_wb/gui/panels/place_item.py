"""Place motor / angular constraint on a joint."""
from PySide import QtGui

from metamaterial_wb.core.errors import MetamaterialError
from metamaterial_wb.core.scene import Scene
from metamaterial_wb.objects import structure
from metamaterial_wb.gui.panels.base import BasePanel
from metamaterial_wb.gui.panels import ranges
from metamaterial_wb.gui.panels.stream import joint_angle_text
from metamaterial_wb.gui.i18n import QT_TRANSLATE_NOOP, translate


class PlaceItemPanel(BasePanel):
    def __init__(self, scene_obj, kind="actuator"):
        self.kind = kind
        self.TITLE = QT_TRANSLATE_NOOP("Metamaterial", "Place motor") if kind == "actuator" else \
            QT_TRANSLATE_NOOP("Metamaterial", "Angular constraint")
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
        # a narrow task dock (the combo view, ~300 px): a field that does not fit beside its label goes below it
        f.setRowWrapPolicy(QtGui.QFormLayout.RowWrapPolicy.WrapLongRows)
        self.name = QtGui.QLineEdit(f"{prefix}{k}")
        self.joint = QtGui.QComboBox()
        self.joint.setSizeAdjustPolicy(QtGui.QComboBox.SizeAdjustPolicy.AdjustToMinimumContentsLengthWithIcon)
        self.joint.setMinimumContentsLength(8)
        self.joint.addItems(self.scene.topology.joint_names)
        self.value = QtGui.QDoubleSpinBox()
        self.value.setDecimals(3)
        ranges.bind(self.value, "value")
        self.value.setSingleStep(0.05)
        self.value_deg = QtGui.QLabel("")          # the joint's rotation, under the value (wraps in a narrow dock)
        self.value_deg.setWordWrap(True)
        f.addRow(translate("Metamaterial", "Name"), self.name)
        f.addRow(translate("Metamaterial", "Joint (or click a hinge)"), self.joint)
        f.addRow(translate("Metamaterial", "Value D (-1..1)"), self.value)
        f.addRow(self.value_deg)
        if kind == "actuator":
            self.amp = QtGui.QDoubleSpinBox()
            ranges.bind(self.amp, "profile.amplitude")
            self.amp.setSingleStep(0.05)
            self.amp.setValue(0.5)
            self.freq = QtGui.QDoubleSpinBox()
            ranges.bind(self.freq, "profile.frequency_hz")
            self.freq.setValue(0.5)
            self.freq.setSuffix(" Hz")
            self.phase = QtGui.QDoubleSpinBox()
            ranges.bind(self.phase, "profile.phase_deg")
            self.phase.setSuffix(" deg")
            f.addRow(translate("Metamaterial", "Sine amplitude"), self.amp)
            f.addRow(translate("Metamaterial", "Frequency"), self.freq)
            f.addRow(translate("Metamaterial", "Phase offset"), self.phase)
        f.addRow(self.problem_label("item"))
        self.layout.addLayout(f)
        self.finish_layout()
        self.value.valueChanged.connect(self._validate)
        self.name.textChanged.connect(self._validate)
        self.joint.currentTextChanged.connect(self._validate)
        self._validate()
        self.watch_selection(scene_obj, on_joint=lambda j: self.joint.setCurrentText(j))

    def _validate(self, *_):
        v = float(self.value.value())
        if self.kind == "actuator":   # the joint's rotation for v: the angle its servo will be sent
            deg, how = joint_angle_text(self.scene, self.joint.currentText(), v)
            self.value_deg.setText(translate("Metamaterial", "= {0} joint rotation").format(deg))
            self.value_deg.setToolTip("\n".join([translate(
                "Metamaterial", "How far the joint turns for this value (plate B relative to plate A, the "
                "servo's sign): the angle a servo on it is sent; closing and opening differ. A servo with "
                "scale_deg in the scene is sent value x scale_deg instead."), how]))
        else:
            self.value_deg.setText("")
        try:
            self.scene_with_item()
            self.set_problem("item", "")
        except MetamaterialError as exc:
            self.set_problem("item", str(exc))

    def scene_with_item(self):
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
        return Scene.from_dict(d), name, joint, profile

    def apply(self):
        _sc, name, joint, profile = self.scene_with_item()   # the whole scene, validated before any change
        doc = self.obj.Document
        self.commit(doc, self.TITLE, lambda: setattr(self, "result", structure.make_item(
            doc, self.obj, self.kind, name, joint, float(self.value.value()), profile)))
