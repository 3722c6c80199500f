"""Workbench set-up: registers commands, menus, toolbars and the preferences page."""
import os

import metamaterial_wb


def initialize(workbench):
    """Called from InitGui.MetamaterialWorkbench.Initialize()."""
    import FreeCADGui

    from metamaterial_wb.gui import commands

    commands.register()
    workbench.appendToolbar("Metamaterial design", commands.DESIGN)
    workbench.appendToolbar("Metamaterial simulation", commands.SIMULATE)
    workbench.appendToolbar("Metamaterial fabrication", commands.FABRICATE)
    workbench.appendToolbar("Metamaterial sleeve", commands.SLEEVE)
    workbench.appendToolbar("Metamaterial inverse design", commands.INVERSE)
    workbench.appendMenu("Metamaterial", commands.DESIGN + ["Separator"] + commands.SIMULATE + ["Separator"]
                         + commands.FABRICATE + ["Separator"] + commands.SLEEVE + ["Separator"] + commands.INVERSE)
    FreeCADGui.addIconPath(os.path.join(metamaterial_wb.RESOURCES_DIR, "icons"))
    ui = os.path.join(metamaterial_wb.RESOURCES_DIR, "ui", "preferences.ui")
    if os.path.exists(ui):
        FreeCADGui.addPreferencePage(ui, "Metamaterial")
