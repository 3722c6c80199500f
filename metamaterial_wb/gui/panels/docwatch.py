"""The document watch under the open task panel (a part of :mod:`metamaterial_wb.gui.panels.base`).

``_DocumentWatch`` is one FreeCAD document observer, added when the first panel is shown (``_watch_documents``):
it closes the panel whose document is closed, has the panel check its structure and items when objects are
deleted or come back, and follows the Undo / Redo steps of the panel's document. :class:`UndoWatch` (a mixin of
:class:`~metamaterial_wb.gui.panels.base.BasePanel`) turns those steps into the panel's stale state: OK refused
while an Undo / Redo has moved its structure away from the values it shows, or while another command or a script
(the Python console, the property editor) has changed what the panel writes back on OK (``EDITS``).

The open panel is ``base.ACTIVE``, read at call time from the module ``_watch_documents`` is given (``base``
imports this module, so this one never imports ``base``: no import cycle).
"""
import json

import FreeCAD
from PySide import QtCore, QtGui

from metamaterial_wb.gui.i18n import translate


_HOST = None    # the module holding ``ACTIVE``, ``_retire`` and ``_close`` (``base``), set by ``_watch_documents``


def _active():
    """The panel being shown (``base.ACTIVE``, read now)."""
    return getattr(_HOST, "ACTIVE", None)


class _DocumentWatch:
    """Closes the open panel when the document it works on is closed (its timers and preview go with it)."""

    def slotDeletedDocument(self, doc):
        p = _active()
        if p is not None and getattr(p, "doc_name", None) == doc.Name:
            p.forget_view()         # its Coin nodes and preview objects go with the document: never touched now
            _HOST._retire(p)        # timers, threads, jobs, the selection observer

            def close():
                if _active() is p:
                    _HOST._close()
            QtCore.QTimer.singleShot(0, close)

    def slotDeletedObject(self, obj):
        """An object is going (Delete, Ctrl+Z of its creation): once it is gone, the open panel checks whether
        it was its structure (``BasePanel.check_target``: playback stops, the preview goes, the panel says so)."""
        self._moved(obj)
        self._check_later(obj, _active())

    def slotCreatedObject(self, obj):
        """An object comes (back): Ctrl+Z of a Delete, Ctrl+Y of Place motor. A motor the open panel named as
        deleted may be back, so it checks its items again (``BasePanel.check_items`` clears the red line)."""
        self._moved(obj)
        p = _active()
        if p is not None and p.ITEM_ROWS and "items" in getattr(p, "problems", {}):
            self._check_later(obj, p)

    def slotChangedObject(self, obj, prop):
        if prop == "Items":
            self.slotCreatedObject(obj)
        else:
            self._moved(obj)
        self._outside(obj, prop)

    # Undo / Redo under the open panel (the slots fire on FreeCAD 0.20, 1.0 and 1.1; an aborted transaction, as
    # when a panel's own OK fails, fires slotAbortTransaction only) -------------------------------------------
    def slotUndoDocument(self, doc):
        self._step(doc, -1)

    def slotRedoDocument(self, doc):
        self._step(doc, +1)

    def slotCommitTransaction(self, doc):
        self._step(doc, 0)

    def slotAbortTransaction(self, doc):
        p = _active()
        if p is not None:
            p._undo["names"].clear()      # what the rollback restored is no Undo / Redo

    @staticmethod
    def _moved(obj):
        """Notes an object created, deleted or changed by an Undo / Redo (the document is ``Transacting``) in the
        open panel's document, for the ``slotUndoDocument`` / ``slotRedoDocument`` that ends it."""
        p = _active()
        if p is None or p._own_change:
            return
        try:   # Transacting first: every property a preview writes comes here, and stops at it
            d = obj.Document
            if d is not None and d.Transacting and d.Name == p.doc_name and p.edits_stored_state():
                p._undo["names"].add(obj.Name)
        except Exception:  # pragma: no cover - an object without a document or name: not the panel's
            pass

    @staticmethod
    def _outside(obj, prop):
        """A property changed neither by an Undo / Redo (``Transacting``) nor by the open panel's own OK: another
        command or a script changed it (a panel's preview writes no property)."""
        p = _active()
        if p is None or p._own_change or not p._undo["state"]:
            return
        try:
            d = obj.Document
            if d is not None and not d.Transacting and d.Name == p.doc_name:
                p.changed_outside(obj.Name, prop)
        except Exception:  # pragma: no cover - an object without a document or name: not the panel's
            pass

    @staticmethod
    def _step(doc, step):
        p = _active()
        try:
            ours = p is not None and doc.Name == p.doc_name and not p._own_change and p.edits_stored_state()
        except Exception:  # pragma: no cover - a document being closed
            ours = False
        if ours:
            p.undo_moved(step)

    @staticmethod
    def _check_later(obj, p):
        """Once the document's change is done, the panel ``p`` checks its structure and items (if ``obj`` is in its
        document)."""
        if p is None or getattr(p, "obj", None) is None:
            return
        try:
            if obj.Document.Name != getattr(p, "doc_name", None):
                return
        except Exception:  # pragma: no cover - an object without a document: check anyway
            pass

        def check():
            if _active() is p and not p.check_target():
                p.check_items()
        QtCore.QTimer.singleShot(0, check)


