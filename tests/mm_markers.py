"""The markers ``pure`` / ``freecad`` / ``gui`` of a test file, from what it imports (tests/conftest.py applies
them; docs/testing.md). Static: the files are parsed, not imported, so this works without FreeCAD."""
import pathlib
import ast
import functools
import os
import re

TESTS = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(TESTS)

FREECAD_MODULES = {"FreeCAD", "FreeCADGui", "Part", "Mesh", "MeshPart", "Import", "ImportGui", "Fem", "Draft",
                   "pivy", "PySide", "PySide2", "PySide6"}
# FreeCAD run in a subprocess, or imported by code handed to one
# (written so that this file's own text does not match: the tests that import it stay pure)
_FREECAD_TEXT = re.compile(r"importorskip\(\s*[\"'](FreeCAD|Part|FreeCADGui)[\"']|\bimport[ ]FreeCAD\b|freecad[c]md"
                           r"|freecad[-]python3")
MARKERS = {"pure": "needs neither FreeCAD nor Qt (runs with `pytest -m pure` on a machine without FreeCAD)",
           "freecad": "needs FreeCAD's App part (Part B-rep, document objects) or runs FreeCAD in a subprocess",
           "gui": "runs inside the FreeCAD GUI (tests/gui, via tests/run_gui_pytest.py)"}


def _imported_names(path):
    """Every module name a file imports, at any depth (function-level imports count: they run)."""
    try:
        tree = ast.parse(pathlib.Path(path).read_text(encoding="utf-8"), path)
    except (OSError, SyntaxError):
        return set()
    out = set()
    mod = os.path.relpath(path, REPO)[:-3].replace(os.sep, ".")
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            out.update(a.name for a in node.names)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                parts = mod.split(".")[: -node.level]
                base = ".".join(parts + ([node.module] if node.module else []))
            else:
                base = node.module or ""
            out.add(base)
            out.update(f"{base}.{a.name}" for a in node.names)
    return out


@functools.lru_cache(maxsize=None)
def _test_helpers():
    """{module name: file} of the helper modules beside the tests (fabhelpers, guihelpers, ...)."""
    out = {}
    for d, dirs, files in os.walk(TESTS):
        dirs[:] = [x for x in dirs if x not in ("__pycache__", "data", "vectors")]
        out.update({f[:-3]: os.path.join(d, f) for f in files if f.endswith(".py")})
    return out


def _source_of(name):
    """The file of a metamaterial_wb module or of a test helper module (None for anything else)."""
    if name.startswith("metamaterial_wb"):
        p = os.path.join(REPO, *name.split("."))
        for cand in (p + ".py", os.path.join(p, "__init__.py")):
            if os.path.isfile(cand):
                return cand
        return None
    return _test_helpers().get(name) if "." not in name else None


@functools.lru_cache(maxsize=None)
def _direct(path):
    """(imports FreeCAD / Qt itself or runs it in a subprocess, the files it imports)."""
    names = _imported_names(path)
    hit = bool({n.split(".")[0] for n in names} & FREECAD_MODULES)
    if not hit and not path.startswith(os.path.join(REPO, "metamaterial_wb") + os.sep):   # tests, scripts
        hit = bool(_FREECAD_TEXT.search(pathlib.Path(path).read_text(encoding="utf-8")))
    return hit, tuple(sorted({_source_of(n) for n in names} - {None, path}))


@functools.lru_cache(maxsize=None)
def _needs_freecad(path):
    seen, todo = {path}, [path]
    while todo:
        hit, deps = _direct(todo.pop())
        if hit:
            return True
        for d in deps:
            if d not in seen:
                seen.add(d)
                todo.append(d)
    return False


def file_marker(path):
    """``gui`` / ``freecad`` / ``pure`` for a test file (the test may still need ``freecad`` by a fixture)."""
    path = os.path.abspath(str(path))
    if path.startswith(os.path.join(TESTS, "gui") + os.sep):
        return "gui"
    return "freecad" if _needs_freecad(path) else "pure"
