"""Load a script that is not a module of a package (a benchmark under benchmarks/, a fixture maker) as a
module, so that a test can call its functions."""
import importlib.util
import os

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def load_script(relpath, name):
    """The module made by running ``REPO/relpath`` under the module name ``name``."""
    spec = importlib.util.spec_from_file_location(name, os.path.join(REPO, relpath))
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod
