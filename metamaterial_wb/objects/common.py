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


def warn(msg):
    """A warning in FreeCAD's report view, and on stderr when headless (FreeCAD's console is silent in library
    mode)."""
    FreeCAD.Console.PrintWarning(msg + "\n")
    if not FreeCAD.GuiUp:
        import sys
        print(msg, file=sys.stderr)


def ensure_range(obj, name, low, high, step):
    """Re-apply the ``[low, high]`` limits of the ``App::PropertyFloatConstraint`` ``name``, keeping its value.

    FreeCAD saves the value of such a property but not its limits: after a reopen any number was accepted as
    typed. Called by ``onDocumentRestored``; it touches nothing that was not touched. A stored value outside the
    range (a file saved while the limits were lost) is clamped, with a warning naming the object, the value and
    the range, and the object is left touched so that the next recompute uses the clamped value.
    """
    if name not in obj.PropertiesList:
        return
    value = float(getattr(obj, name))
    clamped = min(max(value, low), high)
    was_touched = "Touched" in obj.State
    setattr(obj, name, (clamped, low, high, step))
    if clamped != value:
        warn(f"Metamaterial: {obj.Label}.{name} = {value:g} in the file is outside the allowed range "
             f"[{low:g}, {high:g}]; set to {clamped:g}")
    elif not was_touched:
        obj.purgeTouched()


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


def assign(obj, prop, value):
    """``obj.prop = value`` only when it differs. FreeCAD records every set, an equal one too (an undo step, the
    document marked modified), and drops a transaction that recorded nothing: an edit that changes nothing,
    written through this, leaves no trace. Returns whether it wrote."""
    if getattr(obj, prop) == value:
        return False
    setattr(obj, prop, value)
    return True


def json_property(obj, prop, what="an object", kind=dict):
    """The JSON in text property ``prop`` of ``obj`` (empty text: an empty ``kind``), or a SceneError naming the
    object, the property and what it should hold (``json.loads``'s own message named neither)."""
    from metamaterial_wb.core.errors import SceneError
    text = getattr(obj, prop) or ""
    if not text.strip():
        return kind()
    try:
        value = json.loads(text)
    except ValueError as exc:
        raise SceneError(f"{obj.Label}.{prop}", f"not valid JSON ({getattr(exc, 'msg', exc)} at line "
                                                f"{getattr(exc, 'lineno', '?')} column {getattr(exc, 'colno', '?')});"
                                                f" expected {what}") from None
    if not isinstance(value, kind):
        raise SceneError(f"{obj.Label}.{prop}", f"holds {type(value).__name__} JSON; expected {what}")
    return value


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


# ----------------------------------------------------------------------------------------------
# documents restored without the package (issue 19)
# ----------------------------------------------------------------------------------------------
# FreeCAD 0.20.2 (Debian) refuses to import a proxy's module during a document restore unless it lies
# in a Mod folder or is already imported ("PropertyPythonObject::Restore: blocked import of module
# ..."): opening a file headless without importing this package first leaves every Proxy None, and
# saving then writes the proxies as null. Two typed records survive such a save, because FreeCAD
# keeps typed properties without the proxy:
#   * every object carries a hidden ``ProxyClass`` property ("module:Class");
#   * the document's ``Meta`` map holds ``metamaterial_wb.objects.2``: each of our objects with the names
#     of the properties the workbench added to it, written at every save (the <Document> header comes
#     first in Document.xml, so a truncated file still has it). Only our own properties: FreeCAD's differ
#     between versions (1.1 gives a Part::FeaturePython ``ShapeMaterial`` and ``_ElementMapVersion``,
#     0.20 does not), so a file saved on 1.1 would look truncated on 0.20. Files saved before 2026-12
#     hold ``metamaterial_wb.objects`` (counts of all properties): there only the objects and their
#     ``ProxyClass`` are checked.
# When the package is imported (before or after the document was opened) :func:`repair_document`
# re-attaches the proxies from ``ProxyClass``, and reports objects that the manifest names but the
# file lost. A document that cannot be repaired is locked: its FileName is cleared, so ``save()``
# fails (FreeCAD: "Saving document failed") and only Save As to a new file is possible.
PROXY_CLASS = "ProxyClass"
MANIFEST_KEY = "metamaterial_wb.objects.2"
LEGACY_MANIFEST_KEY = "metamaterial_wb.objects"
PROP_DYNAMIC = 21   # Property::PropDynamic as getPropertyStatus reports it (the same on FreeCAD 0.20, 1.0, 1.1)
_REPORTS = {}       # document name -> last repair report (tests, GUI)


def attach_proxy(obj, proxy):
    """``obj.Proxy = proxy`` and record the proxy class in the hidden ``ProxyClass`` property."""
    obj.Proxy = proxy
    tag_proxy(obj, proxy)


