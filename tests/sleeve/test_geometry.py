"""Sleeve B-rep with FreeCAD: valid closed solids, positive volume, volume equal to the unrolled
outline's area times the wall thickness (independent shoelace computation), exports readable."""
import math
import os
import sys
import zipfile

import pytest

FREECAD_LIB = "/usr/lib/freecad-python3/lib"
if os.path.isdir(FREECAD_LIB) and FREECAD_LIB not in sys.path:
    sys.path.append(FREECAD_LIB)
pytest.importorskip("FreeCAD")

from metamaterial_wb.core.sleeve.cell import polygon_area  # noqa: E402
from metamaterial_wb.core.sleeve.spec import SleeveSpec  # noqa: E402
from metamaterial_wb.export.sleeve import export_sleeve  # noqa: E402
from metamaterial_wb.geometry.sleeve import build_all, build_sleeve, check_parts, sleeve_layout  # noqa: E402

SPEC = {"format": "metamaterial-sleeve", "version": 1, "L_mm": 18, "c_mm": 4, "delta_mm": 0.5, "T_mm": 1.8,
        "shear_modulus_MPa": 28, "cell_types": [{"t_mm": 1.0, "h_mm": 6.7}, {"t_mm": 1.1, "h_mm": 7.5}],
        "ring": [0, 0, 1, 1]}


def _expected_volume(spec, samples):
    lay = sleeve_layout(spec)
    voids = 0.0
    for row in spec.pattern:
        for k, typ in enumerate(row):
            g = spec.cells[typ]
            polys = g.holes(samples, top=lay["ring_height"] - g.c / 2, left=spec.cells[row[k - 1]])
            voids += sum(polygon_area(p) for p in polys.values())
    return (2 * math.pi * lay["mid_radius"] * lay["height"] - voids) * spec.T


@pytest.fixture(scope="module")
def parts():
    return build_all(SleeveSpec(SPEC))


def test_every_part_is_one_valid_closed_solid(parts):
    check_parts(parts)
    names = [p[0] for p in parts]
    assert names == ["sleeve", "ring_bottom", "ring_top", "cap_bottom", "cap_top"]
    for name, s, _, _ in parts:
        assert s.isValid() and len(s.Solids) == 1 and s.Volume > 0
        assert all(sh.isClosed() for sh in s.Shells)


def test_sleeve_volume_matches_unrolled_outline(parts):
    spec = SleeveSpec(SPEC)
    sleeve = parts[0][1]
    assert sleeve.Volume == pytest.approx(_expected_volume(spec, 16), rel=1e-6)
    lay = sleeve_layout(spec)
    bb = sleeve.BoundBox
    assert bb.ZLength == pytest.approx(lay["height"], abs=1e-6)
    assert bb.XLength == pytest.approx(2 * lay["outer_radius"], rel=1e-3)
    # the voids go through the wall: a radial line through cell 0's lower void (under the right
    # beam half, just over the bottom bar) misses
    import FreeCAD as App
    import Part
    g = spec.cells[0]
    z = g.c / 2 + 0.3 * g.delta
    a = 0.25 * (g.L + g.c) / lay["mid_radius"]
    line = Part.makeLine(App.Vector(0, 0, z), App.Vector(20 * math.cos(a), 20 * math.sin(a), z))
    assert line.common(sleeve).Length < 1e-6
    # ... while one through the bottom bar hits the wall over its full thickness
    line = Part.makeLine(App.Vector(0, 0, g.c / 4), App.Vector(20, 0, g.c / 4))
    assert line.common(sleeve).Length == pytest.approx(spec.T, abs=1e-6)


def test_two_rings_in_series_stay_one_solid():
    spec = SleeveSpec(dict(SPEC, ring=[0, 1], rings=2))
    s = build_sleeve(spec, samples=8)
    assert s.isValid() and len(s.Solids) == 1
    assert s.Volume == pytest.approx(_expected_volume(spec, 8), rel=1e-6)


