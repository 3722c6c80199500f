"""A small 3MF writer for multi-material prints (pure Python + numpy; no FreeCAD).

    write_3mf("sheet.3mf", parts=[("node_0_0", V, T, "PLA", 1), ("hinge_H0_0", V2, T2, "TPU", 2)],
              layout="prusa")

``parts``: ``(name, vertices (n, 3) float mm, triangles (m, 3) int, material, extruder)`` tuples (or
:class:`MeshPart`). Triangles are counter-clockwise seen from outside (outward normals); every part
must be a closed mesh. Extruders are 1-based (PrusaSlicer / Bambu numbering; Cura gets
``extruder - 1``).

Layouts (docs/fabrication.md, "3MF"):

* ``"prusa"``: ONE mesh object whose parts are contiguous triangle ranges, listed as volumes with
  their extruder in ``Metadata/Slic3r_PE_model.config`` -- PrusaSlicer (2.4 - 2.9) opens it as one
  object with N parts, each on its extruder. Where volumes overlap, the later one wins.
* ``"components"``: one mesh object per part and an assembly object of ``<components>``, with the
  hints of the other slicers: ``Metadata/model_settings.config`` (Bambu Studio / OrcaSlicer part
  extruders), ``cura:extruder_nr`` object metadata (Cura, 0-based) and a per-object
  ``Slic3r_PE_model.config`` (PrusaSlicer loads components as separate objects, each on its extruder).
* ``"objects"``: one independent object (its own build item) per part, for parts that print
  separately (modules), with the same per-object hints.

Both carry core-spec ``<basematerials>`` (material names + display colours) and pass lib3mf's strict
validation. The file is written to a temporary name and renamed: no partial files.
"""
import io
import os
import zipfile
from dataclasses import dataclass
from xml.sax.saxutils import quoteattr, escape

import numpy as np

from metamaterial_wb.core.errors import MetamaterialError
from metamaterial_wb.core.materials import MATERIALS

CORE_NS = "http://schemas.microsoft.com/3dmanufacturing/core/2015/02"
CURA_NS = "http://software.ultimaker.com/xml/cura/3mf/2015/10"
LAYOUTS = ("prusa", "components", "objects")

DEFAULT_COLOURS = MATERIALS          # core/materials.py: the one table

CONTENT_TYPES = """<?xml version="1.0" encoding="UTF-8"?>
<Types xmlns="http://schemas.openxmlformats.org/package/2006/content-types">
 <Default Extension="rels" ContentType="application/vnd.openxmlformats-package.relationships+xml"/>
 <Default Extension="model" ContentType="application/vnd.ms-package.3dmanufacturing-3dmodel+xml"/>
 <Default Extension="config" ContentType="application/xml"/>
</Types>
"""
RELS = """<?xml version="1.0" encoding="UTF-8"?>
<Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships">
 <Relationship Target="/3D/3dmodel.model" Id="rel0" Type="http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel"/>
</Relationships>
"""


@dataclass
class MeshPart:
    name: str
    vertices: np.ndarray
    triangles: np.ndarray
    material: str = "PLA"
    extruder: int = 1


