"""Every visible text of every task panel goes through ``translate("Metamaterial", ...)`` -- checked at run time.

``tests/unit/test_gui_translatable.py`` only sees literals passed straight to a widget; texts set through a
class attribute (``TITLE``), a helper (``button_row``), a list (a combo's items) or an f-string slipped past it.
Here FreeCAD's ``Qt.translate`` (what ``metamaterial_wb.gui.i18n.translate`` calls) is replaced by one that
records every text it returns; each command's task panel is opened on an example, and every window title,
label, button, group box title, combo box item, tab and table header text of the panel must be one of those
texts (or one of them with its ``{0}`` fields formatted). The commands' menu texts and tool tips too.

Allowed without translation (``allowed``), each for a reason:

* numbers, numbers with a unit, a unit alone: not words;
* names the user or the document gives (object names and labels, joint / node / axis / motor / module names, example
  names and descriptions, file paths) and what the document stores (its string properties, e.g. the scene's
  ``SolveWarnings``): data, shown as it is;
* messages of the core (a ``MetamaterialError``'s text, ``core.design.format_report``): the core is pure Python without
  Qt (project rule) and writes English; the GUI shows them as they come.
"""
import json
import os
import re
import string

import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

import FreeCADGui  # noqa: E402
from PySide import QtGui  # noqa: E402

from metamaterial_wb.gui import panels  # noqa: E402
from metamaterial_wb.objects import structure  # noqa: E402
from guihelpers import doc, process, run_panel, workbench  # noqa: E402,F401
from test_gui_panel_details import open_example  # noqa: E402

# units shown on their own (a column header, a spin box's neighbour): not words to translate
UNITS = {"mm", "°", "deg", "N", "N/mm", "N·mm", "Nmm", "MPa", "s", "Hz", "%", "rad", "mm²", "g"}
NUMBER = re.compile(r"^[-+−]?(\d+([.,]\d*)?|[.,]\d+)([eE][-+]?\d+)?\s*(" + "|".join(map(re.escape, UNITS)) + r")?$")
SCENE_EXAMPLE = "fish_axes"        # axes, motors, constraints and modules: every panel has something to show

# every command that opens a task panel, and whether it needs a structure; MM_Animate is left out here: its
# texts (animate.py, profiles.py, animate_clock.py) are being reworked in another change
PANEL_COMMANDS = [("MM_NewStructure", False), ("MM_OpenExample", False), ("MM_Sleeve", False),
                  ("MM_RotaryAxes", True), ("MM_FoldedShape", True), ("MM_Flexibility", True),
                  ("MM_PlaceMotor", True), ("MM_PlaceConstraint", True), ("MM_AddModule", True),
                  ("MM_Simulate", True), ("MM_Export", True), ("MM_FitTarget", True)]


@pytest.fixture
def produced(monkeypatch):
    """The set of texts ``translate`` returned while the test ran."""
    seen = set()
    original = FreeCAD.Qt.translate

    def marking(context, text, *args):
        out = original(context, text, *args)
        seen.add(out)
        return out
    monkeypatch.setattr(FreeCAD.Qt, "translate", marking)
    yield seen


@pytest.fixture
def core_texts(monkeypatch):
    """The messages the core made while the test ran (errors, the design report)."""
    from metamaterial_wb.core import design
    from metamaterial_wb.core.errors import MetamaterialError
    seen = set()

    def init(self, *args):
        ValueError.__init__(self, *args)
        seen.add(str(self))
    monkeypatch.setattr(MetamaterialError, "__init__", init)
    report = design.format_report

    def format_report(*args, **kw):
        lines = report(*args, **kw)
        seen.update(lines)
        return lines
    monkeypatch.setattr(design, "format_report", format_report)
    yield seen


def template_regexes(template):
    """Regexes matching ``template`` with its ``{0}`` fields formatted (fields lazy, then greedy), or None when it
    has no field."""
    try:
        parts = list(string.Formatter().parse(template))
    except ValueError:
        return None
    if not any(field is not None for _lit, field, _spec, _conv in parts):
        return None
    return [re.compile("".join(re.escape(lit) + (group if field is not None else "")
                               for lit, field, _spec, _conv in parts) + r"\Z", re.S) for group in ("(.*?)", "(.*)")]


def words(template):
    return sum(c.isalpha() for lit, *_ in string.Formatter().parse(template) for c in lit)


