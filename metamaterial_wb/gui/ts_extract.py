"""Write ``resources/translations/Metamaterial.ts`` (Qt Linguist's format, what lupdate writes) from the
``translate(context, text)`` / ``QT_TRANSLATE_NOOP(context, text)`` calls under ``metamaterial_wb/gui``.

    python3 -m metamaterial_wb.gui.ts_extract          # then translate with Qt Linguist, lrelease -> .qm

Pure Python (ast): no FreeCAD, no Qt tools needed.
"""
import ast
import os
import sys
from xml.sax.saxutils import escape

GUI = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(GUI))
TS = os.path.join(ROOT, "resources", "translations", "Metamaterial.ts")


def messages(folder=GUI):
    """``{context: {text: [(relative path, line), ...]}}`` of every translatable literal."""
    out = {}
    for d, _dirs, files in os.walk(folder):
        for f in sorted(files):
            if not f.endswith(".py"):
                continue
            path = os.path.join(d, f)
            tree = ast.parse(open(path, encoding="utf-8").read(), path)
            for node in ast.walk(tree):
                if not isinstance(node, ast.Call) or len(node.args) < 2:
                    continue
                fn = node.func
                name = fn.attr if isinstance(fn, ast.Attribute) else getattr(fn, "id", "")
                ctx, text = node.args[:2]
                if name in ("translate", "QT_TRANSLATE_NOOP") and isinstance(ctx, ast.Constant) \
                        and isinstance(text, ast.Constant) and isinstance(text.value, str):
                    rel = os.path.relpath(path, ROOT)
                    out.setdefault(ctx.value, {}).setdefault(text.value, []).append((rel, node.lineno))
    return out


def ts_text(msgs):
    lines = ['<?xml version="1.0" encoding="utf-8"?>', "<!DOCTYPE TS>", '<TS version="2.1">']
    for ctx in sorted(msgs):
        lines += ["<context>", f"    <name>{escape(ctx)}</name>"]
        for text in sorted(msgs[ctx]):
            lines.append("    <message>")
            for rel, line in msgs[ctx][text]:
                lines.append(f'        <location filename="../../{escape(rel)}" line="{line}"/>')
            lines += [f"        <source>{escape(text)}</source>",
                      '        <translation type="unfinished"></translation>', "    </message>"]
        lines.append("</context>")
    lines.append("</TS>")
    return "\n".join(lines) + "\n"


def write_ts(path=TS):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w", encoding="utf-8") as f:
        f.write(ts_text(messages()))
    return path


if __name__ == "__main__":
    print(write_ts(sys.argv[1] if len(sys.argv) > 1 else TS))
