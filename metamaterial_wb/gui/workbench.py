"""Workbench set-up: registers commands, menus, toolbars and the preferences page."""
import os

import metamaterial_wb
from metamaterial_wb.gui.i18n import QT_TRANSLATE_NOOP


def initialize(workbench):
    """Called from InitGui.MetamaterialWorkbench.Initialize()."""
    import FreeCADGui

    from metamaterial_wb.gui import commands

    commands.register()
    # toolbar and menu names are kept in English (FreeCAD stores the user's toolbar choices by them) and shown
    # translated by FreeCAD in the "Workbench" context: marked so that ts_extract / lupdate list them
    workbench.appendToolbar(QT_TRANSLATE_NOOP("Workbench", "Metamaterial design"), commands.DESIGN)
    workbench.appendToolbar(QT_TRANSLATE_NOOP("Workbench", "Metamaterial simulation"), commands.SIMULATE)
    workbench.appendToolbar(QT_TRANSLATE_NOOP("Workbench", "Metamaterial fabrication"), commands.FABRICATE)
    workbench.appendToolbar(QT_TRANSLATE_NOOP("Workbench", "Metamaterial sleeve"), commands.SLEEVE)
    workbench.appendToolbar(QT_TRANSLATE_NOOP("Workbench", "Metamaterial inverse design"), commands.INVERSE)
    workbench.appendMenu(QT_TRANSLATE_NOOP("Workbench", "Metamaterial"), commands.DESIGN + ["Separator"] + commands.SIMULATE + ["Separator"]
                         + commands.FABRICATE + ["Separator"] + commands.SLEEVE + ["Separator"] + commands.INVERSE)
    FreeCADGui.addIconPath(os.path.join(metamaterial_wb.RESOURCES_DIR, "icons"))
    ui = os.path.join(metamaterial_wb.RESOURCES_DIR, "ui", "preferences.ui")
    if os.path.exists(ui):
        FreeCADGui.addPreferencePage(ui, "Metamaterial")
