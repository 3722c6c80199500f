"""Checks of a BuildResult: valid closed solids, rigid/flexible overlap only at the anchors, modules
clear of the sheet in the rest state. Each returns a list of problems (empty = fine)."""
import math

VOLUME_TOL_MM3 = 1e-3


def check_solids(result):
    """Every unique shape: valid, exactly one solid, closed shells, positive volume."""
    problems = []
    for key, shape in result.shapes.items():
        what = f"shape {key[0]} {key[1] if len(key) > 1 else ''}"
        if not shape.isValid():
            problems.append(f"{what}: not a valid B-rep")
        if len(shape.Solids) != 1:
            problems.append(f"{what}: {len(shape.Solids)} solids instead of 1")
        if not all(sh.isClosed() for sh in shape.Shells):
            problems.append(f"{what}: a shell is open")
        if not shape.Volume > 0:
            problems.append(f"{what}: volume {shape.Volume}")
    return problems


def _placed(result, parts):
    return [(q, result.placed_shape(q)) for q in parts]


def _bbox_hit(a, b, grow=0.0):
    return (a.XMin - grow <= b.XMax and b.XMin - grow <= a.XMax and a.YMin - grow <= b.YMax and
            b.YMin - grow <= a.YMax and a.ZMin - grow <= b.ZMax and b.ZMin - grow <= a.ZMax)


def check_sheet(result):
    """Rigid and flexible bodies share no volume; a hinge touches only its own two nodes; the part of a
    hinge inside the node plates' envelope equals its two anchors (closed form)."""
    from metamaterial_wb.geometry import sheet
    from metamaterial_wb.geometry.fc import freecad
    from metamaterial_wb.core.fabrication import anchor_width_mm, neck_width_mm

    App, Part = freecad()
    p = result.params
    s, T = p.plate_side_mm_global, p.sheet_thickness_mm
    nodes = _placed(result, [q for q in result.parts if q.role == "node"])
    hinges = _placed(result, [q for q in result.parts if q.role == "hinge"])
    by_node = {q.info["node"]: (q, sh) for q, sh in nodes}
    problems = []
    from metamaterial_wb.core.scene import parse_joint, joint_nodes
    for hq, hs in hinges:
        kind, i, j = parse_joint(hq.info["joint"])
        own = {f"N{a},{b}" for (a, b) in joint_nodes(kind, i, j)}
        for nq, ns in nodes:
            if not _bbox_hit(hs.BoundBox, ns.BoundBox, 0.01):
                continue
            common = hs.common(ns).Volume
            if common > VOLUME_TOL_MM3:
                problems.append(f"{hq.name} and {nq.name} share {common:.4g} mm3 of material")
            if nq.info["node"] not in own and hs.distToShape(ns)[0] < 1e-6:
                problems.append(f"{hq.name} touches {nq.name}, which is not one of its nodes")
        h = p.hinges[hq.info["joint"]]
        anchor = (p.anchor_depth_mm * anchor_width_mm(p, h) + p.anchor_neck_mm * neck_width_mm(h)) * h.thickness_mm
        for name in sorted(own):
            nq, _ = by_node[name]
            cx, cy = nq.placement.Base.x, nq.placement.Base.y
            env = Part.makeBox(s, s, T, App.Vector(cx - 0.5 * s, cy - 0.5 * s, 0.0))
            inside = hs.common(env).Volume
            if abs(inside - anchor) > 1e-3 * max(anchor, 1.0):
                problems.append(f"{hq.name}: {inside:.4g} mm3 inside {nq.name}'s plate, expected the anchor's "
                                f"{anchor:.4g} mm3")
        # nothing of the hinge outside its own two plates and the gap between them
    for k, (aq, a) in enumerate(hinges):
        for bq, b in hinges[k + 1:]:
            if _bbox_hit(a.BoundBox, b.BoundBox) and a.common(b).Volume > VOLUME_TOL_MM3:
                problems.append(f"hinges {aq.name} and {bq.name} overlap")
    return problems


def _where(result, shape):
    """``"node N<i>,<j> (socket <L>)"``: the node (and nearest socket) under a shape's centre."""
    from metamaterial_wb.geometry.sheet import socket_positions
    p = result.params
    solids = shape.Solids
    c = solids[0].CenterOfMass if len(solids) == 1 else shape.BoundBox.Center
    j, i = round(c.x / p.cell_size_mm), round(-c.y / p.cell_size_mm)
    if (i, j) not in result.scene.topology.node_index:
        return "between the nodes"
    dx, dy = c.x - j * p.cell_size_mm, c.y + i * p.cell_size_mm
    lab = min(socket_positions(p), key=lambda t: (t[1] - dx) ** 2 + (t[2] - dy) ** 2)[0]
    return f"node N{i},{j} (near socket {lab})"


def _turn_about(gp, axis, deg):
    from metamaterial_wb.geometry.fc import freecad
    App, _ = freecad()
    return App.Placement(gp, App.Rotation(axis, deg)).multiply(App.Placement(-gp, App.Rotation()))


