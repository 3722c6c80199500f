"""Test set-up: FreeCAD's library on sys.path (when installed), the checkout first.

Importing FreeCAD prepends every Mod folder to sys.path; a stale installed copy of this workbench
could then shadow the checkout. We import FreeCAD first (if present), then put the checkout at the
front and check that the package really comes from it.
"""
import os
import sys

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
FREECAD_LIB = "/usr/lib/freecad-python3/lib"
if os.path.isdir(FREECAD_LIB) and FREECAD_LIB not in sys.path:
    sys.path.append(FREECAD_LIB)
try:  # noqa: SIM105
    import FreeCAD  # noqa: F401
except Exception:
    pass
if sys.path[0] != REPO:
    sys.path.insert(0, REPO)
for mod in [m for m in sys.modules if m == "metamaterial_wb" or m.startswith("metamaterial_wb.")]:
    if not os.path.abspath(getattr(sys.modules[mod], "__file__", "") or "").startswith(REPO):
        del sys.modules[mod]
import metamaterial_wb  # noqa: E402

assert os.path.abspath(metamaterial_wb.__file__).startswith(REPO), metamaterial_wb.__file__
