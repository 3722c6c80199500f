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
    said = [lab.text() for lab in p.form.findChildren(QtGui.QLabel) if lab.isVisible() and text in lab.text()]
    assert said == [text] and text not in p.error.text(), said        # said once, under the box
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
    shown = spin.lineEdit().text().replace(spin.suffix(), "").strip()    # (Qt dropped it; under load the box may
    assert shown in ("1", spin.textFromValue(1)), spin.lineEdit().text()  # have reformatted its 1 already: 1.00)
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


def test_a_letter_is_refused_as_no_number(doc):
    """A letter is no digit of any script: the box drops it, and (since session 32) it is said as no number, not
    taken for a digit the box does not read (``test_gui_spin_exponent.py``)."""
    p = run_panel("MM_NewStructure")
    keys(p.cell, "a")
    leave(p.cell)
    assert "Cell size (cell_size_mm): a is not a number" in refused(p.cell), refused(p.cell)
    assert "ASCII" not in refused(p.cell), refused(p.cell)
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


# ---- a locale whose decimal point is neither '.' nor ',' (session 31) ------------------------------------------
# Probed on 0.20 (Qt 5.15) and 1.1 (Qt 6): in ar_EG (decimal point '٫' U+066B, digits ٠-٩) the box takes "1٫5" as
# 1.5, but the key watcher read its text with '.' or ',' only: it refused the box ("15 was not taken as typed"),
# every whole number after Tab (the box writes "١٥٠٫٠٠": "150 was not taken"), said "1555 is outside the allowed
# range" for "1٫555" and let "1,5" become 15 in silence. A '٫' in a C / English / German box and a ',' in an English
# one were dropped or read as a group separator (15) in silence. The decimal points Qt's locales use are '.', ','
# and '٫' (all locales listed on both versions).
ARABIC_POINT = "\u066b"


@pytest.fixture
def locale_default():
    """``QLocale.setDefault`` for the test (restored after); returns a function that sets it."""
    old = QtCore.QLocale()

    def use(name):
        loc = QtCore.QLocale(name)
        QtCore.QLocale.setDefault(loc)
        return loc
    yield use
    QtCore.QLocale.setDefault(old)


def _arabic(text):
    return "".join(chr(0x0660 + int(c)) if c.isdigit() else c for c in text)


@pytest.mark.parametrize("typed, value", [("1" + ARABIC_POINT + "5", 1.5), (_arabic("1" + ARABIC_POINT + "5"), 1.5),
                                          ("2" + ARABIC_POINT, 2.0), ("150", 150.0), (_arabic("150"), 150.0)])
def test_a_value_typed_with_the_arabic_decimal_point_is_taken(doc, locale_default, typed, value):
    loc = locale_default("ar_EG")
    p = run_panel("MM_NewStructure")
    spin = p.cell
    spin.setLocale(loc)
    spin.setValue(20)
    process()
    assert spin.locale().decimalPoint() == ARABIC_POINT
    keys(spin, typed)
    assert not refused(spin), refused(spin)
    leave(spin)
    assert spin.value() == value and not refused(spin), (spin.lineEdit().text(), spin.value(), refused(spin))
    p.reject()


def test_a_fold_typed_with_the_arabic_decimal_point_is_stored(doc, locale_default):
    from test_gui_panel_details import open_example
    sc = open_example("fish_axes")
    before = _folds(sc)
    loc = locale_default("ar_EG")
    p = run_panel("MM_FoldedShape")
    spin = p.spins[0]
    spin.setLocale(loc)
    process()
    keys(spin, "-1" + ARABIC_POINT + "5")               # Qt 6 writes a negative number with the sign's mark U+061C
    leave(spin)
    assert spin.value() == -1.5 and not refused(spin), (spin.lineEdit().text(), spin.value(), refused(spin))
    keys(spin, "1" + ARABIC_POINT + "5")
    leave(spin)
    assert spin.value() == 1.5 and not refused(spin), (spin.lineEdit().text(), spin.value(), refused(spin))
    assert press_ok(), p.error.text()
    assert _folds(sc)[0] == 1.5 and _folds(sc)[1:] == before[1:]


