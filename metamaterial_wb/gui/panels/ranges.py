"""Spin-box ranges read from the validators (one owner per quantity): no panel re-types a range.

``bind(spin, field)`` gives a spin box the range the validator allows for ``field`` (a key of
:data:`FIELDS`) and tags it, so ``tests/gui/test_gui_ranges.py`` can walk every panel's spin boxes and
compare them with the validators. A bound that depends on other values (a hinge length below half the
cell, a cell type's t below a quarter of L) is given its widest value here and checked in words by the
validator when the panel applies. Spin boxes that edit no validated quantity (playback speed, the
number of servos a fit searches) are tagged with ``ui_only(spin, reason)``.
"""
from PySide import QtCore, QtGui

from metamaterial_wb.core import motion
from metamaterial_wb.core.scene import sections
from metamaterial_wb.core.sleeve import spec as sleeve_spec

KEYFRAME_T_MAX_S = 1e6       # the validator has no upper bound on a keyframe time; a spin box needs one


def _sleeve_fields():
    out = {k: (lo, hi, lo_open) for k, (lo, hi, _unit, lo_open) in sleeve_spec.RANGES.items()}
    l_max = sleeve_spec.RANGES["L_mm"][1]
    for k, (lo, ratio, lo_open) in sleeve_spec.CELL_TYPE_RANGES.items():
        out["cell_types." + k] = (lo, ratio * l_max, lo_open)
    out["rings"] = (sleeve_spec.RINGS_RANGE[0], sleeve_spec.RINGS_RANGE[1], False)
    out["actuator.core_diameter_mm"] = (sleeve_spec.CAP_RANGE_MM[0], sleeve_spec.CAP_RANGE_MM[1], True)
    return out


def fields():
    """``{field: (low, high, low_open)}`` from the validators' own constants."""
    cell_max = sections.CELL_SIZE_RANGE[1]
    out = {
        "cell_size_mm": (sections.CELL_SIZE_RANGE[0], cell_max, False),
        "axes.fold_deg": (sections.FOLD_RANGE[0], sections.FOLD_RANGE[1], False),
        "value": (sections.VALUE_RANGE[0], sections.VALUE_RANGE[1], False),
        "hinge.length_mm": (0.0, 0.5 * cell_max, True),
        "hinge.width_mm": (0.0, 0.25 * cell_max, True),
        "hinge.thickness_mm": (0.0, sections.THICKNESS_MAX_MM, True),
        "profile.times_s": (0.0, KEYFRAME_T_MAX_S, False),
        "profile.values": (sections.VALUE_RANGE[0], sections.VALUE_RANGE[1], False),
    }
    out.update({"profile." + k: (lo, hi, False) for k, (lo, hi) in motion.PROFILE_RANGES.items()})
    out.update({"sleeve." + k: v for k, v in _sleeve_fields().items()})
    return out


FIELDS = fields()


def spin_range(spin, field):
    """The ``(minimum, maximum)`` a spin box must have for ``field`` (an open low bound becomes the
    smallest positive step the box can show)."""
    lo, hi, low_open = FIELDS[field]
    if low_open:
        lo = lo + (10.0 ** -spin.decimals() if hasattr(spin, "decimals") else 1)
    return lo, hi


def bind(spin, field):
    lo, hi = spin_range(spin, field)
    spin.setRange(lo, hi)
    spin.setProperty("validator_field", field)
    _watch_refused_keys(spin, field)
    return spin


REFUSED = "refused_input"    # the spin box property holding the message of a keystroke its range refused


def _watch_refused_keys(spin, field):
    """A spin box drops a keystroke that would take it past its range (typing 200 in [-180, 180] leaves 20):
    say so instead of clamping in silence. The message goes to the box's ``REFUSED`` property (``BasePanel.accept``
    refuses OK while one is set) and a tooltip; the next keystroke the box takes, or a step of its arrows, clears it."""
    if spin.property("refused_watch") or spin.lineEdit() is None:
        return
    spin.setProperty("refused_watch", True)
    watcher = _RefusedKeys(spin, field)
    spin.installEventFilter(watcher)
    spin.lineEdit().installEventFilter(watcher)
    spin.lineEdit().textEdited.connect(lambda _t: spin.setProperty(REFUSED, ""))
    spin.valueChanged.connect(lambda *_a: spin.setProperty(REFUSED, ""))   # stepped by its arrows or the wheel
    spin._mm_refused_watcher = watcher    # (kept alive with the box)


class _RefusedKeys(QtCore.QObject):
    def __init__(self, spin, field):
        super().__init__(spin)
        self.spin, self.field = spin, field
        self.keys = 0                 # keystrokes seen: only the last one's outcome is judged

    def eventFilter(self, obj, ev):
        if ev.type() == QtCore.QEvent.Type.KeyPress and ev.text() and ev.text().isprintable():
            line = self.spin.lineEdit()
            text = line.text()
            if line.hasSelectedText():
                a = line.selectionStart()
                new = text[:a] + ev.text() + text[a + len(line.selectedText()):]
            else:
                c = line.cursorPosition()
                new = text[:c] + ev.text() + text[c:]
            self.keys += 1
            n = self.keys
            QtCore.QTimer.singleShot(0, lambda: self._after(new, n))
        return False

    def _after(self, new, n):
        """Judge keystroke ``n`` once the box has handled it. Keys that arrive together (fast typing, pasted
        input) are handled before the first timer fires: an earlier key's text is then already extended ("1"
        of "10", below a minimum of 2, is "10" by now), so only the last key is judged."""
        if n != self.keys:
            return
        try:
            if self.spin.lineEdit().text() == new:
                return                                # taken
            core = new
            if self.spin.prefix() and core.startswith(self.spin.prefix()):
                core = core[len(self.spin.prefix()):]
            if self.spin.suffix() and core.endswith(self.spin.suffix()):
                core = core[:-len(self.spin.suffix())]
            value = float(core.strip().replace(",", "."))
        except (ValueError, RuntimeError):            # not a number yet, or the box is gone
            return
        lo, hi = self.spin.minimum(), self.spin.maximum()
        if lo <= value <= hi:
            return                                    # refused for another reason (more decimals than shown)
        msg = f"{self.field}: {value:g} is outside the allowed range [{lo:g}, {hi:g}]; the box kept " \
              f"{self.spin.value():g}"
        self.spin.setProperty(REFUSED, msg)
        QtGui.QToolTip.showText(self.spin.mapToGlobal(QtCore.QPoint(0, self.spin.height())), msg, self.spin)


def ui_only(spin, reason):
    spin.setProperty("ui_only", reason)
    return spin
