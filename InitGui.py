# FreeCAD exec()s this file (no __file__, top-level names invisible in methods): keep it tiny.
import FreeCADGui


class MetamaterialWorkbench(FreeCADGui.Workbench):
    MenuText = "Metamaterial"
    ToolTip = "Sparsely actuated modular metamaterials: design, simulate, fabricate, drive"

    def __init__(self):
        import metamaterial_wb
        self.__class__.Icon = metamaterial_wb.icon_path("Metamaterial_Workbench.svg")

    def Initialize(self):
        from metamaterial_wb.gui import workbench
        workbench.initialize(self)

    def Activated(self):
        pass

    def Deactivated(self):
        pass

    def ContextMenu(self, recipient):
        from metamaterial_wb.gui import commands
        self.appendContextMenu("Metamaterial", commands.SIMULATE)

    def GetClassName(self):
        return "Gui::PythonWorkbench"


FreeCADGui.addWorkbench(MetamaterialWorkbench())
import FreeCAD  # noqa: E402
FreeCAD.__unit_test__ += ["TestMetamaterialGui"]
