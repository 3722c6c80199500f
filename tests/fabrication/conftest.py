"""Fixtures of the fabrication tests: FreeCAD (skip only where it is absent) and small built scenes."""
import os
import shutil
import sys

import pytest

FREECAD_LIB = "/usr/lib/freecad-python3/lib"
if os.path.isdir(FREECAD_LIB) and FREECAD_LIB not in sys.path:
    sys.path.append(FREECAD_LIB)

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
EXAMPLES = os.path.join(REPO, "examples")

DUAL_INI = """printer_technology = FFF
bed_shape = 0x0,250x0,250x210,0x210
max_print_height = 210
gcode_flavor = marlin2
nozzle_diameter = 0.4,0.4
filament_diameter = 1.75,1.75
filament_type = PLA;FLEX
temperature = 215,230
first_layer_temperature = 215,230
bed_temperature = 60,60
first_layer_bed_temperature = 60,60
extruder_offset = 0x0,0x0
layer_height = 0.2
first_layer_height = 0.2
skirts = 0
wipe_tower = 0
"""


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


def make_scene(layout, **kw):
    from metamaterial_wb.core.scene import Scene
    d = {"format": "metamaterial-scene", "version": 1, "name": kw.pop("name", "t"), "layout": layout}
    d.update(kw)
    return Scene.from_dict(d)


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
