"""Shared base of every task panel: layout, error label, OK / Cancel, transactions, 3D-view picking.

Rules kept by every panel:

* nothing is recomputed while a slider moves or the animation plays: placements are moved from the
  stored factorisation (:class:`~metamaterial_wb.objects.engine.LiveSolver`);
* the placements the panel moved are restored when it closes (OK writes the chosen values into the
  properties and recomputes once, inside one transaction);
* errors are shown in the panel in red, never as modal dialogs and never silently ignored.

``ACTIVE`` is the panel being shown (the GUI tests drive it through its widgets).
"""
import contextlib

import FreeCAD
import FreeCADGui
from PySide import QtCore, QtGui

import metamaterial_wb
from metamaterial_wb.core.errors import MetamaterialError
from metamaterial_wb.objects import structure

ACTIVE = None


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


def show(panel):
    global ACTIVE
    if FreeCADGui.Control.activeDialog():
        FreeCADGui.Control.closeDialog()
        if ACTIVE is not None:
            ACTIVE.cleanup()
    ACTIVE = panel
    FreeCADGui.Control.showDialog(panel)
    return panel


def _close():
    global ACTIVE
    ACTIVE = None
    FreeCADGui.Control.closeDialog()


def _fit(doc):
    try:
        gd = FreeCADGui.getDocument(doc.Name)
        if gd is not None and gd.ActiveView is not None and hasattr(gd.ActiveView, "fitAll"):
            gd.ActiveView.fitAll()
    except Exception:  # pragma: no cover - display only
        pass


def _slider(lo=-100, hi=100, value=0):
    s = QtGui.QSlider(QtCore.Qt.Horizontal)
    s.setRange(lo, hi)
    s.setValue(value)
    s.setTickPosition(QtGui.QSlider.TicksBelow)
    s.setTickInterval(max(1, (hi - lo) // 10))
    return s


class BasePanel:
    TITLE = "Metamaterial"
    ICON = "Metamaterial_Workbench.svg"

    def __init__(self):
        self.form = QtGui.QWidget()
        self.form.setWindowTitle(self.TITLE)
        self.form.setWindowIcon(QtGui.QIcon(metamaterial_wb.icon_path(self.ICON)))
        self.layout = QtGui.QVBoxLayout(self.form)
        self.error = QtGui.QLabel("")
        self.error.setWordWrap(True)
        self.error.setStyleSheet("color: #c00000;")
        self._observer = None

    def finish_layout(self):
        self.layout.addWidget(self.error)
        self.layout.addStretch(1)

    def show_error(self, text):
        self.error.setText(text)
        FreeCAD.Console.PrintWarning(f"Metamaterial: {text}\n")

    def getStandardButtons(self):
        return QtGui.QDialogButtonBox.Ok | QtGui.QDialogButtonBox.Cancel

    def apply(self):
        """Do the panel's work; raise MetamaterialError to stay open with the message shown."""

    def cleanup(self):
        if self._observer is not None:
            try:
                FreeCADGui.Selection.removeObserver(self._observer)
            except Exception:
                pass
            self._observer = None

    def accept(self):
        try:
            self.apply()
        except (MetamaterialError, ValueError) as exc:
            self.show_error(str(exc))
            return False
        self.cleanup()
        _close()
        return True

    def reject(self):
        self.cleanup()
        _close()
        return True

    # 3D-view picking --------------------------------------------------------------------
    def watch_selection(self, scene_obj, on_joint=None, on_node=None):
        panel = self

        class Obs:
            def addSelection(self, doc, obj, sub, pnt):
                try:
                    panel._picked(scene_obj, obj, sub, on_joint, on_node)
                except Exception as exc:  # pragma: no cover - interactive
                    panel.show_error(str(exc))

        self._observer = Obs()
        FreeCADGui.Selection.addObserver(self._observer, 0)   # 0: unresolved, keeps "Hinges" + "12.Face3"

    def _picked(self, scene_obj, obj_name, sub, on_joint, on_node):
        # a click in the 3D view arrives as (container, "Hinges.12.Face3") or (Hinges, "12.Face3")
        parts = str(sub or "").split(".")
        for k in range(len(parts) - 1):
            if parts[k] in (getattr(scene_obj.HingeArray, "Name", None), getattr(scene_obj.NodeArray, "Name", None)):
                obj_name, sub = parts[k], ".".join(parts[k + 1:])
                break
        idx = pick_index(sub)
        if idx is None:
            return
        if scene_obj.HingeArray is not None and obj_name == scene_obj.HingeArray.Name and on_joint:
            scene = structure.compose_scene(scene_obj)
            on_joint(scene.topology.joint_names[idx])
        elif scene_obj.NodeArray is not None and obj_name == scene_obj.NodeArray.Name and on_node:
            scene = structure.compose_scene(scene_obj)
            i, j = scene.topology.nodes[idx]
            on_node(f"N{i},{j}")


def pick_index(sub):
    """``"12.Face3"`` (a pick on a link array element) -> 12."""
    if not sub:
        return None
    head = str(sub).split(".", 1)[0]
    return int(head) if head.isdigit() else None


# ----------------------------------------------------------------------------------------------
# New structure and Open example
