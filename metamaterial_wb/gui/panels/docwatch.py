"""The document watch under the open task panel (a part of :mod:`metamaterial_wb.gui.panels.base`).

``_DocumentWatch`` is one FreeCAD document observer, added when the first panel is shown (``_watch_documents``):
it closes the panel whose document is closed, has the panel check its structure and items when objects are
deleted or come back, and follows the Undo / Redo steps of the panel's document. :class:`UndoWatch` (a mixin of
:class:`~metamaterial_wb.gui.panels.base.BasePanel`) turns those steps into the panel's stale state: OK refused
while an Undo / Redo has moved its structure away from the values it shows.

The open panel is ``base.ACTIVE``, read at call time from the module ``_watch_documents`` is given (``base``
imports this module, so this one never imports ``base``: no import cycle).
"""
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


class UndoWatch:
    """The panel's side of the Undo / Redo watch: where the document is on its undo stack since the panel opened,
    and the stale line that refuses OK (a mixin of ``BasePanel``, which sets ``_undo`` and ``_own_change``)."""

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

    def check_stale(self):
        """OK refused, with a line at the top of the panel, while an Undo / Redo has moved the panel's structure
        away from the state the panel shows (``undo_moved``); cleared once the document is back there. A structure
        that is gone is left to ``target_lost``. Said once: that line, never repeated in the panel's error line."""
        u = self._undo
        if self.target_gone():
            return
        if u["pos"] == 0 and not u["branched"]:
            u["touched"] = False
        text = translate("Metamaterial", "the document changed under this panel (Undo / Redo): the values shown "
                                         "are not the stored ones any more; press Cancel and open the panel again "
                                         "to edit the current state (or Undo / Redo back)") if u["touched"] else ""
        self.set_top_problem("stale", text)

    def set_top_problem(self, key, text):
        """Show (``text``) or clear (``""``) the problem ``key`` of the whole panel in its red line at the top of
        the panel (put there the first time; a preview clears the error line, not this one); OK follows. Said
        there only: the panel's error line does not repeat it."""
        lab = self.problem_label(key)
        if text and lab.parent() is None:
            self.layout.insertWidget(0, lab)
        self.set_problem(key, text)
