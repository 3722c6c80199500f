"""Flexibility: global and per-joint hinge sizes with the resulting k1 / k2.

Every size change is checked at once against the scene validator (sizes that fit the cell), the
calibration table and the design (a stored fold must stay within the axis' maximum, which depends on
the hinge length): a problem is shown in red under the hinge sizes and OK is refused.
"""
from PySide import QtGui

from metamaterial_wb.core.errors import MetamaterialError, SceneError
from metamaterial_wb.core.scene import Scene
from metamaterial_wb.objects import structure
from metamaterial_wb.objects.common import assign
from metamaterial_wb.gui.panels.base import BasePanel, button_row
from metamaterial_wb.gui.panels.checks import design_problem
from metamaterial_wb.gui.panels import ranges
from metamaterial_wb.gui.i18n import QT_TRANSLATE_NOOP, translate


class FlexibilityPanel(BasePanel):
    TITLE = QT_TRANSLATE_NOOP("Metamaterial", "Flexibility")
    ICON = "MM_Flexibility.svg"

    def __init__(self, scene_obj):
        super().__init__()
        self.obj = scene_obj
        self.scene = structure.compose_scene(scene_obj)
        self.overrides = {k: dict(v) for k, v in self.scene.joint_overrides.items()}
        g = QtGui.QGroupBox(translate("Metamaterial", "All hinges"))
        f = QtGui.QFormLayout(g)
        self.length = self._spin(self.scene.hinge["length_mm"], "hinge.length_mm")
        self.width = self._spin(self.scene.hinge["width_mm"], "hinge.width_mm")
        self.thick = self._spin(self.scene.hinge["thickness_mm"], "hinge.thickness_mm")
        # an untouched size keeps the stored value exactly (the boxes show 3 decimals: 2.3456 stays 2.3456)
        self._first = {w: (w.value(), float(v)) for w, v in
                       ((self.length, self.scene.hinge["length_mm"]), (self.width, self.scene.hinge["width_mm"]),
                        (self.thick, self.scene.hinge["thickness_mm"]))}
        f.addRow(translate("Metamaterial", "Length"), self.length)
        f.addRow(translate("Metamaterial", "Width"), self.width)
        f.addRow(translate("Metamaterial", "Thickness"), self.thick)
        self.k_label = QtGui.QLabel("")
        f.addRow(translate("Metamaterial", "k1, k2"), self.k_label)
        f.addRow(self.problem_label("hinge"))
        self.layout.addWidget(g)
        pj = QtGui.QGroupBox(translate("Metamaterial", "One joint (click a hinge in the 3D view)"))
        pf = QtGui.QFormLayout(pj)
        self.joint = QtGui.QComboBox()
        self.joint.addItems(self.scene.topology.joint_names)
        self.j_length = self._spin(self.scene.hinge["length_mm"], "hinge.length_mm")
        self.j_width = self._spin(self.scene.hinge["width_mm"], "hinge.width_mm")
        self.jk_label = QtGui.QLabel("")
        self._shown = {}               # joint box -> the value it was given (the user's edit is what differs)
        pf.addRow(translate("Metamaterial", "Joint"), self.joint)
        pf.addRow(translate("Metamaterial", "Length"), self.j_length)
        pf.addRow(translate("Metamaterial", "Width"), self.j_width)
        pf.addRow(translate("Metamaterial", "k1, k2"), self.jk_label)
        bl, (self.set_btn, self.del_btn) = button_row(QT_TRANSLATE_NOOP("Metamaterial", "Set for this joint"),
                                                        QT_TRANSLATE_NOOP("Metamaterial", "Use global size"))
        pf.addRow(bl)
        self.ov_list = QtGui.QListWidget()
        pf.addRow(self.ov_list)
        pf.addRow(self.problem_label("joints"))
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
    def _spin(v, field):
        s = QtGui.QDoubleSpinBox()
        s.setDecimals(3)
        ranges.bind(s, field)          # the validator's widest range; what fits this cell is said in words
        s.setKeyboardTracking(False)
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
            self.k_label.setText(translate("Metamaterial", "k1 = {0:.3f}, k2 = {1:.3f}").format(k1, k2))
        except MetamaterialError:
            self.k_label.setText(translate("Metamaterial", "out of the calibrated range"))
        self._follow_global()
        self._update_jk()
        self.validate()

    def size(self, spin):
        """A global size as OK writes it: the stored value while the box still shows it, else the box's."""
        shown, exact = self._first.get(spin, (None, None))
        return exact if spin.value() == shown else float(spin.value())

    def _update_jk(self, *_):
        """The joint's k1 / k2 as the solver takes them: its own thickness, and k1 / k2 set directly win over
        the sizes (core.calibration.joint_stiffness)."""
        ov = self.overrides.get(self.joint.currentText(), {})
        try:
            k1, k2 = self.k_values(self.j_length.value(), self.j_width.value(),
                                   ov.get("thickness_mm", self.thick.value()))
        except MetamaterialError as exc:
            if not ("k1" in ov and "k2" in ov):
                self.jk_label.setText(str(exc))
                return
            k1 = k2 = None
        k1, k2 = ov.get("k1", k1), ov.get("k2", k2)
        text = translate("Metamaterial", "k1 = {0:.3f}, k2 = {1:.3f}").format(k1, k2)
        direct = [k for k in ("k1", "k2") if k in ov]
        if direct:
            text += translate("Metamaterial", " ({0} set directly for this joint: the sizes do not change it)").format(
                " and ".join(direct))
        self.jk_label.setText(text)

    def _joint_fields(self):
        return ((self.j_length, "length_mm", self.length), (self.j_width, "width_mm", self.width))

    def _show_joint(self, spin, value):
        self._shown[spin] = None                     # not an edit while the box is being set
        spin.setValue(value)
        self._shown[spin] = spin.value()

    def _joint_changed(self, name):
        ov = self.overrides.get(name, {})
        for spin, key, glob in self._joint_fields():
            self._show_joint(spin, ov.get(key, glob.value()))
        self._update_jk()

    def _edited(self, spin):
        """Whether the user changed a joint box since it was last set (by the joint, an override or the global)."""
        return spin.value() != self._shown.get(spin)

    def _follow_global(self):
        """A joint size without an override is the global one: its box follows the global box, unless the user
        is editing it (an edit not yet set is kept)."""
        if not self._shown:
            return
        ov = self.overrides.get(self.joint.currentText(), {})
        for spin, key, glob in self._joint_fields():
            if key not in ov and not self._edited(spin):
                self._show_joint(spin, glob.value())

    def set_override(self):
        """Pin the sizes edited in the joint boxes (only those: a width set here leaves the length following the
        global size); with no edit, both shown sizes are pinned. Sizes already pinned stay as stored."""
        name = self.joint.currentText()
        ov = dict(self.overrides.get(name, {}))
        fields = self._joint_fields()
        edited = [(spin, key, glob) for spin, key, glob in fields if self._edited(spin)]
        if not edited and not any(key in ov for _s, key, _g in fields):
            edited = list(fields)
        for spin, key, glob in edited:
            # a box still equal to the global box keeps the global's exact value (3 decimals shown)
            ov[key] = self.size(glob) if spin.value() == glob.value() else float(spin.value())
            self._shown[spin] = spin.value()
        self.overrides[name] = ov
        self._refresh_list()
        self._update_jk()
        self.validate()            # shown in red under the list at once, OK disabled (not only when OK is pressed)

    def remove_override(self):
        self.overrides.pop(self.joint.currentText(), None)
        self._joint_changed(self.joint.currentText())     # the boxes show the global sizes again
        self._refresh_list()
        self.validate()

    def _refresh_list(self):
        self.ov_list.clear()
        for name, ov in sorted(self.overrides.items()):
            self.ov_list.addItem(f"{name}: " + ", ".join(f"{k} {v:g}" for k, v in sorted(ov.items())))

    @staticmethod
    def joint_list(overrides):
        """``{joint: fields}`` -> the scene's ``joints`` list (sorted, empty entries left out)."""
        return [dict({"joint": k}, **v) for k, v in sorted(overrides.items()) if v]

    def scene_dict(self):
        joints = self.joint_list(self.overrides)
        d = structure.compose_scene(self.obj).to_dict()
        d["hinge"] = {"length_mm": self.size(self.length), "width_mm": self.size(self.width),
                      "thickness_mm": self.size(self.thick)}
        d["joints"] = joints
        return d

    def validate(self):
        """Check the sizes as OK would use them; the problem is shown under the sizes it is about."""
        hinge = joints = ""
        try:
            sc = Scene.from_dict(self.scene_dict())
        except SceneError as exc:
            if str(exc.field).startswith("joints"):
                joints = str(exc)
            else:
                hinge = str(exc)
        else:
            problem = design_problem(sc)
            if problem:
                hinge = translate("Metamaterial", "with these sizes: {0}").format(problem)
        self.set_problem("hinge", hinge)
        self.set_problem("joints", joints)
        return not (hinge or joints)

    def apply(self):
        if not self.validate():
            raise MetamaterialError(self.problem_text())
        d = self.scene_dict()
        joints, h = d["joints"], d["hinge"]
        doc = self.obj.Document

        def change():                                 # equal values write nothing: an untouched OK leaves no trace
            for prop, key in (("HingeLength", "length_mm"), ("HingeWidth", "width_mm"),
                              ("HingeThickness", "thickness_mm")):
                assign(self.obj, prop, h[key])
            structure.set_scene_fields(self.obj, joints=joints or None)
        self.commit(doc, "Flexibility", change)
