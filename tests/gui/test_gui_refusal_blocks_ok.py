"""A value typed into a spin box that the box refused (the key watcher of ``panels/ranges.py``) is a problem of its
field from the moment it is said (GUI audit, session 32): it left OK enabled and said nothing next to the field,
OK being refused only once pressed, in the panel-wide line ("not applied: cell_size_mm: 0 is outside ..."). Now the
refusal is shown in red next to the field and OK is disabled until the box's text is edited to a value it takes."""
import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

from PySide import QtGui  # noqa: E402

from metamaterial_wb.gui.panels import ranges  # noqa: E402
from guihelpers import click, dialog_button, doc, press_ok, run_panel, type_into, workbench  # noqa: E402,F401


def refused(spin):
    return spin.property(ranges.REFUSED) or ""


def red_lines(p):
    """The visible red labels of the panel's form and their texts."""
    return [lab.text() for lab in p.form.findChildren(QtGui.QLabel)
            if lab.isVisible() and lab.text() and "c00000" in lab.styleSheet() and lab is not p.error]


def assert_blocked(p, spin, words):
    text = refused(spin)
    assert words in text, text
    assert not dialog_button("Ok").isEnabled(), "OK stayed enabled with a refused value in a box"
    assert text in p.problems.values(), p.problems
    assert any(text in line for line in red_lines(p)), (text, red_lines(p))


def assert_free(p, spin):
    assert not refused(spin), refused(spin)
    assert not p.problems, p.problems
    assert dialog_button("Ok").isEnabled()
    assert not red_lines(p), red_lines(p)


@pytest.mark.parametrize("box, typed, taken", [("cell", "0", "25"), ("rows", "0", "3")])
def test_a_refused_grid_box_disables_ok_and_says_so_next_to_the_field(doc, box, typed, taken):
    p = run_panel("MM_NewStructure")
    spin = getattr(p, box)
    type_into(spin, typed)
    assert_blocked(p, spin, f": {typed} is outside the allowed range")
    assert not press_ok()
    type_into(spin, taken)
    assert_free(p, spin)
    assert press_ok(), p.error.text()


def test_the_refusal_line_sits_next_to_its_field(doc):
    p = run_panel("MM_NewStructure")
    type_into(p.cell, "0")
    labs = [lab for lab in p.form.findChildren(QtGui.QLabel)
            if lab.isVisible() and refused(p.cell) == lab.text()]
    assert len(labs) == 1 and labs[0] is not p.error, red_lines(p)     # said once, under the box
    lab = labs[0]
    gap = abs(lab.mapTo(p.form, lab.rect().topLeft()).y() - p.cell.mapTo(p.form, p.cell.rect().bottomLeft()).y())
    assert gap < 3 * p.cell.height(), gap                  # under the box, not at the panel's end


@pytest.mark.parametrize("box, typed, taken", [("value", "1.5", "0.5"), ("freq", "1000", "2")])
def test_a_refused_motor_box_disables_ok_until_edited(doc, box, typed, taken):
    run_panel("MM_NewStructure")
    assert press_ok()
    p = run_panel("MM_PlaceMotor")
    p.joint.setCurrentText("H0,3")
    spin = getattr(p, box)
    type_into(spin, typed)
    assert_blocked(p, spin, f": {typed} ")
    type_into(spin, taken)
    assert_free(p, spin)
    assert press_ok(), p.error.text()


def test_a_refusal_the_panel_forgets_frees_ok(doc):
    """New structure clears a grid box's refusal when a file is used instead of the grid: OK follows."""
    p = run_panel("MM_NewStructure")
    type_into(p.cell, "0")
    assert not dialog_button("Ok").isEnabled()
    p._forget_refused()
    assert not p.problems, p.problems
    assert dialog_button("Ok").isEnabled()
    assert not red_lines(p), red_lines(p)
