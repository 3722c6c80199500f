"""Small widgets the task panels share in a narrow task dock (the combo view, ~300 px): a label cut with "..." to
the width it gets (``ElidedLabel``) and a check box whose text wraps (``wrapped_check``); and the event filter that
keeps a focused slider's keys from FreeCAD's shortcuts (``SliderKeys``: Folded shape, Simulate, Animate's timeline)."""
from PySide import QtCore, QtGui


class ElidedLabel(QtGui.QLabel):
    """A one-line label that never widens the panel: cut with "..." to the width it gets, in full in its tooltip."""

    def __init__(self, text=""):
        super().__init__()
        self._full = ""
        self.setMinimumWidth(1)
        self.setSizePolicy(QtGui.QSizePolicy.Policy.Ignored, QtGui.QSizePolicy.Policy.Preferred)
        self.setFullText(text)

    def setFullText(self, text):
        self._full = text
        self.setToolTip(text)
        self._elide()

    def fullText(self):
        return self._full

    def sizeHint(self):
        return self.fontMetrics().size(0, self._full) + QtCore.QSize(2 * self.margin(), 2 * self.margin())

    def resizeEvent(self, ev):
        super().resizeEvent(ev)
        self._elide()

    def _elide(self):
        shown = self.fontMetrics().elidedText(self._full, QtCore.Qt.TextElideMode.ElideRight,
                                              max(1, self.width() - 2 * self.margin()))
        if shown != self.text():
            self.setText(shown)


SLIDER_KEYS = ("Key_Left", "Key_Right", "Key_Up", "Key_Down", "Key_PageUp", "Key_PageDown", "Key_Home", "Key_End")


class SliderKeys(QtCore.QObject):
    """Event filter for a slider: while it has the focus its own keys (arrows, PageUp / PageDown, Home / End, without
    Ctrl / Alt / Shift) reach it instead of the main window's shortcuts (FreeCAD binds Home to its home view), as a
    text field keeps its editing keys. One instance may serve all of a panel's sliders (keep a reference to it)."""

    KEYS = tuple(getattr(QtCore.Qt.Key, n) for n in SLIDER_KEYS)
    PLAIN = (QtCore.Qt.KeyboardModifier.NoModifier, QtCore.Qt.KeyboardModifier.KeypadModifier)

    def eventFilter(self, obj, ev):
        if ev.type() == QtCore.QEvent.Type.ShortcutOverride and hasattr(ev, "key") \
                and ev.key() in self.KEYS and ev.modifiers() in self.PLAIN:
            ev.accept()
            return True
        return False


class _WrapCheck(QtGui.QCheckBox):
    """The box of ``wrapped_check``: its label follows its enabled state."""
    label = None

    def changeEvent(self, ev):
        super().changeEvent(ev)
        if ev.type() == QtCore.QEvent.Type.EnabledChange and self.label is not None:
            self.label.setEnabled(self.isEnabled())


class _CheckLabel(QtGui.QLabel):
    """The text of ``wrapped_check``: word-wrapped; a click on it toggles its box, as a click on a check box's text does."""

    def __init__(self, text, check):
        super().__init__(text)
        self.check = check
        self.setWordWrap(True)
        self.setBuddy(check)

    def mouseReleaseEvent(self, ev):
        super().mouseReleaseEvent(ev)
        if ev.button() == QtCore.Qt.MouseButton.LeftButton and self.check.isEnabled() \
                and self.rect().contains(ev.pos()):
            self.check.click()


def wrapped_check(text):
    """``(check box, row)``: a check box whose text wraps in a narrow task dock (a QCheckBox never wraps its own
    text): the box, named by ``text`` (its accessible name; the label is its buddy), and the word-wrapped text beside
    it, which toggles it when clicked. Put ``row`` in the layout. (Fit to target, Sleeve.)"""
    check = _WrapCheck()
    check.setAccessibleName(text)
    lab = _CheckLabel(text, check)
    check.label = lab
    row = QtGui.QWidget()
    h = QtGui.QHBoxLayout(row)
    h.setContentsMargins(0, 0, 0, 0)
    h.addWidget(check, 0, QtCore.Qt.AlignmentFlag.AlignTop)
    h.addWidget(lab, 1)
    return check, row
