"""Open example: the bundled scene files."""
import json
import os

import FreeCAD
from PySide import QtCore, QtGui

import metamaterial_wb
from metamaterial_wb.core.errors import MetamaterialError
from metamaterial_wb.core.scene import Scene
from metamaterial_wb.objects import structure
from metamaterial_wb.gui.i18n import QT_TRANSLATE_NOOP, translate
from metamaterial_wb.gui.panels.base import BasePanel, _fit


def example_files():
    """Bundled scene files (other JSON files in examples/, e.g. sleeve models, are left out)."""
    d = metamaterial_wb.EXAMPLES_DIR
    out = []
    for f in sorted(os.listdir(d)) if os.path.isdir(d) else []:
        if not f.endswith(".json"):
            continue
        try:
            with open(os.path.join(d, f), encoding="utf-8") as fh:
                if json.load(fh).get("format") == "metamaterial-scene":
                    out.append(f)
        except (OSError, ValueError, AttributeError):
            continue
    return out


class OpenExamplePanel(BasePanel):
    TITLE = QT_TRANSLATE_NOOP("Metamaterial", "Open example")
    ICON = "MM_OpenExample.svg"

    def __init__(self, doc=None):
        super().__init__()
        self.doc = doc
        self.list = QtGui.QListWidget()
        for f in example_files():
            self.list.addItem(f[:-5])
        self.desc = QtGui.QLabel("")
        self.desc.setWordWrap(True)
        self.layout.addWidget(self.list)
        self.layout.addWidget(self.desc)
        self.finish_layout()
        self.list.currentTextChanged.connect(self._describe)
        if self.list.count():
            items = self.list.findItems("fish", QtCore.Qt.MatchFlag.MatchExactly)
            self.list.setCurrentItem(items[0] if items else self.list.item(0))

    def _describe(self, name):
        try:
            with open(metamaterial_wb.example_path(name), encoding="utf-8") as f:
                self.desc.setText(json.load(f).get("description", ""))
        except Exception as exc:
            self.desc.setText(str(exc))

    def select(self, name):
        items = self.list.findItems(name, QtCore.Qt.MatchFlag.MatchExactly)
        if not items:
            raise MetamaterialError(translate("Metamaterial", "no example called {0}; have {1}").format(
                repr(name), example_files()))
        self.list.setCurrentItem(items[0])

    def apply(self):
        item = self.list.currentItem()
        if item is None:
            raise MetamaterialError(translate("Metamaterial", "choose an example"))
        scene = Scene.load(metamaterial_wb.example_path(item.text()))
        doc = self.doc or FreeCAD.ActiveDocument or FreeCAD.newDocument(scene.name or "Metamaterial")
        self.commit(doc, "Open example", lambda: setattr(self, "result", structure.make_structure(doc, scene)))
        _fit(doc)


# ----------------------------------------------------------------------------------------------
