"""Shared base of every task panel: layout, error labels, OK / Cancel, transactions, 3D-view picking.

Rules kept by every panel:

* nothing is recomputed while a slider moves or the animation plays: frames come from the stored
  factorisation (:class:`~metamaterial_wb.core.live.LiveSolver`) and are drawn by the Coin preview
  (``preview_frame``, :mod:`metamaterial_wb.gui.preview`), which writes no document property: a preview
  never marks a document modified;
* the preview goes when the panel closes (OK writes the chosen values into the properties and
  recomputes once, inside one transaction; Cancel writes nothing);
* every error is shown in the panel in words, next to the field it is about (``set_problem``), never as
  a modal dialog, never only in the Report view; a message disappears as soon as its cause is fixed;
* OK is refused (and the OK button disabled) while the panel knows of a problem, and an OK whose
  recompute leaves an object invalid is undone with the object's own error shown;
* a panel never writes values older than the document's: an Undo / Redo that changes its structure while it is
  open, or another command or a script changing what it writes back, makes it stale (``BasePanel.undo_moved``,
  ``changed_outside``) until the document is back where the panel opened it.

``ACTIVE`` is the panel being shown (the GUI tests drive it through its widgets); the document observer and the
Undo / Redo watch are in :mod:`~metamaterial_wb.gui.panels.docwatch`.
"""
import contextlib
import sys

import FreeCAD
import FreeCADGui
from PySide import QtCore, QtGui

import metamaterial_wb
from metamaterial_wb.core.errors import MetamaterialError
from metamaterial_wb.gui.i18n import QT_TRANSLATE_NOOP, translate
from metamaterial_wb.gui.panels import ranges
from metamaterial_wb.gui.panels.docwatch import UndoWatch, _watch_documents

ACTIVE = None
RED = "color: #c00000;"
GREEN = "color: #1a7f2a;"


def np_zeros(n):
    import numpy as np
    return np.zeros(n)


@contextlib.contextmanager
def transaction(doc, name):
    """One undo step: everything inside is committed together, or aborted on an error."""
    doc.openTransaction(name)
    try:
        yield
    except Exception:
        doc.abortTransaction()
        raise
    doc.commitTransaction()


def invalid_objects(doc):
    """``[(label, message)]`` of the document's objects whose last recompute failed."""
    out = []
    for o in doc.Objects:
        state = getattr(o, "State", [])
        if "Invalid" in state or "Error" in state:
            msg = ""
            try:
                msg = o.getStatusString()
            except Exception:  # pragma: no cover - older FreeCAD
                pass
            out.append((o.Label, msg or translate("Metamaterial", "recompute failed")))
    return out


def recompute_checked(doc):
    """Recompute and raise MetamaterialError (the failing object's own message) if any object is invalid
    (FreeCAD does not raise on a failed ``execute()``)."""
    doc.recompute()
    bad = invalid_objects(doc)
    if bad:
        raise MetamaterialError("; ".join(f"{label}: {msg}" for label, msg in bad))


def _retire(panel):
    """The panel's cleanup, never in the way of what comes next (its preview, picker, timers go)."""
    try:
        panel.cleanup()
    except Exception as exc:  # pragma: no cover - a cleanup that fails must not keep the next panel out
        FreeCAD.Console.PrintWarning(f"Metamaterial: cleanup of {type(panel).__name__} failed: {exc}\n")


def ours_shown():
    """True while one of our panels is the open task dialog. ``ACTIVE`` alone can be stale: a dialog closed
    by another tool (``Control.closeDialog()``) never ran our accept / reject, but FreeCAD then sets the
    panel's ``form`` to None and deletes the widget, which is what is checked here."""
    form = getattr(ACTIVE, "form", None)
    if form is None:
        return False
    try:
        form.objectName()           # raises once the C++ widget is deleted
    except RuntimeError:
        return False
    return True


def foreign_dialog_open():
    """True while a task dialog that is not one of our panels is open (a sketch in edit, Part primitives,
    ...): our commands are disabled then and ``show`` refuses, so that dialog is never thrown away."""
    return bool(FreeCADGui.Control.activeDialog()) and not ours_shown()


