"""STEP and 3MF exports: names and volumes survive a re-import, lib3mf strict validation, and the
PrusaSlicer CLI slices the sheet on two extruders with the TPU extruder printing the hinges only."""
import json
import os
import re
import subprocess
import sys
import zipfile
import xml.etree.ElementTree as ET

import numpy as np
import pytest

from fabhelpers import EXAMPLES, REPO

NS = {"m": "http://schemas.microsoft.com/3dmanufacturing/core/2015/02"}


# ------------------------------------------------------------------------------------------------
# helpers
# ------------------------------------------------------------------------------------------------
def lib3mf_read(path):
    """Read with lib3mf in strict mode; returns {name: (n_vertices, n_triangles)} of mesh objects."""
    lib3mf = pytest.importorskip("lib3mf")
    w = lib3mf.get_wrapper()
    model = w.CreateModel()
    reader = model.QueryReader("3mf")
    reader.SetStrictModeActive(True)
    reader.ReadFromFile(str(path))
    warnings = [reader.GetWarning(k) for k in range(reader.GetWarningCount())]
    assert warnings == [], warnings
    out = {}
    it = model.GetMeshObjects()
    while it.MoveNext():
        o = it.GetCurrentMeshObject()
        out[o.GetName()] = (o.GetVertexCount(), o.GetTriangleCount())
    return out


def gcode_extrusions(path):
    """Extruding moves per tool: {tool: array of (x, y, z) end points}."""
    tool, rel, e_abs = None, False, 0.0
    x = y = z = None
    pts = {}
    with open(path) as f:
        for raw in f:
            line = raw.split(";", 1)[0].strip()
            if not line:
                continue
            if re.fullmatch(r"T\d+", line):
                tool = int(line[1:])
                continue
            word = line.split()[0]
            if word == "M83":
                rel = True
            elif word == "M82":
                rel = False
            elif word == "G92":
                m = re.search(r"E(-?[\d.]+)", line)
                if m:
                    e_abs = float(m.group(1))
            elif word in ("G0", "G1"):
                vals = dict((k, float(v)) for k, v in re.findall(r"([XYZE])(-?[\d.]+)", line))
                x, y, z = vals.get("X", x), vals.get("Y", y), vals.get("Z", z)
                if "E" in vals:
                    de = vals["E"] if rel else vals["E"] - e_abs
                    if not rel:
                        e_abs = vals["E"]
                    if de > 1e-6 and tool is not None and x is not None and y is not None:
                        pts.setdefault(tool, []).append((x, y, z))
    return {k: np.array(v) for k, v in pts.items()}


def filament_used(path):
    text = open(path).read()
    m = re.search(r"^; filament used \[mm\] = (.*)$", text, re.M)
    assert m, "no filament summary in the G-code"
    return [float(v) for v in m.group(1).split(",")]


def slice_3mf(exe, ini, path, out, extra=()):
    r = subprocess.run([exe, "--loglevel", "1", "--export-gcode", "--load", ini, *extra, "-o", str(out), str(path)],
                       capture_output=True, encoding="utf-8", errors="replace", timeout=300)
    assert r.returncode == 0, (r.stdout[-2000:], r.stderr[-2000:])
    return str(out)


def footprints(meshes, role_of):
    """XY boxes (xmin, ymin, xmax, ymax) per role from the meshes written to the 3MF."""
    boxes = {}
    for name, V, T, mat, ext in meshes:
        boxes.setdefault(role_of(name), []).append((V[:, 0].min(), V[:, 1].min(), V[:, 0].max(), V[:, 1].max()))
    return {k: np.array(v) for k, v in boxes.items()}


