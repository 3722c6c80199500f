"""Sleeve actuator (issue 9): spec file or parameters -> geometry in the document, prediction."""
import json
import os

import FreeCAD
from PySide import QtCore, QtGui

import metamaterial_wb
from metamaterial_wb.core.errors import MetamaterialError
from metamaterial_wb.gui.panels.base import BasePanel, button_row, transaction, _fit
from metamaterial_wb.gui.panels.jobs import JobBox, ProcessJob, ThreadJob
from metamaterial_wb.gui.panels.widgets import wrapped_check
from metamaterial_wb.gui.panels import ranges
from metamaterial_wb.gui.i18n import QT_TRANSLATE_NOOP, translate
from metamaterial_wb.core.sleeve import spec as sleeve_spec

# The cap the inner membrane pushes on (``actuator.core_diameter_mm``): the validator allows (0, BED_MM] and at most
# what the end ring glued inside the sleeve holds, the inner diameter less two ring walls (checked in words, as
# t <= L / 4 is); its box's range comes from ranges.FIELDS
CAP_FIELD = "sleeve.actuator.core_diameter_mm"


def sleeve_summary_text(summary):
    """The panel's short report of a ``core.sleeve.pipeline.analyse`` summary (plain text lines, translated; the
    core's notes are shown as they come)."""
    lines = []
    none = translate("Metamaterial", "none")        # a peak / valley not within the stroke (null), no peaks at all
    num = lambda x: none if x is None else f"{x:.4g}"  # noqa: E731
    for uc in summary["unit_cells"]:
        if uc.get("note"):
            line = translate("Metamaterial", "cell type {0}: peak {1}, valley {2} (F / G L^2); {3}")
        else:
            line = translate("Metamaterial", "cell type {0}: peak {1}, valley {2} (F / G L^2)")
        lines.append(line.format(uc["type"], num(uc["peak_force"]), num(uc["valley_force"]), uc.get("note")))
    ring = summary["ring"]
    fmt = lambda xs: ", ".join(f"{x:.4g}" for x in xs) or none  # noqa: E731
    lines.append(translate("Metamaterial", "sleeve ({0} x {1} cells): peaks {2}; valleys {3}").format(
        ring["rings"], ring["cells"], fmt(ring["peaks"]), fmt(ring["valleys"])))
    seq = summary["sequence"]
    from metamaterial_wb.core.sleeve.analysis import symmetry_word
    order = {"nothing snapped": translate("Metamaterial", "nothing snapped"),
             "undetermined": translate("Metamaterial", "undetermined"),    # snaps, but a type could not be ordered
             "symmetric": translate("Metamaterial", "symmetric"),
             "asymmetric": translate("Metamaterial", "asymmetric")}[symmetry_word(seq)]
    lines.append(translate("Metamaterial", "sequence: loading {0}, unloading {1} -> {2}").format(
        seq["loading"], seq["unloading"], order))
    if seq["symmetric"] is None and seq.get("note"):              # why the order is incomplete (core's words)
        lines.append(translate("Metamaterial", "sequence: {0}").format(seq["note"]))
    pv = summary.get("pv", {})
    if pv.get("peaks_kPa"):
        lines.append(translate("Metamaterial", "pressure peaks {0} kPa").format(fmt(pv["peaks_kPa"])))
    for note in summary.get("accuracy", {}).get("notes", []):      # the model's measured error (core/sleeve/accuracy)
        lines.append(translate("Metamaterial", "accuracy: {0}").format(note))
    return lines