def _sheet_collisions(mq, ms, sheet_parts, turned, only_node=None):
    """Collisions of module part ``mq`` (solid ``ms``) with the sheet; ``turned`` = (node B, rotation, joint) of a
    clip (node B turned, the clip's own hinge skipped); ``only_node``: check that node only."""
    out = []
    for sq, ss in sheet_parts:
        if only_node is not None and sq.info.get("node") != only_node:
            continue
        if turned is not None:
            if sq.info.get("joint") == turned[2]:
                continue
            if sq.info.get("node") == turned[0]:
                ss = ss.transformed(turned[1].toMatrix())
        if not _bbox_hit(ms.BoundBox, ss.BoundBox):
            continue
        common = ms.common(ss)
        if common.Volume > VOLUME_TOL_MM3:
            what = sq.info.get("node") or f"hinge {sq.info.get('joint')}"
            seated = " seated" if only_node is not None else ""
            out.append(f"module {mq.group!r} (part {mq.name}{seated}) collides with the sheet's {what} "
                       f"({sq.name}, {common.Volume:.4g} mm3)")
    return out


def check_modules(result, sweep_steps=8):
    """Modules share no volume with the sheet (rest state) nor with each other; a collision names both
    modules and where. A constraint clip is checked against its second node turned by the clip angle
    about the joint's pivot (the state it holds), its own joint's hinge excluded (that hinge bends); its rivets
    that wait above node B's sockets on the flat sheet are checked there and, seated, against node B turned.
    A servo's horn adapter is turned about the shaft through the servo's design range against its
    housing (``sweep_steps`` angles each way)."""
    from metamaterial_wb.geometry.fc import freecad

    App, _ = freecad()
    V = App.Vector
    sheet_parts = _placed(result, [q for q in result.parts if q.group == "sheet"])
    mods = _placed(result, [q for q in result.parts if q.role == "module"])
    spec_by_name = {m.name: m for m in result.modules}
    problems = []
    for mq, ms in mods:
        spec = spec_by_name.get(mq.group)
        turned = None
        if spec is not None and spec.type == "constraint_clip":
            x, y, _ = spec.pivot.point_mm
            rot = _turn_about(V(x, y, 0.0), V(0, 0, 1), spec.values["angle_deg"])
            turned = (f"N{spec.b[0]},{spec.b[1]}", rot, spec.joint)
        checks = [(ms, None)]
        if turned is not None and mq.info.get("lifted_mm"):
            # a rivet waiting above node B's socket (flat sheet): also seated, against node B turned (held state)
            checks.append((ms.translated(V(0, 0, -mq.info["lifted_mm"])), turned[0]))
        for shape, only_node in checks:
            problems += _sheet_collisions(mq, shape, sheet_parts, turned, only_node)
    for k, (aq, a) in enumerate(mods):
        for bq, b in mods[k + 1:]:
            if aq.group == bq.group or not _bbox_hit(a.BoundBox, b.BoundBox):
                continue
            common = a.common(b)
            if common.Volume > VOLUME_TOL_MM3:
                problems.append(f"modules {aq.group!r} and {bq.group!r} collide on {_where(result, common)}: parts "
                                f"{aq.name} and {bq.name} share {common.Volume:.4g} mm3")
    for spec in result.modules:
        if spec.type != "servo_housing":
            continue
        parts = {q.name: s for q, s in mods if q.group == spec.name}
        housing, adapter = parts.get(f"{spec.name}_housing"), parts.get(f"{spec.name}_horn_adapter")
        if housing is None or adapter is None:
            continue
        x, y, _ = spec.pivot.point_mm
        lo, hi = spec.pivot.range_deg
        # the range is B relative to A (the joint's own order); the adapter sits on spec.b
        sign = 1.0 if spec.b == _second_node(spec.joint) else -1.0
        angles = sorted(set([0.0] + [lo * k / sweep_steps for k in range(1, sweep_steps + 1)] +
                            [hi * k / sweep_steps for k in range(1, sweep_steps + 1)]))
        for ang in angles:
            moved = adapter.transformed(_turn_about(V(x, y, 0.0), V(0, 0, 1), sign * ang).toMatrix())
            vol = moved.common(housing).Volume
            if vol > VOLUME_TOL_MM3:
                problems.append(f"module {spec.name!r}: the horn adapter hits the housing when the servo turns "
                                f"node B by {ang:.3g} deg ({vol:.4g} mm3; design range {lo:.3g}..{hi:.3g} deg)")
                break
    return problems


def _second_node(joint):
    from metamaterial_wb.core.scene import joint_nodes, parse_joint
    return joint_nodes(*parse_joint(joint))[1]


DEFAULT_CHECKS = ("solids", "modules")
ALL_CHECKS = ("solids", "sheet", "modules")


def check_build(result, checks=DEFAULT_CHECKS):
    """Run the named checks; returns ``(problems, ran)``. The default set (every ``build`` and the
    GUI's export) checks the unique solids and the modules (collisions with the sheet and each other,
    the servo's rotation); ``"sheet"`` adds the rigid/flexible overlap check of every hinge (slow on
    large sheets: ``build --check``)."""
    problems, ran = [], []
    for name in checks:
        if name == "solids":
            problems += check_solids(result)
        elif name == "sheet":
            problems += check_sheet(result)
        elif name == "modules":
            if not result.modules:
                continue
            problems += check_modules(result)
        else:
            raise ValueError(f"unknown check {name!r}; allowed: {ALL_CHECKS}")
        ran.append(name)
    return problems, ran


def check_all(result):
    return check_build(result, ALL_CHECKS)[0]


def angle_between_deg(a, b):
    return math.degrees(math.atan2(a[0] * b[1] - a[1] * b[0], a[0] * b[0] + a[1] * b[1]))
