"""Motion-profile editing for the Animate panel: sine, square, triangle and keyframes.

Square and triangle waves are written as the scene format's ``steps`` and ``keyframes`` profiles
(docs/scene-format.md), with the same amplitude / frequency / phase (deg) meaning as the sine: the
square is ``A sign(sin(2 pi f t + phase))``, the triangle has its peaks where the sine has them. A
``keyframes`` profile is a small time / value table, linear in between, repeating every period.
A stored ``steps`` / ``keyframes`` profile that is exactly such a square / triangle (``wave_fields``: the encoding
``wave_profile`` writes for amplitude / frequency / phase the panel's boxes can hold) is shown as a square / triangle
again; any other one stays "stored steps" / "keyframes".
"""
import math

from PySide import QtGui

from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.core.motion import PROFILE_RANGES
from metamaterial_wb.gui.panels import ranges
from metamaterial_wb.gui.panels.base import button_row
from metamaterial_wb.gui.i18n import QT_TRANSLATE_NOOP, translate

SHAPES = ["sine", "square", "triangle", "keyframes"]
# the shape a motor without a motion profile shows: it holds its value, kept so until another shape is chosen
NONE = "none"
# what the shape combo shows (translated) for each shape it holds as its item data; a stored steps / constant
# profile shows as "stored steps" / "stored constant"
SHAPE_LABELS = {"sine": QT_TRANSLATE_NOOP("Metamaterial", "sine"),
                "square": QT_TRANSLATE_NOOP("Metamaterial", "square"),
                "triangle": QT_TRANSLATE_NOOP("Metamaterial", "triangle"),
                "keyframes": QT_TRANSLATE_NOOP("Metamaterial", "keyframes"),
                NONE: QT_TRANSLATE_NOOP("Metamaterial", "none"),
                "stored steps": QT_TRANSLATE_NOOP("Metamaterial", "stored steps"),
                "stored constant": QT_TRANSLATE_NOOP("Metamaterial", "stored constant")}


def shape_label(shape):
    """The translated text the shape combo shows for ``shape`` (its item data)."""
    if shape in SHAPE_LABELS:
        return translate("Metamaterial", SHAPE_LABELS[shape])
    if shape.startswith("stored "):
        return translate("Metamaterial", "stored {0}").format(shape[len("stored "):])
    return shape
# decimals of the Animate panel's amplitude, frequency (Hz) and phase (deg) boxes
WAVE_DECIMALS = (3, 3, 1)


def profile_value_range(profile, default=0.0):
    """(lowest, highest) value a motion profile takes (``core.motion.profile_value``): offset -+ amplitude for a
    sine, the lowest and highest key of steps / keyframes, ``default`` without a profile."""
    if not profile:
        return float(default), float(default)
    shape = profile.get("shape", "sine")
    if shape == "sine":
        off, amp = float(profile.get("offset", 0.0)), abs(float(profile.get("amplitude", 1.0)))
        if float(profile.get("frequency_hz", 1.0)) == 0.0:   # a constant sin(phase)
            v = off + float(profile.get("amplitude", 1.0)) * math.sin(math.radians(profile.get("phase_deg", 0.0)))
            return v, v
        return off - amp, off + amp
    if shape == "constant":
        v = float(profile.get("value", 0.0))
        return v, v
    values = [float(v) for v in profile.get("values", [])] or [float(default)]
    return min(values), max(values)


def _keys(period, points):
    """Sorted ``(times, values)`` from ``[(t, v)]`` wrapped into [0, period), a key at t = 0 first."""
    pts = {}
    for t, v in points:
        r = round(math.fmod(math.fmod(t, period) + period, period), 9)
        pts[0.0 if r >= period else r] = v      # rounded onto the period itself: that is t = 0 of the next one
    ts = sorted(pts)
    return [float(t) for t in ts], [float(pts[t]) for t in ts]