def test_more_decimals_after_the_arabic_point_are_said_as_decimals(doc, locale_default):
    loc = locale_default("ar_EG")
    p = run_panel("MM_NewStructure")
    spin = p.cell
    spin.setLocale(loc)
    typed = "1" + ARABIC_POINT + "5555"
    keys(spin, typed)
    leave(spin)
    text = refused(spin)
    assert "cell_size_mm" in text and typed in text and "more decimals" in text and "at most 3" in text, text
    assert "outside" not in text and "15555" not in text, text
    assert not press_ok() and _scenes(doc) == []


@pytest.mark.parametrize("locale, typed", [("ar_EG", "1.5"), ("ar_EG", "1,5"), ("en_US", "1,5"),
                                           ("en_US", "1" + ARABIC_POINT + "5"), ("de_DE", "1.5"),
                                           ("de_DE", "1" + ARABIC_POINT + "5"), ("C", "1,5")])
def test_another_locale_s_decimal_point_is_refused_naming_the_box_s_point(doc, locale_default, locale, typed):
    """The box drops the point or reads it as a group separator (15): OK must not take 15 for the 1.5 typed."""
    loc = locale_default(locale)
    p = run_panel("MM_NewStructure")
    spin = p.cell
    spin.setLocale(loc)
    point = loc.decimalPoint()
    keys(spin, typed)
    leave(spin)
    text = refused(spin)
    assert "cell_size_mm" in text and typed in text, text
    assert f"decimal point of this box is {point}, not {typed[1]}" in text, text
    assert "kept 15" in text, text
    assert not press_ok(), f"OK took {spin.value()} for the {typed} typed"
    assert _scenes(doc) == []
    keys(spin, "1" + point + "5")
    leave(spin)
    assert spin.value() == 1.5 and not refused(spin), (spin.value(), refused(spin))
    p.reject()


# ---- (b) the second wording: a locale with its own digits, given digits of a third script ------------------------
@pytest.mark.parametrize("locale, own, digit", [("fa_IR", "\u06f0-\u06f9", ARABIC_3), ("ar_EG", "\u0660-\u0669", WIDE_3)])
def test_digits_of_a_third_script_name_the_box_s_own_digits(doc, locale_default, locale, own, digit):
    """fa_IR reads 0-9 and its own ۰-۹ but not the Arabic-Indic '٣'; ar_EG reads 0-9 and ٠-٩ but not a full-width '３'."""
    loc = locale_default(locale)
    p = run_panel("MM_NewStructure")
    spin = p.rows
    spin.setLocale(loc)
    spin.setValue(1)
    process()
    keys(spin, "1" + digit)
    text = refused(spin)
    assert "Rows" in text and "1" + digit in text, text
    assert f"the box reads only the digits 0-9 and {own}, not {digit}" in text, text
    assert "allowed range" not in text and "kept 1" in text, text
    leave(spin)
    assert spin.value() == 1 and f"not {digit}" in refused(spin), (spin.value(), refused(spin))
    assert not press_ok() and _scenes(doc) == []
    keys(spin, "3")
    leave(spin)
    assert spin.value() == 3 and not refused(spin), refused(spin)
    p.reject()


# ---- a group separator typed: a number grouped the box's way is taken as Qt reads it (session 32) -----------------
# Probed on 0.20 (Qt 5.15) and 1.1 (Qt 6), cell box [1, 1000] mm, 2 decimals, key by key: Qt reads any group
# separator of the box's locale as such ("1,5" in English -> 15, "1,0,0,0" -> 1000), and drops the key that takes
# the number past the maximum ("2,000" leaves "2,00", which it reads as 200). The watcher refused "1,000" in an
# English box (the box held 1000, as meant) and said "2,00 was not taken: the decimal point ..." for "2,000" (the
# maximum was the cause); "1,000.5" became "1,0005 was not taken: the decimal point ...", German "1.000" was refused
# as a decimal point and de_CH's "1'000" (U+2019 on Qt 5) as "1000 was not taken as typed". A number grouped the
# box's way (1-3 digits, then groups of 3, then the box's point) is now read as Qt reads it; any other use of the
# separator stays a decimal point the box does not read.
@pytest.mark.parametrize("locale, typed", [("en_US", "1,000"), ("C", "1,000"), ("de_DE", "1.000"),
                                           ("de_CH", "1{g}000"), ("en_US", "1,000.00")])
