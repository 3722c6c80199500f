"""Issue 14, style: the public API of the core modules carries numpy-style docstrings. Every public function
and method (no leading underscore, defined in the module) has a "Parameters" section when it takes arguments
besides self / cls, and a "Returns" section when its own body has a ``return <expr>``. Properties are
attributes in numpy style (no sections) and are not checked. An AST check: nothing is imported."""
import pathlib
import ast
import os

import pytest

from metamaterial_wb import PACKAGE_DIR

CORE = os.path.join(PACKAGE_DIR, "core")
MODULES = ["scene/model.py", "scene/names.py", "solver.py", "models.py", "motion.py", "live.py", "playback.py",
           "results.py", "fileio.py", "inputfile.py", "joints.py"]
# the scene package's section parsers are internal (Scene.from_dict runs them); its public checker is listed
EXTRA = {"scene/sections.py": {"check_hinge_sizes"}}


def _returns_value(fn):
    """A ``return <expr>`` in ``fn``'s own body (nested functions, lambdas and classes do not count)."""
    stack = list(fn.body)
    while stack:
        n = stack.pop()
        if isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda, ast.ClassDef)):
            continue
        if isinstance(n, ast.Return) and n.value is not None:
            return True
        stack.extend(ast.iter_child_nodes(n))
    return False


def _arguments(fn, method):
    a = fn.args
    names = [x.arg for x in a.posonlyargs + a.args + a.kwonlyargs]
    names += [x.arg for x in (a.vararg, a.kwarg) if x is not None]
    if method and names and names[0] in ("self", "cls"):
        names = names[1:]
    return [n for n in names if not n.startswith("_")]     # private keyword flags are not API


def _is_property(fn):
    return any(isinstance(d, ast.Name) and d.id == "property" or
               isinstance(d, ast.Attribute) and d.attr in ("setter", "getter", "deleter") for d in fn.decorator_list)


def _public(tree, only=None):
    for n in tree.body:
        if isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef)) and not n.name.startswith("_"):
            if only is None or n.name in only:
                yield n.name, n, False
        elif isinstance(n, ast.ClassDef) and not n.name.startswith("_") and only is None:
            for f in n.body:
                if isinstance(f, (ast.FunctionDef, ast.AsyncFunctionDef)) and not f.name.startswith("_") \
                        and not _is_property(f):
                    yield f"{n.name}.{f.name}", f, True


def _sections(doc):
    """Numpy section headers: a title line followed by a line of dashes."""
    lines = [ln.strip() for ln in doc.splitlines()]
    return {lines[k] for k in range(len(lines) - 1) if lines[k] and set(lines[k + 1]) == {"-"}}


def missing_sections(path, only=None):
    tree = ast.parse(pathlib.Path(path).read_text(encoding="utf-8"), path)
    out = []
    for name, fn, method in _public(tree, only):
        secs = _sections(ast.get_docstring(fn) or "")
        if _arguments(fn, method) and "Parameters" not in secs:
            out.append(f"{name}: Parameters")
        if _returns_value(fn) and "Returns" not in secs:
            out.append(f"{name}: Returns")
    return out


@pytest.mark.parametrize("rel", MODULES + sorted(EXTRA))
def test_public_core_api_has_numpy_sections(rel):
    path = os.path.join(CORE, rel)
    found = [n for n, _f, _m in _public(ast.parse(pathlib.Path(path).read_text(encoding="utf-8")), EXTRA.get(rel))]
    assert found, f"{rel}: no public function found (renamed?)"
    missing = missing_sections(path, EXTRA.get(rel))
    assert not missing, f"core/{rel}: numpy docstring sections missing: " + "; ".join(missing)


def test_the_check_catches_a_missing_section(tmp_path):
    """The checker itself: a function without sections, a method returning a value, a documented one."""
    src = tmp_path / "m.py"
    src.write_text('def f(a):\n    """No sections."""\n    return a\n\n\n'
                   'def g():\n    """Nothing to say."""\n\n\n'
                   'def h(x):\n    """Fine.\n\n    Parameters\n    ----------\n    x : int\n\n'
                   '    Returns\n    -------\n    int\n    """\n    return x\n\n\n'
                   'class C:\n    def m(self):\n        """Only returns."""\n\n        def inner():\n'
                   '            return 1\n        return inner\n\n'
                   '    def n(self):\n        """No value."""\n        def inner():\n            return 1\n\n'
                   '    @property\n    def p(self):\n        return 1\n')
    assert missing_sections(str(src)) == ["f: Parameters", "f: Returns", "C.m: Returns"]