def assert_tpu_prints_hinges_only(gcode, meshes, thickness_mm, grow_mm=0.45):
    """Both extruders print; every TPU (T1) extrusion lies in a hinge footprint and below the sheet top,
    every PLA (T0) extrusion in a node footprint. The slicer centres the model: the shift is taken from
    the centre of all extrusions vs the centre of all meshes."""
    used = filament_used(gcode)
    assert len(used) == 2 and min(used) > 0, f"filament used per extruder: {used}"
    ex = gcode_extrusions(gcode)
    assert set(ex) == {0, 1}, f"extruding tools: {sorted(ex)}"
    allv = np.vstack([m[1] for m in meshes])
    allp = np.vstack([ex[0], ex[1]])
    shift = 0.5 * (allp[:, :2].min(0) + allp[:, :2].max(0)) - 0.5 * (allv[:, :2].min(0) + allv[:, :2].max(0))
    fp = footprints(meshes, lambda n: "hinge" if n.startswith("hinge") else "node")
    for tool, role in ((1, "hinge"), (0, "node")):
        p = ex[tool][:, :2] - shift
        b = fp[role]
        inside = ((p[:, None, 0] >= b[None, :, 0] - grow_mm) & (p[:, None, 0] <= b[None, :, 2] + grow_mm) &
                  (p[:, None, 1] >= b[None, :, 1] - grow_mm) & (p[:, None, 1] <= b[None, :, 3] + grow_mm)).any(1)
        assert inside.all(), f"T{tool}: {int((~inside).sum())} of {len(p)} extrusions outside every {role}"
    assert ex[1][:, 2].max() <= thickness_mm + 1e-6


# ------------------------------------------------------------------------------------------------
# STEP
# ------------------------------------------------------------------------------------------------
def _write_instanced(r, path, name):
    from metamaterial_wb.export.step import result_instances, write_step_instanced
    shapes, inst, cols = result_instances(r, r.parts)
    write_step_instanced(str(path), shapes, inst, name, cols)
    return shapes


def test_step_reimport_keeps_names_and_volumes(fc, chain_result, tmp_path):
    """The instanced STEP (what build writes) re-imports as one named body per part, each with its
    volume and place (FreeCAD 0.20, 1.0 and 1.1: run on every lane)."""
    import Import
    r = chain_result
    path = tmp_path / "chain.step"
    _write_instanced(r, path, "chain_sheet")
    doc = fc.newDocument("reimport")
    try:
        Import.insert(str(path), doc.Name, useLinkGroup=False)
        feats = {o.Label: o for o in doc.Objects if o.TypeId == "Part::Feature"}
        assert set(feats) == {q.name for q in r.parts}
        for q in r.parts:
            shape = feats[q.name].Shape
            assert shape.Volume == pytest.approx(r.placed_shape(q).Volume, rel=1e-6), q.name
            bb, ref = shape.BoundBox, r.placed_shape(q).BoundBox
            assert (bb.XMin, bb.YMin, bb.ZMin, bb.XMax, bb.YMax, bb.ZMax) == pytest.approx(
                (ref.XMin, ref.YMin, ref.ZMin, ref.XMax, ref.YMax, ref.ZMax), abs=1e-6), q.name
        assert any(o.TypeId == "App::Part" and o.Label == "chain_sheet" for o in doc.Objects)
    finally:
        fc.closeDocument(doc.Name)


def test_step_writes_each_unique_shape_once(fc, chain_result, tmp_path):
    """Instancing: one closed shell (faces, edges, points) per unique shape, one solid and one named
    product per part; the per-body writer (the first STEP path) wrote a shell per part."""
    from metamaterial_wb.export.step import result_bodies, write_step
    r = chain_result
    inst = tmp_path / "i.step"
    shapes = _write_instanced(r, inst, "c")
    text = inst.read_text()
    assert len(shapes) < len(r.parts)
    assert len(re.findall(r"= CLOSED_SHELL\(", text)) == len(shapes)
    assert len(re.findall(r"= MANIFOLD_SOLID_BREP\(", text)) == len(r.parts)
    names = set(re.findall(r"= PRODUCT\('([^']*)'", text))
    assert names == {q.name for q in r.parts} | {"c"}
    full = tmp_path / "f.step"
    write_step(str(full), result_bodies(r, r.parts), "c")
    assert len(re.findall(r"= CLOSED_SHELL\(", full.read_text())) == len(r.parts)
    assert inst.stat().st_size < full.stat().st_size


