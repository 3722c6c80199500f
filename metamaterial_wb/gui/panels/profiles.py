"""Motion-profile editing for the Animate panel: sine, square, triangle and keyframes.

Square and triangle waves are written as the scene format's ``steps`` and ``keyframes`` profiles
(docs/scene-format.md), with the same amplitude / frequency / phase (deg) meaning as the sine: the
square is ``A sign(sin(2 pi f t + phase))``, the triangle has its peaks where the sine has them. A
``keyframes`` profile is a small time / value table, linear in between, repeating every period.
"""
import math

from PySide import QtGui

from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.core.motion import PROFILE_RANGES
from metamaterial_wb.gui.panels import ranges
from metamaterial_wb.gui.panels.base import button_row
from metamaterial_wb.gui.i18n import translate

SHAPES = ["sine", "square", "triangle", "keyframes"]


def _keys(period, points):
    """Sorted ``(times, values)`` from ``[(t, v)]`` wrapped into [0, period), a key at t = 0 first."""
    pts = {}
    for t, v in points:
        pts[round(math.fmod(math.fmod(t, period) + period, period), 9)] = v
    ts = sorted(pts)
    return [float(t) for t in ts], [float(pts[t]) for t in ts]


def wave_profile(shape, amplitude, frequency_hz, phase_deg, motor=None):
    """The scene profile of a sine / square / triangle wave (validated later by the scene).

    A square or triangle wave needs a frequency > 0 Hz (its period is 1 / f): at 0 Hz it is refused with a
    ``SceneError`` naming the motor (``motor``), the shape and the value, never turned into a sine.
    """
    if shape in ("square", "triangle") and not frequency_hz > 0:
        high = PROFILE_RANGES["frequency_hz"][1]
        raise SceneError(f"motor {motor}" if motor else "",
                         f"a {shape} wave needs a frequency > 0 Hz (its period is 1 / f); "
                         f"got {float(frequency_hz):g} Hz, allowed (0, {high:g}] Hz")
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


def keyframes_profile(points, period_s):
    """``[(t, v)]`` (any order) -> a keyframes profile repeating every ``period_s``."""
    pts = sorted((float(t), float(v)) for t, v in points)
    return {"shape": "keyframes", "times_s": [t for t, _ in pts], "values": [v for _, v in pts],
            "period_s": float(period_s)}


class KeyframeTable(QtGui.QWidget):
    """A small time (s) / value (-1..1) table with Add / Remove, for one motor at a time."""

    def __init__(self, on_change, parent=None):
        super().__init__(parent)
        self.on_change = on_change
        lay = QtGui.QVBoxLayout(self)
        lay.setContentsMargins(0, 0, 0, 0)
        self.title = QtGui.QLabel(translate("Metamaterial", "Keyframes"))
        lay.addWidget(self.title)
        self.table = QtGui.QTableWidget(0, 2)
        self.table.setHorizontalHeaderLabels([translate("Metamaterial", "time (s)"),
                                              translate("Metamaterial", "value (-1..1)")])
        self.table.setMaximumHeight(150)
        self.table.horizontalHeader().setStretchLastSection(True)
        lay.addWidget(self.table)
        row, (self.add_btn, self.del_btn) = button_row("Add key", "Remove last")
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