def show(panel):
    """Open ``panel`` in the task view, replacing one of our own panels; refused (message in the Report
    view, nothing opened, None returned) while another tool's task dialog is open."""
    global ACTIVE
    _watch_documents(sys.modules[__name__])
    if foreign_dialog_open():
        _retire(panel)
        FreeCAD.Console.PrintError(
            f"Metamaterial: {panel.form.windowTitle()} not opened: another tool's task dialog is open; "
            "finish it with OK or Cancel first\n")
        return None
    if FreeCADGui.Control.activeDialog():
        old, ACTIVE = ACTIVE, None
        if old is not None:
            _retire(old)            # first: closing the dialog deletes the old panel's widgets
        FreeCADGui.Control.closeDialog()
    ACTIVE = panel
    panel.remember_state()          # what its OK writes back, as stored now (a change by a script makes it stale)
    FreeCADGui.Control.showDialog(panel)
    reveal(panel.form)
    panel.dialog_shown()
    return panel


def reveal(form):
    """Make the task view that holds ``form`` visible: FreeCAD 1.1 may keep its "Tasks" dock in a hidden
    dock overlay (``OverlayRight``) or tab, so ``showDialog`` alone can leave the panel off screen. Every
    explicitly hidden ancestor of the form is shown and its dock raised. The widgets are found from the
    main window (see ``task_buttons`` for why not through ``parentWidget()``)."""
    if form.isVisible():
        return
    mw = FreeCADGui.getMainWindow()
    try:
        chain = [w for w in mw.findChildren(QtGui.QWidget) if w.isAncestorOf(form)]
        for w in sorted(chain, key=lambda w: sum(1 for v in chain if v.isAncestorOf(w))):   # outermost first
            if w.isHidden():
                w.show()
            if isinstance(w, QtGui.QDockWidget):
                w.raise_()
            if isinstance(w, QtGui.QTabWidget):
                for k in range(w.count()):
                    if w.widget(k) is not None and (w.widget(k) is form or w.widget(k).isAncestorOf(form)):
                        w.setCurrentIndex(k)
        QtGui.QApplication.processEvents()
    except Exception as exc:  # pragma: no cover - display only
        FreeCAD.Console.PrintWarning(f"Metamaterial: could not show the task panel ({exc})\n")
    if not form.isVisible():
        FreeCAD.Console.PrintWarning("Metamaterial: the task panel is hidden (Tasks dock / overlay)\n")


def _close():
    global ACTIVE
    ACTIVE = None
    FreeCADGui.Control.closeDialog()


def _deleted(exc):
    """FreeCAD's words for an object that is gone (deleted, or its document closed)."""
    text = str(exc)
    return isinstance(exc, ReferenceError) or "not part of a document" in text or "deleted object" in text


def _fit(doc):
    try:
        gd = FreeCADGui.getDocument(doc.Name)
        if gd is not None and gd.ActiveView is not None and hasattr(gd.ActiveView, "fitAll"):
            gd.ActiveView.fitAll()
    except Exception:  # pragma: no cover - display only
        pass