def test_step_has_one_colour_per_body(fc, chain_result, tmp_path):
    r = chain_result
    path = tmp_path / "c.step"
    _write_instanced(r, path, "c")
    text = path.read_text()
    assert text.count("STYLED_ITEM('color'") == len(r.parts)
    rgb = re.findall(r"COLOUR_RGB\('',([\d.]+),([\d.]+),([\d.]+)\)", text)
    got = {tuple(round(float(c) * 255) for c in t) for t in rgb}
    assert got == {(0xD9, 0xD9, 0xD9), (0x1E, 0x64, 0xFF)}       # PLA grey, TPU blue
    # every styled item points at a solid
    solids = set(re.findall(r"#(\d+) = MANIFOLD_SOLID_BREP", text))
    styled = set(re.findall(r"STYLED_ITEM\('color',\(#\d+\),#(\d+)\)", text))
    assert styled == solids and len(solids) == len(r.parts)


def step_records(text):
    """``{id: record}`` of a STEP file's DATA section, each record ``#n = ...`` up to (without) its ';',
    whitespace runs folded to one space; strings ('...' with '' inside) may hold any character."""
    data = text[text.index("DATA;") + 5:text.rindex("ENDSEC;")]
    recs, cur, quoted = {}, [], False
    for ch in data:
        if ch == "'":
            quoted = not quoted                 # '' inside a string toggles twice
        if ch == ";" and not quoted:
            rec = re.sub(r"\s+", " ", "".join(cur)).strip()
            cur = []
            if rec:
                m = re.match(r"#(\d+) = (.*)$", rec)
                assert m, f"not an entity record: {rec[:80]!r}"
                recs[int(m.group(1))] = m.group(2)
            continue
        cur.append(ch)
    assert not quoted and not "".join(cur).strip(), "the DATA section ends inside a record"
    return recs


def _instances_ok(body):
    """``body`` (an entity record without ``#n = ``) is ``TYPE(...)`` or a complex entity ``( A(...) B(...) )``:
    parentheses balanced outside strings, nothing after the last one."""
    def groups(t):                            # split t into its top-level "NAME(...)" items; None if malformed
        items, depth, quoted, start = [], 0, False, 0
        for k, ch in enumerate(t):
            if ch == "'":
                quoted = not quoted
            if quoted:
                continue
            if ch == "(":
                depth += 1
            elif ch == ")":
                depth -= 1
                if depth < 0:
                    return None
                if depth == 0:
                    items.append(t[start:k + 1].strip())
                    start = k + 1
        if depth or quoted or t[start:].strip():
            return None
        return items
    b = body.strip()
    if b.startswith("("):
        outer = groups(b)
        if outer != [b]:
            return False
        inner = groups(b[1:-1])
        return bool(inner) and all(re.fullmatch(r"[A-Z][A-Z0-9_]*\s*\(.*\)", i, re.S) for i in inner)
    return re.fullmatch(r"[A-Z][A-Z0-9_]*\(.*\)", b, re.S) is not None and groups(b) == [b]


