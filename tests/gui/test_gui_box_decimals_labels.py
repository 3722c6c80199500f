"""GUI audit on FreeCAD 1.1: the Place motor boxes (sine amplitude, frequency, phase) and New structure's cell size had
Qt's default 2 decimals, so valid scene values (amplitude 0.125, frequency 0.3333 Hz, phase 12.345 deg, a 20.125 mm
cell; docs/scene-format.md sets no resolution) were refused with OK disabled, while the CLI and Animate take them.
Every box bound to a validated quantity (``ranges.bind``) now shows at least ``ranges.BOUND_DECIMALS``.
A refusal named the scene's JSON key ("cell_size_mm: 0.5 is outside ...", "profile.frequency_hz: 60 ...",
"axes.fold_deg: ...", "value: ...") where Rows and Columns said their label: every refusal now names the field as the
panel labels it, the scene key after it in parentheses ("Frequency (profile.frequency_hz): 60 ...")."""
import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

from metamaterial_wb.gui.panels import ranges  # noqa: E402
from guihelpers import doc, press_ok, run_panel, type_into, workbench  # noqa: E402,F401


def _refusal(p):
    return " | ".join(lab.text() for lab in p.problem_labels.values() if lab.isVisible() and lab.text())


def _structure(doc):
    from metamaterial_wb.objects import structure
    p = run_panel("MM_NewStructure")
    assert press_ok(), _refusal(p)
    return structure.find_scene_objects(doc)[0]


def test_the_motor_boxes_take_the_decimals_of_valid_scene_values(doc):
    sc = _structure(doc)
    items = list(sc.Items)
    p = run_panel("MM_PlaceMotor")
    for box, typed, want in (("amp", "0.125", 0.125), ("freq", "0.3333", 0.3333), ("phase", "12.345", 12.345)):
        spin = getattr(p, box)
        type_into(spin, typed)
        assert not spin.property(ranges.REFUSED), spin.property(ranges.REFUSED)
        assert spin.value() == pytest.approx(want, abs=1e-12), (box, spin.lineEdit().text())
    assert press_ok(), _refusal(p)
    assert len(sc.Items) == len(items) + 1
    from metamaterial_wb.objects import structure
    prof = structure.compose_scene(sc).actuators[-1].profile
    assert (prof["amplitude"], prof["frequency_hz"], prof["phase_deg"]) == (0.125, 0.3333, 12.345), prof


def test_a_cell_size_with_three_decimals_is_taken(doc):
    from metamaterial_wb.objects import structure
    p = run_panel("MM_NewStructure")
    type_into(p.cell, "20.125")
    assert not p.cell.property(ranges.REFUSED), p.cell.property(ranges.REFUSED)
    assert press_ok(), _refusal(p)
    assert [s.CellSize.Value for s in structure.find_scene_objects(doc)] == [20.125]


def test_every_bound_double_box_shows_the_bound_decimals(doc):
    """The rule, on every panel a scene opens: no box bound to a scene quantity shows fewer decimals."""
    _structure(doc)
    for cmd in ("MM_PlaceMotor", "MM_NewStructure"):
        p = run_panel(cmd)
        from PySide import QtGui
        boxes = [w for w in p.form.findChildren(QtGui.QDoubleSpinBox) if w.property("validator_field")]
        assert boxes
        for w in boxes:
            field = w.property("validator_field")
            assert w.decimals() >= ranges.decimals(field) >= ranges.BOUND_DECIMALS, (cmd, field, w.decimals())
        from guihelpers import press_cancel
        press_cancel()


def test_a_refusal_names_the_cell_size_box_by_its_label(doc):
    p = run_panel("MM_NewStructure")
    type_into(p.cell, "0.5")
    text = _refusal(p)
    assert text.startswith("Cell size (cell_size_mm): 0.5 is outside the allowed range [1, 1000]"), text
    assert not press_ok()


def test_a_refusal_names_the_motor_boxes_by_their_labels(doc):
    _structure(doc)
    p = run_panel("MM_PlaceMotor")
    type_into(p.freq, "60")
    assert p.freq.property(ranges.REFUSED).startswith(
        "Frequency (profile.frequency_hz): 60 is outside the allowed range [0, 50]"), p.freq.property(ranges.REFUSED)
    type_into(p.freq, "0.5")
    type_into(p.value, "1.5")
    assert p.value.property(ranges.REFUSED).startswith("Value D (-1..1) (value): 1.5 is outside"), \
        p.value.property(ranges.REFUSED)
    assert not press_ok()


def test_a_refusal_names_the_fold_box_by_its_axis(doc):
    from test_gui_panel_details import open_example
    open_example("fish_axes")
    p = run_panel("MM_FoldedShape")
    spin = p.spins[0]
    type_into(spin, "190.5")
    text = spin.property(ranges.REFUSED)
    assert text.startswith("Fold of ") and " (axes.fold_deg): 190.5 is outside the allowed range" in text, text
    head = text.split(" (axes.fold_deg)")[0]
    assert ("vertical" in head or "horizontal" in head) and not head.startswith("axes."), text


def test_a_refusal_names_a_table_box_by_its_column_and_row(doc):
    """The sleeve's cell-type table has no form label: its boxes are named by their column and row."""
    p = run_panel("MM_Sleeve")
    spin = p.types.cellWidget(0, 0)
    type_into(spin, "abc")
    text = spin.property(ranges.REFUSED)
    assert text.startswith("t (mm), row 1 (sleeve.cell_types.t_mm): abc is not a number"), text
