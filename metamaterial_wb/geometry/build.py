"""Build the parts of a scene: the sheet (nodes + hinges) and its modules, each unique shape once.

    result = build_scene(scene)              # validates everything first, then builds
    result.groups()                          # {"sheet": [PlacedPart...], "servo_housing_1": [...], ...}
    result.placed_shape(part)                # the part's solid at its place (FreeCAD Part.Shape)

Shapes are cached by a key made of their parameters: a 20 x 20 sheet has 1281 parts but only a
few dozen unique shapes; copies are placed by transform.
"""
import time

from metamaterial_wb.core.design import effective_tilts_deg
from metamaterial_wb.core.fabrication import fabrication_params
from metamaterial_wb.geometry.parts import BuildResult, PlacedPart  # noqa: F401  (re-exported)
from metamaterial_wb.geometry.progress import Progress, note


def node_part_name(i, j):
    return f"node_{i}_{j}"


def hinge_part_name(kind, i, j):
    return f"hinge_{kind}{i}_{j}"


def build_scene(scene, modules=True, progress=True, stream=None, params=None, **overrides):
    """Validate the scene's fabrication parameters and modules, then build every part.

    Raises SceneError (before any geometry) for invalid parameters. ``modules=False`` builds the
    sheet only.
    """
    from metamaterial_wb.geometry import modules as mod

    t0 = time.perf_counter()
    p = params if params is not None else fabrication_params(scene, effective_tilts_deg(scene), **overrides)
    specs = mod.parse_modules(scene, p) if modules else []
    t_valid = time.perf_counter() - t0
    res = BuildResult(scene, p)
    res.modules = specs
    res.timings["validate_s"] = t_valid
    _build_sheet(res, progress, stream)
    t1 = time.perf_counter()
    for spec in specs:
        mod.build_module(res, spec)
    res.timings["modules_s"] = time.perf_counter() - t1
    if specs:
        note(f"{len(specs)} module(s), {sum(1 for q in res.parts if q.role == 'module')} part(s)", progress, stream)
    res.timings["build_s"] = time.perf_counter() - t0
    return res


def _build_sheet(res, progress, stream):
    from metamaterial_wb.geometry.fc import freecad
    from metamaterial_wb.geometry import sheet

    App, _ = freecad()
    V = App.Vector
    scene, p = res.scene, res.params
    topo = scene.topology
    spec_by_key = {h.key(): h for h in p.hinges.values()}
    prog = Progress("sheet parts", topo.n_nodes + topo.n_joints, stream=stream, enabled=progress)
    t0 = time.perf_counter()
    for (i, j) in topo.nodes:
        feats = sheet.node_features(topo, (i, j), p)
        fkey = tuple(sorted(f[:6] for f in feats))
        key = ("node", fkey)
        if key not in res.shapes:
            res.shapes[key] = sheet.make_node(p, fkey, spec_by_key.__getitem__)
        cx, cy = sheet.node_centre(i, j, p)
        res.parts.append(PlacedPart(node_part_name(i, j), "node", p.rigid_material, p.rigid_extruder, key,
                                    App.Placement(V(cx, cy, 0.0), App.Rotation()), "sheet",
                                    {"node": f"N{i},{j}", "hinges": [f[6] for f in feats]}))
        prog.step()
    t1 = time.perf_counter()
    for (kind, i, j), name in zip(topo.joints, topo.joint_names):
        h = p.hinges[name]
        x, y, ang, side = sheet.joint_frame(kind, i, j, p)
        key = ("hinge", h.key(), side)
        if key not in res.shapes:
            res.shapes[key] = sheet.make_hinge(p, h, side)
        res.parts.append(PlacedPart(hinge_part_name(kind, i, j), "hinge", p.flexible_material, p.flexible_extruder,
                                    key, App.Placement(V(x, y, 0.0), App.Rotation(V(0, 0, 1), ang)), "sheet",
                                    {"joint": name, "tilt_deg": h.tilt_deg, "side": side}))
        prog.step()
    t2 = time.perf_counter()
    n_unique = sum(1 for k in res.shapes if k[0] in ("node", "hinge"))
    prog.done(f" ({n_unique} unique shapes)")
    res.timings["nodes_s"] = t1 - t0
    res.timings["hinges_s"] = t2 - t1