def test_a_number_grouped_the_box_s_way_is_taken_as_qt_reads_it(doc, locale_default, locale, typed):
    loc = locale_default(locale)
    p = run_panel("MM_NewStructure")
    spin = p.cell
    spin.setLocale(loc)
    typed = typed.format(g=loc.groupSeparator())
    keys(spin, typed)
    assert spin.lineEdit().text() in (typed + spin.suffix(), spin.textFromValue(1000) + spin.suffix()), \
        spin.lineEdit().text()                           # (Qt took every key; on 1.1 it may have rewritten them)
    _taken_as_1000(doc, p, spin)


def _taken_as_1000(doc, p, spin):
    """Nothing refused while typing nor after Tab, the box at 1000, and OK builds a scene of 1000 mm cells."""
    assert not refused(spin), refused(spin)
    leave(spin)
    assert spin.value() == 1000 and not refused(spin), (spin.lineEdit().text(), spin.value(), refused(spin))
    assert press_ok(), p.error.text()
    scenes = _scenes(doc)
    assert len(scenes) == 1 and json.loads(scenes[0].SceneJSON)["cell_size_mm"] == 1000, scenes


def _typed_in_cell(locale_default, locale, typed):
    """New structure's cell box in ``locale``, ``typed`` key by key, then Tab: (panel, box, locale, refusal)."""
    loc = locale_default(locale)
    p = run_panel("MM_NewStructure")
    spin = p.cell
    spin.setLocale(loc)
    keys(spin, typed)
    leave(spin)
    return p, spin, loc, refused(spin)


@pytest.mark.parametrize("locale, typed, kept", [("en_US", "2,000", "200"), ("de_DE", "2.000", "200"),
                                                 ("en_US", "1,000.5", "1000"), ("de_DE", "1.000,5", "1000")])
def test_a_grouped_number_above_the_maximum_is_refused_as_outside_the_range(doc, locale_default, locale, typed, kept):
    """Qt drops the last key (2,000 > 1000 leaves "2,00", read as 200): the maximum is the cause, said with the
    whole text typed."""
    p, spin, loc, text = _typed_in_cell(locale_default, locale, typed)
    assert f"Cell size (cell_size_mm): {typed} is outside the allowed range [1, 1000]" in text, text
    assert "decimal point" not in text and f"kept {kept}" in text, text
    assert not press_ok(), f"OK took {spin.value()} for the {typed} typed"
    assert _scenes(doc) == []
    p.reject()


@pytest.mark.parametrize("locale, typed, kept", [("en_US", "1,5", "15"), ("en_US", "12,5", "125"),
                                                 ("en_US", "1,00", "100"), ("en_US", "1,0,0,0", "1000"),
                                                 ("de_DE", "1.5", "15"), ("de_DE", "12.5", "125")])
def test_a_separator_that_is_no_grouping_stays_a_decimal_point_the_box_does_not_read(doc, locale_default, locale,
                                                                                     typed, kept):
    p, spin, loc, text = _typed_in_cell(locale_default, locale, typed)
    wrong = "," if loc.decimalPoint() == "." else "."
    assert f"Cell size (cell_size_mm): {typed} was not taken: the decimal point of this box is {loc.decimalPoint()}, not {wrong}" \
        in text and f"kept {kept}" in text, text
    assert not press_ok() and _scenes(doc) == []
    p.reject()