_WATCH = None


def _watch_documents(host):
    """Adds the one document observer (once); ``host`` is the module holding the open panel (``base``)."""
    global _WATCH, _HOST
    _HOST = host
    if _WATCH is None:
        _WATCH = _DocumentWatch()
        FreeCAD.addDocumentObserver(_WATCH)


# What the OK of each panel writes back (and what its rows stand for). A change made by another command or a script
# to one of these while the panel is open makes it stale, as an Undo does: its OK would write the older value over
# it. Any other change (a label, a property the panel does not write, another object, a motor added, a recompute
# that leaves them equal) keeps it usable: the OK leaves that change as it is. "scene": properties of the structure;
# "json": top-level fields of its SceneJSON; "item" / "module": properties of its motors and constraints / modules.
# Add module and Place motor add to what is stored when OK is pressed; a panel not named here that writes back on OK
# (``edits_stored_state``: Fit to target) watches everything it could be computed from (``_ALL``).
_ROW = ("ItemName", "Kind", "Joint")            # what a Simulate / Animate row stands for
_ALL = {"scene": ("CellSize", "Layout", "HingeLength", "HingeWidth", "HingeThickness", "Model", "UseGlobal",
                  "GlobalDeformation", "Items", "Modules"),
        "json": ("axes", "joint_config", "joints"),
        "item": _ROW + ("Value", "ProfileShape", "Amplitude", "FrequencyHz", "PhaseDeg", "Offset", "ProfileData",
                        "ExtraJSON"),
        "module": ("ModuleType", "TargetKind", "Target", "ModuleData")}
EDITS = {
    "SimulatePanel": {"scene": ("UseGlobal", "GlobalDeformation", "Model"), "item": _ROW + ("Value",)},
    "AnimatePanel": {"item": _ROW + ("ProfileShape", "Amplitude", "FrequencyHz", "PhaseDeg", "ProfileData")},
    "FoldedShapePanel": {"scene": ("Layout",), "json": ("axes", "joint_config")},
    "RotaryAxesPanel": {"scene": ("Layout",), "json": ("axes", "joint_config")},
    "FlexibilityPanel": {"scene": ("Layout", "HingeLength", "HingeWidth", "HingeThickness"), "json": ("joints",)},
    "AddModulePanel": {},
    "PlaceItemPanel": {},
}


def _value(o, prop, fields):
    """``o.prop`` as compared: SceneJSON as its ``fields`` (parsed: layout and key order do not count), lengths
    as floats, links as object names."""
    v = getattr(o, prop)
    if prop == "SceneJSON":
        try:
            data = json.loads(v or "{}")
        except ValueError:
            return v
        return tuple(_field(data, f) for f in fields) if isinstance(data, dict) else v
    if isinstance(v, (list, tuple)):
        return tuple(getattr(x, "Name", x) for x in v)
    if isinstance(v, FreeCAD.DocumentObject):
        return v.Name
    return float(v.Value) if hasattr(v, "Value") and hasattr(v, "Unit") else v


def _field(data, f):
    """A SceneJSON field as compared. Of ``joint_config`` only the hand-written entries: those ``design`` derived
    (with ``"axis"``) follow the axes and the hinge sizes, and every recompute derives them again."""
    v = data.get(f)
    if f == "joint_config" and isinstance(v, dict):
        v = {k: e for k, e in v.items() if not (isinstance(e, dict) and "axis" in e)} or None
    return json.dumps(v, sort_keys=True)


def _stored(obj, spec):
    """``{(object name, property): value}`` of what a panel with ``spec`` (``EDITS``) writes back."""
    out = {}
    for prop in spec.get("scene", ()):
        out[(obj.Name, prop)] = _value(obj, prop, ())
    if spec.get("json"):
        out[(obj.Name, "SceneJSON")] = _value(obj, "SceneJSON", spec["json"])
    for kind, objs in (("item", obj.Items), ("module", obj.Modules)):
        for o in objs:
            for prop in spec.get(kind, ()):
                if prop in o.PropertiesList:
                    out[(o.Name, prop)] = _value(o, prop, ())
    return out