def _as_parts(parts):
    out = []
    names = set()
    for k, item in enumerate(parts):
        mp = item if isinstance(item, MeshPart) else MeshPart(*item)
        v = np.asarray(mp.vertices, dtype=float)
        t = np.asarray(mp.triangles, dtype=np.int64)
        where = f"3MF part {k} ({mp.name!r})"
        if not isinstance(mp.name, str) or not mp.name:
            raise MetamaterialError(f"{where}: a part needs a non-empty name")
        if mp.name in names:
            raise MetamaterialError(f"{where}: the name {mp.name!r} is used twice; part names must be unique")
        names.add(mp.name)
        if v.ndim != 2 or v.shape[1] != 3 or len(v) < 4 or not np.all(np.isfinite(v)):
            raise MetamaterialError(f"{where}: vertices must be a finite (n >= 4, 3) array, got shape {v.shape}")
        if t.ndim != 2 or t.shape[1] != 3 or len(t) < 4:
            raise MetamaterialError(f"{where}: triangles must be an (m >= 4, 3) integer array, got shape {t.shape}")
        if t.min() < 0 or t.max() >= len(v):
            raise MetamaterialError(f"{where}: triangle index {int(t.max()) if t.max() >= len(v) else int(t.min())} "
                                    f"is outside the vertex range [0, {len(v) - 1}]")
        if isinstance(mp.extruder, bool) or not isinstance(mp.extruder, (int, np.integer)) or not 1 <= mp.extruder <= 16:
            raise MetamaterialError(f"{where}: extruder {mp.extruder!r} is outside the allowed range 1..16 (1-based)")
        if not isinstance(mp.material, str) or not mp.material:
            raise MetamaterialError(f"{where}: material must be a name such as \"PLA\" or \"TPU\"")
        out.append(MeshPart(mp.name, v, t, mp.material, int(mp.extruder)))
    if not out:
        raise MetamaterialError("3MF: nothing to write (no parts)")
    return out


def _vertices_xml(v):
    return ('<vertex x="%.5f" y="%.5f" z="%.5f"/>\n' * len(v)) % tuple(v.ravel())


def _triangles_xml(t, prop=None):
    if prop is None:
        return ('<triangle v1="%d" v2="%d" v3="%d"/>\n' * len(t)) % tuple(t.ravel())
    fmt = '<triangle v1="%%d" v2="%%d" v3="%%d" p1="%d"/>\n' % prop
    return (fmt * len(t)) % tuple(t.ravel())


def _colour(c):
    c = c.strip()
    if not c.startswith("#") or len(c) not in (7, 9):
        raise MetamaterialError(f"3MF: colour {c!r} is not #RRGGBB or #RRGGBBAA")
    return (c + "FF" if len(c) == 7 else c).upper()


def _materials_table(parts, materials):
    colours = dict(DEFAULT_COLOURS)
    if materials:
        colours.update({k.upper(): v for k, v in materials.items()})
    names = []
    for mp in parts:
        if mp.material.upper() not in names:
            names.append(mp.material.upper())
    index = {n: k for k, n in enumerate(names)}
    xml = ['<basematerials id="1">\n']
    for n in names:
        xml.append(f' <base name={quoteattr(n)} displaycolor="{_colour(colours.get(n, "#808080"))}"/>\n')
    xml.append('</basematerials>\n')
    return "".join(xml), index


def _transform_attr(M):
    """3MF core transform attribute (m00 m01 m02 m10 ... m32: row vectors, p' = p M) of a 4 x 4
    column-vector matrix ``M`` (p' = M p)."""
    R, t = M[:3, :3], M[:3, 3]
    vals = [R[c, r] for r in range(3) for c in range(3)] + list(t)
    return " ".join(f"{float(v):.9g}" for v in vals)


def _shared_meshes(parts, tol_mm=1e-6):
    """``{k: (first, M)}``: part ``k`` is a rigid copy of part ``first`` (the same triangles, its
    vertices ``M`` applied to ``first``'s within ``tol_mm``; Kabsch fit, checked on every vertex)."""
    out = {}
    firsts = {}
    for k, mp in enumerate(parts):
        key = (hash(mp.triangles.tobytes()), len(mp.vertices), mp.material.upper(), mp.extruder)
        if key not in firsts:
            firsts[key] = []
        hit = None
        for f in firsts[key]:
            A, B = parts[f].vertices, mp.vertices
            ca, cb = A.mean(axis=0), B.mean(axis=0)
            U, _, Wt = np.linalg.svd((A - ca).T @ (B - cb))
            d = np.sign(np.linalg.det(Wt.T @ U.T))
            R = Wt.T @ np.diag([1.0, 1.0, d]) @ U.T
            if d > 0 and np.max(np.abs((A - ca) @ R.T + cb - B)) <= tol_mm:
                M = np.eye(4)
                M[:3, :3], M[:3, 3] = R, cb - R @ ca
                hit = (f, M)
                break
        if hit is None:
            firsts[key].append(k)
        else:
            out[k] = hit
    return out