def wave_profile(shape, amplitude, frequency_hz, phase_deg, motor=None):
    """The scene profile of a sine / square / triangle wave (validated later by the scene).

    A square or triangle wave needs a frequency > 0 Hz (its period is 1 / f): at 0 Hz it is refused with a
    ``SceneError`` naming the motor (``motor``), the shape and the value, never turned into a sine.
    """
    if shape in ("square", "triangle") and not frequency_hz > 0:
        high = PROFILE_RANGES["frequency_hz"][1]
        raise SceneError(translate("Metamaterial", "motor {0}").format(motor) if motor else "",
                         translate("Metamaterial", "a {0} wave needs a frequency > 0 Hz (its period is 1 / f); "
                                   "got {1:g} Hz, allowed (0, {2:g}] Hz").format(shape_label(shape), float(frequency_hz),
                                                                                 high))
    if shape == "sine":
        return {"shape": "sine", "amplitude": float(amplitude), "frequency_hz": float(frequency_hz),
                "phase_deg": float(phase_deg)}
    period = 1.0 / frequency_hz
    phi = math.radians(phase_deg)

    def t_of(theta):                      # the time at which 2 pi f t + phi = theta
        return (theta - phi) / (2.0 * math.pi * frequency_hz)
    a = float(amplitude)
    if shape == "square":
        s0 = math.sin(phi)
        v0 = a if (s0 > 0 or (s0 == 0 and math.cos(phi) > 0)) else -a
        times, values = _keys(period, [(0.0, v0), (t_of(0.0), a), (t_of(math.pi), -a)])
        return {"shape": "steps", "times_s": times, "values": values, "period_s": period}
    if shape == "triangle":
        v0 = a * (2.0 / math.pi) * math.asin(max(-1.0, min(1.0, math.sin(phi))))
        times, values = _keys(period, [(0.0, v0), (t_of(0.5 * math.pi), a), (t_of(1.5 * math.pi), -a)])
        return {"shape": "keyframes", "times_s": times, "values": values, "period_s": period}
    raise ValueError(f"unknown wave shape {shape!r}")


def _number(x):
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)


def _same_numbers(a, b):
    """Equal lists of numbers, zeros of the same sign (a square of amplitude 0 keeps +0.0 / -0.0 apart)."""
    return (isinstance(a, list) and len(a) == len(b) and all(_number(x) for x in a)
            and all(x == y and math.copysign(1.0, x) == math.copysign(1.0, y) for x, y in zip(a, b)))


# the scene shape a square / triangle wave is stored as, and the angle (deg) of 2 pi f t + phase at which the wave
# has its +A key and its -A key: the square steps up at 0 and down at 180, the triangle peaks at 90 and -90
WAVE_STORED = {"square": ("steps", 0.0, 180.0), "triangle": ("keyframes", 90.0, -90.0)}


def square_fields(profile):
    """``(amplitude, frequency_hz, phase_deg)`` of a ``steps`` profile that is exactly the square wave
    ``wave_profile("square", ...)`` writes, else None (``wave_fields``)."""
    return wave_fields(profile, "square")


def stored_wave(profile):
    """``(shape, (amplitude, frequency_hz, phase_deg))`` of a stored profile that is exactly a square or triangle
    wave ``wave_profile`` writes (``wave_fields``), else None."""
    for shape in WAVE_STORED:
        fields = wave_fields(profile, shape)
        if fields is not None:
            return shape, fields
    return None