def test_step_complex_entities_keep_their_brackets(fc, chain_result, tmp_path):
    """Every record of the written STEP is ``TYPE(...)`` or a bracketed complex entity ``( A(...) B(...) )``
    (ISO 10303-21; the instancing once wrote ``#20 = LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT(...);``, which
    OCCT's reader counts as "Incorrect Syntax"), and the 3D context's length unit is the millimetre."""
    path = tmp_path / "c.step"
    _write_instanced(chain_result, path, "c")
    recs = step_records(path.read_text(encoding="utf-8"))
    bad = {k: v[:70] for k, v in recs.items() if not _instances_ok(v)}
    assert bad == {}, f"{len(bad)} malformed records, e.g. {list(bad.items())[:3]}"
    ctx = [v for v in recs.values() if v.startswith("( GEOMETRIC_REPRESENTATION_CONTEXT(3) ")]
    assert ctx, "no bracketed 3D representation context"
    for c in ctx:
        units = re.search(r"GLOBAL_UNIT_ASSIGNED_CONTEXT\( ?\((#\d+),", c).group(1)
        assert recs[int(units[1:])] == "( LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT(.MILLI.,.METRE.) )"
    assert sum(v.startswith("( ") for v in recs.values()) >= 5          # units, contexts, placements


STEP_READER = """import json, os, Part
s = Part.read(os.environ["MMWB_STEP"])
print("MMWB-READ " + json.dumps(sorted(round(x.Volume, 6) for x in s.Solids)))
"""


def _occt_read(path):
    """Read ``path`` with ``Part.read`` (OCCT's STEP reader) in ``freecadcmd``: ``(solid volumes sorted,
    everything it printed)``. OCCT prints its reader's syntax errors ("ERR StepFile : Incorrect Syntax")
    on stdout in FreeCAD's command-line application (a plain ``import FreeCAD`` keeps them silent)."""
    import shutil
    exe = shutil.which("freecadcmd") or shutil.which("FreeCADCmd")
    if exe is None:
        pytest.skip("needs FreeCAD's command-line application (freecadcmd)")
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    env["MMWB_STEP"] = str(path)
    p = subprocess.run([exe, "-c", STEP_READER], env=env, capture_output=True, encoding="utf-8",
                       errors="replace", timeout=300)
    out = p.stdout + p.stderr
    assert p.returncode == 0, out[-2000:]
    vols = [json.loads(line[10:]) for line in p.stdout.splitlines() if line.startswith("MMWB-READ ")]
    assert len(vols) == 1, out[-2000:]
    return vols[0], out


def test_step_reads_without_syntax_errors_in_occt(fc, chain_result, tmp_path):
    """OCCT's STEP reader (FreeCAD's Part.read) reads the instanced STEP without "Incorrect Syntax" and
    finds one solid per part with the built volumes. Control: the same file with the brackets of one
    complex entity removed makes the reader report the error (so its silence means something)."""
    r = chain_result
    path = tmp_path / "c.step"
    _write_instanced(r, path, "c")
    vols, out = _occt_read(path)
    assert "Incorrect Syntax" not in out and "ERR StepFile" not in out, out[-2000:]
    want = sorted(r.placed_shape(q).Volume for q in r.parts)
    assert vols == pytest.approx(want, rel=1e-6)
    text = path.read_text(encoding="utf-8")
    unit = "( LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT(.MILLI.,.METRE.) )"
    assert unit in text
    broken = tmp_path / "broken.step"
    broken.write_text(text.replace(unit, unit[1:-1], 1), encoding="utf-8")
    _, out = _occt_read(broken)
    assert "Incorrect Syntax" in out, out[-2000:]


# ------------------------------------------------------------------------------------------------
# 3MF
# ------------------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def chain_meshes(chain_result):
    from metamaterial_wb.export.mesh import open_edges, part_meshes, signed_volume
    parts = sorted(chain_result.parts, key=lambda q: q.role != "node")
    meshes = part_meshes(chain_result, parts)
    for (name, V, T, _, _), q in zip(meshes, parts):
        assert open_edges(T) == 0, name                                  # closed and consistently oriented
        assert signed_volume(V, T) == pytest.approx(chain_result.placed_shape(q).Volume, rel=5e-3)
    return meshes


