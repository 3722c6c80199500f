"""Fixtures of the fabrication tests: FreeCAD (skip only where it is absent) and small built scenes."""
import os
import shutil
import sys

import pytest

FREECAD_LIB = "/usr/lib/freecad-python3/lib"
if os.path.isdir(FREECAD_LIB) and FREECAD_LIB not in sys.path:
    sys.path.append(FREECAD_LIB)

from fabhelpers import DUAL_INI, EXAMPLES, REPO, make_scene  # noqa: E402,F401


@pytest.fixture(scope="session")
def fc():
    FreeCAD = pytest.importorskip("FreeCAD")
    import Part  # noqa: F401
    return FreeCAD


@pytest.fixture(scope="session")
def prusa_slicer():
    exe = shutil.which("prusa-slicer")
    if exe is None:
        pytest.skip("prusa-slicer is not installed (Debian package prusa-slicer)")
    return exe


@pytest.fixture(scope="session")
def dual_ini(tmp_path_factory):
    path = tmp_path_factory.mktemp("slicer") / "dual.ini"
    path.write_text(DUAL_INI)
    return str(path)


@pytest.fixture(scope="session")
def chain_result(fc):
    from metamaterial_wb.geometry.build import build_scene
    return build_scene(make_scene({"chain": 3}, name="chain"), progress=False)


@pytest.fixture(scope="session")
def grid_result(fc):
    from metamaterial_wb.geometry.build import build_scene
    return build_scene(make_scene({"grid": [3, 3]}, name="grid",
                                  joint_config={"H1,1": {"tilt_deg": 20.0}, "V1,2": {"tilt_deg": -15.0}},
                                  joints=[{"joint": "H0,0", "length_mm": 1.2}]), progress=False)
