"""Layers of the FE rung and the benchmark harness: ``fe`` imports only ``core`` (and itself), ``bench`` only
``core`` and ``fe``, and nothing in ``core`` imports either (the harness used to live in core)."""
import ast
import os

PKG = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))), "metamaterial_wb")


def _imports(folder):
    for root, _dirs, files in os.walk(os.path.join(PKG, folder)):
        for f in files:
            if f.endswith(".py"):
                path = os.path.join(root, f)
                tree = ast.parse(open(path, encoding="utf-8").read())
                for node in ast.walk(tree):
                    if isinstance(node, ast.ImportFrom) and node.module:
                        yield path, node.module
                    elif isinstance(node, ast.Import):
                        for a in node.names:
                            yield path, a.name


def _layer(module):
    parts = module.split(".")
    return parts[1] if parts[0] == "metamaterial_wb" and len(parts) > 1 else None


def test_fe_imports_only_core():
    bad = [(p, m) for p, m in _imports("fe") if _layer(m) not in (None, "core", "fe")]
    assert not bad, bad


def test_bench_imports_only_core_and_fe():
    bad = [(p, m) for p, m in _imports("bench") if _layer(m) not in (None, "core", "fe", "bench")]
    assert not bad, bad


def test_core_does_not_import_fe_or_bench():
    bad = [(p, m) for p, m in _imports("core") if _layer(m) in ("fe", "bench")]
    assert not bad, bad