def test_3mf_prusa_layout(chain_meshes, tmp_path):
    from metamaterial_wb.export.threemf import write_3mf
    path = tmp_path / "p.3mf"
    write_3mf(str(path), chain_meshes, layout="prusa")
    objs = lib3mf_read(path)
    assert len(objs) == 1 and list(objs.values())[0][1] == sum(len(m[2]) for m in chain_meshes)
    cfg = ET.fromstring(zipfile.ZipFile(path).read("Metadata/Slic3r_PE_model.config"))
    vols = cfg.findall("./object/volume")
    assert len(vols) == len(chain_meshes)
    first = 0
    for vol, (name, V, T, mat, ext) in zip(vols, chain_meshes):
        meta = {m.get("key"): m.get("value") for m in vol.findall("metadata")}
        assert meta["name"] == name and int(meta["extruder"]) == ext
        assert (int(vol.get("firstid")), int(vol.get("lastid"))) == (first, first + len(T) - 1)
        first += len(T)
    model = ET.fromstring(zipfile.ZipFile(path).read("3D/3dmodel.model"))
    bases = [b.get("name") for b in model.findall(".//m:basematerials/m:base", NS)]
    assert bases == ["PLA", "TPU"]


@pytest.mark.parametrize("layout", ["components", "objects"])
def test_3mf_components_and_objects_layouts(chain_meshes, tmp_path, layout):
    from metamaterial_wb.export.threemf import write_3mf
    path = tmp_path / f"{layout}.3mf"
    write_3mf(str(path), chain_meshes, layout=layout)
    objs = lib3mf_read(path)
    assert set(objs) == {m[0] for m in chain_meshes}
    z = zipfile.ZipFile(path)
    model = ET.fromstring(z.read("3D/3dmodel.model"))
    ext_of = {m[0]: m[4] for m in chain_meshes}
    for o in model.findall("m:resources/m:object", NS):
        md = o.find("m:metadatagroup/m:metadata", NS)
        if o.find("m:mesh", NS) is not None:
            assert int(md.text) == ext_of[o.get("name")] - 1               # Cura: 0-based
    bambu = ET.fromstring(z.read("Metadata/model_settings.config"))
    items = model.findall("m:build/m:item", NS)
    if layout == "components":
        assert len(items) == 1 and bambu.find("object").get("id") == items[0].get("objectid")
        parts = bambu.findall("object/part")
        assert len(parts) == len(chain_meshes)
        names = {o.get("id"): o.get("name") for o in model.findall("m:resources/m:object", NS)}
        for part in parts:
            meta = {m.get("key"): m.get("value") for m in part.findall("metadata")}
            assert int(meta["extruder"]) == ext_of[names[part.get("id")]]
    else:
        assert len(items) == len(chain_meshes)


def test_3mf_writer_rejects_bad_input(tmp_path):
    from metamaterial_wb.core.errors import MetamaterialError
    from metamaterial_wb.export.threemf import write_3mf
    V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
    T = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    with pytest.raises(MetamaterialError, match="extruder 0"):
        write_3mf(str(tmp_path / "a.3mf"), [("a", V, T, "PLA", 0)])
    with pytest.raises(MetamaterialError, match="outside the vertex range"):
        write_3mf(str(tmp_path / "a.3mf"), [("a", V, T + 1, "PLA", 1)])
    with pytest.raises(MetamaterialError, match="used twice"):
        write_3mf(str(tmp_path / "a.3mf"), [("a", V, T, "PLA", 1), ("a", V, T, "TPU", 2)])
    with pytest.raises(MetamaterialError, match="layout"):
        write_3mf(str(tmp_path / "a.3mf"), [("a", V, T, "PLA", 1)], layout="bambu-project")
    assert not os.listdir(tmp_path)                                        # nothing half-written
    write_3mf(str(tmp_path / "tet.3mf"), [("a", V, T, "PLA", 1)])          # the generic API on a tetrahedron
    assert lib3mf_read(tmp_path / "tet.3mf") == {"tet": (4, 4)}


