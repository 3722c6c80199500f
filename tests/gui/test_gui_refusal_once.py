"""A value a spin box refused (the key watcher of ``panels/ranges.py``: "1 5", "2e-1x", letters, a number out of range)
is said once, in red under the box. It was said twice (GUI audit, session 33): under the box and again in the panel's
error line at the bottom, the same sentence read two times. The panel's error line stays for problems that belong to
no single field (the structure deleted under the panel), and a refusal neither hides nor clears such a line. OK stays
disabled while the box is refused; a value the box takes removes the line under it and OK is enabled again."""
import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

from PySide import QtGui  # noqa: E402

from metamaterial_wb.gui.panels import ranges  # noqa: E402
from guihelpers import dialog_button, doc, press_ok, process, run_panel, type_into, workbench  # noqa: E402,F401


def refused(spin):
    return spin.property(ranges.REFUSED) or ""


def showing(p, text):
    """The panel's visible labels that hold ``text``."""
    return [lab for lab in p.form.findChildren(QtGui.QLabel) if lab.isVisible() and text in lab.text()]


def said_once_under(p, spin, words):
    """The box's refusal holds ``words``, one visible label of the panel says it (not the panel's error line), under
    the box, and OK is disabled. Returns the refusal."""
    text = refused(spin)
    assert words in text, text
    labs = showing(p, text)
    assert len(labs) == 1, [lab.text() for lab in labs]
    lab = labs[0]
    assert lab is not p.error, "the refusal is said in the panel's error line, not under its box"
    top = lab.mapTo(p.form, lab.rect().topLeft()).y()
    bottom = spin.mapTo(p.form, spin.rect().bottomLeft()).y()
    assert top >= bottom - 2, (top, bottom)                      # under the box ...
    assert _in_table(spin) or top - bottom < 3 * spin.height(), (top, bottom)    # ... next to it
    assert not dialog_button("Ok").isEnabled(), "OK enabled with a refused value in a box"
    return text


def _in_table(spin):
    w = spin.parentWidget()
    while w is not None:
        if isinstance(w, QtGui.QTableWidget):
            return True
        w = w.parentWidget()
    return False


def mended(p, spin, text):
    """The box took a value: its refusal is gone from every label and OK is enabled."""
    assert not refused(spin), refused(spin)
    assert not showing(p, text), [lab.text() for lab in showing(p, text)]
    assert not p.problems, p.problems
    assert dialog_button("Ok").isEnabled()


def new_structure_spin(name):
    p = run_panel("MM_NewStructure")
    return p, getattr(p, name)


def place_motor_spin(name):
    assert run_panel("MM_NewStructure") is not None and press_ok()
    p = run_panel("MM_PlaceMotor")
    p.joint.setCurrentText("H0,3")                               # a free joint: the panel has no problem of its own
    process()
    return p, getattr(p, name)


def sleeve_spin(name):
    p = run_panel("MM_Sleeve")
    return p, (p.types.cellWidget(0, 1) if name == "h_mm" else p.dims[name])


CASES = [  # (panel, box, typed, words of the refusal, a value the box takes)
    (new_structure_spin, "cell", "1 5", "reads a space only between groups of three digits", "15"),
    (new_structure_spin, "rows", "abc", "is not a number", "4"),
    (place_motor_spin, "value", "2e-1x", "is not a number", "0.2"),
    (place_motor_spin, "freq", "1000", "is outside the allowed range", "2"),
    (sleeve_spin, "L_mm", "0", "is outside the allowed range", "18"),
    (sleeve_spin, "h_mm", "x", "is not a number", "3"),
]


@pytest.mark.parametrize("opener, box, typed, words, taken", CASES,
                         ids=[f"{c[0].__name__.split('_spin')[0]}-{c[1]}-{c[2]}" for c in CASES])
def test_a_refusal_is_said_once_under_its_box(doc, opener, box, typed, words, taken):
    p, spin = opener(box)
    type_into(spin, typed)
    text = said_once_under(p, spin, words)
    assert not press_ok()
    assert len(showing(p, text)) == 1, [lab.text() for lab in showing(p, text)]
    type_into(spin, taken)
    mended(p, spin, text)
    assert not p.error.text(), p.error.text()
    assert press_ok(), p.error.text()


def test_a_problem_of_no_field_stays_in_the_panel_line_around_a_refusal(doc):
    """The structure deleted under Place motor is said in the panel's line (it belongs to no box); a refusal typed
    afterwards is said under its box and leaves that line alone (it used to overwrite it), and mending the box leaves
    it too (OK stays disabled: the structure is still gone)."""
    p, spin = place_motor_spin("value")
    for name in [o.Name for o in doc.Objects]:
        if doc.getObject(name) is not None:                      # a group's removal may take its members with it
            doc.removeObject(name)
    process(100)
    gone = p.error.text()
    assert "was deleted" in gone and p.error.isVisible(), gone
    assert len(showing(p, gone)) == 1, [lab.text() for lab in showing(p, gone)]
    type_into(spin, "2e-1x")
    text = said_once_under(p, spin, "is not a number")
    assert p.error.text() == gone, p.error.text()
    type_into(spin, "0.2")
    assert not refused(spin) and not showing(p, text), [lab.text() for lab in showing(p, text)]
    assert p.error.text() == gone and p.error.isVisible(), p.error.text()
    assert not dialog_button("Ok").isEnabled()
    assert p.accept() is False
    assert "was deleted" in p.error.text(), p.error.text()
    assert p.reject() is True
