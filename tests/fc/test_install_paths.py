"""The README and docs/gui.md name the Mod folder that this FreeCAD really reads add-ons from (issue 13).

FreeCAD 1.1 moved user add-ons into a versioned folder (~/.local/share/FreeCAD/v1-1/Mod); 0.20 and 1.0
use ~/.local/share/FreeCAD/Mod. Each lane checks its own FreeCAD.
"""
import os

import pytest

FreeCAD = pytest.importorskip("FreeCAD")

from metamaterial_wb import REPO_DIR  # noqa: E402


def _user_mod_dir():
    home = os.path.expanduser("~")
    d = os.path.join(FreeCAD.getUserAppDataDir(), "Mod")
    return "~" + os.path.normpath(d)[len(home):] if d.startswith(home) else os.path.normpath(d)


@pytest.mark.parametrize("doc", ["README.md", os.path.join("docs", "gui.md")])
def test_docs_name_this_freecads_mod_folder(doc):
    text = open(os.path.join(REPO_DIR, doc), encoding="utf-8").read()
    mod = _user_mod_dir()
    assert f"{mod}/MetamaterialWorkbench" in text, (doc, mod, ".".join(FreeCAD.Version()[:3]))
