"""Every visible text of every task panel goes through ``translate("Metamaterial", ...)`` -- checked at run time.

``tests/unit/test_gui_translatable.py`` only sees literals passed straight to a widget; texts set through a
class attribute (``TITLE``), a helper (``button_row``), a list (a combo's items) or an f-string slipped past it.
Here FreeCAD's ``Qt.translate`` (what ``metamaterial_wb.gui.i18n.translate`` calls) is replaced by one that
records every text it returns; each command's task panel is opened on an example, and every window title,
label, button, group box title, combo box item, tab and table header text of the panel must be one of those
texts (or one of them with its ``{0}`` fields formatted). The commands' menu texts and tool tips too. Texts that
appear only after an action are walked after it: Animate with a keyframes row (its key buttons), a moment shown,
playback, a stream error and a short simulated trajectory; Sleeve after its prediction; Fit to target after a
refused run and a fit of a bundled example; a background job's refusal and default status line.

Allowed without translation (``allowed``), each for a reason:

* numbers, numbers with a unit, a unit alone, a list of numbers: not words;
* names the user or the document gives (object names and labels, joint / node / axis / motor / module names, example
  names and descriptions, file paths) and what the document stores (its string properties, e.g. the scene's
  ``SolveWarnings``): data, shown as it is;
* messages of the core (a ``MetamaterialError``'s text raised outside ``metamaterial_wb/gui``,
  ``core.design.format_report``, ``core.inverse.pipeline.summary_lines`` and the progress lines of
  ``core.inverse.pipeline.solve``): the core is pure Python without Qt (project rule) and writes English; the GUI
  shows them as they come. An error the GUI itself raises is a GUI text.

A text of several lines, or a list joined by "; " or by two spaces (the values of the motors), passes when each of
its lines / entries does.
"""
import json
import os
import re
import string
import sys

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

EXAMPLES = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))), "examples")
GUI_DIR = os.sep + os.path.join("metamaterial_wb", "gui") + os.sep

# every command that opens a task panel, and whether it needs a structure
PANEL_COMMANDS = [("MM_NewStructure", False), ("MM_OpenExample", False), ("MM_Sleeve", False),
                  ("MM_RotaryAxes", True), ("MM_FoldedShape", True), ("MM_Flexibility", True),
                  ("MM_PlaceMotor", True), ("MM_PlaceConstraint", True), ("MM_AddModule", True),
                  ("MM_Simulate", True), ("MM_Export", True), ("MM_FitTarget", True), ("MM_Animate", True)]


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


def raised_in_gui():
    """Whether the error being made (``MetamaterialError.__init__`` is running) is raised by a module under
    ``metamaterial_wb/gui``: the first frame outside the errors' own ``__init__`` methods."""
    f = sys._getframe(2)
    while f is not None and f.f_code.co_name == "__init__" and f.f_code.co_filename.endswith("errors.py"):
        f = f.f_back
    return f is not None and GUI_DIR in f.f_code.co_filename


@pytest.fixture
def core_texts(monkeypatch):
    """The messages the core made while the test ran (errors raised outside the GUI, the design report, the
    inverse design's summary lines)."""
    from metamaterial_wb.core import design
    from metamaterial_wb.core.errors import MetamaterialError
    from metamaterial_wb.core.inverse import pipeline
    seen = set()

    def init(self, *args):
        ValueError.__init__(self, *args)
        if not raised_in_gui():
            seen.add(str(self))
    monkeypatch.setattr(MetamaterialError, "__init__", init)

    def recording(fn):
        def wrapped(*args, **kw):
            lines = fn(*args, **kw)
            seen.update(lines)
            return lines
        return wrapped
    monkeypatch.setattr(design, "format_report", recording(design.format_report))
    monkeypatch.setattr(pipeline, "summary_lines", recording(pipeline.summary_lines))
    solve = pipeline.solve

    def solving(*args, progress=None, **kw):         # its progress lines: the job's status line shows them
        def said(msg):
            seen.add(msg)
            progress(msg)
        return solve(*args, progress=said if progress is not None else None, **kw)
    monkeypatch.setattr(pipeline, "solve", solving)
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
            or all(NUMBER.match(x.strip()) is not None for x in t.split(", "))
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


def passes(text, seen, ok):
    """``text`` is allowed (``ok``) or came from ``translate``; a text of several lines, or a list joined by "; " or
    by two spaces, when each of its parts does."""
    if ok(text) or from_translate(text, seen, ok):
        return True
    for sep in ("\n", "; ", "  "):
        parts = [t for t in text.split(sep) if t.strip()]
        if len(parts) > 1:
            return all(passes(t, seen, ok) for t in parts)
    return False


def untranslated(p, produced, core_texts):
    """``["where: 'text'"]``: the texts of panel ``p`` now that neither ``translate`` produced nor are allowed."""
    names = names_of(FreeCAD.ActiveDocument)

    def ok(text):
        return allowed(text, names, core_texts)
    return sorted({f"{where}: {text!r}" for where, text in visible_texts(p.form) if not passes(text, produced, ok)})