# ---- a blank typed between digits (session 32) --------------------------------------------------------------------
# Probed on 0.20 (Qt 5.15) and 1.1 (Qt 6), cell box [1, 1000] mm, key by key: the box drops every blank typed (a
# space, U+00A0, U+202F) in every locale, so "1 5" became 15 without a word (fr_FR, whose group separator is U+202F
# on both, as in en_US). Qt itself reads a blank as a group separator only in a locale that groups with one (fr_FR
# U+202F, nb_NO U+00A0: validate("1 000") is Acceptable there, Invalid in en_US / de_CH). A number grouped by blanks
# in threes is taken in every locale (any of the three blanks: they look alike, the SI way of grouping, and the box
# holds what they group); any other blank between digits is refused in words naming the text typed and how the box
# writes a thousand.
BLANKS = (" ", "\u00a0", "\u202f")


@pytest.mark.parametrize("locale", ["fr_FR", "nb_NO", "en_US", "de_DE"])
@pytest.mark.parametrize("typed", ["1 000", "1{g}000", "1\u00a0000", "1\u202f000", "1 000{p}00", " 1000", "1000 "])
def test_a_number_grouped_by_blanks_in_threes_is_taken(doc, locale_default, locale, typed):
    """Grouped by blanks in threes (the SI way, French's own): taken in every locale, as the box holds 1000."""
    loc = locale_default(locale)
    p = run_panel("MM_NewStructure")
    spin = p.cell
    spin.setLocale(loc)
    typed = typed.format(g=loc.groupSeparator(), p=loc.decimalPoint())
    keys(spin, typed)
    _taken_as_1000(doc, p, spin)


@pytest.mark.parametrize("locale, typed, kept", [("fr_FR", "1 5", "15"), ("fr_FR", "12 5", "125"),
                                                 ("fr_FR", "1{g}5", "15"), ("fr_FR", "1 00", "100"),
                                                 ("fr_FR", "1 0 0 0", "1000"), ("fr_FR", "1 5{p}0", "15"),
                                                 ("nb_NO", "1 5", "15"), ("en_US", "1 5", "15"),
                                                 ("en_US", "1 00", "100"), ("de_DE", "1 5", "15")])
def test_a_blank_that_is_no_grouping_is_refused_naming_how_the_box_groups(doc, locale_default, locale, typed, kept):
    """Qt drops the blank (1 5 -> 15): OK must not take 15 for what was typed."""
    loc = locale_default(locale)
    typed = typed.format(g=loc.groupSeparator(), p=loc.decimalPoint())
    p, spin, loc, text = _typed_in_cell(locale_default, locale, typed)
    thousand = loc.toString(1000)
    if loc.groupSeparator() not in BLANKS:
        thousand = f"1 000 or {thousand}"
    how = f"this box reads a space only between groups of three digits (a thousand is {thousand})"
    assert f"Cell size (cell_size_mm): {typed} was not taken: {how}; the box kept {kept}" in text, text
    assert not press_ok(), f"OK took {spin.value()} for the {typed} typed"
    assert _scenes(doc) == []
    keys(spin, "15")                                       # typed again without the blank: taken
    leave(spin)
    assert spin.value() == 15 and not refused(spin), (spin.value(), refused(spin))
    p.reject()


@pytest.mark.parametrize("typed, kept", [("2 000", "200"), ("1 000{p}5", "1000"), ("1 000 000", "1000")])
def test_a_blank_grouped_number_above_the_maximum_is_refused_as_outside_the_range(doc, locale_default, typed, kept):
    loc = locale_default("fr_FR")
    typed = typed.format(p=loc.decimalPoint())
    p, spin, loc, text = _typed_in_cell(locale_default, "fr_FR", typed)
    assert f"Cell size (cell_size_mm): {typed} is outside the allowed range [1, 1000]; the box kept {kept}" in text, text
    assert not press_ok() and _scenes(doc) == []
    p.reject()


def test_a_blank_in_a_whole_number_box_is_refused_too(doc, locale_default):
    """The integer Rows box (QSpinBox) drops the blank the same way: 1 2 would be 12."""
    loc = locale_default("fr_FR")
    p = run_panel("MM_NewStructure")
    spin = p.rows
    spin.setLocale(loc)
    spin.setValue(1)
    process()
    keys(spin, "1 2")
    leave(spin)
    text = refused(spin)
    assert "Rows: 1 2 was not taken: this box reads a space only between groups of three digits" in text, text
    assert not press_ok() and _scenes(doc) == []
    p.reject()