# ------------------------------------------------------------------------------------------------
# slicing
# ------------------------------------------------------------------------------------------------
def test_prusaslicer_two_extruders_tpu_prints_hinges_only(prusa_slicer, dual_ini, chain_meshes, chain_result,
                                                          tmp_path):
    from metamaterial_wb.export.threemf import write_3mf
    path = tmp_path / "chain.3mf"
    write_3mf(str(path), chain_meshes, layout="prusa")
    g = slice_3mf(prusa_slicer, dual_ini, path, tmp_path / "chain.gcode")
    assert_tpu_prints_hinges_only(g, chain_meshes, chain_result.params.sheet_thickness_mm)


def test_mutation_hinges_on_first_extruder_fails(prusa_slicer, dual_ini, chain_meshes, chain_result, tmp_path):
    """The check above must fail when the hinges go to extruder 1 (the mutation)."""
    from metamaterial_wb.export.threemf import write_3mf
    bad = [(n, V, T, m, 1) for (n, V, T, m, e) in chain_meshes]
    path = tmp_path / "bad.3mf"
    write_3mf(str(path), bad, layout="prusa")
    g = slice_3mf(prusa_slicer, dual_ini, path, tmp_path / "bad.gcode")
    with pytest.raises(AssertionError):
        assert_tpu_prints_hinges_only(g, bad, chain_result.params.sheet_thickness_mm)
    # and swapping the extruders (nodes in TPU) fails too
    swapped = [(n, V, T, m, 3 - e) for (n, V, T, m, e) in chain_meshes]
    write_3mf(str(path), swapped, layout="prusa")
    g = slice_3mf(prusa_slicer, dual_ini, path, tmp_path / "swapped.gcode")
    with pytest.raises(AssertionError):
        assert_tpu_prints_hinges_only(g, swapped, chain_result.params.sheet_thickness_mm)


def test_components_layout_sliced_on_two_extruders(prusa_slicer, dual_ini, chain_meshes, tmp_path):
    from metamaterial_wb.export.threemf import write_3mf
    path = tmp_path / "comp.3mf"
    write_3mf(str(path), chain_meshes, layout="components")
    g = slice_3mf(prusa_slicer, dual_ini, path, tmp_path / "comp.gcode", extra=("--dont-arrange",))
    used = filament_used(g)
    assert len(used) == 2 and min(used) > 0
    # TPU share of the filament ~ hinge share of the volume (PrusaSlicer loads components as objects)
    vol = {True: 0.0, False: 0.0}
    from metamaterial_wb.export.mesh import signed_volume
    for n, V, T, m, e in chain_meshes:
        vol[n.startswith("hinge")] += signed_volume(V, T)
    assert used[1] / sum(used) == pytest.approx(vol[True] / (vol[True] + vol[False]), abs=0.08)


def _prusa_roundtrip_objects(exe, path, out):
    """``[(volume matrix rounded, extruder or None)]`` of every object PrusaSlicer loads from ``path``
    (its own --export-3mf, positions kept)."""
    r = subprocess.run([exe, "--loglevel", "1", "--export-3mf", "--dont-arrange", "-o", str(out), str(path)],
                       capture_output=True, encoding="utf-8", errors="replace", timeout=300)
    assert r.returncode == 0, r.stderr[-2000:]
    cfg = zipfile.ZipFile(out).read("Metadata/Slic3r_PE_model.config").decode()
    objs = []
    for m in re.finditer(r'<object id="\d+".*?</object>', cfg, re.S):
        mat = re.search(r'key="matrix" value="([^"]*)"', m.group(0)).group(1)
        ext = re.search(r'type="volume" key="extruder" value="([^"]*)"', m.group(0))
        objs.append((tuple(round(float(x), 3) for x in mat.split()[:12]), ext.group(1) if ext else None))
    return sorted(objs, key=lambda o: o[0])


