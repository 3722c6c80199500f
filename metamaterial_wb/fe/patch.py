"""A small patch of the sheet in CalculiX: rigid plates joined by solid TPU hinges, actuated joints.

Every hinge of the lattice (``core.lattice.geometry.LatticeGeometry``: the beam from plate A's corner to plate
B's along the edge line) becomes a solid box ``rest x w x t`` of 20-node bricks (C3D20R) on that chord, in its
hinge frame. Plates are rigid bodies (PLA is ~130 times stiffer than TPU): every plate's rigid body holds the
end faces of the hinges it carries, with its reference node at the plate centre. An actuator prescribes the
relative rotation of its two plates about the sheet normal (``*EQUATION`` through a driver node) to the
lattice's own target, so the FE solves the same loading as the lattice models; the plate nearest the centre is
held. Geometrically nonlinear (``NLGEOM``), Neo-Hooke TPU. No plate contact: compare with the lattice models
run with ``contact=False`` (at amplitude 0.05 no hinge comes near contact).

Untilted (planar) scenes only.
"""

import numpy as np

from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.fe import ccx, checks
from metamaterial_wb.fe.mesh import box_union_mesh, graded
from metamaterial_wb.core.extrapolation import representative_size


def _hinge_box(rest, w, t, h, nz):
    return box_union_mesh([(0.0, rest, -w / 2, w / 2, -t / 2, t / 2)], hinge_lines(rest, w, t, h, nz))


def hinge_lines(rest, w, t, h, nz):
    """The grid lines ``(xs, ys, zs)`` of one hinge's box: element size ``h`` along it (``rest`` long) and across
    it (at least two elements across its width ``w``), ``nz`` elements through its thickness ``t``."""
    hw = min(h, w / 2.0)
    return graded(0.0, rest, h), graded(-w / 2, w / 2, hw), graded(-t / 2, t / 2, t / nz)


def patch_deck(scene, h=0.4, nz=4, increments=5, E=None, nu=None):
    """``(deck, meta)``: the ccx input for the scene's sheet and what is needed to read the answer (with
    ``element_mm``, the largest brick edges along, across and through the hinges, and ``h_eff_mm``, the cube root of
    the mean brick volume: the sizes the mesh has, ``h`` and ``nz`` being rounded up to whole counts per hinge)."""
    from metamaterial_wb.core.lattice.geometry import LatticeGeometry, fixed_items
    from metamaterial_wb.core.lattice.solve import _support_node

    h = checks.number("h", h, 0.0, None, "mm", low_open=True)
    nz = checks.integer("nz", nz, 1, 64, "elements through the hinge's thickness")
    increments = checks.integer("increments", increments, 1)
    geo = LatticeGeometry(scene)
    if not geo.planar:
        raise SceneError("joints", "the FE patch handles untilted hinges only (tilted hinges fold out of plane)")
    joints, values, psi, names = fixed_items(scene, geo)
    E = geo.E if E is None else checks.number("E", E, 0.0, None, "MPa", low_open=True)
    nu = geo.nu if nu is None else checks.poisson("nu", nu)
    rest = float(geo.rest)
    checks.element_count("h", h, sum((rest / h) * (w / min(h, w / 2.0)) * nz for w in np.asarray(geo.w, float)))
    nodes, elems, ends, sizes = [], [], {}, []
    base = 0
    for k in range(geo.m):
        box = _hinge_box(float(geo.rest), float(geo.w[k]), float(geo.t[k]), h, nz)
        sizes += [[float(np.diff(g).max()) for g in box.lines]] * box.n_elements
        Q = geo.Q0[k]
        pA = geo.X0[geo.a[k]] + geo.rA[k]
        X = pA + box.nodes @ Q.T
        nodes.append(X)
        elems.append(box.elements + base)
        for plate, face in ((geo.a[k], box.nodes_where(0, 0.0)), (geo.b[k], box.nodes_where(0, float(geo.rest)))):
            ends.setdefault(int(plate), []).append(face + base)
        base += box.n_nodes
    nodes = np.concatenate(nodes)
    elems = np.concatenate(elems)
    nn = nodes.shape[0]
    ref = {p: nn + 1 + 2 * i for i, p in enumerate(range(geo.n))}
    rot = {p: nn + 2 + 2 * i for i, p in enumerate(range(geo.n))}
    drv0 = nn + 2 * geo.n + 1
    out = ["*HEADING\nmetamaterial_wb: sheet patch, rigid plates, solid TPU hinges\n*NODE\n", ccx.fmt_nodes(nodes)]
    for p in range(geo.n):
        x, y, z = geo.X0[p]
        out.append(f"{ref[p]},{x:.9g},{y:.9g},{z:.9g}\n{rot[p]},{x:.9g},{y:.9g},{z:.9g}\n")
    for i in range(len(joints)):
        out.append(f"{drv0 + i},0,0,0\n")
    out.append("*ELEMENT, TYPE=C3D20R, ELSET=TPU\n")
    out.append(ccx.fmt_elements(elems, np.arange(1, elems.shape[0] + 1)))
    for p in range(geo.n):
        if p in ends:
            out += [f"*NSET, NSET=P{p}\n", ccx.fmt_set(np.unique(np.concatenate(ends[p])) + 1)]
    out.append("*NSET, NSET=NREF\n" + ccx.fmt_set([ref[p] for p in range(geo.n)]))
    out.append("*NSET, NSET=NROT\n" + ccx.fmt_set([rot[p] for p in range(geo.n)]))
    G = E / (2 * (1 + nu))
    K = E / (3 * (1 - 2 * nu))
    out.append(f"*MATERIAL, NAME=TPU\n*HYPERELASTIC, NEO HOOKE\n{G / 2:.9g},{2.0 / K:.9g}\n")
    out.append("*SOLID SECTION, ELSET=TPU, MATERIAL=TPU\n")
    for p in range(geo.n):
        if p in ends:
            out.append(f"*RIGID BODY, NSET=P{p}, REF NODE={ref[p]}, ROT NODE={rot[p]}\n")
    # actuators: rot_z(B) - rot_z(A) - driver = 0, driver prescribed to the lattice's target psi. The first
    # term of an equation is its dependent DOF (ccx): never the held plate, never twice the same plate
    sup = _support_node(geo)
    dependent = set()
    for i, j in enumerate(joints):
        A, B = int(geo.a[j]), int(geo.b[j])
        terms = [(rot[B], 1.0, B), (rot[A], -1.0, A)]
        terms.sort(key=lambda x: (x[2] == sup or x[2] in dependent))
        if terms[0][2] == sup or terms[0][2] in dependent:
            raise SceneError(names[i], "the FE patch cannot drive this joint (both plates already carry an actuator "
                                       "or the held plate)")
        dependent.add(terms[0][2])
        eq = ",".join(f"{n},3,{c:g}" for n, c, _ in terms)
        out.append(f"*EQUATION\n3\n{eq},{drv0 + i},1,-1.0\n")
    inc = 1.0 / increments
    bc = f"{ref[sup]},1,3,0\n{rot[sup]},1,3,0\n"
    bc += "".join(f"{drv0 + i},1,1,{float(psi[i]):.12g}\n" for i in range(len(joints)))
    out.append(f"*STEP, NLGEOM, INC=1000\n*STATIC\n{inc:.6g},1.0,{inc / 64:.6g},{inc:.6g}\n*BOUNDARY\n{bc}"
               "*NODE PRINT, NSET=NREF\nU\n*NODE PRINT, NSET=NROT\nU\n*END STEP\n")
    meta = {"geo": geo, "ref": ref, "rot": rot, "support": sup, "dofs": 3 * nn, "elements": int(elems.shape[0]),
            "h_mm": h, "nz": nz, "element_mm": np.max(sizes, axis=0).tolist(), "h_eff_mm": representative_size(sizes)}
    return "".join(out), meta