def wave_fields(profile, shape):
    """``(amplitude, frequency_hz, phase_deg)`` of a stored profile that is exactly the ``shape`` ("square": a
    ``steps`` profile, "triangle": a ``keyframes`` one) ``wave_profile(shape, ...)`` writes for values the panel's
    boxes hold (``WAVE_DECIMALS``), else None.

    The phase is given in (-180, 180] deg (a wave stored with 270 deg shows -90 deg: the stored profile
    is the same). Any other profile (other values, times or fields, a hair off, no period) gives None."""
    stored, up, down = WAVE_STORED[shape]
    if not isinstance(profile, dict) or profile.get("shape") != stored or \
            set(profile) != {"shape", "times_s", "values", "period_s"}:
        return None
    times, values, period = profile["times_s"], profile["values"], profile["period_s"]
    if not (isinstance(times, list) and isinstance(values, list) and 1 <= len(times) == len(values) <= 3
            and all(_number(x) for x in times + values) and _number(period) and period > 0):
        return None
    amp = round(max(abs(float(v)) for v in values), WAVE_DECIMALS[0])
    freq = round(1.0 / float(period), WAVE_DECIMALS[1])
    lo, hi = PROFILE_RANGES["frequency_hz"]
    if not (PROFILE_RANGES["amplitude"][0] <= amp <= PROFILE_RANGES["amplitude"][1] and lo < freq <= hi):
        return None
    # each key gives a phase: a +A key at t lies where 2 pi f t + phase = up, a -A key where it is down (a key a
    # hair before the period end, from the wrap, is tried too); the phase in (-180, 180] first, then one or more
    # turns away (those can differ in the last digit of a wrapped time), nearest to 0 first
    low, high = PROFILE_RANGES["phase_deg"]
    turns = sorted(range(-int(high // 360) - 1, int(high // 360) + 2), key=lambda k: (abs(k), k))
    firsts = []
    for t, v in zip(times, values):
        turn = round(math.fmod((up if math.copysign(1.0, v) > 0 else down) - 360.0 * float(t) / float(period),
                               360.0), WAVE_DECIMALS[2])
        turn = turn + 360.0 if turn <= -180.0 else (turn - 360.0 if turn > 180.0 else turn)
        if turn not in firsts:
            firsts.append(turn)
    tried = set()
    for phase in (round(turn + 360.0 * k, WAVE_DECIMALS[2]) for k in turns for turn in firsts):
        if not low <= phase <= high or phase in tried:
            continue
        tried.add(phase)
        # a phase of -0 deg gives a triangle starting at -0.0 (its sign kept apart): shown as 0 deg
        for ph in ((0.0, -0.0) if phase == 0 else (phase,)):
            try:
                want = wave_profile(shape, amp, freq, ph)
            except (SceneError, ValueError, ZeroDivisionError):  # pragma: no cover - freq > 0 checked
                return None
            if _same_numbers(times, want["times_s"]) and _same_numbers(values, want["values"]) and \
                    float(period) == want["period_s"]:
                return amp, freq, 0.0 if ph == 0 else ph
    return None


ONCE = float("inf")      # the period of a keyframes profile stored without one: it plays once, holding the last value


def keyframes_profile(points, period_s):
    """``[(t, v)]`` (any order) -> a keyframes profile repeating every ``period_s`` (None: played once, no
    ``period_s`` written, as the scene format allows)."""
    pts = sorted((float(t), float(v)) for t, v in points)
    out = {"shape": "keyframes", "times_s": [t for t, _ in pts], "values": [v for _, v in pts]}
    if period_s is not None:
        out["period_s"] = float(period_s)
    return out


class KeyframeTable(QtGui.QWidget):
    """A small time (s) / value (-1..1) table with Add / Remove, for one motor at a time."""

    def __init__(self, on_change, parent=None):
        super().__init__(parent)
        self.on_change = on_change
        lay = QtGui.QVBoxLayout(self)
        lay.setContentsMargins(0, 0, 0, 0)
        self.title = QtGui.QLabel(translate("Metamaterial", "Keyframes"))
        self.title.setWordWrap(True)          # a long motor name wraps in a narrow task dock
        lay.addWidget(self.title)
        self.table = QtGui.QTableWidget(0, 2)
        self.table.setHorizontalHeaderLabels([translate("Metamaterial", "time (s)"),
                                              translate("Metamaterial", "value (-1..1)")])
        self.table.setMaximumHeight(150)
        self.table.horizontalHeader().setStretchLastSection(True)
        lay.addWidget(self.table)
        row, (self.add_btn, self.del_btn) = button_row(QT_TRANSLATE_NOOP("Metamaterial", "Add key"),
                                                       QT_TRANSLATE_NOOP("Metamaterial", "Remove last"))
        lay.addLayout(row)
        self.add_btn.clicked.connect(lambda: self.add_key(self._next_time(), 0.0))
        self.del_btn.clicked.connect(self.remove_key)
        self._quiet = False

    def _next_time(self):
        pts = self.points()
        return (pts[-1][0] + 0.5) if pts else 0.0

    def add_key(self, t, v):
        r = self.table.rowCount()
        self.table.insertRow(r)
        for c, (val, field, step) in enumerate(((t, "profile.times_s", 0.1), (v, "profile.values", 0.05))):
            w = QtGui.QDoubleSpinBox()
            w.setDecimals(3)
            ranges.bind(w, field)
            w.setSingleStep(step)
            w.setValue(float(val))
            w.valueChanged.connect(self._changed)
            self.table.setCellWidget(r, c, w)
        self._changed()

    def remove_key(self):
        if self.table.rowCount() > 1:
            self.table.removeRow(self.table.rowCount() - 1)
            self._changed()

    def points(self):
        return [(self.table.cellWidget(r, 0).value(), self.table.cellWidget(r, 1).value())
                for r in range(self.table.rowCount())]

    def set_points(self, name, points):
        self._quiet = True
        self.title.setText(translate("Metamaterial", "Keyframes of {0}").format(name))
        self.table.setRowCount(0)
        for t, v in points:
            self.add_key(t, v)
        self._quiet = False

    def _changed(self, *_):
        if not self._quiet:
            self.on_change()