def test_shared_component_meshes_and_what_prusaslicer_makes_of_them(prusa_slicer, chain_meshes, chain_result,
                                                                     tmp_path):
    """share_meshes writes copies of one unique shape as components of one mesh with a transform (valid
    for lib3mf's strict reader). PrusaSlicer 2.5 places every copy right, but gives only the first
    object made from a mesh its extruder: the copies of a TPU hinge would print in PLA. That is why
    build does not share meshes in the components file (docs/fabrication.md, "3MF"); when this test
    fails because PrusaSlicer keeps the extruders, sharing can be switched on there."""
    from metamaterial_wb.export.threemf import write_3mf
    full, shared = tmp_path / "full.3mf", tmp_path / "shared.3mf"
    write_3mf(str(full), chain_meshes, layout="components")
    write_3mf(str(shared), chain_meshes, layout="components", share_meshes=True)
    model = ET.fromstring(zipfile.ZipFile(shared).read("3D/3dmodel.model"))
    meshes = [o for o in model.findall("m:resources/m:object", NS) if o.find("m:mesh", NS) is not None]
    comps = model.findall("m:resources/m:object/m:components/m:component", NS)
    assert len(comps) == len(chain_meshes) and len(meshes) == len({q.key for q in chain_result.parts})
    assert sum(c.get("transform") is not None for c in comps) == len(chain_meshes) - len(meshes)
    lib3mf_read(shared)                                           # strict mode: raises on any error
    a = _prusa_roundtrip_objects(prusa_slicer, shared, tmp_path / "rs.3mf")
    b = _prusa_roundtrip_objects(prusa_slicer, full, tmp_path / "rf.3mf")
    assert [o[0] for o in a] == [o[0] for o in b]                 # every copy at its place
    assert all(o[1] for o in b)
    lost = [o for o in a if o[1] is None]
    assert len(lost) == len(chain_meshes) - len(meshes)           # exactly the copies lose their extruder


# ------------------------------------------------------------------------------------------------
# the seed's fish and gripper through the CLI
# ------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("example", ["fish_modules", "gripper"])
def test_examples_build_export_and_slice(fc, prusa_slicer, dual_ini, tmp_path, example):
    from metamaterial_wb.core.scene import Scene
    from metamaterial_wb.export.mesh import part_meshes
    from metamaterial_wb.geometry.build import build_scene
    from metamaterial_wb.geometry import validity
    scene_path = os.path.join(EXAMPLES, f"{example}.json")
    out = tmp_path / "out"
    r = subprocess.run([sys.executable, "-m", "metamaterial_wb", "build", scene_path, "--out", str(out),
                        "--modules"], cwd=REPO, capture_output=True, encoding="utf-8", errors="replace", timeout=600)
    assert r.returncode == 0, r.stderr[-3000:]
    assert "build: sheet parts" in r.stderr                                # progress on stderr
    files = sorted(os.listdir(out))
    scene = Scene.load(scene_path)
    mods = [m.get("name") for m in scene.modules]
    assert f"{example}_sheet.step" in files and f"{example}_sheet.3mf" in files
    assert f"{example}_sheet_components.3mf" in files and f"{example}_assembly.step" in files
    for name in mods:                                                     # modules print separately
        assert f"{example}_{name}.3mf" in files and f"{example}_{name}.step" in files
    for f in files:
        if f.endswith(".3mf"):
            objs = lib3mf_read(out / f)
            if f.endswith("_sheet.3mf"):
                assert len(objs) == 1
            elif not f.endswith("_components.3mf"):
                assert all(not k.startswith(("node", "hinge")) for k in objs)
    res = build_scene(scene, progress=False)
    assert validity.check_all(res) == []
    sheet = sorted([q for q in res.parts if q.group == "sheet"], key=lambda q: q.role != "node")
    # the classic perimeter generator slices these 28-node sheets ~2x faster than Arachne (2.5's default)
    g = slice_3mf(prusa_slicer, dual_ini, out / f"{example}_sheet.3mf", tmp_path / "sheet.gcode",
                  extra=("--perimeter-generator", "classic", "--resolution", "0.05"))
    assert_tpu_prints_hinges_only(g, part_meshes(res, sheet), res.params.sheet_thickness_mm)
    # one module file slices on a single extruder
    g2 = slice_3mf(prusa_slicer, dual_ini, out / f"{example}_{mods[0]}.3mf", tmp_path / "mod.gcode")
    assert len(filament_used(g2)) == 1