class FEPatchResult:
    """Plate rotations ``phi`` (about the sheet normal, radians), ``positions_mm`` of the plate centres,
    ``rotations`` (n, 3, 3), and the run info; what :func:`metamaterial_wb.bench.fidelity.compare` reads."""

    def __init__(self, phi, positions, info):
        self.phi = np.asarray(phi, float)
        self.positions_mm = np.asarray(positions, float)
        c, s = np.cos(self.phi), np.sin(self.phi)
        R = np.zeros((self.phi.size, 3, 3))
        R[:, 0, 0], R[:, 0, 1], R[:, 1, 0], R[:, 1, 1], R[:, 2, 2] = c, -s, s, c, 1.0
        self.rotations = R
        self.info = info
        self.converged = True


def solve_patch(scene, h=0.4, nz=4, increments=5, timeout_s=1800.0):
    """Run the patch through ccx; an :class:`FEPatchResult` (final increment)."""
    deck, meta = patch_deck(scene, h, nz, increments)
    tables, info = ccx.run(deck, "patch", timeout_s)
    geo = meta["geo"]
    u_rows = ccx.table(tables, ("displacements", "NREF"), "patch", list(meta["ref"].values()))
    u = u_rows[-1][1]
    r = ccx.table(tables, ("displacements", "NROT"), "patch", list(meta["rot"].values()))[-1][1]
    X = np.array([geo.X0[p] + u[meta["ref"][p]] for p in range(geo.n)])
    phi = np.array([r[meta["rot"][p]][2] for p in range(geo.n)])
    info.update({k: meta[k] for k in ("dofs", "elements", "h_mm", "nz", "element_mm", "h_eff_mm")})
    info["increments"] = len(u_rows)
    info["max_out_of_plane_rotation_rad"] = float(max(np.abs(r[meta["rot"][p]][:2]).max() for p in range(geo.n)))
    return FEPatchResult(phi, X, info)


def patch_scene(amplitude, n=3):
    """The n x n patch with two actuated joints (the FE rung's validation scene)."""
    from metamaterial_wb.core.scene import Scene
    return Scene.from_dict({"format": "metamaterial-scene", "version": 1, "name": f"fe-patch-{n}x{n}",
                            "description": "FE rung: n x n patch, two actuated joints", "layout": {"grid": [n, n]},
                            "actuators": [{"name": "m1", "joint": "H1,0", "value": amplitude},
                                          {"name": "m2", "joint": f"H{n - 1},{n - 1}", "value": -amplitude}]})


__all__ = ["patch_deck", "solve_patch", "patch_scene", "FEPatchResult"]
