"""The document guard: an App-level observer that keeps our objects' data across sessions (issue 19).

Registered from the add-on's ``Init.py`` (which FreeCAD runs in ``freecadcmd`` and in a plain-Python
``import FreeCAD`` too, whenever the add-on lies in a Mod folder), and again, idempotently, when
``objects.structure`` is imported. It must stay cheap: this module imports only FreeCAD at load time;
the repair code (:mod:`metamaterial_wb.objects.common`) is imported when a document needs it.

What it does (the repair itself is :func:`~metamaterial_wb.objects.common.repair_document`):

* after a document is restored (Python observers get no restore signal on 0.20, 1.0 or 1.1, but an
  opened document is activated right after its restore, with ``Restoring`` already False): our
  objects whose proxy is missing (the file was saved by a session without the add-on) get it back
  from their hidden ``ProxyClass``, with a message; a damaged file is reported and locked (its
  FileName cleared, so ``save()`` fails and only Save As to a new file is possible);
* before every save: the same re-attach (so a save never writes dropped proxies over the file), and
  the object manifest in the document's ``Meta``. A save cannot be vetoed from Python (0.20, 1.0 and
  1.1 all write the file even when the observer raises), hence re-attach-before-save.

A document still being restored is never checked: its objects exist before their properties do, so
every object would look lost (this once locked sound files opened with the add-on installed).
"""
import FreeCAD


def _restoring(doc):
    return bool(getattr(doc, "Restoring", False))


def _has_dropped_proxies(doc):
    from metamaterial_wb.objects.common import PROXY_CLASS
    return any(PROXY_CLASS in o.PropertiesList and getattr(o, "Proxy", None) is None for o in doc.Objects)


def check(doc):
    """Repair ``doc`` once (after its restore); never raises into FreeCAD."""
    try:
        from metamaterial_wb.objects import common
        if _restoring(doc) or doc.Name in common._REPORTS:
            return None
        return common.repair_document(doc)
    except Exception as exc:  # noqa: BLE001 - an observer must never break FreeCAD
        FreeCAD.Console.PrintError(f"Metamaterial: document check failed: {exc}\n")
        return None


class DocumentGuard:
    def slotActivateDocument(self, doc):        # every version: right after an open
        check(doc)

    def slotDeletedDocument(self, doc):
        try:
            from metamaterial_wb.objects import common
            common._REPORTS.pop(doc.Name, None)
        except Exception:  # noqa: BLE001
            pass

    def slotStartSaveDocument(self, doc, filename):
        try:
            from metamaterial_wb.objects import common
            if _has_dropped_proxies(doc):
                common._REPORTS.pop(doc.Name, None)
                common.repair_document(doc)
            common.write_manifest(doc)
        except Exception as exc:  # noqa: BLE001
            FreeCAD.Console.PrintError(f"Metamaterial: could not keep the document's objects: {exc}\n")


def install():
    """Register the guard once per FreeCAD session and check the documents already open."""
    if getattr(FreeCAD, "_metamaterial_doc_guard", None) is not None:
        return FreeCAD._metamaterial_doc_guard
    guard = DocumentGuard()
    FreeCAD.addDocumentObserver(guard)
    FreeCAD._metamaterial_doc_guard = guard
    for doc in list(FreeCAD.listDocuments().values()):
        check(doc)        # skips a document mid-restore: its activation checks it when complete
    return guard
