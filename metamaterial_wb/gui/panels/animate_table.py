"""Animate's motion-profile rows (a part of :class:`~metamaterial_wb.gui.panels.animate.AnimatePanel`).

One row per motor: its shape (sine / square / triangle / keyframes; "none" for a motor without a profile, which
holds its value; "stored steps" / "stored constant" for a steps / constant profile kept as stored until
another shape is chosen), amplitude, frequency, phase and the servo angle range the profile sweeps. The rows show
as a table where it fits the panel's width, else as a form, one motor under the other (a narrow task dock): the
same widgets move between the table's cells and the form (:meth:`ProfileRows._fit_profiles`, called on every
resize of the panel through :class:`OnResize`). A keyframes row is edited in the one keyframe table under the
rows. :meth:`ProfileRows.profiles` reads the rows back; a row the user did not touch keeps its stored profile
exactly.

The panel provides ``scene``, ``angles`` (``stream.ServoAngles``), ``form`` / ``layout`` / ``set_problem``
(``BasePanel``), ``stats`` (built last: the rows are fitted only once it exists) and, for
:meth:`ProfileRows._profiles_changed`, ``preview_scene`` and ``_warn_follow`` (the playback clock).
"""
from PySide import QtCore, QtGui

from metamaterial_wb.core.errors import MetamaterialError
from metamaterial_wb.core.scene import Scene
from metamaterial_wb.gui.panels.widgets import ElidedLabel
from metamaterial_wb.gui.panels.profiles import (NONE, ONCE, SHAPES, WAVE_DECIMALS, keyframes_profile,
                                                 profile_value_range, shape_label, stored_wave, wave_profile)
from metamaterial_wb.gui.panels import ranges
from metamaterial_wb.gui.i18n import translate


GRID = 2        # px a table cell's widget loses to the grid lines


class OnResize(QtCore.QObject):
    """Event filter calling ``callback`` when the widget it watches is resized."""

    def __init__(self, callback):
        super().__init__()
        self.callback = callback

    def eventFilter(self, obj, ev):
        if ev.type() == QtCore.QEvent.Type.Resize:
            self.callback()
        return False


def set_profile(actuator, profile):
    """Put a motor's profile into its scene dict; None (a motor without one) leaves it without."""
    if profile is None:
        actuator.pop("profile", None)
    else:
        actuator["profile"] = profile


