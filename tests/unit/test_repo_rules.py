"""Project rules that would otherwise only live in the docs."""
import ast
import collections
import os

from metamaterial_wb import PACKAGE_DIR, REPO_DIR


def _py_files(root):
    for d, dirs, files in os.walk(root):
        dirs[:] = [x for x in dirs if x != "__pycache__"]
        for f in files:
            if f.endswith(".py"):
                yield os.path.join(d, f)


def _imports(path):
    tree = ast.parse(open(path, encoding="utf-8").read(), path)
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for a in node.names:
                yield a.name.split(".")[0]
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            yield node.module.split(".")[0]


def test_core_never_imports_freecad_or_qt():
    bad = []
    for p in _py_files(os.path.join(PACKAGE_DIR, "core")):
        for mod in _imports(p):
            if mod in {"FreeCAD", "FreeCADGui", "Part", "Mesh", "PySide", "PySide2", "pivy", "Import", "ImportGui"}:
                bad.append((os.path.relpath(p, REPO_DIR), mod))
    assert not bad, bad


def test_only_gui_imports_qt_and_freecadgui():
    bad = []
    for p in _py_files(PACKAGE_DIR):
        rel = os.path.relpath(p, PACKAGE_DIR)
        if rel.startswith("gui" + os.sep):
            continue
        for mod in _imports(p):
            if mod in {"FreeCADGui", "PySide", "PySide2"}:
                bad.append((rel, mod))
    assert not bad, bad


def test_test_modules_have_unique_names():
    """pytest imports test folders without __init__.py by basename: two equal names break collection."""
    names = collections.Counter(os.path.basename(p) for p in _py_files(os.path.join(REPO_DIR, "tests"))
                                if os.path.basename(p) != "conftest.py")
    assert [n for n, c in names.items() if c > 1] == []
    for p in _py_files(os.path.join(REPO_DIR, "tests")):
        assert "conftest" not in set(_imports(p)), f"{p}: import helpers from a uniquely named module"
