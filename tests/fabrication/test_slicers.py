"""Slicer hand-off: the sheet's 3MF files sit on the bed (no arrange needed), parts on their extruders,
sliced with the bundled PrusaSlicer profile (0.4 mm nozzles, 0.1 mm layers, slow TPU); Cura's parser
finds every part's extruder."""
import json
import os
import re
import subprocess
import sys
import zipfile

import numpy as np
import pytest

from fabhelpers import REPO
from test_export import filament_used, gcode_extrusions

PROFILE = os.path.join(REPO, "metamaterial_wb", "export", "profiles", "prusaslicer_dual_pla_tpu_0.1mm.ini")


def _ini(key):
    m = re.search(rf"^{key}\s*=\s*(.*)$", open(PROFILE).read(), re.M)
    return m.group(1).strip()


@pytest.fixture(scope="module")
def one(tmp_path_factory, fc):
    d = tmp_path_factory.mktemp("slicers")
    src = d / "one.json"
    src.write_text(json.dumps({"format": "metamaterial-scene", "version": 1, "name": "one", "layout": {"grid": [1, 1]}}))
    out = d / "out"
    r = subprocess.run([sys.executable, "-m", "metamaterial_wb", "build", str(src), "--out", str(out), "--3mf",
                        "--quiet"], cwd=REPO, capture_output=True, encoding="utf-8", errors="replace", timeout=300)
    assert r.returncode == 0, r.stderr
    return out, json.load(open(out / "manifest.json"))


def test_components_3mf_slices_on_the_bed_without_arrange(one, prusa_slicer, tmp_path):
    """PrusaSlicer --dont-arrange keeps the file's positions: every extrusion lies on the profile's bed,
    TPU (T1) only inside the hinges and PLA (T0) inside the nodes, at the positions the manifest gives
    (sheet coordinates + the 3MF offset)."""
    out, m = one
    g = tmp_path / "c.gcode"
    r = subprocess.run([prusa_slicer, "--loglevel", "1", "--export-gcode", "--load", PROFILE, "--dont-arrange",
                        "-o", str(g), str(out / "one_sheet_components.3mf")], capture_output=True,
                       encoding="utf-8", errors="replace", timeout=600)
    assert r.returncode == 0, r.stderr[-2000:]
    text = open(g).read()
    assert re.search(r"^; layer_height = 0.1$", text, re.M)
    used = filament_used(g)
    assert len(used) == 2 and min(used) > 0
    ex = gcode_extrusions(g)
    bed = np.array([[float(c) for c in p.split("x")] for p in _ini("bed_shape").split(",")])
    for tool, pts in ex.items():
        assert pts[:, 0].min() >= bed[:, 0].min() and pts[:, 0].max() <= bed[:, 0].max(), tool
        assert pts[:, 1].min() >= bed[:, 1].min() and pts[:, 1].max() <= bed[:, 1].max(), tool
    off = np.array(m["sheet_3mf_offset_mm"][:2])
    s = m["fabrication"]["cell_size_mm"] - 2.0           # plate side (default 2 mm hinges)
    nodes = [np.array(p["placement"]["base_mm"][:2]) + off for p in m["parts"] if p["role"] == "node"]
    # every PLA extrusion within a node plate (plus half an extrusion width); skirt excluded (z > first layer)
    p0 = ex[0][ex[0][:, 2] > 0.25][:, :2]
    inside = np.zeros(len(p0), bool)
    for c in nodes:
        inside |= (np.abs(p0 - c) <= 0.5 * s + 0.45).all(axis=1)
    assert inside.all(), f"{int((~inside).sum())} PLA extrusions outside every node"
    # TPU: within the gaps' hinge zones, i.e. outside every node's inner core and on the sheet's bounding box
    p1 = ex[1][ex[1][:, 2] > 0.25][:, :2]
    for c in nodes:
        assert not (np.abs(p1 - c) < 0.5 * s - 6.0).all(axis=1).any()
    assert ex[1][:, 2].max() <= 7.0 + 1e-6


def test_profile_has_slow_tpu_and_fine_layers():
    assert _ini("nozzle_diameter") == "0.4,0.4" and _ini("layer_height") == "0.1"
    pla, tpu = (float(v) for v in _ini("filament_max_volumetric_speed").split(","))
    assert tpu <= 2.0 < pla
    assert _ini("filament_type") == "PLA;FLEX"


def test_cura_parser_reads_the_built_components_file(one):
    """Cura's parser (libSavitar) on the file `build` wrote: every node on extruder 0, every hinge on 1."""
    Savitar = pytest.importorskip("Savitar")
    out, m = one
    scene = Savitar.ThreeMFParser().parse(zipfile.ZipFile(out / "one_sheet_components.3mf").read("3D/3dmodel.model"))
    nodes = scene.getSceneNodes()
    assert len(nodes) == 1
    got = {c.getName(): int(c.getSettings()["extruder_nr"].value) for c in nodes[0].getChildren()}
    want = {p["name"]: p["extruder"] - 1 for p in m["parts"]}
    assert got == want and set(got.values()) == {0, 1}


def test_module_3mfs_slice_on_the_bed_every_part_printed(tmp_path, prusa_slicer, fc):
    """The seed's worm set-up: the servo module's 3MF (housing, horn adapter and four blind rivets, each in
    its print pose) and the friction pad's (pad and four rivets), sliced by PrusaSlicer with the bundled
    profile and --dont-arrange: every extrusion lies on the bed, every part gets a first layer inside its
    own footprint (nothing floats, the rivets lie on their flats), and the print is as tall as the
    tallest part."""
    from test_done_when import _setup
    from test_manifest import read_3mf_meshes
    src = tmp_path / "worm.json"
    src.write_text(json.dumps(_setup("worm")))
    out = tmp_path / "out"
    r = subprocess.run([sys.executable, "-m", "metamaterial_wb", "build", str(src), "--out", str(out), "--3mf",
                        "--modules", "--quiet"], cwd=REPO, capture_output=True, encoding="utf-8", errors="replace",
                       timeout=600)
    assert r.returncode == 0, r.stderr
    bed = np.array([[float(c) for c in p.split("x")] for p in _ini("bed_shape").split(",")])
    layer = float(_ini("first_layer_height"))
    for module in ("servo_rear", "pad_front"):
        g = tmp_path / f"{module}.gcode"
        r = subprocess.run([prusa_slicer, "--loglevel", "1", "--export-gcode", "--load", PROFILE, "--dont-arrange",
                            "-o", str(g), str(out / f"worm_{module}.3mf")], capture_output=True,
                           encoding="utf-8", errors="replace", timeout=600)
        assert r.returncode == 0, r.stderr[-2000:]
        single = tmp_path / f"{module}_t0.gcode"          # one tool: PrusaSlicer writes no tool change
        single.write_text("T0\n" + g.read_text())
        pts = gcode_extrusions(single)[0]
        assert (pts[:, :2] >= bed.min(axis=0)).all() and (pts[:, :2] <= bed.max(axis=0)).all(), module
        first = pts[pts[:, 2] <= layer + 1e-6][:, :2]
        meshes = read_3mf_meshes(out / f"worm_{module}.3mf")
        assert any("rivet" in n for n in meshes)
        for name, (V, _) in meshes.items():
            lo, hi = V[:, :2].min(axis=0) - 0.5, V[:, :2].max(axis=0) + 0.5
            assert ((first >= lo) & (first <= hi)).all(axis=1).sum() > 10, (module, name)
        top = max(float(np.ptp(V[:, 2])) for V, _ in meshes.values())
        assert pts[:, 2].max() == pytest.approx(top, abs=0.15), module
