"""STEP export without a GUI: one named body per part inside an assembly, with colours.

:func:`write_step_instanced` (what ``build`` writes) writes each unique shape's B-rep once and every
part as a named product placed by its assembly transformation (:func:`instanced_step_text`): a
20 x 20 sheet (1281 parts, 16 unique shapes) in 3 MB instead of 87 MB (docs/benchmarks.md).
:func:`write_step` (one full B-rep per body) stays for one-off bodies (sleeves).

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


def _export_assembly(assembly_name, labelled_shapes):
    """STEP text of one assembly ``assembly_name`` holding ``[(label, shape)]`` as FreeCAD's exporter writes
    it: a hidden helper document (closed again, the user's active document restored), a temporary
    ``.mmwb-<pid>-*.step`` file (stale ones of exports killed with SIGKILL are swept first)."""
    from metamaterial_wb.core.fileio import sweep_stale, temp_prefix
    from metamaterial_wb.geometry.fc import freecad

    App, Part = freecad()
    import Import

    active = App.ActiveDocument            # closing the helper document must not leave none active
    try:
        doc = App.newDocument("mmwb_step_export", hidden=True)
    except TypeError:                      # older FreeCAD without the keyword
        doc = App.newDocument("mmwb_step_export")
    try:
        asm = doc.addObject("App::Part", "Assembly")
        asm.Label = assembly_name
        objs = []
        for k, (label, shape) in enumerate(labelled_shapes):
            o = doc.addObject("Part::Feature", f"b{k}")
            o.Label = label
            o.Shape = shape
            objs.append(o)
        asm.addObjects(objs)
        sweep_stale(tempfile.gettempdir())
        fd, tmp = tempfile.mkstemp(suffix=".step", prefix=temp_prefix("mmwb"))
        os.close(fd)
        try:
            Import.export([asm], tmp)
            with open(tmp, encoding="utf-8", errors="replace") as f:
                return f.read()
        finally:
            os.unlink(tmp)
    finally:
        App.closeDocument(doc.Name)
        if active is not None and active.Name in App.listDocuments():
            App.setActiveDocument(active.Name)


def write_step(path, bodies, assembly_name="structure", colours=True):
    """Write ``bodies`` = ``[(name, shape, colour_hex_or_None)]`` (shapes already at their place) as one
    STEP assembly named ``assembly_name`` with one named body per entry. Atomic."""
    from metamaterial_wb.core.fileio import write_atomic

    names = [b[0] for b in bodies]
    if len(set(names)) != len(names):
        raise MetamaterialError("STEP: body names must be unique")
    if not bodies:
        raise MetamaterialError("STEP: nothing to write (no bodies)")
    text = _export_assembly(assembly_name, [(name, shape) for name, shape, _ in bodies])
    if colours:
        table = {name: col for (name, _, col) in bodies if col}
        text = colorize_step(text, table)
    write_atomic(path, text)
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


# ------------------------------------------------------------------------------------------------
# instanced assembly: each unique shape once, every part a named product that maps it into place
# ------------------------------------------------------------------------------------------------
def _entities(data):
    """``[(id, type, body)]`` of a STEP DATA section (entity bodies without ';': ours never hold one). A
    complex entity ``#n = ( A(...) B(...) )`` has the type ``""`` and its body keeps the outer brackets
    (ISO 10303-21 requires them; without, OCCT's reader reports "Incorrect Syntax")."""
    out = []
    for chunk in data.split(";"):
        chunk = chunk.strip()
        if not chunk:
            continue
        m = _ENTITY.match(chunk)
        if m and m.group(2):                    # (_ENTITY also matches "( ... )" with an empty type)
            out.append((int(m.group(1)), m.group(2), m.group(3)))
        else:                                   # complex entity: #n = ( A(...) B(...) )
            m2 = re.match(r"#(\d+)\s*=\s*(\(.*\))\s*$", chunk, re.S)
            if not m2:
                raise MetamaterialError(f"STEP instancing: cannot read entity {chunk[:60]!r}")
            out.append((int(m2.group(1)), "", m2.group(2)))
    return out


def _axis_text(eid, placement):
    """Entities of an AXIS2_PLACEMENT_3D ``#eid`` for a FreeCAD placement (ids eid .. eid + 3)."""
    m = placement.toMatrix()
    o = (m.A14, m.A24, m.A34)
    z = (m.A13, m.A23, m.A33)
    x = (m.A11, m.A21, m.A31)

    def real(c):                           # ISO 10303-21 reals: a decimal point, an upper-case exponent
        c = float(c)
        if abs(c) < 1e-15:
            return "0."
        t = repr(c).upper()
        if "." not in t:
            t = t.replace("E", ".E") if "E" in t else t + "."
        return t

    def f(v):
        return ",".join(real(c) for c in v)
    return [f"#{eid} = AXIS2_PLACEMENT_3D('',#{eid + 1},#{eid + 2},#{eid + 3});",
            f"#{eid + 1} = CARTESIAN_POINT('',({f(o)}));",
            f"#{eid + 2} = DIRECTION('',({f(z)}));",
            f"#{eid + 3} = DIRECTION('',({f(x)}));"]


def instanced_step_text(proto_text, proto_names, instances):
    """Turn FreeCAD's STEP of the unique shapes (one product per shape, named ``proto_names[key]``,
    under one top product) into the instanced assembly. Every instance ``(name, key, placement)``
    becomes a named product of the top assembly, placed by its assembly transformation, whose B-rep
    representation holds a MANIFOLD_SOLID_BREP of its own on the *shared* closed shell: the faces,
    edges and points of a unique shape are written once. (Sharing the whole representation -- one
    product per shape with named instances, or MAPPED_ITEMs -- makes OCCT's reader see one shape and
    FreeCAD names every instance after the first; an own solid per body keeps each body's name.)"""
    start = proto_text.find("DATA;")
    end = proto_text.rfind("ENDSEC;")
    if start < 0 or end < start:
        raise MetamaterialError("STEP instancing: no DATA section in the exported file")
    ents = _entities(proto_text[start + 5:end])
    body = {eid: (typ, b) for eid, typ, b in ents}

    def refs(eid):
        return [int(x) for x in _REF.findall(body[eid][1])]

    def first_str(eid):
        m = re.match(r"\s*'((?:[^']|'')*)'", body[eid][1])
        return m.group(1).replace("''", "'") if m else None

    by_type = {}
    for eid, (typ, _) in body.items():
        by_type.setdefault(typ, []).append(eid)
    prod_by_name = {first_str(e): e for e in by_type.get("PRODUCT", [])}
    pdf_of = {refs(e)[0]: e for e in by_type.get("PRODUCT_DEFINITION_FORMATION", [])}
    pd_of = {refs(e)[0]: e for e in by_type.get("PRODUCT_DEFINITION", [])}
    pds_of = {refs(e)[0]: e for e in by_type.get("PRODUCT_DEFINITION_SHAPE", []) if refs(e)}
    sdr_of = {refs(e)[0]: e for e in by_type.get("SHAPE_DEFINITION_REPRESENTATION", [])}
    nauo_of = {refs(e)[1]: e for e in by_type.get("NEXT_ASSEMBLY_USAGE_OCCURRENCE", [])}
    cdsr_of = {refs(e)[1]: e for e in by_type.get("CONTEXT_DEPENDENT_SHAPE_REPRESENTATION", [])}
    cat_of = {}
    for e in by_type.get("PRODUCT_RELATED_PRODUCT_CATEGORY", []):
        for r in refs(e):
            cat_of[r] = e
    drop = set()
    proto = {}                 # key -> (representation type, its origin, its context, [solid bodies])
    for key, pname in proto_names.items():
        prod = prod_by_name[pname]
        pd = pd_of[pdf_of[prod]]
        pds = pds_of[pd]
        sdr = sdr_of[pds]
        rep = refs(sdr)[1]
        rrefs = refs(rep)
        solids = [x for x in rrefs[:-1] if body[x][0] in ("MANIFOLD_SOLID_BREP", "BREP_WITH_VOIDS")]
        if not solids or len(solids) + 1 != len(rrefs) - 1:
            raise MetamaterialError(f"STEP instancing: shape {pname} is not a solid B-rep")
        proto[key] = (body[rep][0], rrefs[0], rrefs[-1], [body[x] for x in solids])
        drop |= {prod, pdf_of[prod], pd, pds, sdr, rep, cat_of.get(prod, -1)} | set(solids)
        nauo = nauo_of[pd]
        pl_pds = pds_of[nauo]
        cdsr = cdsr_of[pl_pds]
        rr = refs(cdsr)[0]
        drop |= {nauo, pl_pds, cdsr, rr}
        drop |= {r for r in refs(rr) if body[r][0] == "ITEM_DEFINED_TRANSFORMATION"}
    tops = [e for n, e in prod_by_name.items() if n not in proto_names.values()]
    if len(tops) != 1:
        raise MetamaterialError("STEP instancing: expected one top product")
    top_pd = pd_of[pdf_of[tops[0]]]
    top_rep = refs(sdr_of[pds_of[top_pd]])[1]
    prod_ctx = refs(tops[0])[-1]
    pd_ctx = refs(top_pd)[-1]
    out = []
    nid = max(body) + 1
    for name, key, placement in instances:
        rtype, origin, ctx, solids = proto[key]
        n = nid
        q = name.replace("'", "''")
        sol = [f"#{n + 6 + k}" for k in range(len(solids))]
        out += [f"#{n} = PRODUCT('{q}','{q}','',(#{prod_ctx}));",
                f"#{n + 1} = PRODUCT_DEFINITION_FORMATION('','',#{n});",
                f"#{n + 2} = PRODUCT_DEFINITION('design','',#{n + 1},#{pd_ctx});",
                f"#{n + 3} = PRODUCT_DEFINITION_SHAPE('','',#{n + 2});",
                f"#{n + 4} = SHAPE_DEFINITION_REPRESENTATION(#{n + 3},#{n + 5});",
                f"#{n + 5} = {rtype}('',(#{origin},{','.join(sol)}),#{ctx});"]
        out += [f"{sid} = {t}({b});" for sid, (t, b) in zip(sol, solids)]
        m = n + 6 + len(solids)
        out += [f"#{m} = PRODUCT_RELATED_PRODUCT_CATEGORY('part',$,(#{n}));",
                f"#{m + 1} = NEXT_ASSEMBLY_USAGE_OCCURRENCE('{q}','{q}','',#{top_pd},#{n + 2},$);",
                f"#{m + 2} = PRODUCT_DEFINITION_SHAPE('Placement','Placement of an item',#{m + 1});",
                f"#{m + 3} = CONTEXT_DEPENDENT_SHAPE_REPRESENTATION(#{m + 4},#{m + 2});",
                f"#{m + 4} = ( REPRESENTATION_RELATIONSHIP('','',#{n + 5},#{top_rep}) "
                f"REPRESENTATION_RELATIONSHIP_WITH_TRANSFORMATION(#{m + 5}) SHAPE_REPRESENTATION_RELATIONSHIP() );",
                f"#{m + 5} = ITEM_DEFINED_TRANSFORMATION('','',#{origin},#{m + 6});"]
        out += _axis_text(m + 6, placement)
        nid = m + 10
    kept = []
    for eid, typ, b in ents:
        if eid in drop:
            continue
        kept.append(f"#{eid} = {typ}({b});" if typ else f"#{eid} = {b};")
    return proto_text[:start + 5] + "\n" + "\n".join(kept + out) + "\n" + proto_text[end:]


def write_step_instanced(path, shapes, instances, assembly_name="structure", colours=None):
    """Write the instanced STEP assembly: ``shapes`` = ``{key: shape}`` (each written once, as built),
    ``instances`` = ``[(name, key, FreeCAD placement)]`` (every part a named body of the assembly),
    ``colours`` = ``{key: "#RRGGBB"}``. Atomic. Re-import gives one named body per instance."""
    from metamaterial_wb.core.fileio import write_atomic

    names = [i[0] for i in instances]
    if not instances:
        raise MetamaterialError("STEP: nothing to write (no bodies)")
    if len(set(names)) != len(names):
        raise MetamaterialError("STEP: body names must be unique")
    bad = [n for n in names if ";" in n or "\\" in n]
    if bad:
        raise MetamaterialError(f"STEP: body name {bad[0]!r} holds ';' or '\\'")
    used = list(dict.fromkeys(i[1] for i in instances))
    proto = {key: f"mmwb_shape_{k}" for k, key in enumerate(used)}
    text = _export_assembly(assembly_name, [(proto[key], shapes[key]) for key in used])
    text = instanced_step_text(text, proto, instances)
    if colours:
        by_key = {k: c for k, c in colours.items() if c}
        text = colorize_step(text, {name: by_key[key] for name, key, _ in instances if key in by_key})
    write_atomic(path, text)
    return path


def result_instances(result, parts):
    """``(shapes, instances, colours)`` for :func:`write_step_instanced` from a BuildResult."""
    from metamaterial_wb.core.materials import MATERIALS

    shapes = {q.key: result.shapes[q.key] for q in parts}
    colours = {q.key: MATERIALS.get(q.material) for q in parts}
    return shapes, [(q.name, q.key, q.placement) for q in parts], colours
