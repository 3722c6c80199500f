"""View providers of the metamaterial objects (icons, colours, double-click opens a panel)."""
import FreeCADGui

from metamaterial_wb.objects.common import ViewProviderBase, set_color


class ViewProviderScene(ViewProviderBase):
    ICON = "MM_Simulate.svg"

    def setEdit(self, vobj, mode=0):
        if mode != 0:
            return None
        from metamaterial_wb.gui import panels
        # refused (another tool's task dialog is open): no edit mode without a panel
        return panels.show(panels.SimulatePanel(vobj.Object)) is not None

    def unsetEdit(self, vobj, mode=0):
        return True

    def doubleClicked(self, vobj):
        from metamaterial_wb.gui import panels
        if FreeCADGui.Control.activeDialog():
            return True
        panels.show(panels.SimulatePanel(vobj.Object))
        return True


class ViewProviderShapeSource(ViewProviderBase):
    ICON = "MM_NewStructure.svg"


class ViewProviderItem(ViewProviderBase):
    ICON = "MM_PlaceMotor.svg"
    COLOURS = {"actuator": (0.90, 0.08, 0.08), "constraint": (0.15, 0.35, 0.95)}   # red motor, blue clip

    def __init__(self, vobj):
        super().__init__(vobj)
        self._kind = getattr(vobj.Object, "Kind", "actuator")
        set_color(vobj, self.COLOURS.get(self._kind, self.COLOURS["actuator"]))

    def updateData(self, obj, prop):
        """A motor turned into a clip turns blue (and back). The first Kind seen (on restore: the saved one) only
        sets the reference, so a colour the user chose is kept when the file is opened again."""
        if prop != "Kind" or obj.ViewObject is None:
            return
        if getattr(self, "_kind", None) not in (None, obj.Kind):
            set_color(obj.ViewObject, self.COLOURS.get(obj.Kind, self.COLOURS["actuator"]))
        self._kind = obj.Kind

    def getIcon(self):
        import metamaterial_wb
        kind = getattr(getattr(self, "Object", None), "Kind", "actuator")
        return metamaterial_wb.icon_path("MM_PlaceConstraint.svg" if kind == "constraint" else "MM_PlaceMotor.svg")


class ViewProviderModule(ViewProviderBase):
    ICON = "MM_AddModule.svg"

    def __init__(self, vobj):
        super().__init__(vobj)
        set_color(vobj, (0.20, 0.65, 0.30))