class SleevePanel(BasePanel):
    """Open a ``metamaterial-sleeve`` spec, edit its main parameters, build the sleeve (OK, one undo
    step) and optionally run the prediction (core.sleeve.pipeline.analyse) in the background."""
    TITLE = QT_TRANSLATE_NOOP("Metamaterial", "Sleeve actuator")
    ICON = "MM_Sleeve.svg"
    DEFAULT = os.path.join(metamaterial_wb.EXAMPLES_DIR, "sleeve.json")

    def __init__(self, doc=None):
        super().__init__()
        self.doc = doc
        self.raw = {}
        # the spec's own value of each spin box set from it, until the user edits that box: a box shows a few
        # decimals (t 1.0985 as 1.099, G below 0.001 at its smallest step), the spec keeps the exact value
        self.exact = {}
        self._loading = False       # set_spec fills the widgets: one check when it is done, none on the way
        fl = QtGui.QHBoxLayout()
        self.path = QtGui.QLineEdit("")
        self.open_btn = QtGui.QPushButton(translate("Metamaterial", "Open..."))
        fl.addWidget(QtGui.QLabel(translate("Metamaterial", "Spec")))
        fl.addWidget(self.path)
        fl.addWidget(self.open_btn)
        self.layout.addLayout(fl)
        # a narrow task dock (the combo view, ~300 px): a field that does not fit beside its label goes below it, the
        # table's two columns share the width it gets, long check box texts wrap
        f = QtGui.QFormLayout()
        f.setRowWrapPolicy(QtGui.QFormLayout.RowWrapPolicy.WrapLongRows)
        self.name = QtGui.QLineEdit("sleeve")
        f.addRow(translate("Metamaterial", "Name"), self.name)
        self.dims = {}
        for key, label in (("L_mm", translate("Metamaterial", "L (beam span)")),
                           ("c_mm", translate("Metamaterial", "c (pillar width)")),
                           ("delta_mm", translate("Metamaterial", "delta (gap)")),
                           ("T_mm", translate("Metamaterial", "T (wall thickness)")),
                           ("shear_modulus_MPa", translate("Metamaterial", "G (shear modulus)"))):
            w = QtGui.QDoubleSpinBox()
            w.setDecimals(3)
            ranges.bind(w, "sleeve." + key)        # the spec validator's range (L up to 1000 mm)
            w.setSingleStep(0.1)
            w.setSuffix(" MPa" if key.endswith("MPa") else " mm")
            f.addRow(label, w)
            self.dims[key] = w
            self._track_edits(w)
        # the cap (actuator.core_diameter_mm): automatic (the validator's default, which follows the widest cap a
        # narrower sleeve's end rings hold; the box shows the cap used) or the user's value, kept as typed
        self.cap = QtGui.QDoubleSpinBox()
        self.cap.setDecimals(3)
        ranges.bind(self.cap, CAP_FIELD)
        self.cap.setSingleStep(0.1)
        self.cap.setSuffix(" mm")
        self._track_edits(self.cap)
        self.cap_auto = QtGui.QCheckBox(translate("Metamaterial", "automatic"))
        self.cap_auto.setToolTip(translate(
            "Metamaterial", "the default cap, {0:g} mm, or the widest cap the end rings hold, the sleeve's inner "
            "diameter N (L + c) / pi - T less two {1:g} mm ring walls, when that is smaller; untick to give your own "
            "(kept as typed, refused when it does not fit)").format(
                sleeve_spec.DEFAULT_CAP_MM, sleeve_spec.END_RING_MIN_WALL_MM))
        cl = QtGui.QHBoxLayout()
        cl.addWidget(self.cap, 1)
        cl.addWidget(self.cap_auto)
        f.addRow(translate("Metamaterial", "Cap diameter (core_diameter_mm)"), cl)
        self.layout.addLayout(f)
        self.types = QtGui.QTableWidget(0, 2)
        self.types.setHorizontalHeaderLabels([translate("Metamaterial", "t (mm)"), translate("Metamaterial", "h (mm)")])
        self.types.setMaximumHeight(130)
        self.types.horizontalHeader().setSectionResizeMode(QtGui.QHeaderView.ResizeMode.Stretch)
        self.types.setTabKeyNavigation(False)     # Tab goes from box to box (``_tab_order``), not from cell to cell
        self.layout.addWidget(QtGui.QLabel(translate("Metamaterial", "Cell types (row = type index)")))
        self.layout.addWidget(self.types)
        bl, (add, rem) = button_row(QT_TRANSLATE_NOOP("Metamaterial", "Add type"),
                                   QT_TRANSLATE_NOOP("Metamaterial", "Remove last"))
        self.add_btn = add
        add.clicked.connect(lambda: self.add_type(1.0, 7.0))
        rem.clicked.connect(self.remove_type)
        self.layout.addLayout(bl)
        f2 = QtGui.QFormLayout()
        f2.setRowWrapPolicy(QtGui.QFormLayout.RowWrapPolicy.WrapLongRows)
        self.ring = QtGui.QLineEdit("0, 0, 1, 1")
        self.ring.setToolTip(translate("Metamaterial", "cell type index of each cell around the circumference"))
        self.rings = QtGui.QSpinBox()
        ranges.bind(self.rings, "sleeve.rings")
        f2.addRow(translate("Metamaterial", "Ring pattern"), self.ring)
        f2.addRow(translate("Metamaterial", "Rings"), self.rings)
        f2.addRow("", self.problem_label("spec"))     # the whole spec checked on every edit (``check_spec``)
        self.frame_nl, frame_row = wrapped_check(
            translate("Metamaterial", "Check on a 3-D frame: first peaks and sequence"))
        frame_row.setToolTip(translate("Metamaterial", "model.frame_nonlinear: the same beams as a nonlinear 3-D "
                                           "frame on the cylinder (core/sleeve/frame3d_nl.py), which bends the wall out "
                                           "of it as the printed sleeve does: each uniform ring's first peak (under a "
                                           "second per cell type) and the sleeve's snapping sequence and lean (about "
                                           "10 s per ring; stacked rings with the plates between them "
                                           "free). Needs the curved single-layout ring"))
        self.frame_nl.setToolTip(frame_row.toolTip())
        f2.addRow(frame_row)
        self.layout.addLayout(f2)
        pl = QtGui.QHBoxLayout()
        self.predict_btn = QtGui.QPushButton(translate("Metamaterial", "Predict"))
        self.predict_btn.setToolTip(translate("Metamaterial", "Unit-cell and sleeve force-displacement curves, snapping sequence "
                                    "(core.sleeve, about a second per curve)"))
        pl.addWidget(self.predict_btn)
        self.layout.addLayout(pl)
        self.jobbox = JobBox()
        self.progress = self.jobbox.progress
        self.layout.addWidget(self.jobbox)
        self.result = QtGui.QLabel("")
        self.result.setWordWrap(True)
        self.result.setTextInteractionFlags(QtCore.Qt.TextInteractionFlag.TextSelectableByMouse)
        self.layout.addWidget(self.result)
        el = QtGui.QHBoxLayout()
        self.export_dir = QtGui.QLineEdit(os.path.join(os.path.expanduser("~"), "sleeve_export"))
        self.export_btn = QtGui.QPushButton(translate("Metamaterial", "Export STEP + 3MF"))
        self.export_btn.setToolTip(translate("Metamaterial", "sleeve.step (named bodies) and sleeve.3mf (TPU sleeve, PLA rings and caps, "
                                   "per-part extruders; sleeve_plate1.3mf, sleeve_plate2.3mf, ... when the parts need "
                                   "more than one bed, and an earlier export's plates this one does not write are "
                                   "removed), as 'sleeve SPEC --step --3mf'"))
        self.export_btn.clicked.connect(lambda: self.export(self.export_dir.text().strip()))
        el.addWidget(self.export_dir)
        el.addWidget(self.export_btn)
        self.layout.addLayout(el)
        self.finish_layout()
        # ``summary``: the prediction of the spec the fields describe now (None when there is none, or the spec was
        # edited since); ``predicted``: (spec key, summary) of the last finished prediction, shown marked as for the
        # earlier values once the fields differ from them; ``_predicting``: the spec key of the running prediction
        self.summary = None
        self.predicted = None
        self._predicting = None
        self.created = []
        self.prediction = ThreadJob(self.jobbox, self._predicted, self._prediction_failed, self._prediction_cancelled)
        self.export_job = ProcessJob(self.jobbox, self._exported, self._export_failed, self._export_cancelled)
        self.staging, self.export_target, self.exported = None, None, []
        self.open_btn.clicked.connect(self._browse)
        self.predict_btn.clicked.connect(self.predict)
        # every edit is checked: the fields, the cap, and the t / h boxes of the table (add_type: cell widgets
        # send no itemChanged)
        self.name.textChanged.connect(self.check_spec)
        self.ring.textChanged.connect(self.check_spec)
        self.rings.valueChanged.connect(self.check_spec)
        for w in list(self.dims.values()) + [self.cap]:
            w.valueChanged.connect(self.check_spec)
        self.cap_auto.toggled.connect(self._cap_mode)
        self.frame_nl.toggled.connect(self.check_spec)  # the prediction depends on it: a shown one goes stale
        if os.path.exists(self.DEFAULT) and self.load_spec(self.DEFAULT):
            # the example is where the panel starts, not the user's choice: its cap, the seed's (the validator's
            # default), is automatic and follows the sleeve the user makes of it. A spec the user opens keeps its own
            if self.exact.get(self.cap) == sleeve_spec.DEFAULT_CAP_MM:
                self.cap_auto.setChecked(True)

    def check_spec(self, *_):
        """The spec as the fields give it, checked at once: its error in red under the pattern, OK disabled.
        An automatic cap shows the diameter the spec gives it."""
        if self._loading:
            return True
        try:
            spec = self.spec()
        except (MetamaterialError, ValueError) as exc:
            self.set_problem("spec", str(exc))
            self._show_prediction()
            return False
        self.set_problem("spec", "")
        if self.cap_auto.isChecked():
            self._show_cap(spec)
        self._show_prediction()
        return True

    def _spec_key(self):
        """What a prediction depends on: the spec the fields describe, without its name (None: the fields give no
        spec)."""
        try:
            d = self.spec_dict()
        except (MetamaterialError, ValueError):
            return None
        d.pop("name", None)
        return json.dumps(d, sort_keys=True)

    def _show_prediction(self):
        """The prediction shown is for the values in the fields, or says it is not: after an edit the last one is
        kept, greyed, under a line saying it is for the earlier values (editing them back makes it current again),
        and ``summary`` is None; a running one says when the fields were edited since Predict was pressed."""
        if self.prediction.running:
            edited = self._predicting is not None and self._spec_key() != self._predicting
            self.result.setText(translate("Metamaterial", "predicting the values from when Predict was pressed "
                                          "(edited since) ...") if edited
                                else translate("Metamaterial", "predicting ..."))
            return
        if self.predicted is None:
            return
        key, summary = self.predicted
        lines = sleeve_summary_text(summary)
        if key is not None and key == self._spec_key():
            self.summary = summary
            self.result.setStyleSheet("")
            text = "\n".join(lines)
        else:
            self.summary = None
            self.result.setStyleSheet("QLabel { color: gray; }")
            text = "\n".join([translate("Metamaterial", "prediction for the earlier values (edited since; press "
                                         "Predict for the values shown):")] + lines)
        if self.result.text() != text:
            self.result.setText(text)

    def _show_cap(self, spec):
        """The automatic cap's diameter in its (disabled) box, kept exactly for when the user unticks automatic."""
        self.cap.blockSignals(True)          # a shown value is no edit (no check, no loss of the exact value)
        try:
            self.cap.setValue(spec.core_diameter)
        finally:
            self.cap.blockSignals(False)
        self.exact[self.cap] = spec.core_diameter
        if spec.core_diameter_note:
            tip = translate("Metamaterial", "automatic: {0:.6g} mm, the widest cap the end rings ({1:g} mm walls) hold "
                            "inside the sleeve's inner diameter (the default {2:g} mm does not fit)").format(
                spec.core_diameter, sleeve_spec.END_RING_MIN_WALL_MM, sleeve_spec.DEFAULT_CAP_MM)
        else:
            tip = translate("Metamaterial", "automatic: the default cap, {0:g} mm").format(spec.core_diameter)
        self.cap.setToolTip(tip)

    def _cap_mode(self, automatic):
        """Automatic: the spec gives no cap (the validator's default). Unticked: the box starts from the cap shown,
        exactly, and the user's value is kept from then on."""
        self.cap.setEnabled(not automatic)
        if automatic:
            self.cap.setProperty(ranges.REFUSED, "")      # a keystroke its range refused goes with the value typed
        else:
            self.cap.setToolTip(translate("Metamaterial", "actuator.core_diameter_mm: the cap the inner membrane "
                                          "pushes on, in the opening of the end ring; at most the sleeve's inner "
                                          "diameter N (L + c) / pi - T less two {0:g} mm ring walls").format(
                sleeve_spec.END_RING_MIN_WALL_MM))
        self.check_spec()

    def _browse(self):  # pragma: no cover - modal file dialog, tests call load_spec
        path, _ = QtGui.QFileDialog.getOpenFileName(self.form, translate("Metamaterial", "Sleeve spec"), "",
                                                    translate("Metamaterial", "Sleeve spec (*.json)"))
        if path:
            self.load_spec(path)

    def add_type(self, t, h):
        r = self.types.rowCount()
        self.types.insertRow(r)
        for c, v in enumerate((t, h)):
            w = QtGui.QDoubleSpinBox()
            w.setDecimals(3)
            ranges.bind(w, ("sleeve.cell_types.t_mm", "sleeve.cell_types.h_mm")[c])   # t <= L/4, h <= 0.6 L: in words
            w.setSingleStep(0.05)
            self._set_exact(w, v)
            self._track_edits(w)
            w.valueChanged.connect(self.check_spec)     # after _track_edits: the check reads the edited value
            self.types.setCellWidget(r, c, w)
        self._tab_order()
        self.check_spec()              # the pattern may name the type just added

    def _tab_order(self):
        """Tab follows the panel's lines: the table's t / h boxes (made after the rest of the panel, so last in Qt's
        focus chain) come right after the table, row by row, before the buttons under it."""
        prev = self.types
        for r in range(self.types.rowCount()):
            for c in range(2):
                w = self.types.cellWidget(r, c)
                if w is not None:
                    QtGui.QWidget.setTabOrder(prev, w)
                    prev = w
        QtGui.QWidget.setTabOrder(prev, self.add_btn)

    def _track_edits(self, w):
        """A spin box the user changes gives its own (shown) value from then on."""
        w.valueChanged.connect(lambda *_: self.exact.pop(w, None))

    def _set_exact(self, w, v):
        """Show ``v`` in ``w`` (rounded to its decimals) and keep ``v`` itself for the spec."""
        w.setValue(float(v))
        self.exact[w] = float(v)

    def value(self, w):
        """The spec's value of spin box ``w``: the exact value it was set to, or the user's edit."""
        return self.exact.get(w, round(w.value(), 6))

    def remove_type(self):
        if self.types.rowCount() > 1:
            self.types.removeRow(self.types.rowCount() - 1)
            self.check_spec()          # the pattern may name the type just removed

    def load_spec(self, path):
        """Fill the widgets from a spec file (validated by core.sleeve.spec). Returns True on success."""
        from metamaterial_wb.core.sleeve.spec import SleeveSpec
        try:
            spec = SleeveSpec.load(path)
        except (OSError, MetamaterialError) as exc:
            self.show_error(translate("Metamaterial", "{0}: {1}").format(path, exc))
            return False
        self.path.setText(str(path))
        self.set_spec(spec)
        return True

    def set_spec(self, spec):
        self._loading = True
        try:
            self._fill(spec)
        finally:
            self._loading = False
        self.check_spec()             # a valid spec: any error the fields had goes

    def _fill(self, spec):
        self.raw = dict(spec.raw)
        self.exact = {}
        self.name.setText(spec.name)
        for key, attr in (("L_mm", "L"), ("c_mm", "c"), ("delta_mm", "delta"), ("T_mm", "T"),
                          ("shear_modulus_MPa", "G")):
            self._set_exact(self.dims[key], getattr(spec, attr))
        self.types.setRowCount(0)
        for g in spec.cells:
            self.add_type(g.t, g.h)
        uniform = all(row == spec.pattern[0] for row in spec.pattern)
        self.ring.setText(", ".join(str(v) for v in spec.pattern[0]))
        self.rings.setValue(spec.M)
        self.ring.setEnabled(uniform)
        self.rings.setEnabled(uniform)
        self.frame_nl.setChecked(spec.frame_nonlinear)
        self.frame_nl.setEnabled(spec.ring_curvature and spec.layout == "single")
        given = isinstance(spec.raw.get("actuator"), dict) and "core_diameter_mm" in spec.raw["actuator"]
        self.cap_auto.blockSignals(True)
        self.cap_auto.setChecked(not given)           # a spec's own cap is kept as given
        self.cap_auto.blockSignals(False)
        self._cap_mode(not given)
        self._set_exact(self.cap, spec.core_diameter)
        self.summary = self.predicted = None        # a prediction still running is shown as for its own values
        self.result.setStyleSheet("")
        self.result.setText("")
        self.error.setText("")
        if not uniform:
            self.result.setText(translate("Metamaterial", "this spec has a per-ring pattern; it is kept as in the file"))

    def spec_dict(self):
        """The spec the widgets describe: the loaded file's other fields (model, actuator, ...) kept."""
        d = {k: v for k, v in self.raw.items() if k not in ("cell_types",)}
        d["format"] = "metamaterial-sleeve"
        d.setdefault("version", 1)
        d["name"] = self.name.text().strip() or "sleeve"
        for key, w in self.dims.items():
            d[key] = self.value(w)
        d["cell_types"] = [{"t_mm": self.value(self.types.cellWidget(r, 0)),
                            "h_mm": self.value(self.types.cellWidget(r, 1))} for r in range(self.types.rowCount())]
        if self.ring.isEnabled():
            try:
                d["ring"] = [int(x) for x in self.ring.text().replace(";", ",").split(",") if x.strip()]
            except ValueError:
                raise MetamaterialError(translate("Metamaterial", "ring pattern {0}: expected cell type indices "
                                                  "separated by commas, e.g. 0, 0, 1, 1").format(
                    repr(self.ring.text()))) from None
            d["rings"] = int(self.rings.value())
            d.pop("pattern", None)
        actuator = dict(d.get("actuator", {}))
        if self.cap_auto.isChecked():
            actuator.pop("core_diameter_mm", None)     # the validator's default cap
        else:
            actuator["core_diameter_mm"] = self.value(self.cap)
        if actuator or "actuator" in d:
            d["actuator"] = actuator
        model = dict(d.get("model", {}))
        if self.frame_nl.isEnabled() and self.frame_nl.isChecked():
            model["frame_nonlinear"] = True
        else:
            model.pop("frame_nonlinear", None)
        if model or "model" in d:
            d["model"] = model
        return d

    def spec(self):
        from metamaterial_wb.core.sleeve.spec import SleeveSpec
        return SleeveSpec(self.spec_dict(), "panel")

    # prediction (background thread, progress + Cancel) --------------------------------------
    @property
    def job(self):
        if self.prediction.running:
            return self.prediction
        return self.export_job if self.export_job.running else None

    def predict(self):
        from metamaterial_wb.core.sleeve.pipeline import analyse
        if self.prediction.running:
            return False
        if self.export_job.running:         # one job at a time: the progress bar and Cancel are the export's
            self.show_error(translate("Metamaterial", "predict: the export is still running: wait or cancel it"))
            return False
        try:
            spec = self.spec()
        except MetamaterialError as exc:
            self.show_error(str(exc))
            return False
        self.clear_error()
        self.predict_btn.setEnabled(False)
        self.summary = self.predicted = None
        self._predicting = self._spec_key()
        self.result.setStyleSheet("")
        self.result.setText(translate("Metamaterial", "predicting ..."))
        stages = []
        step = translate("Metamaterial", "predicting: {0}")     # here: the work runs in another thread

        def work(report):
            def log(stage):
                stages.append(stage)
                report(min(0.95, 0.1 * len(stages)), step.format(stage))
            return analyse(spec, log=log)[0]
        return self.prediction.start(work, text=translate("Metamaterial", "predicting ..."))

    def _predicted(self, summary):
        self.predict_btn.setEnabled(True)
        self.predicted, self._predicting = (self._predicting, summary), None
        self.result.setText("")
        self._show_prediction()          # for the values it ran on: marked as earlier if edited meanwhile

    def _prediction_failed(self, message):
        self.predict_btn.setEnabled(True)
        self._predicting = None
        self.result.setText("")
        self.show_error(translate("Metamaterial", "prediction failed: {0}").format(message))

    def _prediction_cancelled(self):
        self.predict_btn.setEnabled(True)
        self._predicting = None
        self.result.setText(translate("Metamaterial", "prediction cancelled"))

    def wait_prediction(self, timeout_s=120.0):
        return self.prediction.wait(timeout_s)

    def export(self, folder):
        """Write sleeve.step and sleeve.3mf into ``folder`` in the background (a child process builds,
        meshes and writes them into a staging folder inside ``folder``; the files are moved in when it
        ends: nothing half-written, Cancel leaves nothing). Returns True when the export started, False
        with the error shown; ``wait_export()`` waits, ``exported`` lists the paths written."""
        from metamaterial_wb.gui.exporting import Staging

        if self.export_job.running:
            self.show_error(translate("Metamaterial", "export: an export is running (Cancel it first)"))
            return False
        if self.prediction.running:         # one job at a time: the progress bar and Cancel are the prediction's
            self.show_error(translate("Metamaterial", "export: the prediction is still running: wait or cancel it"))
            return False
        if not folder:
            self.show_error(translate("Metamaterial", "export: choose a folder"))
            return False
        folder = os.path.abspath(os.path.expanduser(folder))   # ~ is the home folder
        self.exported = []
        try:
            spec_dict = self.spec_dict()
            self.spec().check_end_pieces()                # the validator's message, before anything runs
            self.staging = Staging(folder, "sleeve-export")    # inside the folder; sweeps a killed FreeCAD's first
            jpath = os.path.join(self.staging.path, "job.json")
            out = os.path.join(self.staging.path, "out")
            os.makedirs(out)
            with open(jpath, "w", encoding="utf-8") as f:
                json.dump({"spec": spec_dict, "out_dir": out}, f)
        except (MetamaterialError, OSError) as exc:
            self._drop_staging(created=True)
            self.show_error(translate("Metamaterial", "export: {0}").format(exc))
            return False
        self.export_target = folder
        self.error.setText("")
        self.export_btn.setEnabled(False)
        self.export_job.start("metamaterial_wb.gui.sleeve_export_job", [jpath],
                              text=translate("Metamaterial", "building the sleeve ..."))
        return True

    def _drop_staging(self, created=False):
        """The staging folder goes; with ``created`` (a failed or cancelled export) the folders it made too."""
        if self.staging is not None:
            self.staging.discard(created)
        self.staging = None

    def _exported(self, result):
        self.export_btn.setEnabled(True)
        names = list(result.get("files", []))
        try:
            from metamaterial_wb.core.errors import MetamaterialError
            from metamaterial_wb.core.fileio import commit_set, remove_outputs
            from metamaterial_wb.export.sleeve import earlier_plates
            os.makedirs(self.export_target, exist_ok=True)
            stale = earlier_plates(self.export_target, names)    # an earlier export's plates this one does not write
            commit_set(os.path.join(self.staging.path, "out"), self.export_target, names)   # all together or none
        except (OSError, MetamaterialError) as exc:   # a user's folder where a file goes is refused
            self._export_failed(translate("Metamaterial", "cannot move the files into {0}: {1}").format(
                self.export_target, exc))
            return
        gone = remove_outputs(self.export_target, stale)
        self._drop_staging()
        self.exported = [os.path.join(self.export_target, n) for n in names]
        FreeCAD.Console.PrintMessage("Metamaterial sleeve export: " + ", ".join(self.exported) + "\n")
        text = translate("Metamaterial", "wrote {0}").format(", ".join(names))
        if gone:
            text += "; " + translate("Metamaterial", "removed the earlier export's {0}").format(", ".join(gone))
        self.jobbox.summary.setText(translate("Metamaterial", "wrote {0} file(s) to {1}: {2} ({3:.1f} s)").format(
            len(names), self.export_target, ", ".join(names), float(result.get("seconds", 0.0))))
        self.result.setText((self.result.text() + "\n" if self.result.text() else "") + text)

    def _export_failed(self, message):
        self.export_btn.setEnabled(True)
        self._drop_staging(created=True)
        self.show_error(translate("Metamaterial", "export: {0}").format(message))

    def _export_cancelled(self):
        self.export_btn.setEnabled(True)
        self._drop_staging(created=True)
        self.jobbox.summary.setText(translate("Metamaterial", "export cancelled: nothing written"))

    def wait_export(self, timeout_s=300.0):
        return self.export_job.wait(timeout_s)

    def cleanup(self):
        self.prediction.stop()
        if self.export_job.running:
            self.export_job.stop()
            self._drop_staging(created=True)
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
