"""The sleeve's 3MF prints on the bundled printer profile (audit): the parts used to sit at their assembled positions,
concentric about (0, 0), so a valid wide sleeve (20 cells, 142 mm across; the validator allows 240 mm) could not be
sliced ("Objects could not fit on the bed", exit 134) and with --dont-arrange the five parts overlapped, partly at
negative X / Y. Now each part stands on the bed side by side with the others, in the profile's bed; parts that do
not fit one bed go on further plates, one 3MF each."""
import itertools
import os
import re
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET
import zipfile

import numpy as np
import pytest

from metamaterial_wb.core.errors import MetamaterialError
from metamaterial_wb.core.sleeve import spec as sleeve_spec
from metamaterial_wb.core.sleeve.spec import SleeveSpec

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
PROFILE = os.path.join(REPO, "metamaterial_wb", "export", "profiles", "prusaslicer_dual_pla_tpu_0.1mm.ini")
NS = "{http://schemas.microsoft.com/3dmanufacturing/core/2015/02}"
TYPES = [{"t_mm": 1.0, "h_mm": 6.7}, {"t_mm": 1.1, "h_mm": 7.5}]
PARTS = ["sleeve", "ring_bottom", "ring_top", "cap_bottom", "cap_top"]


def _ini(key):
    return re.search(rf"^{key}\s*=\s*(.*)$", open(PROFILE, encoding="utf-8").read(), re.M).group(1).strip()


def _bed():
    pts = np.array([[float(c) for c in p.split("x")] for p in _ini("bed_shape").split(",")])
    return pts.min(axis=0), pts.max(axis=0), float(_ini("max_print_height"))


def _disc(d, h, n=96):
    """A closed prism of ``n`` sides, ``d`` across, ``h`` high, centred on the origin (a part's footprint)."""
    a = np.linspace(0, 2 * np.pi, n, endpoint=False)
    ring = np.column_stack([d / 2 * np.cos(a), d / 2 * np.sin(a)])
    V = np.vstack([np.column_stack([ring, np.zeros(n)]), np.column_stack([ring, np.full(n, h)])])
    T = [(0, k + 1, k) for k in range(1, n - 1)] + [(n, n + k, n + k + 1) for k in range(1, n - 1)]
    for k in range(n):
        j = (k + 1) % n
        T += [(k, j, n + j), (k, n + j, n + k)]
    return V, np.array(T)


def _check_plates(plates, names):
    """Every part once, each on the bed (z from 0, within the bed's outline and height), none overlapping another
    of its plate (footprints at least 6 mm apart: PrusaSlicer's own arrange distance, duplicate_distance)."""
    lo, hi, height = _bed()
    seen = []
    for plate in plates:
        boxes = []
        for name, V, _, _, _ in plate:
            seen.append(name)
            assert V[:, 2].min() == pytest.approx(0.0, abs=1e-9), name
            assert (V[:, :2] >= lo - 1e-9).all() and (V[:, :2] <= hi + 1e-9).all(), name
            assert V[:, 2].max() <= height, name
            boxes.append((name, V[:, :2].min(axis=0), V[:, :2].max(axis=0)))
        for (a, alo, ahi), (b, blo, bhi) in itertools.combinations(boxes, 2):
            apart = np.maximum(blo - ahi, alo - bhi)         # gap along x and y (negative: the spans overlap)
            assert apart.max() >= 6.0 - 1e-9, (a, b)
    assert sorted(seen) == sorted(names)


def test_the_validators_size_limits_are_the_bundled_profiles_bed():
    """scene-format.md: the limits exist so that the sleeve prints on the bundled printer - the same numbers."""
    lo, hi, height = _bed()
    assert sleeve_spec.BED_MM == pytest.approx(min(hi - lo))
    assert sleeve_spec.MAX_HEIGHT_MM == pytest.approx(height)
    from metamaterial_wb.export.sleeve import profile_bed
    assert profile_bed() == (tuple(lo), tuple(hi), height)


