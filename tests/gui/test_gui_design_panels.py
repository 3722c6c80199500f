"""New structure and Add module through real widgets (from an audit on FreeCAD 0.20).

New structure: a scene file and the grid editor do not get in each other's way. While the file field holds
a path the grid, its presets and the cell size are disabled (the file brings its own layout, cell size and
motors) and their problems do not block OK; clearing the file field gives them back. The Name field names
the structure made from a file: it shows the file's name unless the user typed one.

Add module: only targets of the chosen module's kind are picked in the 3D view; a click on the other kind
is not reported as a pick, the target stays, and the panel says what the module goes on.
"""
import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

import FreeCADGui  # noqa: E402

import metamaterial_wb  # noqa: E402
from metamaterial_wb.objects import structure  # noqa: E402
from guihelpers import (click, click_view, dialog_button, doc, hinge_mid, hover_view, press_ok, process,  # noqa: E402,F401,E501
                        run_panel, screen_point, type_into, workbench)

FISH = metamaterial_wb.example_path("fish")
WORM = metamaterial_wb.example_path("worm")


def open_example(name):
    p = run_panel("MM_OpenExample")
    p.select(name)
    assert press_ok(), p.error.text()
    FreeCADGui.SendMsgToActiveView("ViewFit")
    process(50)
    return structure.find_scene_objects(FreeCAD.ActiveDocument)[-1]


def clear_field(edit):
    """Select the line edit's text, delete it with Backspace and leave the field (Tab), as a user would."""
    from PySide import QtCore
    from guihelpers import qtest
    edit.setFocus()
    edit.selectAll()
    qtest().keyClick(edit, QtCore.Qt.Key.Key_Backspace)
    qtest().keyClick(edit, QtCore.Qt.Key.Key_Tab)
    process()
    assert edit.text() == ""


def grid_widgets(p):
    return [p.rows, p.cols, p.cell, p.grid_btn, p.chain_btn, p.clear_btn] + list(p.buttons.values())


# ---- New structure: scene file vs grid editor ---------------------------------------------------------
def test_a_scene_file_is_not_blocked_by_an_empty_grid(doc):
    p = run_panel("MM_NewStructure")
    click(p.clear_btn)
    assert "grid" in p.problems and not dialog_button("Ok").isEnabled()     # no cells: the grid is refused
    type_into(p.file, FISH)
    assert p.status.text() == "scene fish.json: 12 cells, 2 motors"
    assert p.problems == {}, "the unused grid's problems do not block a scene file"
    assert not p.problem_label("grid").isVisible()
    assert dialog_button("Ok").isEnabled()
    assert press_ok(), p.error.text()
    sc = structure.find_scene_objects(doc)[-1]
    assert sorted(i.ItemName for i in sc.Items) == ["head", "tail"] and sc.SceneName == "fish"


def test_the_grid_and_cell_size_are_disabled_while_a_file_is_loaded(doc):
    p = run_panel("MM_NewStructure")
    type_into(p.file, FISH)
    assert p.status.text() == "scene fish.json: 12 cells, 2 motors"
    assert all(not w.isEnabled() for w in grid_widgets(p)), "the grid editor is not used for a file"
    note = p.file_note.text()
    assert p.file_note.isVisible() and "scene file" in note and "Clear the file field" in note, note
    type_into(p.cell, "30")                      # a disabled box takes no keystrokes
    assert p.cell.value() == 20.0
    assert p.file.text() == FISH and p.loaded_scene is not None, "the file is kept"
    assert press_ok(), p.error.text()
    sc = structure.find_scene_objects(doc)[-1]
    assert sorted(i.ItemName for i in sc.Items) == ["head", "tail"]
    assert sc.CellSize.Value == pytest.approx(27.0)


def test_clearing_the_file_field_gives_the_grid_back(doc):
    p = run_panel("MM_NewStructure")
    click(p.clear_btn)
    type_into(p.file, FISH)
    assert not p.clear_btn.isEnabled()
    clear_field(p.file)
    assert all(w.isEnabled() for w in grid_widgets(p))
    assert not p.file_note.isVisible()
    assert "grid" in p.problems and not dialog_button("Ok").isEnabled(), "the grid's own problem is back"
    click(p.grid_btn)
    type_into(p.cell, "30")
    assert p.problems == {} and p.status.text() == "12 cells: a valid layout"
    assert press_ok(), p.error.text()
    sc = structure.find_scene_objects(doc)[-1]
    assert list(sc.Items) == [] and sc.CellSize.Value == pytest.approx(30.0)


