"""STEP export without a GUI: one named body per part inside an assembly, with colours.

FreeCAD 0.20's headless ``Import.export`` writes names and the assembly (AP214) but no colours
(colours live in view providers). :func:`colorize_step` adds them afterwards as plain STEP text:
for every product whose name is in the colour table it follows PRODUCT -> PRODUCT_DEFINITION_FORMATION
-> PRODUCT_DEFINITION -> PRODUCT_DEFINITION_SHAPE -> SHAPE_DEFINITION_REPRESENTATION -> its
representation's MANIFOLD_SOLID_BREP items and appends the style chain OCCT itself writes
(COLOUR_RGB ... STYLED_ITEM) inside a MECHANICAL_DESIGN_GEOMETRIC_PRESENTATION_REPRESENTATION.
"""
import os
import re
import tempfile

from metamaterial_wb.core.errors import MetamaterialError
from metamaterial_wb.core.materials import hex_to_rgb

_ENTITY = re.compile(r"#(\d+)\s*=\s*([A-Z0-9_]*)\s*\((.*)\)\s*$", re.S)
_REF = re.compile(r"#(\d+)")


def _hex_to_rgb(c):
    return hex_to_rgb(c if str(c).startswith("#") else f"#{c}")


def colorize_step(text, colours):
    """Return STEP ``text`` with a colour style on the solids of every product named in ``colours``
    (``{product name: "#RRGGBB"}``). Products not in the table stay uncoloured."""
    start = text.find("DATA;")
    end = text.rfind("ENDSEC;")
    if start < 0 or end < start:
        raise MetamaterialError("STEP colours: no DATA section in the exported file")
    data = text[start + 5:end]
    ents = {}
    for chunk in data.split(";"):
        chunk = chunk.strip()
        m = _ENTITY.match(chunk)
        if m:
            ents[int(m.group(1))] = (m.group(2), m.group(3))
    by_type = {}
    for eid, (typ, body) in ents.items():
        by_type.setdefault(typ, []).append(eid)

    def refs(eid):
        return [int(x) for x in _REF.findall(ents[eid][1])]

    product_name = {}
    for eid in by_type.get("PRODUCT", []):
        m = re.match(r"\s*'((?:[^']|'')*)'", ents[eid][1])
        if m:
            product_name[eid] = m.group(1).replace("''", "'")
    # reverse links along the chain
    pdf_of = {}
    for typ in ("PRODUCT_DEFINITION_FORMATION", "PRODUCT_DEFINITION_FORMATION_WITH_SPECIFIED_SOURCE"):
        for eid in by_type.get(typ, []):
            r = refs(eid)
            if r:
                pdf_of[r[0]] = eid
    pd_of = {}
    for eid in by_type.get("PRODUCT_DEFINITION", []):
        r = refs(eid)
        if r:
            pd_of[r[0]] = eid
    pds_of = {}
    for eid in by_type.get("PRODUCT_DEFINITION_SHAPE", []):
        r = refs(eid)
        if r:
            pds_of.setdefault(r[0], eid)
    rep_of = {}
    for eid in by_type.get("SHAPE_DEFINITION_REPRESENTATION", []):
        r = refs(eid)
        if len(r) >= 2:
            rep_of[r[0]] = r[1]
    next_id = max(ents) + 1 if ents else 1
    out = []
    styled_by_ctx = {}
    cache_colour = {}
    for pid, name in product_name.items():
        if name not in colours:
            continue
        try:
            rep = rep_of[pds_of[pd_of[pdf_of[pid]]]]
        except KeyError:
            continue
        rrefs = refs(rep)
        ctx = rrefs[-1]
        breps = [x for x in rrefs[:-1] if ents.get(x, ("",))[0] in ("MANIFOLD_SOLID_BREP", "BREP_WITH_VOIDS")]
        if not breps:
            continue
        colour = colours[name]
        if colour not in cache_colour:
            r, g, b = _hex_to_rgb(colour)
            ids = list(range(next_id, next_id + 7))
            next_id += 7
            out += [f"#{ids[0]} = COLOUR_RGB('',{r:.6f},{g:.6f},{b:.6f});",
                    f"#{ids[1]} = FILL_AREA_STYLE_COLOUR('',#{ids[0]});",
                    f"#{ids[2]} = FILL_AREA_STYLE('',(#{ids[1]}));",
                    f"#{ids[3]} = SURFACE_STYLE_FILL_AREA(#{ids[2]});",
                    f"#{ids[4]} = SURFACE_SIDE_STYLE('',(#{ids[3]}));",
                    f"#{ids[5]} = SURFACE_STYLE_USAGE(.BOTH.,#{ids[4]});",
                    f"#{ids[6]} = PRESENTATION_STYLE_ASSIGNMENT((#{ids[5]}));"]
            cache_colour[colour] = ids[6]
        psa = cache_colour[colour]
        for brep in breps:
            out.append(f"#{next_id} = STYLED_ITEM('color',(#{psa}),#{brep});")
            styled_by_ctx.setdefault(ctx, []).append(next_id)
            next_id += 1
    for ctx, items in styled_by_ctx.items():
        lst = ",".join(f"#{k}" for k in items)
        out.append(f"#{next_id} = MECHANICAL_DESIGN_GEOMETRIC_PRESENTATION_REPRESENTATION('',({lst}),#{ctx});")
        next_id += 1
    if not out:
        return text
    return text[:end] + "\n".join(out) + "\n" + text[end:]


def write_step(path, bodies, assembly_name="structure", colours=True):
    """Write ``bodies`` = ``[(name, shape, colour_hex_or_None)]`` (shapes already at their place) as one
    STEP assembly named ``assembly_name`` with one named body per entry. Atomic."""
    from metamaterial_wb.core.fileio import write_atomic
    from metamaterial_wb.geometry.fc import freecad

    App, Part = freecad()
    import Import

    names = [b[0] for b in bodies]
    if len(set(names)) != len(names):
        raise MetamaterialError("STEP: body names must be unique")
    if not bodies:
        raise MetamaterialError("STEP: nothing to write (no bodies)")
    active = App.ActiveDocument            # closing the helper document must not leave none active
    try:
        doc = App.newDocument("mmwb_step_export", hidden=True)
    except TypeError:                      # older FreeCAD without the keyword
        doc = App.newDocument("mmwb_step_export")
    try:
        asm = doc.addObject("App::Part", "Assembly")
        asm.Label = assembly_name
        objs = []
        for k, (name, shape, _) in enumerate(bodies):
            o = doc.addObject("Part::Feature", f"b{k}")
            o.Label = name
            o.Shape = shape
            objs.append(o)
        asm.addObjects(objs)
        fd, tmp = tempfile.mkstemp(suffix=".step", prefix=".mmwb-")
        os.close(fd)
        try:
            Import.export([asm], tmp)
            with open(tmp, encoding="utf-8", errors="replace") as f:
                text = f.read()
        finally:
            os.unlink(tmp)
        if colours:
            table = {name: col for (name, _, col) in bodies if col}
            text = colorize_step(text, table)
        write_atomic(path, text)
    finally:
        App.closeDocument(doc.Name)
        if active is not None and active.Name in App.listDocuments():
            App.setActiveDocument(active.Name)
    return path


def result_bodies(result, parts):
    """``[(name, placed unique copy of the shape, colour)]`` for STEP from a BuildResult."""
    from metamaterial_wb.core.materials import MATERIALS

    out = []
    for part in parts:
        shape = result.shapes[part.key].copy()
        shape.Placement = part.placement
        out.append((part.name, shape, MATERIALS.get(part.material)))
    return out