def build_3mf_bytes(parts, layout="prusa", materials=None, object_name="structure", title=None,
                    application="metamaterial_wb", share_meshes=False):
    """The 3MF package as bytes (see :func:`write_3mf`)."""
    if layout not in LAYOUTS:
        raise MetamaterialError(f"3MF layout {layout!r} is unknown; allowed: {', '.join(LAYOUTS)}")
    parts = _as_parts(parts)
    mat_xml, mat_index = _materials_table(parts, materials)
    head = [f'<?xml version="1.0" encoding="UTF-8"?>\n<model unit="millimeter" xml:lang="en-US" '
            f'xmlns="{CORE_NS}"' + (f' xmlns:cura="{CURA_NS}"' if layout != "prusa" else "") + '>\n',
            f'<metadata name="Application">{escape(application)}</metadata>\n',
            f'<metadata name="Title">{escape(title or object_name)}</metadata>\n',
            '<resources>\n', mat_xml]
    files = {}
    if layout == "prusa":
        first = mat_index[parts[0].material.upper()]
        body = [f'<object id="2" type="model" name={quoteattr(object_name)} pid="1" pindex="{first}">\n'
                '<mesh>\n<vertices>\n']
        offset = 0
        for mp in parts:
            body.append(_vertices_xml(mp.vertices))
        body.append('</vertices>\n<triangles>\n')
        cfg = ['<?xml version="1.0" encoding="UTF-8"?>\n<config>\n <object id="2" instances_count="1">\n',
               f'  <metadata type="object" key="name" value={quoteattr(object_name)}/>\n',
               f'  <metadata type="object" key="extruder" value="{parts[0].extruder}"/>\n']
        tri0 = 0
        for mp in parts:
            idx = mp.triangles + offset
            m = mat_index[mp.material.upper()]
            body.append(_triangles_xml(idx, None if m == first else m))
            offset += len(mp.vertices)
            cfg.append(f'  <volume firstid="{tri0}" lastid="{tri0 + len(mp.triangles) - 1}">\n'
                       f'   <metadata type="volume" key="name" value={quoteattr(mp.name)}/>\n'
                       f'   <metadata type="volume" key="volume_type" value="ModelPart"/>\n'
                       f'   <metadata type="volume" key="extruder" value="{mp.extruder}"/>\n'
                       f'  </volume>\n')
            tri0 += len(mp.triangles)
        body.append('</triangles>\n</mesh>\n</object>\n</resources>\n<build>\n <item objectid="2"/>\n</build>\n'
                    '</model>\n')
        cfg.append(' </object>\n</config>\n')
        files["Metadata/Slic3r_PE_model.config"] = "".join(cfg)
    else:
        body = []
        ids = []
        shared = _shared_meshes(parts) if (share_meshes and layout == "components") else {}
        xforms = {}
        for k, mp in enumerate(parts):
            if k in shared:                      # a copy of an earlier mesh: a component with a transform
                first, M = shared[k]
                ids.append(ids[first])
                xforms[k] = M
                continue
            oid = 2 + k
            ids.append(oid)
            body.append(f'<object id="{oid}" type="model" name={quoteattr(mp.name)} pid="1" '
                        f'pindex="{mat_index[mp.material.upper()]}">\n'
                        f'<metadatagroup>\n <metadata name="cura:extruder_nr" preserve="1" type="xs:string">'
                        f'{mp.extruder - 1}</metadata>\n</metadatagroup>\n<mesh>\n<vertices>\n')
            body.append(_vertices_xml(mp.vertices))
            body.append('</vertices>\n<triangles>\n')
            body.append(_triangles_xml(mp.triangles))
            body.append('</triangles>\n</mesh>\n</object>\n')
        asm = 2 + len(parts)
        if layout == "components":
            body.append(f'<object id="{asm}" type="model" name={quoteattr(object_name)}>\n<components>\n')
            for k, oid in enumerate(ids):
                tr = f' transform="{_transform_attr(xforms[k])}"' if k in xforms else ""
                body.append(f' <component objectid="{oid}"{tr}/>\n')
            body.append('</components>\n</object>\n</resources>\n'
                        f'<build>\n <item objectid="{asm}"/>\n</build>\n</model>\n')
        else:
            body.append('</resources>\n<build>\n')
            body.extend(f' <item objectid="{oid}"/>\n' for oid in ids)
            body.append('</build>\n</model>\n')
        bambu = ['<?xml version="1.0" encoding="UTF-8"?>\n<config>\n']
        if layout == "components":
            bambu += [f' <object id="{asm}">\n', f'  <metadata key="name" value={quoteattr(object_name)}/>\n',
                      f'  <metadata key="extruder" value="{parts[0].extruder}"/>\n']
        prusa = ['<?xml version="1.0" encoding="UTF-8"?>\n<config>\n']
        for k, (oid, mp) in enumerate(zip(ids, parts)):
            if k in shared:
                continue
            if layout == "components":
                bambu.append(f'  <part id="{oid}" subtype="normal_part">\n'
                             f'   <metadata key="name" value={quoteattr(mp.name)}/>\n'
                             f'   <metadata key="extruder" value="{mp.extruder}"/>\n  </part>\n')
            else:
                bambu.append(f' <object id="{oid}">\n  <metadata key="name" value={quoteattr(mp.name)}/>\n'
                             f'  <metadata key="extruder" value="{mp.extruder}"/>\n </object>\n')
            prusa.append(f' <object id="{oid}" instances_count="1">\n'
                         f'  <metadata type="object" key="name" value={quoteattr(mp.name)}/>\n'
                         f'  <metadata type="object" key="extruder" value="{mp.extruder}"/>\n'
                         f'  <volume firstid="0" lastid="{len(mp.triangles) - 1}">\n'
                         f'   <metadata type="volume" key="name" value={quoteattr(mp.name)}/>\n'
                         f'   <metadata type="volume" key="volume_type" value="ModelPart"/>\n'
                         f'   <metadata type="volume" key="extruder" value="{mp.extruder}"/>\n'
                         f'  </volume>\n </object>\n')
        if layout == "components":
            bambu.append(' </object>\n')
        bambu.append('</config>\n')
        prusa.append('</config>\n')
        files["Metadata/model_settings.config"] = "".join(bambu)
        files["Metadata/Slic3r_PE_model.config"] = "".join(prusa)
    model = "".join(head) + "".join(body)
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w", zipfile.ZIP_DEFLATED, compresslevel=6) as z:
        z.writestr("[Content_Types].xml", CONTENT_TYPES)
        z.writestr("_rels/.rels", RELS)
        z.writestr("3D/3dmodel.model", model)
        for name, text in files.items():
            z.writestr(name, text)
    return buf.getvalue()


def write_3mf(path, parts, layout="prusa", materials=None, object_name=None, title=None,
              application="metamaterial_wb", share_meshes=False):
    """Write a 3MF file atomically. Returns the path.

    ``share_meshes`` (``"components"`` layout): a part that is a rigid copy of an earlier one (equal
    triangles, vertices within 1e-6 mm of a rotated and shifted copy) is written as a component of
    the earlier mesh with a transform instead of a mesh of its own. Off by default: PrusaSlicer 2.5
    places every copy right but gives only the first object made from a mesh its per-object
    extruder (tests/fabrication/test_export.py), and Cura and Bambu Studio / OrcaSlicer name a
    component after its mesh, so copies would lose their part names.
    """
    from metamaterial_wb.core.fileio import write_atomic

    name = object_name or os.path.splitext(os.path.basename(os.fspath(path)))[0]
    data = build_3mf_bytes(parts, layout=layout, materials=materials, object_name=name, title=title,
                           application=application, share_meshes=share_meshes)
    write_atomic(path, data, mode="wb")
    return path