@pytest.mark.parametrize("cmd,needs_scene", PANEL_COMMANDS, ids=[c for c, _ in PANEL_COMMANDS])
def test_every_text_of_the_panel_went_through_translate(doc, produced, core_texts, cmd, needs_scene):
    if needs_scene:
        open_example(SCENE_EXAMPLE)
    p = run_panel(cmd)
    process()
    bad = untranslated(p, produced, core_texts)
    p.reject()
    assert not bad, f"{cmd}: texts not produced by translate():\n" + "\n".join(bad)


def walked(p, produced, core_texts, step, seen):
    """Collect the untranslated texts of ``p`` after the action ``step`` (named so in ``seen``)."""
    seen += [f"after {step}: {b}" for b in untranslated(p, produced, core_texts)]


def test_animate_texts_after_its_actions(doc, produced, core_texts):
    """Texts that appear only once the user acts: a keyframes row's table (title, Add key / Remove last), a key
    added, a moment shown (time, the motors' values line, the frame's stats), playback (the achieved rate), a
    stream error reported by the streaming thread, a simulation refused while one runs, and a short simulated
    trajectory (its status line, the trajectory line)."""
    open_example(SCENE_EXAMPLE)
    p = run_panel("MM_Animate")
    process()
    bad = []
    motor = list(p.shapes)[0]
    p.set_shape(motor, "keyframes")
    process()
    assert p.keyframes.isVisibleTo(p.form) and p.key_motor == motor
    p.keyframes.add_btn.click()
    process()
    assert len(p.keyframes.points()) == 3
    walked(p, produced, core_texts, "a keyframes row and a key added", bad)
    p.show_time(0.5)
    p.play()
    process(400)
    p.pause()
    walked(p, produced, core_texts, "a moment and playback", bad)
    p.stream._failed("the serial link went quiet")      # what the streaming thread reports on a failure
    p.show_time(0.25)
    assert "the serial link went quiet" in p.error.text(), p.error.text()
    walked(p, produced, core_texts, "a stream error", bad)
    p.clear_error()
    assert p.simulate_trajectory(0.1)
    assert p.simulate_trajectory(0.1) is False and p.error.text()       # one at a time
    walked(p, produced, core_texts, "a second simulation refused", bad)
    assert p.wait_simulation(300)
    assert p.trajectory is not None, p.error.text()
    walked(p, produced, core_texts, "a simulated trajectory", bad)
    p.reject()
    assert not bad, "Animate: texts not produced by translate():\n" + "\n".join(bad)


def test_sleeve_texts_after_its_prediction(doc, produced, core_texts):
    """The prediction's summary lines and status line; a spec file that cannot be read, a ring pattern that is no
    list of numbers."""
    p = run_panel("MM_Sleeve")
    process()
    bad = []
    assert p.predict()
    assert p.wait_prediction(600)
    assert p.summary is not None and p.result.text(), p.error.text()
    walked(p, produced, core_texts, "the prediction", bad)
    assert not p.load_spec(os.path.join(EXAMPLES, "no_such_sleeve.json"))
    walked(p, produced, core_texts, "a spec file that cannot be read", bad)
    p.ring.setText("0, x")
    process()
    walked(p, produced, core_texts, "a ring pattern with a letter", bad)
    p.reject()
    assert not bad, "Sleeve: texts not produced by translate():\n" + "\n".join(bad)


def test_fit_to_target_texts_after_a_fit(doc, produced, core_texts):
    """A run without a target (refused), then the fish's values fitted to its bundled tail target: the result
    lines (one per motor, the summary, the time), the job's status line."""
    open_example(SCENE_EXAMPLE)
    p = run_panel("MM_FitTarget")
    process()
    bad = []
    assert p.run() is False and p.error.text()
    walked(p, produced, core_texts, "a run without a target", bad)
    p.path.setText(os.path.join(EXAMPLES, "fish_tail_target.json"))
    p.values_only.setChecked(True)
    p.geometry_checks.setChecked(False)
    p.workers.setValue(1)
    assert p.run() is not False, p.error.text()
    assert p.run() is False and p.error.text()           # one fit at a time
    walked(p, produced, core_texts, "a second run refused", bad)
    assert p.wait(600) and p.result is not None, p.error.text()
    assert p.status.text()
    walked(p, produced, core_texts, "a fit", bad)
    p.reject()
    assert not bad, "Fit to target: texts not produced by translate():\n" + "\n".join(bad)


def test_a_background_job_says_its_default_status_translated(produced, core_texts):
    """A job started without a status text of its own shows the default one."""
    from metamaterial_wb.gui.panels import jobs
    box = jobs.JobBox()
    job = jobs.ThreadJob(box, lambda r: None)
    assert job.start(lambda report: 1)
    assert job.wait(60) and job.outcome == "done"
    text = box.status.text()
    assert text and from_translate(text, produced), f"job status not produced by translate(): {text!r}"


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