def test_wide_parts_go_side_by_side_and_onto_further_plates():
    """The 20-cell sleeve's footprints (142 mm sleeve, 138 mm rings, 134 mm caps) on the 330 x 240 mm bed: three
    plates, every part on the bed, none overlapping; the sleeve on the first."""
    from metamaterial_wb.export.sleeve import lay_out_plates
    sizes = {"sleeve": (141.9, 20.0), "ring_bottom": (138.3, 6.0), "ring_top": (138.3, 6.0),
             "cap_bottom": (134.3, 2.0), "cap_top": (134.3, 2.0)}
    meshes = []
    for name, (d, h) in sizes.items():
        V, T = _disc(d, h)
        meshes.append((name, V + np.array([0.0, 0.0, 30.0]), T, "TPU" if name == "sleeve" else "PLA", 1))
    plates = lay_out_plates(meshes)
    assert len(plates) == 3 and plates[0][0][0] == "sleeve"
    _check_plates(plates, PARTS)
    # a small sleeve's parts all fit one bed
    small = [(n, *_disc(30.0 if n == "sleeve" else 26.0, 5.0), "PLA", 1) for n in PARTS]
    one = lay_out_plates(small)
    assert len(one) == 1
    _check_plates(one, PARTS)


def test_from_170_mm_across_every_part_prints_alone():
    """32 cells of the seed's L + c (226 mm across): five plates, one part each."""
    from metamaterial_wb.export.sleeve import lay_out_plates
    meshes = [(n, *_disc(d, 5.0), "PLA", 1) for n, d in zip(PARTS, (225.9, 222.3, 222.3, 218.3, 218.3))]
    plates = lay_out_plates(meshes)
    assert [[m[0] for m in p] for p in plates] == [[n] for n in PARTS]
    _check_plates(plates, PARTS)


@pytest.mark.skipif(shutil.which("prusa-slicer") is None, reason="PrusaSlicer not installed")
def test_the_largest_sleeve_allowed_fills_the_beds_short_side_and_slices(tmp_path):
    """The validator's largest outer diameter (BED_MM, 240 mm) as a tube 20 mm high: laid out alone, centred, and
    sliced by PrusaSlicer with the bundled profile, arranging and not."""
    from metamaterial_wb.export.sleeve import lay_out_plates
    from metamaterial_wb.export.threemf import write_3mf
    n = 360
    a = np.linspace(0, 2 * np.pi, n, endpoint=False)
    ro, ri, h = sleeve_spec.BED_MM / 2, sleeve_spec.BED_MM / 2 - 1.8, 20.0
    V = np.array([(r * np.cos(t), r * np.sin(t), z) for r in (ro, ri) for z in (0.0, h) for t in a])
    T = []
    for k in range(n):
        j = (k + 1) % n
        T += [(k, j, n + j), (k, n + j, n + k), (2 * n + k, 3 * n + j, 2 * n + j), (2 * n + k, 3 * n + k, 3 * n + j),
              (n + k, n + j, 3 * n + j), (n + k, 3 * n + j, 3 * n + k), (k, 2 * n + j, j), (k, 2 * n + k, 2 * n + j)]
    plates = lay_out_plates([("sleeve", V, np.array(T), "TPU", 2)])
    assert len(plates) == 1
    _check_plates(plates, ["sleeve"])
    path = tmp_path / "sleeve.3mf"
    write_3mf(str(path), plates[0], layout="objects")
    for extra in ([], ["--dont-arrange"]):
        r = subprocess.run(["prusa-slicer", "--loglevel", "1", "--export-gcode", "--load", PROFILE, *extra, "-o",
                            str(tmp_path / "g.gcode"), str(path)], capture_output=True, encoding="utf-8",
                           errors="replace", timeout=600)
        assert r.returncode == 0, (extra, r.stderr[-1500:])


def test_a_part_larger_than_the_bed_is_refused_naming_its_size_and_the_bed():
    from metamaterial_wb.export.sleeve import lay_out_plates
    V, T = _disc(250.0, 10.0)
    with pytest.raises(MetamaterialError) as ei:
        lay_out_plates([("sleeve", V, T, "TPU", 2)])
    msg = str(ei.value)
    assert "sleeve" in msg and "250" in msg and "330 x 240" in msg and "prusaslicer_dual_pla_tpu_0.1mm.ini" in msg
    V, T = _disc(100.0, 310.0)
    with pytest.raises(MetamaterialError) as ei:
        lay_out_plates([("sleeve", V, T, "TPU", 2)])
    assert "310" in str(ei.value) and "300" in str(ei.value)


