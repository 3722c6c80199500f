"""Project rules that would otherwise only live in the docs."""
import pathlib
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
    tree = ast.parse(pathlib.Path(path).read_text(encoding="utf-8"), path)
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
    lines = pathlib.Path(path).read_text(encoding="utf-8").splitlines(keepends=True)
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


# ------------------------------------------------------------------------------------------------------
# layers (issue 14): bottom to top; a module may import its own floor and the floors below, never above
LAYERS = {"core": 0, "parallel": 0, "geometry": 1, "export": 2, "hardware": 2, "fe": 2, "bench": 3,
          "objects": 3, "gui": 4, "cli": 4}
# allowed side-ways imports on one floor: (from package, to package)
SIDEWAYS_FORBIDDEN = {("export", "hardware"), ("hardware", "export"), ("gui", "cli"), ("cli", "gui")}
# Known violations still to be moved (issue 14). Each entry is (importing module, imported module); the
# test fails on any violation not listed here AND on any entry that no longer occurs (so the list shrinks).
KNOWN_VIOLATIONS = set()
KNOWN_CYCLES = set()


def _module_name(path):
    rel = os.path.relpath(path, REPO_DIR)[:-3].replace(os.sep, ".")
    return rel[: -len(".__init__")] if rel.endswith(".__init__") else rel


def _package_imports():
    """{module: set of imported metamaterial_wb modules}, function-level imports included."""
    edges = {}
    for p in _py_files(PACKAGE_DIR):
        m = _module_name(p)
        out = edges.setdefault(m, set())
        for node in ast.walk(ast.parse(pathlib.Path(p).read_text(encoding="utf-8"), p)):
            if isinstance(node, ast.ImportFrom):
                if node.level:
                    parts = m.split(".")
                    if not p.endswith("__init__.py"):
                        parts = parts[:-1]
                    parts = parts[: len(parts) - node.level + 1]
                    base = ".".join(parts + ([node.module] if node.module else []))
                else:
                    base = node.module or ""
                if not base.startswith("metamaterial_wb"):
                    continue
                for a in node.names:
                    full = f"{base}.{a.name}"
                    is_mod = os.path.exists(os.path.join(REPO_DIR, *full.split(".")) + ".py") or \
                        os.path.isdir(os.path.join(REPO_DIR, *full.split(".")))
                    out.add(full if is_mod else base)
            elif isinstance(node, ast.Import):
                out.update(a.name for a in node.names if a.name.startswith("metamaterial_wb"))
    return edges


def _floor(mod):
    parts = mod.split(".")
    return parts[1] if len(parts) > 1 else ""


def test_imports_run_down_the_layers():
    bad = set()
    for a, targets in _package_imports().items():
        fa = _floor(a)
        for b in targets:
            fb = _floor(b)
            if fa not in LAYERS or fb not in LAYERS:
                continue
            if LAYERS[fb] > LAYERS[fa] or (fa, fb) in SIDEWAYS_FORBIDDEN:
                bad.add((a, b))
    new = sorted(bad - KNOWN_VIOLATIONS)
    gone = sorted(KNOWN_VIOLATIONS - bad)
    assert not new, "imports that run up a layer (or between the two front doors):\n" + "\n".join(
        f"  {a} -> {b}" for a, b in new)
    assert not gone, "fixed, remove from KNOWN_VIOLATIONS:\n" + "\n".join(f"  {a} -> {b}" for a, b in gone)


def test_no_import_cycles_between_modules():
    edges = _package_imports()

    def reach(a):
        seen, todo = set(), [a]
        while todo:
            for b in edges.get(todo.pop(), ()):
                if b not in seen:
                    seen.add(b)
                    todo.append(b)
        return seen
    cycles = {tuple(sorted((a, b))) for a, ts in edges.items() for b in ts if a != b and a in reach(b)}
    # a cycle through a package __init__ re-export is still a cycle; report the module pairs
    new = sorted(cycles - KNOWN_CYCLES)
    gone = sorted(KNOWN_CYCLES - cycles)
    assert not new, "import cycles:\n" + "\n".join(f"  {a} <-> {b}" for a, b in new)
    assert not gone, "fixed, remove from KNOWN_CYCLES:\n" + "\n".join(f"  {a} <-> {b}" for a, b in gone)


def test_nothing_imports_the_cli():
    bad = [(a, b) for a, ts in _package_imports().items() for b in ts
           if _floor(b) == "cli" and _floor(a) != "cli"
           and (a, b) not in KNOWN_VIOLATIONS and a != "metamaterial_wb.__main__"]
    assert not bad, bad
