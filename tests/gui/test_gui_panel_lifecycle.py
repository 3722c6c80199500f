"""A panel's life around other panels and its document, as a person meets it: another command while Animate is
open, the document closed or the structure deleted while a panel is open."""
import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

import FreeCADGui  # noqa: E402

from metamaterial_wb.gui import panels  # noqa: E402
from metamaterial_wb.objects import structure  # noqa: E402
from guihelpers import doc, press_ok, process, run_panel, workbench  # noqa: E402,F401


def open_fish(doc):
    p = run_panel("MM_OpenExample")
    p.select("fish")
    assert press_ok()
    return structure.find_scene_objects(doc)[-1]


def arrays_shown(sc):
    """The node and hinge arrays are drawn (a panel's preview switches them off while it runs)."""
    return all(a.ViewObject.SwitchNode.whichChild.getValue() != -1 for a in (sc.NodeArray, sc.HingeArray))


def test_another_command_while_animate_is_open_opens_its_panel(doc):
    """Animate's cleanup touched its widgets after the dialog had deleted them: the next command failed, no
    panel opened, and the sheet stayed hidden."""
    sc = open_fish(doc)
    a = run_panel("MM_Animate")
    a.step(2)
    p = run_panel("MM_PlaceConstraint")
    assert p is not a and type(p).__name__ == "PlaceItemPanel"
    assert panels.active() is p
    p.reject()
    process()
    assert arrays_shown(sc)


def test_closing_the_document_closes_its_panel(doc):
    """A playing Animate panel outlived its document: its timer printed tracebacks 30 times a second."""
    open_fish(doc)
    a = run_panel("MM_Animate")
    a.play()
    process(200)
    FreeCAD.closeDocument(doc.Name)
    process(300)
    assert not FreeCADGui.Control.activeDialog() and panels.active() is None
    assert not a.timer.isActive()


def test_ok_after_the_structure_was_deleted_says_why(doc):
    sc = open_fish(doc)
    p = run_panel("MM_PlaceMotor")
    p.joint.setCurrentText("H0,3")                 # a free joint: the panel has no problem of its own
    process()
    assert not p.problems, p.problems
    for name in [o.Name for o in doc.Objects]:
        if doc.getObject(name) is not None:       # a group's removal may take its members with it
            doc.removeObject(name)
    process()
    assert p.accept() is False
    assert "was deleted" in p.error.text(), p.error.text()
    assert p.reject() is True