# --- the real thing: FreeCAD builds, PrusaSlicer slices ------------------------------------------
def _read_3mf(path):
    with zipfile.ZipFile(path) as z:
        root = ET.fromstring(z.read("3D/3dmodel.model"))
    out = []
    for obj in root.iter(f"{NS}object"):
        mesh = obj.find(f"{NS}mesh")
        if mesh is None:                    # an assembly of components
            continue
        V = np.array([[float(v.get(k)) for k in "xyz"] for v in mesh.find(f"{NS}vertices")])
        out.append((obj.get("name"), V, None, None, None))
    return out


def _freecad():
    lib = "/usr/lib/freecad-python3/lib"
    if os.path.isdir(lib) and lib not in sys.path:
        sys.path.append(lib)
    pytest.importorskip("FreeCAD")


def test_a_small_sleeves_parts_lie_side_by_side_on_one_bed(tmp_path):
    _freecad()
    from metamaterial_wb.export.sleeve import export_sleeve
    files = export_sleeve(SleeveSpec({"format": "metamaterial-sleeve", "cell_types": TYPES, "ring": [0, 0, 1, 1]}),
                          str(tmp_path), step=False, threemf=True)
    assert files == ["sleeve.3mf"]
    _check_plates([_read_3mf(tmp_path / "sleeve.3mf")], PARTS)


@pytest.fixture(scope="module")
def wide(tmp_path_factory):
    """The audit's sleeve: 20 cells, ring [0] * 10 + [1] * 10, 142 mm across (about 1.5 min to build)."""
    _freecad()
    from metamaterial_wb.export.sleeve import export_sleeve
    folder = tmp_path_factory.mktemp("wide")
    spec = SleeveSpec({"format": "metamaterial-sleeve", "cell_types": TYPES, "ring": [0] * 10 + [1] * 10})
    assert 2 * spec.radius_mm + spec.T == pytest.approx(141.85, abs=0.01)
    return folder, export_sleeve(spec, str(folder), step=False, threemf=True)


def test_a_wide_sleeves_3mf_files_are_plates_on_the_bed(wide):
    folder, files = wide
    # the caps are the core's (24.6 mm, held in the end rings' openings): the sleeve, a ring and both caps, the other ring
    assert files == ["sleeve_plate1.3mf", "sleeve_plate2.3mf"]
    plates = [_read_3mf(folder / f) for f in files]
    assert plates[0][0][0] == "sleeve"
    first = sorted(p[0] for p in plates[0])
    assert len(first) == 4 and {"sleeve", "cap_bottom", "cap_top"} <= set(first), first
    _check_plates(plates, PARTS)


@pytest.mark.skipif(shutil.which("prusa-slicer") is None, reason="PrusaSlicer not installed")
@pytest.mark.parametrize("arrange", [True, False])
def test_every_plate_slices_with_the_bundled_profile(wide, tmp_path, arrange):
    """As a user slices them (PrusaSlicer arranges; the audit's command, which exited 134) and with --dont-arrange
    (the file's own positions): exit 0, and without arranging every extrusion lies on the profile's bed."""
    folder, files = wide
    lo, hi, _ = _bed()
    for f in files:
        g = tmp_path / (f + ".gcode")
        r = subprocess.run(["prusa-slicer", "--loglevel", "1", "--export-gcode", "--load", PROFILE,
                            *([] if arrange else ["--dont-arrange"]), "-o", str(g), str(folder / f)],
                           capture_output=True, encoding="utf-8", errors="replace", timeout=900)
        assert r.returncode == 0, (f, r.stderr[-1500:])
        text = g.read_text(encoding="utf-8")
        used = [float(v) for v in re.search(r"^; filament used \[mm\] = (.*)$", text, re.M).group(1).split(",")]
        # the sleeve in TPU (extruder 2) beside PLA on the first plate; the others PLA only (extruder 1, at PLA's
        # first-layer temperature; PrusaSlicer lists the one extruder used)
        if f == files[0]:
            assert len(used) == 2 and min(used) > 0, (f, used)
        else:
            pla_first_layer = _ini("first_layer_temperature").split(",")[0]
            assert len(used) == 1 and used[0] > 0 and f"M109 S{pla_first_layer} " in text, (f, used)
            assert "\nT1" not in text, f
        if not arrange:
            xy = np.array([[float(v) for v in m] for m in
                           re.findall(r"^G1 X(-?[\d.]+) Y(-?[\d.]+)[^\n;]* E[\d.]+", g.read_text(encoding="utf-8"), re.M)])
            assert len(xy) > 100, f
            assert (xy >= lo).all() and (xy <= hi).all(), f

