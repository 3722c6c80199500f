"""Translation of the workbench's user-visible texts through FreeCAD's Qt translation.

Every label, button, check box, group box, form row, title and tool tip the GUI sets goes through
``translate("Metamaterial", text)`` (``FreeCAD.Qt.translate``, FreeCAD 0.20+); a text with values is
translated as a template first, then formatted (``translate(CTX, "frame {0}").format(n)``), so a
translator sees the whole sentence. ``QT_TRANSLATE_NOOP`` marks texts stored for later translation.
``python3 -m metamaterial_wb.gui.ts_extract`` writes ``resources/translations/Metamaterial.ts``.
"""
CONTEXT = "Metamaterial"


def translate(context, text):
    try:
        import FreeCAD
        return FreeCAD.Qt.translate(context, text)
    except Exception:  # pragma: no cover - outside FreeCAD (pure tests) or an old FreeCAD
        return text


def QT_TRANSLATE_NOOP(context, text):  # noqa: N802 - Qt's name, which lupdate recognises
    return text
