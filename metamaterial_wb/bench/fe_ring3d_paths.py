"""The curved FE ring's stored static paths (issue 18): the meshes, the path stored for each, where a dynamic run
snapped, and the path's convergence over the in-plane meshes (Richardson in the element size). Shared by the
section's report (``fe_ring3d``) and its corner-integrated part (``fe_ring3d_corner``)."""
import re

import numpy as np


def cell_geometry():
    """The seed's unit cell (the geometry every stored run used)."""
    from metamaterial_wb.core.sleeve.cell import CellGeometry
    return CellGeometry()


MESHES = {"r1": (1, 1), "r2": (2, 1), "r3": (3, 1), "r4": (4, 1), "layers2": (1, 2), "r2layers2": (2, 2)}
MESH_NAMES = {"r1": "r = 1", "r2": "r = 2", "r3": "r = 3", "r4": "r = 4", "layers2": "two bricks through the wall",
              "r2layers2": "r = 2 and two bricks through the wall"}

NUMBER = {1: "one", 2: "two", 3: "three", 4: "four", 5: "five", 6: "six"}


def stop_reason(stopped, curve=None):
    """Why a stored ccx run stopped, in a few words: its ``*ERROR`` line, else for a solver exit (``ccx.run``'s
    message ends with the cut-off tail of ccx's output) the exit code and, from the stored ``curve``, how small
    the last increments had become and how flat the force was there (a limit or a bifurcation ahead)."""
    text = (stopped or "").strip()
    if not text:
        return ""
    err = re.search(r"\*ERROR[^\n]*", text)
    if err:
        return err.group(0).strip()
    code = re.search(r"exit code (-?\d+)", text)
    if not code:
        return text.splitlines()[0].strip()
    s = f"ccx gave up, exit code {code.group(1)}"
    if curve and len(curve["d"]) > 6:
        d, F = np.asarray(curve["d"], float), np.asarray(curve["F"], float)
        step = np.diff(d)[-5:].mean()
        k0 = F[1] / d[1]
        j = int(np.searchsorted(d, d[-1] - 0.005))
        k1 = (F[-1] - F[j]) / max(d[-1] - d[j], 1e-30)
        s += (f", its increments cut to {step:.1e} d/L, the force flat at {1e3 * F[-1]:.3f}e-3 (its slope over the "
              f"last 0.005 d/L {100 * k1 / k0:.0f} % of the initial one)")
    return s


def tilt_facts(d, deg):
    """Largest tilt of the top plate and where it passes 1 degree (a sentence's piece)."""
    d, deg = np.asarray(d, float)[:len(deg)], np.asarray(deg, float)
    on = np.nonzero(deg > 1.0)[0]
    k = int(np.argmax(deg))
    return (f"{deg[k]:.1f} deg at d/L {d[k]:.3f}, above 1 deg from d/L {d[on[0]]:.3f}" if len(on)
            else f"at most {deg[k]:.2f} deg")


def _kinds(ex):
    p = sum(1 for k in ex if k[0] == "peak")
    v = len(ex) - p
    return f"{p} peak{'s' if p != 1 else ''}, {v} valle{'ys' if v != 1 else 'y'}"


def snap(x, drop=0.05, window=0.0005):
    """The first place where the force falls by more than ``drop`` of its maximum so far within ``window`` of d/L
    (a dynamic snap in a displacement-controlled run), or None: {"i", "d0", "F0", "Fmin", "dd", "tilt0", "tilt1"}."""
    d, F = np.asarray(x["d"], float), np.asarray(x["F"], float)
    deg = np.asarray(x["tilt_deg"], float)
    for i in range(1, len(F)):
        j = np.flatnonzero((d > d[i]) & (d <= d[i] + window))
        if j.size and F[i] - F[j].min() > drop * F[:i + 1].max():
            k = i
            m = int(j[np.argmin(F[j])])
            return {"i": k, "d0": float(d[k]), "F0": float(F[k]), "Fmin": float(F[m]), "dd": float(d[m] - d[k]),
                    "tilt0": float(deg[min(k, len(deg) - 1)]), "tilt1": float(deg[-1])}
    return None


