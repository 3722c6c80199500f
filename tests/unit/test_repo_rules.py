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


# names that FreeCAD 1.0 / 1.1's numpy 2.x, scipy 1.14+ and Part no longer have, or that crash there
_REMOVED = {
    "np.trapz": "numpy 2.4 removed it: a version-independent trapezoid helper",
    "np.product": "numpy 2 removed it: np.prod", "np.cumproduct": "numpy 2 removed it: np.cumprod",
    "np.alltrue": "numpy 2 removed it: np.all", "np.sometrue": "numpy 2 removed it: np.any",
    "np.in1d": "deprecated in numpy 2: np.isin", "np.row_stack": "deprecated in numpy 2: np.vstack",
    "np.float_": "numpy 2 removed it: np.float64", "np.complex_": "numpy 2 removed it: np.complex128",
    "np.NaN": "numpy 2 removed it: np.nan", "np.Inf": "numpy 2 removed it: np.inf",
    "np.infty": "numpy 2 removed it: np.inf", "np.asfarray": "numpy 2 removed it",
    "np.round_": "numpy 2 removed it: np.round", "np.msort": "numpy 2 removed it",
    "np.find_common_type": "numpy 2 removed it", "np.cast[": "numpy 2 removed it",
    "integrate.simps": "scipy 1.14 removed it: simpson", "integrate.cumtrapz": "scipy 1.14 removed it",
    "scipy.misc": "scipy 1.12 removed it",
    "Part.makeCompound": "kills FreeCAD 1.0 / 1.1 run from plain Python: use Part.Compound(shapes)",
    ".exec_(": "PySide6 (FreeCAD 1.1) deprecates it: .exec()",
}


def _code_only(path):
    """The file's text with comments and string literals blanked (docs may name the removed names)."""
    import io
    import tokenize
    lines = open(path, encoding="utf-8").read().splitlines(keepends=True)
    for tok in tokenize.generate_tokens(io.StringIO("".join(lines)).readline):
        if tok.type in (tokenize.COMMENT, tokenize.STRING):
            (r0, c0), (r1, c1) = tok.start, tok.end
            for r in range(r0, r1 + 1):
                a = c0 if r == r0 else 0
                b = c1 if r == r1 else len(lines[r - 1].rstrip("\n"))
                lines[r - 1] = lines[r - 1][:a] + " " * (b - a) + lines[r - 1][b:]
    return "".join(lines)


def test_no_names_removed_in_numpy2_scipy_or_freecad1():
    import re
    me = os.path.abspath(__file__)
    bad = []
    for top in ("metamaterial_wb", "tests", "benchmarks", "InitGui.py", "Init.py"):
        root = os.path.join(REPO_DIR, top)
        files = [root] if root.endswith(".py") else _py_files(root)
        for p in files:
            if os.path.abspath(p) == me:
                continue
            text = _code_only(p)
            for name, why in _REMOVED.items():
                pat = re.escape(name) + (r"\b" if name[-1].isalnum() or name[-1] == "_" else "")
                for m in re.finditer(pat, text):
                    line = text.count("\n", 0, m.start()) + 1
                    bad.append(f"{os.path.relpath(p, REPO_DIR)}:{line}: {name} ({why})")
    assert not bad, "\n".join(bad)