def tag_proxy(obj, proxy):
    value = f"{type(proxy).__module__}:{type(proxy).__name__}"
    ensure_property(obj, "App::PropertyString", PROXY_CLASS, "Base",
                    "Proxy class of this object (lets the workbench re-attach it after a restore without it)",
                    hidden=True)
    if getattr(obj, PROXY_CLASS) != value:
        setattr(obj, PROXY_CLASS, value)


def _ours(doc):
    return [o for o in doc.Objects if PROXY_CLASS in o.PropertiesList]


def own_properties(obj):
    """The names of the properties the workbench added to ``obj`` (FreeCAD's own, which differ between
    FreeCAD versions, left out)."""
    return sorted(n for n in obj.PropertiesList if PROP_DYNAMIC in obj.getPropertyStatus(n))


def write_manifest(doc):
    """``doc.Meta[MANIFEST_KEY]``: {object name: [names of its own properties]} of every object of ours."""
    text = json.dumps({o.Name: own_properties(o) for o in sorted(_ours(doc), key=lambda o: o.Name)},
                      sort_keys=True)
    meta = dict(doc.Meta)
    if meta.get(MANIFEST_KEY) != text or LEGACY_MANIFEST_KEY in meta:
        meta[MANIFEST_KEY] = text
        meta.pop(LEGACY_MANIFEST_KEY, None)
        doc.Meta = meta


def _manifest(doc):
    """{object name: [property names]} from the file's record; a legacy record (counts) gives empty lists."""
    meta = dict(doc.Meta)
    for key, legacy in ((MANIFEST_KEY, False), (LEGACY_MANIFEST_KEY, True)):
        if key not in meta:
            continue
        try:
            rec = json.loads(meta[key])
        except ValueError:
            return {}
        if not isinstance(rec, dict):
            return {}
        return {str(k): ([] if legacy or not isinstance(v, list) else [str(n) for n in v]) for k, v in rec.items()}
    return {}


def repair_document(doc, announce=True):
    """Re-attach lost proxies and report lost objects; lock the document if anything is missing.

    Returns ``{"restored": [...], "lost": [...], "unknown": [...], "locked": bool}``.
    """
    import importlib

    restored, unknown = [], []
    for o in doc.Objects:   # files saved before ProxyClass existed: tag our objects now
        p = getattr(o, "Proxy", None)
        if p is not None and type(p).__module__.startswith("metamaterial_wb.") and PROXY_CLASS not in o.PropertiesList:
            tag_proxy(o, p)
    for o in _ours(doc):
        if getattr(o, "Proxy", None) is not None:
            continue
        mod_name, _, cls_name = (getattr(o, PROXY_CLASS) or "").partition(":")
        try:
            if not mod_name.startswith("metamaterial_wb."):
                raise ImportError(mod_name)
            klass = getattr(importlib.import_module(mod_name), cls_name)
            proxy = klass.__new__(klass)
            o.Proxy = proxy
            if hasattr(proxy, "onDocumentRestored"):
                proxy.onDocumentRestored(o)
            restored.append(o.Name)
        except Exception:  # noqa: BLE001 - reported below, never raised into FreeCAD's restore
            unknown.append(o.Name)
    # lost: missing, or its data never restored (a truncated Document.xml: the object list comes
    # first, so the object exists but its properties, ProxyClass among them, stop at the cut)
    lost = []
    for name, props in sorted(_manifest(doc).items()):
        o = doc.getObject(name)
        if o is None or PROXY_CLASS not in o.PropertiesList or not set(props) <= set(o.PropertiesList):
            lost.append(name)
    locked = bool(lost or unknown)
    report = {"restored": restored, "lost": lost, "unknown": unknown, "locked": locked}
    if locked and doc.FileName:
        report["file"] = doc.FileName
        doc.FileName = ""          # FreeCAD refuses save() without a file name: no overwrite of the original
    _REPORTS[doc.Name] = report
    if announce and (restored or locked):
        msg = f"Metamaterial: document {doc.Label!r}"
        if restored:
            msg += (f": {len(restored)} object(s) had been restored without the metamaterial_wb package "
                    f"(their proxies were lost); re-attached: {', '.join(restored[:8])}"
                    + (" ..." if len(restored) > 8 else ""))
        if lost:
            msg += (f"; the file is damaged: {len(lost)} object(s) lost ({', '.join(lost[:8])}"
                    + (" ..." if len(lost) > 8 else "") + ")")
        if unknown:
            msg += f"; {len(unknown)} object(s) could not be re-attached ({', '.join(unknown[:8])})"
        if locked:
            msg += f"; not saving over {report.get('file', 'the file')}: use Save As to keep what is left"
        FreeCAD.Console.PrintWarning(msg + "\n")
        if not FreeCAD.GuiUp:      # headless: FreeCAD's console is silent in library mode
            import sys
            print(msg, file=sys.stderr)
    return report


def repair_report(doc):
    return _REPORTS.get(doc.Name)
