"""Test set-up: FreeCAD's library on sys.path (when installed), the checkout first, and the markers.

Importing FreeCAD prepends every Mod folder to sys.path; a stale installed copy of this workbench
could then shadow the checkout. We import FreeCAD first (if present), then put the checkout at the
front and check that the package really comes from it.

Markers (docs/testing.md), given to every test automatically:

* ``gui``: tests under ``tests/gui`` (they run inside a real FreeCAD, ``tests/run_gui_pytest.py``);
* ``freecad``: the test file (or a helper module of the tests it imports) imports FreeCAD, Part, Qt or a
  ``metamaterial_wb`` module that does, at any depth and inside functions too, or runs FreeCAD in a
  subprocess, or the test asks for the ``fc`` fixture;
* ``pure``: everything else; ``pytest -m pure`` runs without FreeCAD. ``MM_NO_FREECAD=1`` hides FreeCAD
  from the tests on a machine that has it (the check that the pure set really needs none); without
  FreeCAD, files marked ``freecad`` / ``gui`` are not even collected.
"""
import os
import sys

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
FREECAD_LIB = "/usr/lib/freecad-python3/lib"
NO_FREECAD = bool(os.environ.get("MM_NO_FREECAD"))
if not NO_FREECAD and os.path.isdir(FREECAD_LIB) and FREECAD_LIB not in sys.path:
    sys.path.append(FREECAD_LIB)
if NO_FREECAD:   # hide FreeCAD for real: geometry/fc.py would otherwise add its path and import it
    class _HideFreeCAD:
        NAMES = {"FreeCAD", "FreeCADGui", "Part", "Mesh", "MeshPart", "Import", "ImportGui", "Fem", "pivy"}

        def find_spec(self, name, path=None, target=None):
            if name.split(".")[0] in self.NAMES:
                raise ImportError(f"MM_NO_FREECAD=1: {name} is hidden from the tests")
            return None

    sys.meta_path.insert(0, _HideFreeCAD())
FREECAD_AVAILABLE = False
if not NO_FREECAD:
    try:
        import FreeCAD  # noqa: F401
        FREECAD_AVAILABLE = True
    except Exception:
        pass
if sys.path[0] != REPO:
    sys.path.insert(0, REPO)
for mod in [m for m in sys.modules if m == "metamaterial_wb" or m.startswith("metamaterial_wb.")]:
    if not os.path.abspath(getattr(sys.modules[mod], "__file__", "") or "").startswith(REPO):
        del sys.modules[mod]
import metamaterial_wb  # noqa: E402

assert os.path.abspath(metamaterial_wb.__file__).startswith(REPO), metamaterial_wb.__file__

if os.path.dirname(os.path.abspath(__file__)) not in sys.path:   # pytest's prepend mode puts it there; be sure
    sys.path.append(os.path.dirname(os.path.abspath(__file__)))
from mm_markers import MARKERS, file_marker  # noqa: E402  (tests/mm_markers.py: the classification)


def pytest_configure(config):
    for name, text in MARKERS.items():
        config.addinivalue_line("markers", f"{name}: {text}")


def pytest_ignore_collect(collection_path, config):
    p = str(collection_path)
    if FREECAD_AVAILABLE or not p.endswith(".py") or os.path.basename(p) == "conftest.py":
        return None
    return True if file_marker(p) != "pure" else None


def pytest_collection_modifyitems(config, items):
    import pytest
    for item in items:
        m = file_marker(item.fspath)
        if m == "pure" and "fc" in getattr(item, "fixturenames", ()):
            m = "freecad"
        item.add_marker(getattr(pytest.mark, m))