def test_the_name_field_names_a_structure_made_from_a_file(doc):
    p = run_panel("MM_NewStructure")
    type_into(p.file, WORM)
    assert p.name.text() == "worm", "the field shows the name the file gives"
    type_into(p.file, FISH)
    assert p.name.text() == "fish", "another file: its name (the field was not typed in)"
    type_into(p.name, "mine")
    assert press_ok(), p.error.text()
    assert structure.find_scene_objects(doc)[-1].SceneName == "mine"
    # a name typed first is kept when the file is chosen
    p = run_panel("MM_NewStructure")
    type_into(p.name, "mine2")
    type_into(p.file, WORM)
    assert p.name.text() == "mine2"
    assert press_ok(), p.error.text()
    sc = structure.find_scene_objects(doc)[-1]
    assert sc.SceneName == "mine2" and sorted(i.ItemName for i in sc.Items) == ["front", "rear"]
    # clearing the file: the file's name goes with it
    p = run_panel("MM_NewStructure")
    type_into(p.file, WORM)
    clear_field(p.file)
    assert p.name.text() == "structure"
    p.reject()


# ---- Add module: picks of the wrong kind -------------------------------------------------------------
def node_point(sc, name):
    from metamaterial_wb.gui.preview import global_placement
    i, j = (int(v) for v in name[1:].split(","))
    k = list(structure.compose_scene(sc).topology.nodes).index((i, j))
    return global_placement(sc.NodeArray).multVec(sc.NodeArray.PlacementList[k].Base)


def test_add_module_picks_only_targets_of_its_kind(doc):
    sc = open_example("fish")
    p = run_panel("MM_AddModule")
    p.set_type("friction_pad")
    process()
    p.target.setCurrentText("N0,0")              # the user chooses the target (the panel opens with none)
    assert p.target.currentText() == "N0,0"
    hinge = screen_point(hinge_mid(sc, "H0,2"))
    click_view(hinge)
    assert p.target.currentText() == "N0,0", "a hinge is no target for a friction pad"
    assert not p.pick_label.text().startswith("picked"), p.pick_label.text()
    lab = p.problem_label("pick")
    assert lab.isVisible() and "a friction pad goes on a node; H0,2 is a hinge" in lab.text(), lab.text()
    assert not dialog_button("Ok").isEnabled()
    node = screen_point(node_point(sc, "N0,3"))
    hover_view(node)
    assert p.pick_label.text() == "under the cursor: node N0,3 (click to pick it)"
    hover_view(hinge)                            # the hinge under the cursor: the panel says why it is no target
    assert p.pick_label.text().startswith("under the cursor: hinge H0,2") and \
        "a friction pad goes on a node" in p.pick_label.text(), p.pick_label.text()
    click_view(node)
    assert p.target.currentText() == "N0,3" and p.pick_label.text() == "picked node N0,3"
    assert not lab.isVisible() and dialog_button("Ok").isEnabled()
    # the reverse: a joint module and a click on a node
    p.set_type("servo_housing")
    process()
    p.target.setCurrentText("H0,0")
    assert p.target.currentText() == "H0,0"
    click_view(node)
    assert p.target.currentText() == "H0,0"
    assert not p.pick_label.text().startswith("picked"), p.pick_label.text()
    assert lab.isVisible() and "a servo housing goes across a joint" in lab.text() and "N0,3 is a node" in lab.text()
    assert not dialog_button("Ok").isEnabled()
    p.target.setCurrentText("H0,1")              # choosing a target in the list clears it too
    assert not lab.isVisible() and dialog_button("Ok").isEnabled()
    click_view(node)
    assert lab.isVisible()
    click_view(hinge)
    assert p.target.currentText() == "H0,2" and p.pick_label.text() == "picked hinge H0,2"
    assert not lab.isVisible()
    # the panel asks for the kind the module goes on
    p.set_type("friction_pad")
    process()
    assert p.pick_label.text() == "Click a node in the 3D view"
    p.set_type("servo_housing")
    process()
    assert p.pick_label.text() == "Click a hinge in the 3D view"
    p.target.setCurrentText("H0,2")
    assert press_ok(), p.error.text()
    assert [(m.ModuleType, m.Target) for m in sc.Modules] == [("servo_housing", "H0,2")]


def test_new_structure_back_from_a_big_grid_keeps_the_full_grid(doc):
    # beyond 32 rows the layout is the full grid (no buttons); coming back below 32 left no cell checked and the
    # layout empty, so the user's grid vanished on the way back
    p = run_panel("MM_NewStructure")
    cols = p.cols.value()
    type_into(p.rows, "40")
    assert p.big() and len(p.cells()) == 40 * cols
    type_into(p.rows, "5")
    assert not p.big()
    assert p.cells() == [(i, j) for i in range(5) for j in range(cols)], p.cells()
    assert p.problems == {} and dialog_button("Ok").isEnabled(), p.problems
    assert press_ok(), p.error.text()
    assert sum(r.count("#") for r in structure.find_scene_objects(doc)[-1].Layout) == 5 * cols
