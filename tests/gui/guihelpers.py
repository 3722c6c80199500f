"""Fixtures and helpers shared by the GUI test modules (imported after their GuiUp guard)."""
import FreeCAD
import FreeCADGui
import pytest
from PySide import QtGui

from metamaterial_wb.gui import panels


@pytest.fixture(scope="module", autouse=True)
def workbench():
    FreeCADGui.activateWorkbench("MetamaterialWorkbench")
    yield


@pytest.fixture
def doc():
    """A fresh active document; any open task panel is rejected and the document closed afterwards."""
    d = FreeCAD.newDocument("MMGui")
    FreeCAD.setActiveDocument(d.Name)
    name = d.Name
    yield d
    if FreeCADGui.Control.activeDialog():
        if panels.active() is not None:
            panels.active().reject()
        else:
            FreeCADGui.Control.closeDialog()
    if name in FreeCAD.listDocuments():
        FreeCAD.closeDocument(name)


def run_panel(cmd):
    """Run a workbench command and return the task panel it opened."""
    FreeCADGui.runCommand(cmd)
    QtGui.QApplication.processEvents()
    p = panels.active()
    assert p is not None and FreeCADGui.Control.activeDialog(), f"{cmd} opened no task panel"
    return p