def _slider(lo=-100, hi=100, value=0):
    s = QtGui.QSlider(QtCore.Qt.Orientation.Horizontal)
    s.setRange(lo, hi)
    s.setValue(value)
    s.setTickPosition(QtGui.QSlider.TickPosition.TicksBelow)
    s.setTickInterval(max(1, (hi - lo) // 10))
    return s


def task_buttons(panel=None):
    """The OK / Cancel button box of the task dialog that shows ``panel`` (default: the active panel), or
    None when no panel is shown.

    The box is the one inside the task view (``Gui::TaskView::TaskView``) that holds the panel's form:
    boxes elsewhere in the main window (another dock, a dialog of another tool) are never returned; of
    several in that task view, the newest one not explicitly hidden wins (a closed dialog's box waits
    for its deletion hidden). Visibility on screen is not asked: on FreeCAD 1.1 the task view may sit in
    a collapsed overlay tab.

    Every widget is found from the main window, whose Python wrapper lives as long as FreeCAD: wrappers
    made for the form's ancestors (``parentWidget()``) or through their ``findChildren()`` are
    invalidated with their descendants' wrappers when they are collected (PySide), which would kill the
    panel's own widgets."""
    panel = ACTIVE if panel is None else panel
    form = getattr(panel, "form", None)
    if form is None:
        return None
    mw = FreeCADGui.getMainWindow()
    views = [w for w in mw.findChildren(QtGui.QWidget)
             if w.metaObject().className() == "Gui::TaskView::TaskView" and w.isAncestorOf(form)]
    if not views:
        return None
    sb = QtGui.QDialogButtonBox.StandardButton
    boxes = [box for box in mw.findChildren(QtGui.QDialogButtonBox)
             if views[-1].isAncestorOf(box) and not form.isAncestorOf(box)
             and any(box.button(b) is not None for b in (sb.Ok, sb.Close))]
    live = [box for box in boxes if not box.isHidden()]
    return (live or boxes or [None])[-1]


def button_row(*labels):
    """``(layout, [buttons])``: push buttons with these labels side by side in one row. The labels are translated
    here: callers mark them with ``QT_TRANSLATE_NOOP("Metamaterial", ...)`` so that ts_extract / lupdate list them."""
    row = QtGui.QHBoxLayout()
    buttons = [QtGui.QPushButton(translate("Metamaterial", label)) for label in labels]
    for b in buttons:
        row.addWidget(b)
    return row, buttons


def spin_refused(spin, key, text):
    """The key watcher of ``ranges`` refused a value typed into ``spin`` (``text``; "" once cleared, ``spin`` None
    when the box is gone): the panel showing the box makes it a problem of that field under ``key``."""
    p = ACTIVE
    if p is None:
        return
    if not text:
        if key in getattr(p, "problems", {}):
            p.refused_problem(spin, key, "")
        return
    try:
        form = p.form
        if form is None or spin is None or not form.isAncestorOf(spin):
            return
    except RuntimeError:           # the form is gone
        return
    p.refused_problem(spin, key, text)


ranges.REFUSAL_LISTENER = spin_refused


def _layout_path(layout, widget):
    """``[(layout, index), ...]`` from the innermost layout holding ``widget`` (or the widget that holds it: a
    table, a group box) out to ``layout``; [] when ``layout`` does not hold it. Walked down from the
    panel's own layouts (no wrapper is made for an ancestor, see ``task_buttons``)."""
    for i in range(layout.count()):
        item = layout.itemAt(i)
        w = item.widget()
        if w is not None and (w is widget or w.isAncestorOf(widget)):
            inner = w.layout() if w is not widget else None
            return (_layout_path(inner, widget) if inner is not None else []) + [(layout, i)]
        sub = item.layout()
        if sub is not None:
            path = _layout_path(sub, widget)
            if path:
                return path + [(layout, i)]
    return []


def place_under(layout, label, widget):
    """Put ``label`` on the line under ``widget``: a row of the nearest form layout, or the next place in the
    nearest vertical box (under a grid or a table that holds it). False when ``layout`` does not hold it."""
    vertical = (QtGui.QBoxLayout.Direction.TopToBottom, QtGui.QBoxLayout.Direction.BottomToTop)
    for lay, i in _layout_path(layout, widget):
        if isinstance(lay, QtGui.QFormLayout):
            row = lay.getItemPosition(i)[0]
            lay.insertRow(row + 1, label)
            return True
        if isinstance(lay, QtGui.QBoxLayout) and lay.direction() in vertical:
            lay.insertWidget(i + 1, label)
            return True
    return False


def red_label(text=""):
    lab = QtGui.QLabel(text)
    lab.setWordWrap(True)
    lab.setStyleSheet(RED)
    lab.setVisible(bool(text))
    return lab


class BasePanel(UndoWatch):
    TITLE = QT_TRANSLATE_NOOP("Metamaterial", "Metamaterial")   # subclasses: their own, marked the same way
    ICON = "Metamaterial_Workbench.svg"
    VIEW_ATTRS = ()        # attributes holding the panel's own Coin nodes or preview objects (``forget_view``)
    ITEM_ROWS = False      # a slider / row per motor or constraint: a deleted one is named, OK refused (check_items)

    def __init__(self):
        self.form = QtGui.QWidget()
        self.form.setWindowTitle(translate("Metamaterial", self.TITLE))
        self.form.setWindowIcon(QtGui.QIcon(metamaterial_wb.icon_path(self.ICON)))
        self.layout = QtGui.QVBoxLayout(self.form)
        self.error = QtGui.QLabel("")
        self.error.setWordWrap(True)
        self.error.setStyleSheet(RED)
        self.problem_labels = {}     # field key -> red QLabel beside / under the field
        self.problems = {}           # field key -> message (OK is refused while not empty)
        self.picker = None
        self._observer = None
        self.live_preview = None     # gui.preview.Preview while the panel previews frames
        self._preview_scene = None
        self.doc_name = FreeCAD.ActiveDocument.Name if FreeCAD.ActiveDocument is not None else None
        # where the document is on its undo stack since the panel opened (``undo_moved``)
        self._undo = {"pos": 0, "branched": False, "touched": False, "names": set(), "state": {}, "dirty": set()}
        self._own_change = False     # True while the panel's own OK writes (its recompute, transaction, abort)

    def finish_layout(self):
        self.layout.addWidget(self.error)
        self.layout.addStretch(1)

    # messages ---------------------------------------------------------------------------
    def show_error(self, text):
        """A panel-wide message (also written to the Report view)."""
        self.error.setText(text)
        if text:
            FreeCAD.Console.PrintWarning(f"Metamaterial: {text}\n")

    def clear_error(self):
        self.error.setText("")

    def problem_label(self, key):
        """The red label of field ``key`` (created on first use; the panel puts it next to the field)."""
        if key not in self.problem_labels:
            self.problem_labels[key] = red_label()
        return self.problem_labels[key]

    def set_problem(self, key, text):
        """Show (``text``) or clear (``""`` / None) the problem of one field; OK follows."""
        lab = self.problem_label(key)
        lab.setText(text or "")
        lab.setVisible(bool(text) and lab.parent() is not None)   # never a floating window
        if text:
            self.problems[key] = text
        else:
            self.problems.pop(key, None)
        self.update_ok()

    def refused_problem(self, spin, key, text):
        """A value typed into ``spin`` that the box refused (``ranges``; ``text`` "" once cleared): a problem of the
        field, said once, in its red line put under the box the first time (OK is disabled while it stands). The
        panel-wide line is left to the problems of no single field: a refusal neither repeats nor hides them."""
        lab = self.problem_label(key)
        if text and lab.parent() is None and not place_under(self.layout, lab, spin):
            k = self.layout.indexOf(self.error)
            self.layout.insertWidget(k if k >= 0 else self.layout.count(), lab)
        self.set_problem(key, text)

    def problem_text(self):
        return "; ".join(self.problems.values())

    def update_ok(self):
        box = task_buttons() if ACTIVE is self else None
        ok = box.button(QtGui.QDialogButtonBox.StandardButton.Ok) if box is not None else None
        if ok is not None:
            ok.setEnabled(not self.problems)

    def dialog_shown(self):
        """Called once the task dialog exists (the OK button can be enabled / disabled now)."""
        self.update_ok()

    def getStandardButtons(self):
        return QtGui.QDialogButtonBox.StandardButton.Ok | QtGui.QDialogButtonBox.StandardButton.Cancel

    # OK / Cancel ------------------------------------------------------------------------
    def apply(self):
        """Do the panel's work; raise MetamaterialError to stay open with the message shown."""

    def commit(self, doc, title, change):
        """``change()`` then a checked recompute, as one undo step; an invalid result is undone (and
        recomputed back) and its error raised."""
        self._own_change = True
        try:
            if any("Touched" in getattr(o, "State", ()) for o in doc.Objects):
                doc.recompute()     # what an Undo left to recompute, outside the step: a change of nothing records none
            with transaction(doc, title):
                change()
                recompute_checked(doc)
        except MetamaterialError:
            doc.recompute()
            raise
        finally:
            self._own_change = False

    # live preview ---------------------------------------------------------------------
    def preview_frame(self, scene_obj, solver, frame):
        """Draw a solved frame in the 3D view without writing the document (the Coin preview; its boxes
        follow the per-joint hinge sizes of ``solver.scene``)."""
        if self.live_preview is None:
            from metamaterial_wb.gui.preview import Preview
            self.live_preview = Preview(scene_obj, solver.scene)
            self._preview_scene = solver.scene
        elif self._preview_scene is not solver.scene:
            self.live_preview.set_scene(solver.scene)
            self._preview_scene = solver.scene
        self.live_preview.show(solver, frame)

    def remove_preview(self):
        if self.live_preview is not None:
            self.live_preview.remove()
            self.live_preview = None
            self._preview_scene = None

    def target_gone(self):
        """True when the object the panel edits (``self.obj``) is no longer in its document (deleted, its creation
        undone, or the document closed)."""
        obj = getattr(self, "obj", None)
        if obj is None:
            return False
        try:
            name, doc = obj.Name, obj.Document      # FreeCAD 1.1: a removed object has no name
            return not name or doc is None or doc.getObject(name) is None
        except (ReferenceError, RuntimeError):
            return True

    def check_target(self):
        """True (after ``target_lost``) when the structure the panel edits is gone; the panels call it before
        every frame they draw, so nothing is drawn for a deleted structure."""
        if self.target_gone():
            self.target_lost()
            return True
        return False

    def check_items(self):
        """An actuator or constraint the panel shows (``self.scene``, composed when it opened) was deleted from
        the structure (Delete, Ctrl+Z of Place motor): OK is refused and the panel names it (its slider or row would
        keep acting on a motor that is gone); the red line stays at the top of the panel (``set_top_problem``)."""
        scene = getattr(self, "scene", None)
        if not self.ITEM_ROWS or scene is None or not hasattr(scene, "fixed_items") or self.target_gone():
            return
        try:
            present = {it.ItemName for it in self.obj.Items if getattr(it, "ItemName", None)}
        except (ReferenceError, RuntimeError, AttributeError):
            return
        gone = [it.name for _kind, it in scene.fixed_items() if it.name not in present]
        text = translate("Metamaterial", "{0} this panel shows was deleted from the structure (press Cancel and "
                                         "open the panel again)").format(", ".join(repr(n) for n in gone)) if gone \
            else ""
        self.set_top_problem("items", text)           # "" once the motor is back (Ctrl+Z of the Delete, Ctrl+Y)

    def target_lost(self):
        """The structure is gone: the preview goes, OK is refused and the panel says so (once). Panels with a
        timer or a stream stop them too."""
        if getattr(self, "_lost", False):
            return
        self._lost = True
        try:
            self.remove_preview()
        except Exception:  # pragma: no cover - its view objects went with the structure
            self.live_preview = self._preview_scene = None
        text = translate("Metamaterial", "the structure this panel edits was deleted (press Cancel)")
        self.set_problem("structure", text)    # its own key: a panel's "target" problem (Add module) clears it not
        self.show_error(text)

    def lost_on(self, exc):
        """True (after ``target_lost``) when ``exc`` is FreeCAD's error for a deleted object."""
        if isinstance(exc, (ReferenceError, RuntimeError)) and (_deleted(exc) or self.target_gone()):
            self.target_lost()
            return True
        return False

    def forget_view(self):
        """The document (and its 3D view) is being closed: drop the preview, the picker's callbacks and the
        ``VIEW_ATTRS`` without removing them (removing nodes from a view being destroyed crashes FreeCAD)."""
        self.live_preview = self._preview_scene = None
        if self.picker is not None:
            self.picker.view = None
            self.picker = None
        for attr in self.VIEW_ATTRS:
            setattr(self, attr, None)

    def cleanup(self):
        self.remove_preview()
        if self.picker is not None:
            self.picker.remove()
            self.picker = None
        if self._observer is not None:
            try:
                FreeCADGui.Selection.removeObserver(self._observer)
            except Exception:  # pragma: no cover
                pass
            self._observer = None

    def accept(self):
        if self.problems:
            self.show_error(translate("Metamaterial", "not applied: {0}").format(self.problem_text()))
            return False
        REFUSED = ranges.REFUSED
        refused = [w.property(REFUSED) for w in self.form.findChildren(QtGui.QAbstractSpinBox) if w.property(REFUSED)]
        if refused:                                   # a value typed past a box's range: never clamped in silence
            self.show_error(translate("Metamaterial", "not applied: {0}").format(refused[0]))
            return False
        gone = translate("Metamaterial", "not applied: the structure this panel edits was deleted (press Cancel)")
        if self.target_gone():
            self.show_error(gone)
            return False
        try:
            self.apply()
        except (MetamaterialError, ValueError) as exc:
            self.show_error(str(exc))
            return False
        except (ReferenceError, RuntimeError) as exc:
            if not _deleted(exc):
                raise
            self.show_error(gone)
            return False
        self.cleanup()
        _close()
        return True

    def reject(self):
        self.cleanup()
        _close()
        return True

    # 3D-view picking --------------------------------------------------------------------
    @staticmethod
    def pick_hint(on_joint):
        """The line that says what a click in the 3D view picks (a hinge, else a node)."""
        return translate("Metamaterial", "Click a hinge in the 3D view") if on_joint else \
            translate("Metamaterial", "Click a node in the 3D view")

    def watch_selection(self, scene_obj, on_joint=None, on_node=None):
        """Pick joints / nodes in the 3D view: the one nearest to the click ray (any hinge size), with
        the one under the cursor highlighted before the click (``picking.Picker``)."""
        from metamaterial_wb.gui.panels.picking import Picker
        self.pick_label = QtGui.QLabel(self.pick_hint(bool(on_joint)))
        self.pick_label.setWordWrap(True)
        self.layout.insertWidget(max(0, self.layout.count() - 2), self.pick_label)
        try:
            self.picker = Picker(scene_obj, on_joint=on_joint, on_node=on_node, panel=self)
        except Exception as exc:  # pragma: no cover - no 3D view
            self.picker = None
            FreeCAD.Console.PrintWarning(f"Metamaterial: no 3D-view picking ({exc})\n")
        # a hinge / node selected otherwise (tree, Python, a click the picker left to FreeCAD) counts too
        panel = self

        class Obs:
            def addSelection(self, doc, obj, sub, pnt):
                try:
                    panel._selected(scene_obj, obj, sub, on_joint, on_node)
                except Exception as exc:  # pragma: no cover - interactive
                    panel.show_error(str(exc))

        self._observer = Obs()
        FreeCADGui.Selection.addObserver(self._observer, 0)   # 0: unresolved, keeps "Hinges" + "12.Face3"

    def _selected(self, scene_obj, obj_name, sub, on_joint, on_node):
        # a selection arrives as (container, "Hinges.12.Face3") or (Hinges, "12.Face3")
        parts = str(sub or "").split(".")
        for k in range(len(parts) - 1):
            if parts[k] in (getattr(scene_obj.HingeArray, "Name", None), getattr(scene_obj.NodeArray, "Name", None)):
                obj_name, sub = parts[k], ".".join(parts[k + 1:])
                break
        idx = pick_index(sub)
        if idx is None:
            return
        from metamaterial_wb.objects import structure
        scene = structure.compose_scene(scene_obj)
        if scene_obj.HingeArray is not None and obj_name == scene_obj.HingeArray.Name and on_joint:
            name = scene.topology.joint_names[idx]
            self.picked("joint", name)
            on_joint(name)
        elif scene_obj.NodeArray is not None and obj_name == scene_obj.NodeArray.Name and on_node:
            i, j = scene.topology.nodes[idx]
            self.picked("node", f"N{i},{j}")
            on_node(f"N{i},{j}")

    def picked(self, kind, name, hover=False):
        """The picker's report: say in the panel what is under the cursor / what was picked."""
        if kind == "joint":
            text = translate("Metamaterial", "under the cursor: hinge {0} (click to pick it)") if hover else \
                translate("Metamaterial", "picked hinge {0}")
        else:
            text = translate("Metamaterial", "under the cursor: node {0} (click to pick it)") if hover else \
                translate("Metamaterial", "picked node {0}")
        self.pick_label.setText(text.format(name))


def pick_index(sub):
    """``"12.Face3"`` (a pick on a link array element) -> 12."""
    if not sub:
        return None
    head = str(sub).split(".", 1)[0]
    return int(head) if head.isdigit() else None