def test_prusaslicer_reads_one_object_with_named_parts(prusa_slicer, chain_meshes, tmp_path):
    """PrusaSlicer's own 3MF round trip: one object whose volumes carry our names and extruders."""
    from metamaterial_wb.export.threemf import write_3mf
    src = tmp_path / "p.3mf"
    write_3mf(str(src), chain_meshes, layout="prusa")
    rt = tmp_path / "rt.3mf"
    r = subprocess.run([prusa_slicer, "--loglevel", "1", "--export-3mf", "-o", str(rt), str(src)],
                       capture_output=True, encoding="utf-8", errors="replace", timeout=300)
    assert r.returncode == 0, r.stderr[-2000:]
    cfg = ET.fromstring(zipfile.ZipFile(rt).read("Metadata/Slic3r_PE_model.config"))
    objects = cfg.findall("object")
    assert len(objects) == 1
    got = []
    for vol in objects[0].findall("volume"):
        meta = {m.get("key"): m.get("value") for m in vol.findall("metadata")}
        got.append((meta["name"], int(meta.get("extruder", 0))))
    assert got == [(m[0], m[4]) for m in chain_meshes]


def test_cura_parser_reads_the_extruder_of_every_part(chain_meshes, tmp_path):
    """Cura's own 3MF parser (libSavitar, Debian python3-savitar) sees one group whose children are our
    parts, each with its 0-based extruder_nr."""
    Savitar = pytest.importorskip("Savitar")
    from metamaterial_wb.export.threemf import write_3mf
    path = tmp_path / "cura.3mf"
    write_3mf(str(path), chain_meshes, layout="components", object_name="chain")
    scene = Savitar.ThreeMFParser().parse(zipfile.ZipFile(path).read("3D/3dmodel.model"))
    nodes = scene.getSceneNodes()
    assert len(nodes) == 1 and nodes[0].getName() == "chain"
    got = [(c.getName(), int(c.getSettings()["extruder_nr"].value)) for c in nodes[0].getChildren()]
    assert got == [(m[0], m[4] - 1) for m in chain_meshes]


def test_step_colours_read_back_by_freecad_gui(fc, chain_result, tmp_path):
    """FreeCAD's GUI importer (OCCT's XCAF reader, independent of our writer) finds the PLA and TPU colours
    on every body."""
    import shutil
    if shutil.which("xvfb-run") is None or shutil.which("freecad") is None:
        pytest.skip("needs xvfb-run and the FreeCAD GUI")
    r = chain_result
    step = tmp_path / "c.step"
    _write_instanced(r, step, "c")
    here = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data")
    cfg = tmp_path / "user.cfg"
    shutil.copy(os.path.join(here, "freecad_user.cfg"), cfg)        # FreeCAD rewrites it on exit
    out = tmp_path / "colours.json"
    env = dict(os.environ, STEP=str(step), OUT=str(out))
    p = subprocess.run(["xvfb-run", "-a", "freecad", "-u", str(cfg), os.path.join(here, "step_colours_macro.py")],
                       env=env, capture_output=True, encoding="utf-8", errors="replace", timeout=300)
    assert p.returncode == 0, p.stderr[-2000:]
    colours = json.loads(out.read_text())
    assert set(colours) == {q.name for q in r.parts}
    for q in r.parts:
        want = (0x1E / 255, 0x64 / 255, 1.0) if q.role == "hinge" else (0xD9 / 255,) * 3
        assert colours[q.name] == pytest.approx(want, abs=2e-3), q.name
