"""``solve SCENE.json --out RESULT.json [--set NAME=VALUE ...] [--global G]``."""
import math
import time

NAME = "solve"
HELP = "solve a scene: node deformations D and poses, written as JSON"


def add_arguments(p):
    p.add_argument("scene", help="scene file (JSON, docs/scene-format.md)")
    p.add_argument("--out", required=True, help="result file (JSON)")
    p.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                   help="change one actuator's or constraint's value (repeatable)")
    p.add_argument("--global", dest="global_g", type=float, default=None, metavar="G",
                   help="global deformation: every D = G in [-1, 1] (perfect propagation)")
    p.add_argument("--backend", default="auto", choices=("auto", "superlu", "cholmod", "dense"),
                   help="linear solver (default: CHOLMOD when installed, else SuperLU)")


def parse_sets(items):
    """``["m1=0.5", ...]`` -> ``[("m1", 0.5), ...]`` with clear errors."""
    from metamaterial_wb.core.errors import SceneError

    out = []
    for s in items:
        if "=" not in s:
            raise SceneError(f"--set {s}", "expected NAME=VALUE, e.g. --set m1=0.5")
        name, _, val = s.partition("=")
        try:
            v = float(val)
        except ValueError:
            raise SceneError(f"--set {name}", f"{val!r} is not a number") from None
        out.append((name.strip(), v))
    return out


def result_dict(scene, D, warnings, timings, global_g=None):
    """The result document shared by ``solve`` and the GUI's export of a solved state."""
    from metamaterial_wb.core import kinematics

    t = time.perf_counter()
    pos, R, phi = kinematics.node_poses(scene, D)
    timings = dict(timings)
    timings["kinematics_s"] = time.perf_counter() - t
    topo = scene.topology
    nodes = []
    for k, (i, j) in enumerate(topo.nodes):
        nodes.append({"i": i, "j": j, "name": f"N{i},{j}", "D": float(D[k]),
                      "rotation_deg": math.degrees(float(phi[k])),
                      "position_mm": [float(x) for x in pos[k]],
                      "rotation": [[float(x) for x in row] for row in R[k]]})
    return {"format": "metamaterial-result", "version": 1, "scene": scene.name,
            "global_deformation": global_g,
            "actuators": {a.name: a.value for a in scene.actuators},
            "constraints": {c.name: c.value for c in scene.constraints},
            "nodes": nodes, "warnings": list(warnings), "timings": timings}


def run(args):
    from metamaterial_wb.core.fileio import write_json
    from metamaterial_wb.core.scene import Scene
    from metamaterial_wb.core.solver import solve_scene

    t0 = time.perf_counter()
    scene = Scene.load(args.scene)
    for name, v in parse_sets(args.set):
        scene.set_value(name, v)
    g = args.global_g if args.global_g is not None else scene.global_deformation
    D, _, warnings, timings = solve_scene(scene, global_deformation=g, backend=args.backend)
    res = result_dict(scene, D, warnings, timings, g)
    res["timings"]["total_s"] = time.perf_counter() - t0
    write_json(args.out, res)
    for w in warnings:
        print(f"warning: {w}", file=__import__("sys").stderr)
    return 0
