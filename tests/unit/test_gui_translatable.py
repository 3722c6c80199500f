"""Issue 14 item 6: every user-visible text the GUI sets on a label, button, check box, group box, form
row or window title goes through ``translate("Metamaterial", ...)`` (``FreeCAD.Qt.translate``), so the
workbench can be translated; ``resources/translations/Metamaterial.ts`` lists those texts (lupdate's
format) and is up to date with the code. Pure AST check: no FreeCAD needed."""
import pathlib
import ast
import os
import xml.etree.ElementTree as ET


ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
GUI = os.path.join(ROOT, "metamaterial_wb", "gui")
TS = os.path.join(ROOT, "resources", "translations", "Metamaterial.ts")
CONSTRUCTORS = {"QLabel", "QPushButton", "QCheckBox", "QRadioButton", "QGroupBox", "QAction"}
# owned by another engineer this round (issue 17's fit panel): its texts are wrapped when it is merged
OWNED_ELSEWHERE = set()
SETTERS = {"setText", "setWindowTitle", "setTitle", "setToolTip", "setPlaceholderText", "addRow"}


def gui_files():
    for d, _dirs, files in os.walk(GUI):
        for f in sorted(files):
            if f.endswith(".py") and f not in OWNED_ELSEWHERE:
                yield os.path.join(d, f)


def literal(node):
    return isinstance(node, ast.JoinedStr) or (isinstance(node, ast.Constant) and isinstance(node.value, str)
                                               and node.value.strip() != "")


def call_name(node):
    f = node.func
    return f.attr if isinstance(f, ast.Attribute) else f.id if isinstance(f, ast.Name) else ""


def untranslated():
    bad = []
    for path in gui_files():
        tree = ast.parse(pathlib.Path(path).read_text(encoding="utf-8"), path)
        for node in ast.walk(tree):
            if not isinstance(node, ast.Call) or not node.args:
                continue
            name = call_name(node)
            if name in CONSTRUCTORS or name in SETTERS:
                arg = node.args[0]
                parts = [arg]
                while isinstance(parts[0], ast.BinOp):    # "a" + b + "c": every literal part
                    parts[:1] = [parts[0].left, parts[0].right]
                for arg in parts:
                    if not literal(arg):
                        continue
                    bad.append(f"{os.path.relpath(path, ROOT)}:{node.lineno}: {name}({ast.unparse(arg)[:50]})")
    return bad


def test_every_visible_text_goes_through_translate():
    bad = untranslated()
    assert not bad, "texts not translatable:\n" + "\n".join(bad)


def test_the_ts_file_lists_every_translatable_text():
    from metamaterial_wb.gui.ts_extract import messages
    assert os.path.exists(TS), "resources/translations/Metamaterial.ts missing (/usr/bin/python3 -m metamaterial_wb.gui.ts_extract)"
    root = ET.parse(TS).getroot()
    assert root.tag == "TS"
    have = {(c.findtext("name"), m.findtext("source")) for c in root.iter("context") for m in c.iter("message")}
    want = {(c, t) for c, texts in messages().items() for t in texts}
    assert len(want) > 50
    assert want <= have, f"regenerate the .ts file: {sorted(want - have)[:5]}"


def test_spin_box_refusals_are_translatable():
    """A spin box's refusal ("... is outside the allowed range ...; the box kept ...", gui/panels/ranges.py) is a
    message the user reads in the panel: it was built with f-strings, out of reach of a translation."""
    sources = {m.text for m in ET.parse(TS).getroot().iter("source")}
    for text in ("{0} is outside the allowed range {1}{2}", "; the box kept {0}",
                 "{0} has more decimals than the box takes (at most {1} decimals){2}",
                 "{0} is not a whole number (at most 0 decimals){1}",
                 "{0} was not taken as typed (allowed range {1}, at most {2} decimals){3}"):
        assert text in sources, text
