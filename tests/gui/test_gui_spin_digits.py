"""Digits of another script typed into a spin box (session 30): Qt (C / English locale, 0.20 and 1.1) drops an
Arabic-Indic '٣' (U+0663) or a full-width '３' (U+FF13) as it drops a letter, but the key watcher read them as
numbers (``\\d`` and Python's ``float`` take any script's digits) and refused the box with words that did not fit:
"٣٠٠ is outside the allowed range [-180, 180]" or "٣ was not taken as typed (allowed range ...)". The refusal
now says what happened: the box reads only the ASCII digits 0-9.

``QTest.keyClicks`` cannot type a character beyond Latin-1 (Qt 5 aborts the process): such a key is sent as the
key event a keyboard layout gives (its code and its text)."""
import json

import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

from PySide import QtCore, QtGui  # noqa: E402

from metamaterial_wb.gui.panels import ranges  # noqa: E402
from guihelpers import doc, press_ok, process, qtest, run_panel, workbench  # noqa: E402,F401

ARABIC_3, ARABIC_0, WIDE_3 = "\u0663", "\u0660", "\uff13"


def keys(spin, text, select=True):
    """Type ``text`` into the box's line edit (over its whole text when ``select``), key by key."""
    spin.setFocus()
    line = spin.lineEdit()
    if select:
        line.selectAll()
    for ch in text:
        if ch.isascii():
            qtest().keyClicks(line, ch)
        else:
            for t in (QtCore.QEvent.Type.KeyPress, QtCore.QEvent.Type.KeyRelease):
                QtGui.QApplication.sendEvent(line, QtGui.QKeyEvent(t, ord(ch), QtCore.Qt.KeyboardModifier.NoModifier, ch))
    process()


def leave(spin):
    qtest().keyClick(spin.lineEdit(), QtCore.Qt.Key.Key_Tab)
    process()


def refused(spin):
    return spin.property(ranges.REFUSED) or ""


def _folds(sc):
    return [a["fold_deg"] for a in json.loads(sc.SceneJSON)["axes"]]


def _scenes(d):
    from metamaterial_wb.objects import structure
    return structure.find_scene_objects(d)


def test_a_fold_typed_in_arabic_indic_digits_is_said_as_digits_the_box_does_not_read(doc):
    from test_gui_panel_details import open_example
    sc = open_example("fish_axes")
    before = _folds(sc)
    p = run_panel("MM_FoldedShape")
    spin = p.spins[0]
    shown = spin.lineEdit().text()
    keys(spin, ARABIC_3 + ARABIC_0 + ARABIC_0)
    leave(spin)
    assert spin.lineEdit().text() == shown                # (Qt dropped every key)
    text = refused(spin)
    assert "fold_deg" in text and ARABIC_3 + ARABIC_0 + ARABIC_0 in text and "only the ASCII digits 0-9" in text, text
    assert "outside the allowed range" not in text, text  # 300 was never in the box
    assert not press_ok(), "OK took a fold the keys did not make"
    assert "only the ASCII digits 0-9" in p.error.text(), p.error.text()
    assert _folds(sc) == before
    keys(spin, "30")                                       # ASCII digits over the whole text are taken
    leave(spin)
    assert not refused(spin), refused(spin)
    assert press_ok(), p.error.text()
    assert _folds(sc)[0] == 30.0 and _folds(sc)[1:] == before[1:]


@pytest.mark.parametrize("digit", [ARABIC_3, WIDE_3])
@pytest.mark.parametrize("box, name", [("cell", "cell_size_mm"), ("rows", "Rows")])
def test_a_foreign_digit_after_an_ascii_one_is_refused_in_words(doc, box, name, digit):
    """'1' then '٣' (or '３'): the box keeps 1, the user meant 13; OK must not take 1 in silence."""
    p = run_panel("MM_NewStructure")
    spin = getattr(p, box)
    keys(spin, "1" + digit)
    assert spin.lineEdit().text().replace(spin.suffix(), "").strip() == "1", spin.lineEdit().text()   # (Qt dropped it)
    text = refused(spin)
    assert name in text and "1" + digit in text and f"only the ASCII digits 0-9, not {digit}" in text, text
    assert "allowed range" not in text and "kept 1" in text, text
    leave(spin)
    assert spin.value() == 1 and f"not {digit}" in refused(spin), (spin.value(), refused(spin))
    assert not press_ok(), f"OK took {spin.value()} for the 1{digit} typed"
    assert _scenes(doc) == []
    keys(spin, "3")
    leave(spin)
    assert not refused(spin), refused(spin)
    p.reject()


def test_a_letter_is_still_dropped_without_a_word(doc):
    """A letter is no digit of any script: the box drops it and nothing is said (as before)."""
    p = run_panel("MM_NewStructure")
    keys(p.cell, "a")
    leave(p.cell)
    assert not refused(p.cell), refused(p.cell)
    p.reject()


def test_a_box_whose_locale_has_those_digits_takes_them(doc):
    """In an Arabic locale the box reads '٣' itself: it is taken as 3 and nothing is refused."""
    p = run_panel("MM_NewStructure")
    spin = p.rows
    spin.setLocale(QtCore.QLocale("ar_EG"))
    spin.setValue(1)
    process()
    keys(spin, ARABIC_3)
    assert spin.lineEdit().text() == ARABIC_3 and not refused(spin), (spin.lineEdit().text(), refused(spin))
    leave(spin)
    assert spin.value() == 3 and not refused(spin), (spin.value(), refused(spin))
    p.reject()