def test_step_and_3mf_export(tmp_path):
    spec = SleeveSpec(dict(SPEC, ring=[0, 1]))
    files = export_sleeve(spec, str(tmp_path), step=True, threemf=True)
    assert sorted(files) == ["sleeve.3mf", "sleeve.step"]
    import Part
    sh = Part.read(str(tmp_path / "sleeve.step"))
    assert len(sh.Solids) == 5 and all(s.isValid() for s in sh.Solids)
    with zipfile.ZipFile(tmp_path / "sleeve.3mf") as z:
        model = z.read("3D/3dmodel.model").decode()
    assert "TPU" in model and "PLA" in model


def test_flat_unit_cell_solid_area():
    from metamaterial_wb.core.sleeve.cell import CellGeometry
    from metamaterial_wb.geometry.sleeve import build_unit_cell
    g = CellGeometry()
    s = build_unit_cell(g, samples=16)
    assert s.isValid() and len(s.Solids) == 1
    voids = sum(polygon_area(p) for p in g.holes(16).values())
    assert s.Volume == pytest.approx((g.width * g.height - voids) * g.T, rel=1e-9)


def test_document_objects():
    import FreeCAD as App
    from metamaterial_wb.geometry.sleeve import add_to_document
    doc = App.newDocument("sleeve_test")
    try:
        objs = add_to_document(SleeveSpec(dict(SPEC, ring=[0, 1])), doc)
        assert [o.Name for o in objs] == ["sleeve", "ring_bottom", "ring_top", "cap_bottom", "cap_top"]
        assert all(o.Shape.isValid() for o in objs)
    finally:
        App.closeDocument(doc.Name)


@pytest.mark.skipif(__import__("shutil").which("prusa-slicer") is None, reason="PrusaSlicer not installed")
def test_3mf_reads_in_prusaslicer_as_manifold(tmp_path):
    """An independent reader: PrusaSlicer's --info on the exported 3MF."""
    import subprocess
    spec = SleeveSpec(dict(SPEC, ring=[0, 1]))
    export_sleeve(spec, str(tmp_path), step=False, threemf=True)
    r = subprocess.run(["prusa-slicer", "--info", str(tmp_path / "sleeve.3mf")], capture_output=True,
                       text=True, timeout=300)
    out = r.stdout
    assert out.count("manifold = yes") == 5 and "manifold = no" not in out
    vols = [float(line.split("=")[1]) for line in out.splitlines() if line.strip().startswith("volume =")]
    brep = build_sleeve(spec).Volume
    assert vols[0] == pytest.approx(brep, rel=0.01)


def test_picture_shows_the_parts_in_their_colours(parts, tmp_path):
    """The sleeve's picture goes through the one mesh renderer (export/render.py): a PNG of the figure's
    size in which both part colours appear (TPU blue, PLA grey) and the background stays white."""
    import numpy as np
    from matplotlib import image

    from metamaterial_wb.core.materials import MATERIALS, hex_to_rgb
    from metamaterial_wb.export.sleeve import render_png
    path = render_png(parts, str(tmp_path / "sleeve.png"), size_in=(3.0, 3.0), dpi=60)
    img = image.imread(path)[..., :3]
    assert img.shape[:2] == (180, 180)
    assert np.allclose(img[0, 0], 1.0), "the corner is background"
    flat = img.reshape(-1, 3)
    flat = flat[flat.min(axis=1) < 0.97]          # the drawing, without the white background

    def share_like(colour):
        rgb = np.array(hex_to_rgb(colour))
        # any shade of the colour: a pixel proportional to it (flat shading scales the base colour)
        scale = (flat @ rgb) / (rgb @ rgb)
        return float(np.mean(np.linalg.norm(flat - scale[:, None] * rgb, axis=1) < 0.03))
    assert len(flat) > 0.1 * 180 * 180
    assert share_like(MATERIALS["TPU"]) > 0.1
    assert share_like(MATERIALS["PLA"]) > 0.1
