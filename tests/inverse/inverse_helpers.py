"""Shared helpers of the inverse-design tests (planted answers)."""
import numpy as np

from metamaterial_wb.core import design
from metamaterial_wb.core.models import run_model
from metamaterial_wb.core.scene import Scene


def scene_with(base, acts, constraints=()):
    """``base`` (a Scene or an example path) with actuators ``[(joint, value)]`` and constraints."""
    s = Scene.load(base) if isinstance(base, str) else base
    d = s.to_dict()
    d["actuators"] = [{"name": f"m{k + 1}", "joint": j, "value": v} for k, (j, v) in enumerate(acts)]
    d["constraints"] = [{"name": f"c{k + 1}", "joint": j, "value": v} for k, (j, v) in enumerate(constraints)]
    s = Scene.from_dict(d)
    design.ensure_configured(s)
    return s


def planted_result(scene, model="quadratic"):
    from metamaterial_wb.cli.solve import result_dict
    return result_dict(scene, run_model(model, scene), None, model)


def write_stl(path, tri):
    tri = np.asarray(tri, dtype=float)
    with open(path, "w") as f:
        f.write("solid t\n")
        for t in tri:
            nrm = np.cross(t[1] - t[0], t[2] - t[0])
            nrm = nrm / (np.linalg.norm(nrm) or 1.0)
            f.write(f" facet normal {nrm[0]:.17g} {nrm[1]:.17g} {nrm[2]:.17g}\n  outer loop\n")
            for v in t:
                f.write(f"   vertex {v[0]:.17g} {v[1]:.17g} {v[2]:.17g}\n")
            f.write("  endloop\n endfacet\n")
        f.write("endsolid t\n")


def grid_surface(scene, pos, margin=0.0):
    """Triangles through the node centres of a grid scene (the sheet's mid-surface)."""
    topo = scene.topology
    ij = topo.node_ij()
    tri = []
    for k, (i, j) in enumerate(ij):
        a = topo.node_id(i, j)
        b = topo.node_id(i, j + 1)
        c = topo.node_id(i + 1, j)
        d = topo.node_id(i + 1, j + 1)
        if min(a, b, c, d) >= 0:
            tri.append([pos[a], pos[b], pos[d]])
            tri.append([pos[a], pos[d], pos[c]])
    return np.array(tri)
