"""Commands of the Metamaterial workbench. Each one opens a task panel or does one undoable step."""
import FreeCAD
import FreeCADGui

import metamaterial_wb
from metamaterial_wb.gui.i18n import QT_TRANSLATE_NOOP, translate
from metamaterial_wb.objects import structure


def is_invalid(obj):
    """True when the object's last recompute failed (its ``getStatusString()`` says why)."""
    state = getattr(obj, "State", [])
    return "Invalid" in state or "Error" in state


def selected_scene(doc=None):
    """The Scene of the first selected object that belongs to a structure, or None."""
    doc = doc or FreeCAD.ActiveDocument
    if doc is None:
        return None
    try:
        for o in FreeCADGui.Selection.getSelection(doc.Name):
            sc = structure.scene_object_of(o)
            if sc is not None:
                return sc
    except Exception:
        pass
    return None


def current_scene(doc=None):
    """The Scene object the user means: the selected structure, else the last one in the document that is
    not invalid (else the last one: ``Activated`` then says why it is invalid and opens nothing)."""
    doc = doc or FreeCAD.ActiveDocument
    if doc is None:
        return None
    sc = selected_scene(doc)
    if sc is not None:
        return sc
    scenes = structure.find_scene_objects(doc)
    valid = [sc for sc in scenes if not is_invalid(sc)]
    return (valid or scenes or [None])[-1]


class _Command:
    NAME = ""
    ICON = ""
    MENU = ""
    TIP = ""
    NEEDS_SCENE = True

    def GetResources(self):
        # MENU / TIP are marked QT_TRANSLATE_NOOP("Metamaterial", ...) in COMMANDS (so ts_extract / lupdate list them)
        # and translated here, when FreeCAD reads them (addCommand): FreeCAD's own lookup of a Python command's texts
        # uses the command's name as context (Gui::PythonCommand::applyCommandData), which finds nothing and keeps
        # these translated texts
        return {"Pixmap": metamaterial_wb.icon_path(self.ICON), "MenuText": translate("Metamaterial", self.MENU),
                "ToolTip": translate("Metamaterial", self.TIP)}

    def IsActive(self):
        from metamaterial_wb.gui.panels import base
        if base.foreign_dialog_open():     # another tool's task dialog (sketch in edit, ...): never thrown away
            return False
        if not self.NEEDS_SCENE:
            return True
        doc = FreeCAD.ActiveDocument
        return doc is not None and any(getattr(getattr(o, "Proxy", None), "Type", "") == "MetamaterialScene"
                                       for o in doc.Objects)

    def panel(self, scene_obj):
        raise NotImplementedError

    def Activated(self):
        from metamaterial_wb.core.errors import MetamaterialError
        from metamaterial_wb.gui import panels
        menu = translate("Metamaterial", self.MENU)
        if panels.base.foreign_dialog_open():
            FreeCAD.Console.PrintError(translate("Metamaterial", "{0}: another tool's task dialog is open; finish it "
                                                 "with OK or Cancel first").format(menu) + "\n")
            self.last_error = translate("Metamaterial", "another task dialog is open")
            return
        try:
            if self.NEEDS_SCENE:
                sc = current_scene()
                if sc is None:
                    FreeCAD.Console.PrintError(translate("Metamaterial", "{0}: no metamaterial structure in the active "
                                                         "document").format(menu) + "\n")
                    return
                if is_invalid(sc) and selected_scene() is None:   # only invalid ones: say why
                    msg = sc.getStatusString() or translate("Metamaterial", "recompute failed")
                    why = translate("Metamaterial", "{0} is invalid: {1} (to open {2} on it anyway, to mend it, select "
                                    "it in the tree first)").format(sc.Label, msg, menu)
                    FreeCAD.Console.PrintError(f"{menu}: {why}\n")
                    self.last_error = why
                    return
                panels.show(self.panel(sc))
            else:
                panels.show(self.panel(FreeCAD.ActiveDocument))
        except MetamaterialError as exc:   # e.g. the structure is invalid: say why, open nothing
            FreeCAD.Console.PrintError(f"{menu}: {exc}\n")
            self.last_error = str(exc)


def _cmd(name, icon, menu, tip, make_panel, needs_scene=True):
    cls = type(name, (_Command,), {"NAME": name, "ICON": icon, "MENU": menu, "TIP": tip,
                                   "NEEDS_SCENE": needs_scene,
                                   "panel": lambda self, arg: make_panel(arg)})
    return cls()


def _panels():
    from metamaterial_wb.gui import panels as tp
    return tp