def from_translate(text, seen, ok=lambda t: False, depth=0):
    """``text`` is a text ``translate`` returned, or such a template formatted. A template with words of its own
    takes any values; one with (almost) none (``"{0}, {1}"``, ``"k1 = {0}"``) only values that pass themselves (a
    translated text, or ``ok``: a number, a name)."""
    if text in seen or (depth and ok(text)):
        return True
    if depth > 3:
        return False
    for t in seen:
        rxs = template_regexes(t)
        for rx in rxs or ():
            m = rx.match(text)
            if m and (words(t) >= 3 or all(from_translate(g, seen, ok, depth + 1) for g in m.groups())):
                return True
    return False


def names_of(document):
    """Names the user or the document gives, and what the document stores: never translated."""
    names = set()
    for o in document.Objects:
        names |= {o.Name, o.Label}
        for prop in o.PropertiesList:
            try:
                v = getattr(o, prop)
            except Exception:
                continue
            if isinstance(v, str):
                names |= {v} | set(v.splitlines())
            elif isinstance(v, (list, tuple)) and all(isinstance(x, str) for x in v):
                names |= set(v)
    for sc in structure.find_scene_objects(document):
        scene = structure.compose_scene(sc)
        names |= set(scene.topology.joint_names)
        names |= {f"N{i},{j}" for i, j in scene.topology.nodes}
        names |= {it.name for _kind, it in scene.fixed_items()}
        names |= {str(a.name) for a in scene.axes if getattr(a, "name", "")}
        names |= {str(m.get("name")) for m in scene.modules if isinstance(m, dict)}
    examples = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))), "examples")
    for f in os.listdir(examples):
        names.add(os.path.splitext(f)[0])
        if f.endswith(".json"):
            try:
                with open(os.path.join(examples, f), encoding="utf-8") as fh:
                    names.add(str(json.load(fh).get("description", "")))
            except (OSError, ValueError, AttributeError):
                pass
    return names


def allowed(text, names, core=()):
    t = text.strip()
    return (NUMBER.match(t) is not None or t in UNITS or t in names or t in core
            or all(line in core or line in names for line in t.splitlines())
            or os.path.isabs(t) or (os.sep in t and os.path.exists(t)))


def visible_texts(form):
    """``[(where, text)]``: the panel's window title and the texts of its labels, buttons, group boxes, combo box
    items, tabs and table headers (hidden ones too: they are shown in some state of the panel)."""
    out = [("window title", form.windowTitle())]
    for w in form.findChildren(QtGui.QWidget):
        kind = type(w).__name__
        if hasattr(w, "fullText"):                   # an ElidedLabel: its whole text (shown cut with "...")
            out.append((kind, w.fullText()))
        elif isinstance(w, QtGui.QLabel):
            out.append((kind, w.text()))
        elif isinstance(w, QtGui.QAbstractButton):
            out.append((kind, w.text()))
        if isinstance(w, QtGui.QGroupBox):
            out.append((kind, w.title()))
        if isinstance(w, QtGui.QComboBox):
            out += [(kind + " item", w.itemText(i)) for i in range(w.count())]
        if isinstance(w, QtGui.QTabWidget):
            out += [(kind + " tab", w.tabText(i)) for i in range(w.count())]
        if isinstance(w, QtGui.QTableWidget):
            for head, n in ((w.horizontalHeaderItem, w.columnCount()), (w.verticalHeaderItem, w.rowCount())):
                out += [(kind + " header", head(i).text()) for i in range(n) if head(i) is not None]
    return [(where, text) for where, text in out if text and text.strip()]


@pytest.mark.parametrize("cmd,needs_scene", PANEL_COMMANDS, ids=[c for c, _ in PANEL_COMMANDS])
def test_every_text_of_the_panel_went_through_translate(doc, produced, core_texts, cmd, needs_scene):
    if needs_scene:
        open_example(SCENE_EXAMPLE)
    p = run_panel(cmd)
    process()
    names = names_of(FreeCAD.ActiveDocument)

    def ok(text):
        return allowed(text, names, core_texts)
    bad = sorted({f"{where}: {text!r}" for where, text in visible_texts(p.form)
                  if not ok(text) and not from_translate(text, produced, ok)})
    p.reject()
    assert not bad, f"{cmd}: texts not produced by translate():\n" + "\n".join(bad)


def test_every_command_menu_text_and_tool_tip_went_through_translate(produced):
    from metamaterial_wb.gui import commands
    commands.register()
    bad = []
    for name, c in commands.INSTANCES.items():
        res = c.GetResources()
        for key in ("MenuText", "ToolTip"):
            if not from_translate(res[key], produced):
                bad.append(f"{name} {key}: {res[key]!r}")
    assert not bad, "command texts not produced by translate():\n" + "\n".join(bad)
