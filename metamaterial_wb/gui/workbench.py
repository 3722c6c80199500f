"""Workbench set-up: registers commands, menus and toolbars."""


def initialize(workbench):
    """Called from InitGui.MetamaterialWorkbench.Initialize()."""
    try:
        from metamaterial_wb.gui import commands
    except ImportError:  # commands arrive with the workbench issue
        return
    names = commands.register()
    workbench.appendToolbar("Metamaterial", names)
    workbench.appendMenu("Metamaterial", names)