COMMANDS = [
    ("MM_NewStructure", "MM_NewStructure.svg", QT_TRANSLATE_NOOP("Metamaterial", "New structure"),
     QT_TRANSLATE_NOOP("Metamaterial", "Lay out a new metamaterial sheet: toggle cells on a grid, chain / grid presets, "
                                       "or load a scene file"),
     lambda doc: _panels().NewStructurePanel(doc), False),
    ("MM_OpenExample", "MM_OpenExample.svg", QT_TRANSLATE_NOOP("Metamaterial", "Open example"),
     QT_TRANSLATE_NOOP("Metamaterial", "Open one of the bundled examples (fish, worm, ...)"),
     lambda doc: _panels().OpenExamplePanel(doc), False),
    ("MM_RotaryAxes", "MM_RotaryAxes.svg", QT_TRANSLATE_NOOP("Metamaterial", "Rotary axes"),
     QT_TRANSLATE_NOOP("Metamaterial", "Pick the grid lines the structure folds about; rule violations are listed"),
     lambda sc: _panels().RotaryAxesPanel(sc), True),
    ("MM_FoldedShape", "MM_FoldedShape.svg", QT_TRANSLATE_NOOP("Metamaterial", "Folded shape"),
     QT_TRANSLATE_NOOP("Metamaterial", "One slider per axis (with its maximum); Confirm runs the joint configuration"),
     lambda sc: _panels().FoldedShapePanel(sc), True),
    ("MM_Flexibility", "MM_Flexibility.svg", QT_TRANSLATE_NOOP("Metamaterial", "Flexibility"),
     QT_TRANSLATE_NOOP("Metamaterial", "Global and per-joint hinge sizes, with the resulting k1 / k2"),
     lambda sc: _panels().FlexibilityPanel(sc), True),
    ("MM_PlaceMotor", "MM_PlaceMotor.svg", QT_TRANSLATE_NOOP("Metamaterial", "Place motor"),
     QT_TRANSLATE_NOOP("Metamaterial", "Put a servo on a joint (click a hinge); shown as a red sphere"),
     lambda sc: _panels().PlaceItemPanel(sc, "actuator"), True),
    ("MM_PlaceConstraint", "MM_PlaceConstraint.svg", QT_TRANSLATE_NOOP("Metamaterial", "Angular constraint"),
     QT_TRANSLATE_NOOP("Metamaterial", "Hold a joint at a fixed deformation (clip); shown as a blue disc"),
     lambda sc: _panels().PlaceItemPanel(sc, "constraint"), True),
    ("MM_AddModule", "MM_AddModule.svg", QT_TRANSLATE_NOOP("Metamaterial", "Add module"),
     QT_TRANSLATE_NOOP("Metamaterial", "Servo housing, connection hubs, friction pad or clip on a node or joint"),
     lambda sc: _panels().AddModulePanel(sc), True),
    ("MM_Simulate", "MM_Simulate.svg", QT_TRANSLATE_NOOP("Metamaterial", "Simulate"),
     QT_TRANSLATE_NOOP("Metamaterial", "Global-deformation slider and one slider per motor and constraint, "
                                       "solved live"),
     lambda sc: _panels().SimulatePanel(sc), True),
    ("MM_Animate", "MM_Animate.svg", QT_TRANSLATE_NOOP("Metamaterial", "Animate"),
     QT_TRANSLATE_NOOP("Metamaterial", "Play the motors' motion profiles (sine amplitude, frequency, phase); "
                                       "stream to hardware"),
     lambda sc: _panels().AnimatePanel(sc), True),
    ("MM_Export", "MM_Export.svg", QT_TRANSLATE_NOOP("Metamaterial", "Export STEP / 3MF"),
     QT_TRANSLATE_NOOP("Metamaterial", "Write STEP (named bodies) and 3MF (per-part materials) for dual-extruder "
                                       "printers"),
     lambda sc: _panels().ExportPanel(sc), True),
    ("MM_Sleeve", "MM_Sleeve.svg", QT_TRANSLATE_NOOP("Metamaterial", "Sleeve actuator"),
     QT_TRANSLATE_NOOP("Metamaterial", "Design a metamaterial sleeve actuator (curved-beam cells around a cylinder) "
                       "from a spec file or parameters, build it, predict its force-displacement peaks and snapping "
                       "sequence"),
     lambda doc: _panels().SleevePanel(doc), False),
    ("MM_FitTarget", "MM_FitTarget.svg", QT_TRANSLATE_NOOP("Metamaterial", "Fit to target"),
     QT_TRANSLATE_NOOP("Metamaterial", "Inverse design: place N servos and find their values so the structure best "
                       "reaches a target shape (file or document object); runs in the background"),
     lambda sc: __import__("metamaterial_wb.gui.panels.fit_target", fromlist=["x"]).FitTargetPanel(sc), True),
]

DESIGN = ["MM_NewStructure", "MM_OpenExample", "MM_RotaryAxes", "MM_FoldedShape"]
SIMULATE = ["MM_Flexibility", "MM_PlaceMotor", "MM_PlaceConstraint", "MM_AddModule", "MM_Simulate", "MM_Animate"]
FABRICATE = ["MM_Export"]
SLEEVE = ["MM_Sleeve"]
INVERSE = ["MM_FitTarget"]

_REGISTERED = False
INSTANCES = {}   # command name -> the Python command object (tests read last_error)


def register():
    global _REGISTERED
    names = [c[0] for c in COMMANDS]
    if not _REGISTERED:
        for name, icon, menu, tip, make, needs in COMMANDS:
            INSTANCES[name] = _cmd(name, icon, menu, tip, make, needs)
            FreeCADGui.addCommand(name, INSTANCES[name])
        _REGISTERED = True
    return names
