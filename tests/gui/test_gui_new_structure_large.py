"""New structure with large layouts, through real widgets: one edit costs work for what changed, not rows x cols.

A person drags / types the Rows and Columns boxes up to 2000 (the boxes' maximum). Beyond 32 x 32 the layout is
the full grid; it used to be checked on every keystroke by building the whole scene (its cells and topology:
1.2-2.9 s per edit at 1000 x 1000 on FreeCAD 0.20) and listed cell by cell for the status count. A full rectangle
is always connected and without holes, so only the size budget can refuse it: the panel now checks just that,
with the validator's own message, and the full check runs when OK builds the scene. Below the limit one more
row or column used to remake every toggle button (1024 at 32 x 32: 0.7-1.8 s); now only the new ones are made.
The tests count the cells built per edit and keep the button objects; they time nothing.
"""
import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

from PySide import QtCore  # noqa: E402

from metamaterial_wb.core.errors import MetamaterialError  # noqa: E402
from metamaterial_wb.core.scene import Scene, sections  # noqa: E402
from guihelpers import dialog_button, doc, process, qtest, run_panel, type_into, workbench  # noqa: E402,F401


def grid_error(rows, cols):
    """The scene validator's verdict on a full rows x cols grid ("" when valid)."""
    try:
        Scene.from_dict({"format": "metamaterial-scene", "version": 1, "layout": {"grid": [rows, cols]}})
    except MetamaterialError as exc:
        return str(exc)
    return ""


@pytest.fixture
def built(monkeypatch):
    """The number of cells of every layout the scene validator checks / builds a topology for."""
    sizes = []
    real_validate, real_topology = sections.validate_layout, sections.Topology

    def validate(cells, *a, **k):
        sizes.append(len(cells))
        return real_validate(cells, *a, **k)

    def topology(cells, *a, **k):
        sizes.append(len(cells))
        return real_topology(cells, *a, **k)

    monkeypatch.setattr(sections, "validate_layout", validate)
    monkeypatch.setattr(sections, "Topology", topology)
    return sizes


def test_edits_of_a_large_grid_do_not_build_its_cells(doc, built):
    p = run_panel("MM_NewStructure")
    assert p.rows.maximum() == p.cols.maximum() == 2000
    type_into(p.rows, "1000")
    type_into(p.cols, "1000")
    assert p.problems == {} and p.status.text() == "1000000 cells: a valid layout (the full grid)"
    assert dialog_button("Ok").isEnabled()
    edits = [(lambda: type_into(p.rows, "999"), "999000 cells"),
             (lambda: type_into(p.cols, "1001"), "999999 cells"),
             (lambda: type_into(p.cell, "25"), "999999 cells"),
             (lambda: type_into(p.cols, "1000"), "999000 cells")]
    for edit, status in edits:
        built.clear()
        edit()
        assert p.problems == {} and p.status.text() == f"{status}: a valid layout (the full grid)"
        assert max(built, default=0) <= 1, f"an edit built layouts of {built} cells (only the 1-cell size check)"
    built.clear()                                   # the spin box's arrow key, as a drag does it
    p.rows.setFocus()
    qtest().keyClick(p.rows, QtCore.Qt.Key.Key_Up)
    process()
    assert p.rows.value() == 1000 and p.status.text() == "1000000 cells: a valid layout (the full grid)"
    assert max(built, default=0) <= 1, built
    p.reject()


def test_a_large_grid_is_refused_exactly_as_the_scene_validator_refuses_it(doc):
    p = run_panel("MM_NewStructure")
    for rows, cols in ((1000, 1001), (2000, 501), (2000, 2000), (2000, 500), (1000, 1000)):
        type_into(p.rows, str(rows))
        type_into(p.cols, str(cols))
        assert (p.rows.value(), p.cols.value()) == (rows, cols)
        expected = grid_error(rows, cols) if rows * cols > 1_000_000 else ""
        assert p.problems.get("grid", "") == expected
        assert dialog_button("Ok").isEnabled() == (not expected)
    assert grid_error(2000, 500) == "", "a grid the panel accepts is a valid scene"
    assert "1001000 cells" in grid_error(1000, 1001)
    scene = p.scene()                               # what OK builds: the full check of 1000 x 1000
    assert len(scene.cells) == 1_000_000
    p.reject()


def test_one_more_row_or_column_keeps_the_grids_buttons(doc):
    p = run_panel("MM_NewStructure")
    type_into(p.rows, "32")
    type_into(p.cols, "31")
    assert len(p.buttons) == 32 * 31
    p.clear()
    p.toggle(0, 0)
    p.toggle(0, 1)
    before = dict(p.buttons)
    type_into(p.cols, "32")
    assert len(p.buttons) == 32 * 32
    kept = [k for k, b in before.items() if p.buttons[k] is b]
    assert len(kept) == len(before), f"{len(before) - len(kept)} of {len(before)} buttons were made again"
    assert sorted(p.cells()) == [(0, 0), (0, 1)] and p.status.text() == "2 cells: a valid layout"
    assert not any(p.buttons[(i, 31)].isChecked() for i in range(32)), "a new column comes empty"
    assert p.buttons[(5, 31)].toolTip() == "cell [5, 31]"
    before = dict(p.buttons)
    type_into(p.rows, "31")
    assert sorted(p.buttons) == sorted(k for k in before if k[0] < 31)
    assert all(p.buttons[k] is before[k] for k in p.buttons)
    assert len(p.headers) == 31 + 32
    type_into(p.rows, "40")                         # the full grid (no buttons); back below the limit it stays full
    assert p.buttons == {} and p.headers == [] and not p.grid_widget.isVisible()
    type_into(p.rows, "3")
    assert len(p.buttons) == 3 * 32 and all(b.isChecked() for b in p.buttons.values())
    assert p.status.text() == "96 cells: a valid layout" and len(p.headers) == 3 + 32
    p.reject()
