"""Helpers shared by the FeaturePython proxies (App side: headless-safe, no Qt, no FreeCADGui).

Persistence on FreeCAD 0.20.2 + Python 3.11 (notes/freecad-workbench.md 2.2): a proxy must define
``dumps/loads`` AND alias ``__getstate__/__setstate__``, return small JSON data, and never keep a
document object in its state. All data lives in typed properties.
"""
import json

import FreeCAD

OUTPUT = 8          # property attribute: Output (changing it does not touch the object)
READONLY = 1
HIDDEN = 4

_EXEC_COUNTS = {}   # (document name, object name) -> number of execute() calls (tests, this session only)


def count_execute(obj):
    key = (obj.Document.Name, obj.Name)
    _EXEC_COUNTS[key] = _EXEC_COUNTS.get(key, 0) + 1


def execute_count(obj):
    return _EXEC_COUNTS.get((obj.Document.Name, obj.Name), 0)


def ensure_property(obj, ptype, name, group, tip, default=None, attr=0, readonly=False, hidden=False):
    """Add a property if it is missing (idempotent; used by __init__ and onDocumentRestored)."""
    if name in obj.PropertiesList:
        return False
    obj.addProperty(ptype, name, group, tip, attr, readonly, hidden)
    if default is not None:
        setattr(obj, name, default)
    return True


class ProxyBase:
    """Common persistence: the state is ``{"Type": ..., "schema": ...}``."""

    Type = "MetamaterialBase"
    SCHEMA = 1

    def dumps(self):
        return {"Type": self.Type, "schema": self.SCHEMA}

    def loads(self, state):
        if isinstance(state, dict):
            self._loaded_schema = state.get("schema", self.SCHEMA)
        return None

    __getstate__ = dumps
    __setstate__ = loads


class ViewProviderBase:
    """View provider proxy: an icon, and nothing stored."""

    ICON = "Metamaterial_Workbench.svg"

    def __init__(self, vobj):
        vobj.Proxy = self

    def attach(self, vobj):
        self.Object = vobj.Object

    def getIcon(self):
        import metamaterial_wb
        return metamaterial_wb.icon_path(self.ICON)

    def updateData(self, obj, prop):
        return

    def onChanged(self, vobj, prop):
        return

    def dumps(self):
        return None

    def loads(self, state):
        return None

    __getstate__ = dumps
    __setstate__ = loads


def set_color(vobj, rgb):
    """Shape colour for 0.20 (ShapeColor) and 1.x (ShapeAppearance): see geometry.fc.set_shape_colour."""
    from metamaterial_wb.geometry.fc import set_shape_colour
    set_shape_colour(vobj, rgb)


def attach_view_provider(obj, vp_class_name, module="metamaterial_wb.gui.viewproviders"):
    """Attach a view provider proxy when the GUI is up (objects stay creatable headless)."""
    if not FreeCAD.GuiUp or obj.ViewObject is None:
        return None
    import importlib
    mod = importlib.import_module(module)
    return getattr(mod, vp_class_name)(obj.ViewObject)


def json_prop(obj, name, default=None):
    txt = getattr(obj, name, "") or ""
    if not txt.strip():
        return default
    return json.loads(txt)