PATH_D = (0.05, 0.10, 0.14, 0.17, 0.22, 0.30, 0.40, 0.45)


def _path(c, mesh, suffix=""):
    """The static path stored for ``mesh`` (``p1_<mesh><suffix>``; r = 1 without a suffix: the trace up to its
    snap), or None."""
    if mesh == "r1" and not suffix:
        tr = c.get("trace")
        if tr is None:
            return None
        sn = snap(tr)
        k = sn["i"] + 1 if sn else len(tr["F"])
        return {"d": tr["d"][:k], "F": tr["F"][:k]}
    return c.get("p1_" + mesh + suffix)


def path_convergence(c, suffix="", points=PATH_D):
    """Force along the path on r = 1, 2, 3 (``p1_<mesh><suffix>``) at fixed d/L (``points`` and the r = 2 probes),
    extrapolated in h ~ 1/r, and P1 and the valley after it on each mesh: ``{"rows": [(d, [F per mesh or None],
    ext, err, n_meshes)], "p1": [(d, F)], "p1_ext": (d, F, err F, err d), "valley", "valley_ext", "figures"}``;
    ``"figures"``: the extrapolations' inputs as ``extrapolation.order_note`` takes them, ``{"rows": [...],
    "p1": [...], "valley": [...]}`` (:func:`order_note` words them)."""
    from metamaterial_wb.core.extrapolation import richardson3
    from metamaterial_wb.fe.sleeve2d import peak_valley
    meshes = [m for m in ("r1", "r2", "r3", "r4") if _path(c, m, suffix) is not None]
    paths = {m: _path(c, m, suffix) for m in meshes}
    rows, figures = [], {"rows": [], "p1": [], "valley": []}
    probes = set() if suffix else {round(v["d"], 3) for k, v in c.get("stability", {}).items()
                                   if k.startswith("r2@") and v.get("eigenvalues")}
    for d in sorted(set(points) | probes):
        vals = [float(np.interp(d, paths[m]["d"], paths[m]["F"])) if paths[m]["d"][-1] >= d - 1e-9 else None
                for m in meshes]
        have = [(MESHES[m][0], v) for m, v in zip(meshes, vals) if v is not None]
        if len(have) >= 2:
            h, v = [1.0 / r for r, _ in have], [v for _, v in have]
            ext, err, _ = richardson3(h, v)
            rows.append((d, vals, ext[0], err[0], len(have)))
            figures["rows"].append((f"d/L {d:.2f}", h, v))
        else:
            rows.append((d, vals, None, None, len(have)))
    pv = [peak_valley(paths[m]["d"], paths[m]["F"]) for m in meshes]

    def extrapolated(qs, name):
        ok = [(MESHES[m][0], q) for m, q in zip(meshes, qs) if np.isfinite(q[1])]
        if len(ok) < 2:
            return None
        h, v = [1.0 / r for r, _ in ok], [[q[0], q[1]] for _, q in ok]
        ext, err, _ = richardson3(h, v)
        figures[name.lower()].append(([f"{name} at d/L", name], h, v))
        return (ext[0], ext[1], err[1], err[0])
    p1, valley = [q[:2] for q in pv], [q[2:] for q in pv]
    return {"meshes": meshes, "rows": rows, "p1": p1, "p1_ext": extrapolated(p1, "P1"), "valley": valley,
            "valley_ext": extrapolated(valley, "valley"), "figures": figures}


def order_note(pc, parts=("rows", "p1", "valley")):
    """``extrapolation.order_note`` of the extrapolations a text shows from :func:`path_convergence`'s ``pc``
    (``parts`` of its ``"figures"``): ``""`` when every order was observed inside the range."""
    from metamaterial_wb.core.extrapolation import order_note as note
    return note([f for part in parts for f in pc["figures"][part]])