class ProfileRows:
    """The motors' profile rows (table or per-motor form), their keyframe table and reading the profiles back (a
    mixin of the Animate panel)."""

    def _build_profile_rows(self, keyframe_table):
        """Build the rows (table + form), the keyframe table (``keyframe_table``: its class, passed by the panel so
        that ``animate.KeyframeTable`` is the one used) and the period note, and add them to the panel's layout;
        each row then shows its shape's fields and ``untouched`` records what the rows show at first."""
        heads = [translate("Metamaterial", "motor"), translate("Metamaterial", "shape"),
                 translate("Metamaterial", "amplitude"), translate("Metamaterial", "freq (Hz)"),
                 translate("Metamaterial", "phase (deg)"), translate("Metamaterial", "servo angle range")]
        range_tip = translate("Metamaterial", "Lowest .. highest angle sent to the servo over the profile's swing "
                              "(closing and opening differ, the sign is the servo's)")
        self.table = QtGui.QTableWidget(len(self.scene.actuators), 6)
        self.table.setHorizontalHeaderLabels(heads)
        self.table.horizontalHeaderItem(5).setToolTip(range_tip)
        # the same widgets as a form, one motor under the other, where the table would scroll sideways (a narrow
        # task dock): the row's widgets move between the table's cells and this form (_fit_profiles)
        self.motor_form = QtGui.QWidget()
        self.motor_grid = QtGui.QGridLayout(self.motor_form)
        self.motor_grid.setContentsMargins(0, 0, 0, 0)
        self.motor_grid.setColumnStretch(1, 1)
        self.cells = {}           # motor -> [(widget, its table cell's holder, its (row, column) in the form)]
        self.as_form = False
        self.spins, self.shapes, self.amp_deg, self.keys, self.stored = {}, {}, {}, {}, {}
        # a keyframes profile's period, fixed once (the stored one, or when a row becomes keyframes): never the
        # timeline length shown, which is not stored
        self.key_periods = {}
        self.spin_tips = {}
        for r, a in enumerate(self.scene.actuators):
            # a motor without a profile shows "none" and keeps its value until another shape is chosen; its
            # boxes then start from a still sine
            p = a.profile or {"shape": "none", "amplitude": 0.0, "frequency_hz": 0.5, "phase_deg": 0.0}
            self.table.setItem(r, 0, QtGui.QTableWidgetItem(a.name))
            shape = p.get("shape", "sine")
            # a square / triangle the panel wrote (stored as steps / keyframes) shows as such again, its boxes
            # editable
            known = stored_wave(p)
            wave = dict(zip(("amplitude", "frequency_hz", "phase_deg"), known[1])) if known else \
                (p if shape in ("sine", "none") else {})
            combo = QtGui.QComboBox()              # the shapes as item data, shown translated
            for s in SHAPES:
                combo.addItem(shape_label(s), s)
            if known:
                combo.setCurrentIndex(combo.findData(known[0]))
            elif shape in ("sine", "keyframes"):
                combo.setCurrentIndex(combo.findData(shape))
            elif shape == "none":
                combo.insertItem(0, shape_label(NONE), NONE)
                combo.setCurrentIndex(0)
            else:                                  # steps / constant from a file: kept as stored until changed
                self.stored[a.name] = dict(p)
                combo.insertItem(0, shape_label(f"stored {shape}"), f"stored {shape}")
                combo.setCurrentIndex(0)
            self.keys[a.name] = list(zip(p.get("times_s", [0.0, 0.5]), p.get("values", [0.0, 0.5])))
            if shape == "keyframes":              # stored without a period: it plays once and stays so
                self.key_periods[a.name] = float(p["period_s"]) if p.get("period_s") else ONCE
            self.shapes[a.name] = combo
            sp = []
            for c, (key, default) in enumerate((("amplitude", 0.5), ("frequency_hz", 0.5), ("phase_deg", 0.0)), start=2):
                w = QtGui.QDoubleSpinBox()
                w.setDecimals(WAVE_DECIMALS[c - 2])
                ranges.bind(w, "profile." + key)
                w.setSingleStep(0.05 if key != "phase_deg" else 15.0)
                w.setValue(float(wave.get(key, default)))
                w.valueChanged.connect(self._profiles_changed)
                self.spin_tips[w] = w.toolTip()
                sp.append(w)
            self.spins[a.name] = sp
            lab = QtGui.QLabel("")
            lab.setToolTip(self.angles.tooltip([a.name]))
            self.amp_deg[a.name] = lab
            base = 6 * r
            name = ElidedLabel(a.name)
            font = name.font()
            font.setBold(True)
            name.setFont(font)
            self.motor_grid.addWidget(name, base, 0, 1, 2)
            self.cells[a.name] = []
            for c, w in enumerate([combo, *sp, lab], start=1):
                head = QtGui.QLabel(heads[c])
                if w in sp:                        # a refused key names the box ("amplitude of m1 (profile.amplitude)")
                    w.setAccessibleName(translate("Metamaterial", "{0} of {1}").format(heads[c], a.name))
                if c == 5:
                    head.setToolTip(range_tip)
                self.motor_grid.addWidget(head, base + c, 0)
                holder = QtGui.QWidget()
                lay = QtGui.QHBoxLayout(holder)
                lay.setContentsMargins(0, 0, 0, 0)
                lay.addWidget(w)
                self.table.setCellWidget(r, c, holder)
                self.cells[a.name].append((w, holder, (base + c, 1)))
            combo.currentIndexChanged.connect(lambda *_, n=a.name: self._shape_changed(n))
        self.motor_form.setVisible(False)
        self.table.setMaximumHeight(40 + 30 * max(1, len(self.scene.actuators)))
        self.table.horizontalHeader().setStretchLastSection(True)
        self.table.resizeColumnsToContents()
        self.layout.addWidget(self.table)
        self.layout.addWidget(self.motor_form)
        self.keyframes = keyframe_table(self._keys_edited)
        self.keyframes.setVisible(False)
        self.key_motor = None
        self.period_note = QtGui.QLabel("")
        self.period_note.setWordWrap(True)
        self.period_note.setStyleSheet("color: #a05a00;")
        self.layout.addWidget(self.keyframes)     # in the form before a row shows it (no parent: its own window)
        self.layout.addWidget(self.period_note)
        for a in self.scene.actuators:        # each row's shape shows its fields (stored rows: read-only)
            self._shape_ui(a.name)
        self.untouched = {a.name: self._row_state(a.name) for a in self.scene.actuators}

    def shape_of(self, name):
        """The shape a motor's row shows (the combo's item data: "sine", ..., "none", "stored steps")."""
        return self.shapes[name].currentData()

    def _row_state(self, name):
        """What a motor's row shows: its shape, its three spin boxes and its keyframes."""
        return (self.shape_of(name), tuple(w.value() for w in self.spins[name]), tuple(self.keys[name]))

    def profiles(self):
        """The motors' profiles (None: the motor has none); a row the user did not touch keeps its stored profile
        exactly (the spin boxes round 0.1234 to 0.123, and an OK that changed nothing writes nothing)."""
        out = {}
        for a in self.scene.actuators:
            shape = self.shape_of(a.name)
            if a.profile and self._row_state(a.name) == getattr(self, "untouched", {}).get(a.name):
                out[a.name] = dict(a.profile)
                continue
            if shape.startswith("stored"):
                out[a.name] = dict(self.stored[a.name])
                continue
            if shape == NONE:                 # a motor without a profile keeps none (it holds its value)
                out[a.name] = None
                continue
            if shape == "keyframes":
                out[a.name] = keyframes_profile(self.keys[a.name], self.key_period(a.name))
                continue
            amp, f, ph = self._wave_fields(a, shape)
            p = wave_profile(shape, amp, f, ph, motor=a.name)
            if shape == "sine" and a.profile and a.profile.get("offset"):
                p["offset"] = a.profile["offset"]
            out[a.name] = p
        return out

    def _wave_fields(self, a, shape):
        """Amplitude, frequency and phase of a touched row: a spin box still at its first value keeps the stored
        sine's exact field (changing the frequency rounded an amplitude of 0.1234 to 0.123)."""
        vals = [w.value() for w in self.spins[a.name]]
        first = getattr(self, "untouched", {}).get(a.name)
        if first is not None and shape == "sine" and (a.profile or {}).get("shape", "sine") == "sine" and a.profile:
            for k, key in enumerate(("amplitude", "frequency_hz", "phase_deg")):
                if vals[k] == first[1][k] and key in a.profile:
                    vals[k] = float(a.profile[key])
        return vals

    def _last_key(self, name):
        return max((t for t, _v in self.keys[name]), default=0.0)

    def key_period(self, name):
        """A keyframes profile's period: the one fixed for the row (stored, or set when it became keyframes),
        extended to the last key + 0.1 s while a key lies beyond it (``period_note`` says so); never the
        timeline length, which is not stored."""
        last = self._last_key(name)
        fixed = self.key_periods.get(name)
        if fixed is None:
            fixed = self._fix_key_period(name)
        if fixed == ONCE:                     # a stored one-shot profile (no period_s): no period is made up
            return None
        return float(fixed) if last < fixed else round(last + 0.1, 9)

    def _fix_key_period(self, name):
        """The period a row gets when it becomes keyframes: the wave's period of the row (1 / its frequency),
        else the last key + 0.1 s."""
        f = self.spins[name][1].value() if name in self.spins else 0.0
        last = self._last_key(name)
        period = 1.0 / f if f > 0 else 0.0
        if period <= last:
            period = round(last + 0.1, 9)
        self.key_periods[name] = period
        return period

    def _update_period_note(self):
        notes = []
        for name in self.shapes:
            if self.shape_of(name) != "keyframes":
                continue
            fixed = self.key_periods.get(name)
            if fixed is None:
                fixed = self._fix_key_period(name)
            last = self._last_key(name)
            if fixed == ONCE:
                if name == self.key_motor:
                    notes.append(translate("Metamaterial", "{0}: keyframes play once (stored without a period) and "
                                                           "hold the last value").format(name))
                continue
            if last >= fixed:
                notes.append(translate("Metamaterial", "{0}: a key at {1:.3f} s lies beyond the period of {2:.3f} s: "
                                                       "the period becomes {3:.3f} s").format(
                    name, last, fixed, self.key_period(name)))
            elif name == self.key_motor:
                notes.append(translate("Metamaterial", "{0}: keyframes repeat every {1:.3f} s").format(name, fixed))
        self.period_note.setText("\n".join(notes))

    def _shape_ui(self, name):
        """Show the fields of the row's shape: the wave boxes for sine / square / triangle, the keyframe table
        for keyframes; a stored steps / constant profile is kept as it is (its boxes disabled)."""
        shape = self.shape_of(name)
        wave = shape in ("sine", "square", "triangle")
        if shape.startswith("stored"):
            tip = translate("Metamaterial", "{0} keeps its {1} profile as stored: these boxes do not apply to it. "
                                            "Choose another shape to replace it.").format(
                name, shape_label(shape[len("stored "):]))
        elif shape == NONE:
            tip = translate("Metamaterial", "{0} has no motion profile: it holds its value, these boxes do not "
                                            "apply to it. Choose a shape to give it one.").format(name)
        elif shape == "keyframes":
            tip = translate("Metamaterial", "a keyframes profile is edited in its time / value table below")
        else:
            tip = ""
        for w in self.spins[name]:
            w.setEnabled(wave)
            base = self.spin_tips.get(w, "")
            w.setToolTip(tip if not base else (base if not tip else tip + "\n" + base))
        self.shapes[name].setToolTip(tip if shape.startswith("stored") or shape == NONE else "")
        if shape == "keyframes":
            if name not in self.key_periods:
                self._fix_key_period(name)
            self.key_motor = name
            self.keyframes.set_points(name, self.keys[name])
            self.keyframes.setVisible(True)
        elif self.key_motor == name:
            self.keyframes.setVisible(False)
            self.key_motor = None

    def _shape_changed(self, name):
        self._shape_ui(name)
        self._profiles_changed()

    def _keys_edited(self):
        if self.key_motor is not None:
            self.keys[self.key_motor] = self.keyframes.points()
        self._profiles_changed()

    def set_shape(self, name, shape):
        """Choose ``shape`` ("sine", "square", ...) in a motor's row; an unknown one changes nothing."""
        combo = self.shapes[name]
        k = combo.findData(shape)
        if k >= 0:
            combo.setCurrentIndex(k)

    def set_profile(self, name, amplitude=None, frequency_hz=None, phase_deg=None):
        w = self.spins[name]
        for spin, v in zip(w, (amplitude, frequency_hz, phase_deg)):
            if v is not None:
                spin.setValue(v)

    # the profile rows: a table where it fits, else a form, one motor under the other -------------------
    def table_width(self):
        """The width the profile table needs to show every column whole (no sideways scroll)."""
        t = self.table
        need = t.verticalHeader().sizeHint().width() + 2 * t.frameWidth() + 4
        return need + sum(self._column_width(c) for c in range(6))

    def _column_width(self, c):
        """Column c's width that shows its header and every cell's widget whole (+ the grid line)."""
        cells = [ws[c - 1][0].sizeHint().width() + GRID for ws in self.cells.values()] if c else \
            [self.table.sizeHintForColumn(0)]
        return max([self.table.horizontalHeader().sectionSizeHint(c)] + cells)

    def _fit_profiles(self):
        """Show the profile rows as the table when it fits the panel's width, else as the per-motor form (a
        narrow task dock); the same widgets move between the two."""
        if not hasattr(self, "cells") or not hasattr(self, "stats"):     # still being built
            return
        m = self.layout.contentsMargins()
        room = self.form.width() - m.left() - m.right()
        as_form = self.table_width() > room
        if as_form == self.as_form:
            if not as_form:
                self._size_columns()
            return
        self.as_form = as_form
        for ws in self.cells.values():
            for w, holder, (row, col) in ws:
                if as_form:
                    holder.layout().removeWidget(w)
                    self.motor_grid.addWidget(w, row, col)
                else:
                    self.motor_grid.removeWidget(w)
                    holder.layout().addWidget(w)
        self.table.setVisible(not as_form)
        self.motor_form.setVisible(as_form)
        if not as_form:
            self._size_columns()

    def _size_columns(self):
        for c in range(5):                      # the last one stretches
            self.table.horizontalHeader().resizeSection(c, self._column_width(c))

    def _profiles_changed(self, *_):
        d = self.scene.to_dict()
        try:
            prof = self.profiles()
        except MetamaterialError as exc:     # a square / triangle at 0 Hz (profiles.wave_profile)
            self.set_problem("profiles", str(exc))
            return
        for a in d["actuators"]:
            set_profile(a, prof[a["name"]])
        self._update_period_note()
        for a in self.scene.actuators:
            if a.name in self.amp_deg:
                span = self.angles.span(a.name, *profile_value_range(prof[a.name], a.value))
                self.amp_deg[a.name].setText(translate("Metamaterial", "? deg") if span is None else
                                             translate("Metamaterial", "{0:+.1f} .. {1:+.1f} deg").format(*span))
        self._fit_profiles()
        try:
            self.preview_scene = Scene.from_dict(d)
            self.set_problem("profiles", "")
        except MetamaterialError as exc:
            self.set_problem("profiles", str(exc))
            return
        self._warn_follow()
