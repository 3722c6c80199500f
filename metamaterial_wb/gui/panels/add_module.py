"""Add module: housings, hubs and clips on joints, hubs and pads on nodes.

A joint carries at most one module and a node socket at most one: a second module on the same joint
or node is refused in the panel, naming the module already there (checked while choosing, before OK).
"""
from PySide import QtGui

from metamaterial_wb.core.errors import MetamaterialError
from metamaterial_wb.objects import structure
from metamaterial_wb.gui.panels.base import BasePanel
from metamaterial_wb.gui.i18n import translate


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
        f.addRow(translate("Metamaterial", "Module"), self.type)
        f.addRow(translate("Metamaterial", "On (or click in the 3D view)"), self.target)
        f.addRow(self.problem_label("target"))
        self.layout.addLayout(f)
        self.finish_layout()
        self.type.currentIndexChanged.connect(self._targets)
        self.target.currentTextChanged.connect(self._check)
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

    def occupant(self, target):
        """The module already on joint / node ``target`` (its name), or None."""
        for k, m in enumerate(self.scene.modules):
            where = m.get("joint") or m.get("node")
            if where == target:
                return m.get("name") or f"{m.get('type', 'module')} #{k + 1}"
        return None

    def _check(self, *_):
        target = self.target.currentText()
        who = self.occupant(target) if target else None
        kind = "joint" if self.module_type() in self.ON_JOINT else "node"
        self.set_problem("target", f"{kind} {target} already carries the module {who!r}: one module per "
                                   f"{'joint' if kind == 'joint' else 'node socket'}; choose another {kind} "
                                   f"or delete {who!r} first" if who else "")

    def _pick(self, name):
        i = self.target.findText(name)
        if i >= 0:
            self.target.setCurrentIndex(i)

    def apply(self):
        t = self.module_type()
        target = self.target.currentText()
        if not target:
            raise MetamaterialError("choose a node or joint for the module")
        self._check()
        if self.problems:
            raise MetamaterialError(self.problem_text())
        doc = self.obj.Document
        data = {}
        if t == "servo_housing":
            from metamaterial_wb.gui import preferences
            data["servo"] = preferences.get("DefaultServo")
        self.commit(doc, "Add module", lambda: setattr(self, "result",
                                                       structure.make_module(doc, self.obj, t, target, data)))


# ----------------------------------------------------------------------------------------------