class UndoWatch:
    """The panel's side of the Undo / Redo watch: where the document is on its undo stack since the panel opened,
    what another command or a script changed of what it writes back, and the stale line that refuses OK (a mixin
    of ``BasePanel``, which sets ``_undo`` and ``_own_change``)."""

    def edits_stored_state(self):
        """True for a panel that writes back on OK what it copied from its structure when it opened (it has a
        structure ``obj`` and an OK button; Export, with Close only, reads the structure when it runs)."""
        ok = QtGui.QDialogButtonBox.StandardButton.Ok
        return getattr(self, "obj", None) is not None and (self.getStandardButtons() & ok) == ok

    def undo_moved(self, step):
        """The document moved under the open panel: ``step`` -1 an Undo, +1 a Redo, 0 a new step committed by another
        tool. The panel's values were copied when it opened: after an Undo / Redo that changed its structure (or an
        object the structure links: motors, modules, arrays) an OK, an untouched one too, would write them over the
        document's. The panel is stale (``check_stale``) until the document is back where the panel opened it (its
        position on the undo stack; no new step committed after an Undo). An Undo of other objects does not count."""
        u = self._undo
        names, u["names"] = u["names"], set()
        if step == 0:
            if u["pos"] < 0:
                u["branched"] = True        # a new step after an Undo drops the redo list that led back
            else:
                u["pos"] += 1
            return
        u["pos"] += step
        try:
            obj = self.obj
            mine = {obj.Name} | {o.Name for o in obj.OutListRecursive}
        except Exception:                   # the structure went: check_target says so
            mine = set()
        if names & mine:
            u["touched"] = True
        QtCore.QTimer.singleShot(0, lambda: _active() is self and self.check_stale())

    def remember_state(self):
        """What the panel's OK writes back (``EDITS``), as stored when the panel opens (``base.show``)."""
        self._undo["state"] = {}
        if self.edits_stored_state():
            try:
                self._undo["state"] = _stored(self.obj, EDITS.get(type(self).__name__, _ALL))
            except Exception:  # pragma: no cover - a structure that cannot be read: check_target says why
                pass

    def changed_outside(self, name, prop):
        """Another command or a script changed ``prop`` of the object ``name`` (``_DocumentWatch._outside``): if the
        panel writes it back, it checks once the change is done whether it is still the stored value."""
        u = self._undo
        if (name, prop) not in u["state"]:
            return
        u["dirty"].add((name, prop))
        if not u.get("pending"):
            u["pending"] = True

            def check():
                u["pending"] = False
                if _active() is self:
                    self.check_stale()
            QtCore.QTimer.singleShot(0, check)

    def changed_since(self):
        """``["Label.Property", ...]`` of what another command or a script changed of what the panel writes back
        and is not back at the value the panel opened with. A motor that is gone is left to ``check_items``."""
        out = []
        doc = FreeCAD.getDocument(self.doc_name)
        spec = EDITS.get(type(self).__name__, _ALL)
        for name, prop in sorted(self._undo["dirty"]):
            o = doc.getObject(name)
            if o is None:
                continue                    # gone: check_items / target_lost say so
            was, now = self._undo["state"][(name, prop)], _value(o, prop, spec.get("json", ()))
            if now == was:
                continue                    # back at the value the panel opened with
            if prop == "SceneJSON" and isinstance(was, tuple) and isinstance(now, tuple):
                out += [f"{o.Label}.SceneJSON[{f!r}]" for f, a, b in zip(spec["json"], was, now) if a != b]
            else:
                out.append(f"{o.Label}.{prop}")
        return out

    def check_stale(self):
        """OK refused, with a line at the top of the panel, while an Undo / Redo has moved the panel's structure
        away from the state the panel shows (``undo_moved``) or another command or a script has changed what the
        panel writes back (``changed_outside``); cleared once the document is back there. A structure that is gone
        is left to ``target_lost``. Said once: that line, never repeated in the panel's error line."""
        u = self._undo
        if self.target_gone():
            return
        if u["pos"] == 0 and not u["branched"]:
            u["touched"] = False
        try:
            changed = self.changed_since()
        except Exception:  # pragma: no cover - a document being closed
            changed = []
        if u["touched"]:
            text = translate("Metamaterial", "the document changed under this panel (Undo / Redo): the values shown "
                                             "are not the stored ones any more; press Cancel and open the panel again "
                                             "to edit the current state (or Undo / Redo back)")
        elif changed:
            text = translate("Metamaterial", "{0} changed under this panel (another command or a script): OK would "
                                             "write the older value shown here over it; press Cancel and open the "
                                             "panel again to edit the current state (or change it back)"
                             ).format(", ".join(changed))
        else:
            text = ""
        self.set_top_problem("stale", text)

    def set_top_problem(self, key, text):
        """Show (``text``) or clear (``""``) the problem ``key`` of the whole panel in its red line at the top of
        the panel (put there the first time; a preview clears the error line, not this one); OK follows. Said
        there only: the panel's error line does not repeat it."""
        lab = self.problem_label(key)
        if text and lab.parent() is None:
            self.layout.insertWidget(0, lab)
        self.set_problem(key, text)
