"""Shared constants and helpers of the fabrication tests (a uniquely named module: `conftest` is
ambiguous when several test folders each have one)."""
import os

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


def make_scene(layout, **kw):
    from metamaterial_wb.core.scene import Scene
    d = {"format": "metamaterial-scene", "version": 1, "name": kw.pop("name", "t"), "layout": layout}
    d.update(kw)
    return Scene.from_dict(d)


def run_build(tmp_path, scene, *args):
    """``build`` run as a user runs it on the scene dict ``scene`` (written to tmp_path/s.json) into
    tmp_path/out: ``(CompletedProcess, out folder)``."""
    import json
    import subprocess
    import sys
    path = tmp_path / "s.json"
    path.write_text(json.dumps(scene))
    out = tmp_path / "out"
    r = subprocess.run([sys.executable, "-m", "metamaterial_wb", "build", str(path), "--out", str(out), *args],
                       capture_output=True, text=True, cwd=REPO, timeout=600)
    return r, out
