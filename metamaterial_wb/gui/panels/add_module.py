"""Add module: housings, hubs and clips on joints, hubs and pads on nodes.

A joint carries at most one module and a node socket at most one: a second module on the same joint
or node is refused in the panel, naming the module already there (checked while choosing, before OK). An
angular-constraint clip holds the scene's constraint on its joint: on a joint without one it is refused the same way.
Only a target of the chosen module's kind is picked in the 3D view: a click on a hinge for a node module
(or on a node for a joint module) picks nothing, keeps the target and says what the module goes on; the
hover marker lights only targets of the chosen kind (the other kind is named as no target, unlit).
The panel opens with no target (a placeholder entry; a red line says what is missing and OK waits) unless the
user selected a hinge / node before opening it: that selection counts as chosen. A target the user chose is
kept per kind (hinge / node) while the module changes. The panel fits a narrow task dock (~300 px): labels
above their fields, the combo boxes elide their names (in full in their tooltips).
"""
from PySide import QtCore, QtGui

import FreeCADGui

from metamaterial_wb.core.errors import MetamaterialError
from metamaterial_wb.objects import structure
from metamaterial_wb.gui.panels.base import BasePanel
from metamaterial_wb.gui.i18n import QT_TRANSLATE_NOOP, translate


class AddModulePanel(BasePanel):
    TITLE = QT_TRANSLATE_NOOP("Metamaterial", "Add module")
    ICON = "MM_AddModule.svg"
    # English here (marked for ts_extract / lupdate), translated where shown
    LABELS = {"servo_housing": QT_TRANSLATE_NOOP("Metamaterial", "Servo housing (across a joint)"),
              "connection_hub": QT_TRANSLATE_NOOP("Metamaterial", "Connection hub (node)"),
              "stable_hub": QT_TRANSLATE_NOOP("Metamaterial", "Stable connection hub (across a joint)"),
              "friction_pad": QT_TRANSLATE_NOOP("Metamaterial", "Friction pad (node)"),
              "constraint_clip": QT_TRANSLATE_NOOP("Metamaterial", "Angular-constraint clip (joint)")}
    ON_JOINT = structure.JOINT_MODULES
    NOUNS = {"servo_housing": QT_TRANSLATE_NOOP("Metamaterial", "a servo housing"),
             "connection_hub": QT_TRANSLATE_NOOP("Metamaterial", "a connection hub"),
             "stable_hub": QT_TRANSLATE_NOOP("Metamaterial", "a stable connection hub"),
             "friction_pad": QT_TRANSLATE_NOOP("Metamaterial", "a friction pad"),
             "constraint_clip": QT_TRANSLATE_NOOP("Metamaterial", "an angular-constraint clip")}

    def __init__(self, scene_obj):
        super().__init__()
        self.obj = scene_obj
        self.scene = structure.compose_scene(scene_obj)
        self._chosen = {"joint": None, "node": None}   # the target the user chose, per kind (None: not yet)
        self._filling = False
        f = QtGui.QFormLayout()
        f.setRowWrapPolicy(QtGui.QFormLayout.RowWrapPolicy.WrapAllRows)   # labels above: fits a narrow dock
        self.type = QtGui.QComboBox()
        for t in structure.MODULE_TYPES:
            self.type.addItem(translate("Metamaterial", self.LABELS[t]), t)
            self.type.setItemData(self.type.count() - 1, self.type.itemText(self.type.count() - 1),
                                  QtCore.Qt.ItemDataRole.ToolTipRole)
        self.target = QtGui.QComboBox()
        for combo in (self.type, self.target):
            combo.setSizeAdjustPolicy(QtGui.QComboBox.SizeAdjustPolicy.AdjustToMinimumContentsLengthWithIcon)
            combo.setMinimumContentsLength(12)
            combo.currentTextChanged.connect(combo.setToolTip)     # the name in full when the combo cuts it
        for text, field in ((translate("Metamaterial", "Module"), self.type),
                            (translate("Metamaterial", "On (or click in the 3D view)"), self.target)):
            lab = QtGui.QLabel(text)
            lab.setWordWrap(True)
            f.addRow(lab, field)
        f.addRow(self.problem_label("choose"))
        f.addRow(self.problem_label("target"))
        f.addRow(self.problem_label("constraint"))      # a clip on a joint without the constraint it holds
        f.addRow(self.problem_label("pick"))
        f.addRow(self.problem_label("preferences"))     # a module material or servo the fabrication does not know
        self.layout.addLayout(f)
        self.finish_layout()
        self.type.currentIndexChanged.connect(self._targets)
        self.target.currentTextChanged.connect(self._check)
        self.target.activated.connect(self._target_chosen)
        # both kinds are watched so that a click on the wrong kind is told apart from a click on nothing
        self.watch_selection(scene_obj, on_joint=self._pick_joint, on_node=self._pick_node)
        self._preselection(scene_obj)
        self._targets()
        self.type.setToolTip(self.type.currentText())

    def module_type(self):
        return self.type.itemData(self.type.currentIndex())

    def set_type(self, t):
        self.type.setCurrentIndex(structure.MODULE_TYPES.index(t))

    def on_joint(self):
        """True when the chosen module goes across a joint (its targets are hinges), False for a node."""
        return self.module_type() in self.ON_JOINT

    def kind(self):
        """``"joint"`` or ``"node"``: what the chosen module goes on."""
        return "joint" if self.on_joint() else "node"

    def target_name(self):
        """The chosen target (``"H0,1"`` / ``"N2,3"``), or None while the placeholder entry is shown."""
        return self.target.itemData(self.target.currentIndex()) or None

    def placeholder(self):
        return (translate("Metamaterial", "(click a hinge or choose)") if self.on_joint()
                else translate("Metamaterial", "(click a node or choose)"))

    def _preselection(self, scene_obj):
        """A hinge / node the user selected before opening the panel counts as chosen (the selection observer
        only sees selections made while the panel is open)."""
        try:
            sel = FreeCADGui.Selection.getSelectionEx("", 0)    # unresolved: keeps "Hinges.12.Face3" paths
        except Exception:  # pragma: no cover - no GUI selection
            return
        for s in sel:
            for sub in (list(s.SubElementNames) or [""]):
                try:
                    self._selected(scene_obj, s.ObjectName, sub, lambda n: self._remember("joint", n),
                                   lambda n: self._remember("node", n))
                except Exception:  # pragma: no cover - an unrelated selection
                    pass

    def _remember(self, kind, name):
        self._chosen[kind] = name

    def _targets(self, *_):
        self._filling = True
        try:
            self.target.clear()
            self.target.addItem(self.placeholder(), None)
            names = (list(self.scene.topology.joint_names) if self.on_joint()
                     else [f"N{i},{j}" for i, j in self.scene.topology.nodes])
            for n in names:
                self.target.addItem(n, n)
            i = self.target.findData(self._chosen[self.kind()]) if self._chosen[self.kind()] else -1
            self.target.setCurrentIndex(max(i, 0))
        finally:
            self._filling = False
        self.target.setToolTip(self.target.currentText())
        self._check()
        self.set_problem("pick", "")
        if getattr(self, "picker", None) is not None:
            self.picker.refresh()             # the candidate under the cursor may have become (no) target
        if getattr(self, "pick_label", None) is not None:
            self.pick_label.setText(self.pick_hint(self.on_joint()))

    def occupant(self, target):
        """The module already on joint / node ``target`` (its name), or None."""
        for k, m in enumerate(self.scene.modules):
            where = m.get("joint") or m.get("node")
            if where == target:
                return m.get("name") or f"{m.get('type', 'module')} #{k + 1}"
        return None

    def is_target(self, kind):
        """Whether a hinge (``kind`` "joint") / node ("node") is a target of the chosen module (the picker
        lights only these)."""
        return (kind == "joint") == self.on_joint()

    def _check(self, *_):
        if self._filling:
            return
        target = self.target_name()
        kind = self.kind()
        self._chosen[kind] = target           # also None: the placeholder chosen again clears the choice
        self.set_problem("choose", "" if target else (
            translate("Metamaterial", "On: no hinge chosen yet; click one in the 3D view or choose it in the list")
            if kind == "joint" else
            translate("Metamaterial", "On: no node chosen yet; click one in the 3D view or choose it in the list")))
        self.set_problem("pick", "")          # a target chosen (in the list or by a pick) answers a refused click
        who = self.occupant(target) if target else None
        if not who:
            taken = ""
        elif kind == "joint":
            taken = translate("Metamaterial", "joint {0} already carries the module {1}: one module per joint; "
                                              "choose another joint or delete {1} first").format(target, repr(who))
        else:
            taken = translate("Metamaterial", "node {0} already carries the module {1}: one module per node socket; "
                                              "choose another node or delete {1} first").format(target, repr(who))
        self.set_problem("target", taken)
        self.set_problem("constraint", self._clip_problem(target))
        from metamaterial_wb.gui.panels.checks import preference_problem
        keys = ["ModuleMaterial"] + (["DefaultServo"] if self.module_type() == "servo_housing" else [])
        self.set_problem("preferences", preference_problem(keys, self.scene))   # (its socket lip, if it sets one)

    def _clip_problem(self, target):
        """A clip holds the angle of the scene's constraint on its joint (the panel has no angle field): on a joint
        without one it cannot be built (``geometry.modules``), said before OK, naming the joint and what to do."""
        if self.module_type() != "constraint_clip" or not target or \
                any(c.joint == target for c in self.scene.constraints):
            return ""
        return translate("Metamaterial", "joint {0} has no angular constraint for the clip to hold: place one on {0} "
                                         "first (Angular constraint), then add the clip").format(target)

    def goes_on(self):
        """``"a friction pad goes on a node"`` / ``"a servo housing goes across a joint"``."""
        noun = translate("Metamaterial", self.NOUNS.get(self.module_type(),
                                                        QT_TRANSLATE_NOOP("Metamaterial", "this module")))
        if self.module_type() == "constraint_clip":
            return translate("Metamaterial", "{0} goes on a joint").format(noun)
        if self.on_joint():
            return translate("Metamaterial", "{0} goes across a joint").format(noun)
        return translate("Metamaterial", "{0} goes on a node").format(noun)

    def picked(self, kind, name, hover=False):
        """A hinge / node under the cursor or clicked: a pick when it fits the module, else the reason why not."""
        if self.is_target(kind):
            return super().picked(kind, name, hover)
        if kind == "joint":
            text = translate("Metamaterial", "under the cursor: hinge {0} (not a target: {1})") if hover else \
                translate("Metamaterial", "not picked: hinge {0} ({1})")
        else:
            text = translate("Metamaterial", "under the cursor: node {0} (not a target: {1})") if hover else \
                translate("Metamaterial", "not picked: node {0} ({1})")
        self.pick_label.setText(text.format(name, self.goes_on()))

    def _wrong_kind(self, kind, name):
        text = translate("Metamaterial", "{0}; {1} is a hinge: click a node or choose one in the list (the target is "
                                         "still {2})") if kind == "joint" else \
            translate("Metamaterial", "{0}; {1} is a node: click a hinge or choose one in the list (the target is "
                                      "still {2})")
        self.set_problem("pick", text.format(self.goes_on(), name,
                                             self.target_name() or translate("Metamaterial", "none")))

    def _pick_joint(self, name):
        if self.on_joint():
            self._pick(name)
        else:
            self._wrong_kind("joint", name)

    def _pick_node(self, name):
        if self.on_joint():
            self._wrong_kind("node", name)
        else:
            self._pick(name)

    def _target_chosen(self, *_):
        self.set_problem("pick", "")

    def _pick(self, name):
        i = self.target.findData(name)
        if i >= 0:
            self.target.setCurrentIndex(i)
            self.set_problem("pick", "")

    def apply(self):
        t = self.module_type()
        target = self.target_name()
        if not target:
            raise MetamaterialError(self.problems.get("choose")
                                   or translate("Metamaterial", "choose a node or joint for the module"))
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
