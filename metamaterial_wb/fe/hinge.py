"""One TPU hinge between two PLA plates in CalculiX: its stiffness (the lattice's hinge law) and its
moment-rotation curve through the working range, against the beam theory the lattice uses.

Geometry (hinge frame of ``core/lattice/geometry``): ``x`` along the hinge (``e1``, length ``L``), ``y`` across
it in the sheet's plane (``e2``, the hinge width ``w``, the soft bending direction), ``z`` the sheet normal
(``e3``, the thickness ``t``). The hinge ``[0, L] x [-w/2, w/2] x [-t/2, t/2]`` is bonded to two PLA plate
blocks of length ``plate_len`` and width ``w + 2 plate_margin`` (same thickness). Plate A's far face is
clamped; plate B's far face is a rigid body whose reference node sits at the hinge end ``(L, 0, 0)``, where
the lattice measures its hinge strains ``(u, Theta)``.

* :func:`stiffness`: six linear steps, one unit end displacement or rotation each, give the 6 x 6 end
  stiffness in the lattice's DOF order ``(u1, u2, u3, T1, T2, T3)``: compare with
  ``core.lattice.geometry.beam_tip_stiffness``.
* :func:`bending_curve`: geometrically nonlinear (``NLGEOM``), Neo-Hooke TPU, plate B turned about the sheet
  normal to ``angle_deg`` with its translations free (pure bending) or held (``held=True``: the end turns in
  place, as where neighbouring plates hold a hinge's chord); moment and end displacement per increment.

Meshes: 20-node bricks with reduced integration (C3D20R) on a graded structured grid
(:mod:`metamaterial_wb.fe.mesh`), nominal element size ``h`` in the hinge (the grid rounds its counts up:
:func:`element_sizes` gives the bricks' own edges and the representative size mesh studies extrapolate with);
:func:`mesh_study` refines ``h``. Bad sizes or moduli are refused (``HingeSpec.check``, ``fe.checks``).
"""
import math
import time

import numpy as np

from metamaterial_wb.fe import ccx, checks
from metamaterial_wb.fe.mesh import box_union_mesh, graded
from metamaterial_wb.core.extrapolation import extrapolate, representative_size

PLA_E, PLA_NU = 3500.0, 0.36          # MPa, printed PLA (typical datasheet values)
REF, ROT = 900001, 900002             # rigid-body reference and rotation nodes


class HingeSpec:
    """Sizes in mm, moduli in MPa. Defaults: the scene's default hinge (2 x 0.8 x 7 mm, TPU 95A 26 MPa)."""

    def __init__(self, length=2.0, width=0.8, thickness=7.0, E=26.0, nu=0.45, plate_len=1.5, plate_margin=1.5,
                 plate_E=PLA_E, plate_nu=PLA_NU):
        self.L, self.w, self.t, self.E, self.nu = length, width, thickness, E, nu
        self.plate_len, self.plate_margin, self.plate_E, self.plate_nu = plate_len, plate_margin, plate_E, plate_nu
        self.check()

    def check(self):
        """Check every field (sizes and moduli positive and finite, Poisson ratios from 0 to 0.5, 0.5 excluded)
        and store it as a float; a SceneError names the first bad one (``HingeSpec.<argument>: <value>; allowed:
        ...``). Run by the constructor and again by every mesh and deck (a field may have been changed since)."""
        for arg, attr in (("length", "L"), ("width", "w"), ("thickness", "t"), ("plate_len", "plate_len"),
                          ("plate_margin", "plate_margin")):
            setattr(self, attr, checks.number(f"HingeSpec.{arg}", getattr(self, attr), 0.0, None, "mm", low_open=True))
        for arg in ("E", "plate_E"):
            setattr(self, arg, checks.number(f"HingeSpec.{arg}", getattr(self, arg), 0.0, None, "MPa", low_open=True))
        self.nu = checks.poisson("HingeSpec.nu", self.nu)
        self.plate_nu = checks.poisson("HingeSpec.plate_nu", self.plate_nu)
        return self

    def beam_K(self):
        from metamaterial_wb.core.lattice.geometry import beam_tip_stiffness
        return beam_tip_stiffness(np.array([self.L]), np.array([self.w]), np.array([self.t]), self.E, self.nu)[0]

    def describe(self):
        return f"{self.L:g} x {self.w:g} x {self.t:g} mm TPU (E {self.E:g} MPa, nu {self.nu:g}) between PLA plates"


def hinge_mesh(spec, h):
    """The structured C3D20R mesh with element size ``h`` (mm) in the hinge, graded to 4 h in the plates
    (``hinge_lines``; the sizes its bricks have: ``element_sizes``)."""
    L, w, t, Lp, mg = spec.L, spec.w, spec.t, spec.plate_len, spec.plate_margin
    xs, ys, zs = hinge_lines(spec, h)
    W = w / 2 + mg
    boxes = [(0.0, L, -w / 2, w / 2, -t / 2, t / 2),            # 0: hinge (TPU)
             (-Lp, 0.0, -W, W, -t / 2, t / 2),                  # 1: plate A (PLA)
             (L, L + Lp, -W, W, -t / 2, t / 2)]                 # 2: plate B (PLA)
    return box_union_mesh(boxes, (xs, ys, zs))


def element_sizes(spec, h):
    """The bricks of the hinge in its mesh of nominal size ``h``: ``{"element_mm": [along, across, through],
    "h_eff_mm"}``, the edge lengths (``mesh.graded`` rounds the counts up, so they are ``h`` or less along and across,
    about ``2 h`` through) and the representative size the mesh studies extrapolate with, the cube root of the
    brick volume (``richardson.representative_size``)."""
    xs, ys, zs = hinge_lines(spec, h)
    size = [float(np.diff(g[(g >= lo - 1e-9) & (g <= hi + 1e-9)]).max())
            for g, lo, hi in ((xs, 0.0, spec.L), (ys, -spec.w / 2, spec.w / 2), (zs, -spec.t / 2, spec.t / 2))]
    return {"element_mm": size, "h_eff_mm": representative_size(size)}


def hinge_lines(spec, h):
    """The grid lines ``(xs, ys, zs)`` of ``hinge_mesh``: spacing ``h`` along the hinge, ``min(h, w / 2)`` across
    it, ``max(2 h, t / 40)`` through it (``t / 4`` for a thin one), each count rounded up; growing to ``4 h`` in
    the plates."""
    spec.check()
    h = checks.number("h", h, 0.0, None, "mm", low_open=True)
    L, w, t, Lp, mg = spec.L, spec.w, spec.t, spec.plate_len, spec.plate_margin
    hw = min(h, w / 2.0)                                 # at least two elements across the width
    checks.element_count("h", h, (L / h) * (w / hw) * (t / max(2 * h, t / 40.0) if t > 4 * h else 4))  # the hinge's
    xs = np.concatenate([graded(-Lp, 0.0, h, 4 * h, "high")[:-1], graded(0.0, L, h),
                         graded(L, L + Lp, h, 4 * h, "low")[1:]])
    ys = np.concatenate([graded(-w / 2 - mg, -w / 2, hw, 4 * h, "high")[:-1], graded(-w / 2, w / 2, hw),
                         graded(w / 2, w / 2 + mg, hw, 4 * h, "low")[1:]])
    zs = graded(-t / 2, t / 2, max(2 * h, t / 40.0)) if t > 4 * h else graded(-t / 2, t / 2, t / 4)
    return xs, ys, zs


def _deck_head(spec, mesh, hyperelastic):
    spec.check()
    L = spec.L
    fixA = mesh.nodes_where(0, -spec.plate_len) + 1
    faceB = mesh.nodes_where(0, L + spec.plate_len) + 1
    ids = np.arange(1, mesh.n_elements + 1)
    out = ["*HEADING\nmetamaterial_wb: one TPU hinge between two PLA plates\n", "*NODE\n",
           ccx.fmt_nodes(mesh.nodes), f"{REF},{L:.9g},0,0\n{ROT},{L:.9g},0,0\n"]
    for part, name in ((0, "TPU"), (1, "PLA"), (2, "PLA")):
        sel = mesh.part == part
        out.append(f"*ELEMENT, TYPE=C3D20R, ELSET={name}\n")
        out.append(ccx.fmt_elements(mesh.elements[sel], ids[sel]))
    out += ["*NSET, NSET=FIXA\n", ccx.fmt_set(fixA), "*NSET, NSET=FACEB\n", ccx.fmt_set(faceB),
            f"*NSET, NSET=NREF\n{REF}\n*NSET, NSET=NROT\n{ROT}\n"]
    out.append("*MATERIAL, NAME=TPU\n")
    if hyperelastic:
        G = spec.E / (2 * (1 + spec.nu))
        K = spec.E / (3 * (1 - 2 * spec.nu))
        out.append(f"*HYPERELASTIC, NEO HOOKE\n{G / 2:.9g},{2.0 / K:.9g}\n")
    else:
        out.append(f"*ELASTIC\n{spec.E:.9g},{spec.nu:.9g}\n")
    out.append(f"*MATERIAL, NAME=PLA\n*ELASTIC\n{spec.plate_E:.9g},{spec.plate_nu:.9g}\n")
    out.append("*SOLID SECTION, ELSET=TPU, MATERIAL=TPU\n*SOLID SECTION, ELSET=PLA, MATERIAL=PLA\n")
    out.append(f"*RIGID BODY, NSET=FACEB, REF NODE={REF}, ROT NODE={ROT}\n")
    return "".join(out)


_PRINT = "*NODE PRINT, NSET=NREF\nU, RF\n*NODE PRINT, NSET=NROT\nU, RF\n"


def stiffness_deck(spec, mesh, du=1e-3, dr=1e-3):
    du = checks.number("du", du, 0.0, None, "mm", low_open=True)
    dr = checks.number("dr", dr, 0.0, None, "rad", low_open=True)
    steps = []
    for k in range(6):
        vals = [0.0] * 6
        vals[k] = du if k < 3 else dr
        bc = "".join(f"{REF},{d + 1},{d + 1},{vals[d]:.9g}\n" for d in range(3))
        bc += "".join(f"{ROT},{d + 1},{d + 1},{vals[3 + d]:.9g}\n" for d in range(3))
        steps.append(f"*STEP\n*STATIC\n*BOUNDARY, OP=NEW\nFIXA,1,3,0\n{bc}{_PRINT}*END STEP\n")
    return _deck_head(spec, mesh, hyperelastic=False) + "".join(steps)


def _end_table(tables, job):
    """Per printed time: (time, reference-node U and RF, rotation-node U and RF); an :class:`ccx.FEError` naming
    ``job`` and the table if one is missing (``ccx.table``)."""
    uR, fR = (ccx.table(tables, (q, "NREF"), job, [REF]) for q in ("displacements", "forces"))
    uT, fT = (ccx.table(tables, (q, "NROT"), job, [ROT]) for q in ("displacements", "forces"))
    return [(t, a[REF], b[REF], c[ROT], d[ROT]) for (t, a), (_, b), (_, c), (_, d) in zip(uR, fR, uT, fT)]


def stiffness(spec, h, timeout_s=600.0):
    """``(K (6, 6) in N/mm, N, N mm per unit rotation, info)`` of the FE hinge with mesh size ``h``."""
    mesh = hinge_mesh(spec, h)
    du, dr = 1e-3, 1e-3
    tables, info = ccx.run(stiffness_deck(spec, mesh, du, dr), "hinge_K", timeout_s)
    rows = _end_table(tables, "hinge_K")
    if len(rows) != 6:
        raise ccx.FEError(f"expected 6 load cases in the ccx output, found {len(rows)}")
    K = np.zeros((6, 6))
    for k, (_t, _u, f, _r, m) in enumerate(rows):
        K[:, k] = np.concatenate([f, m]) / (du if k < 3 else dr)
    K = 0.5 * (K + K.T)
    info.update({"h_mm": h, "nodes": mesh.n_nodes, "elements": mesh.n_elements, "dofs": 3 * mesh.n_nodes,
                 **element_sizes(spec, h)})
    return K, info


def bending_deck(spec, mesh, angle_deg, increments=8, held=False):
    th = math.radians(checks.number("angle_deg", angle_deg, -180.0, 180.0, "deg"))
    increments = checks.integer("increments", increments, 1)
    bc = f"FIXA,1,3,0\n{ROT},1,2,0\n{ROT},3,3,{th:.12g}\n"
    if held:
        bc += f"{REF},1,3,0\n"
    inc = 1.0 / increments
    step = (f"*STEP, NLGEOM, INC=1000\n*STATIC\n{inc:.6g},1.0,{inc / 64:.6g},{inc:.6g}\n*BOUNDARY\n{bc}"
            f"{_PRINT}*END STEP\n")
    return _deck_head(spec, mesh, hyperelastic=True) + step


def bending_curve(spec, h, angle_deg=45.0, increments=8, held=False, timeout_s=900.0):
    """Nonlinear bending about the sheet normal: ``{"angle_rad", "moment_Nmm", "end_u_mm" (k, 3),
    "end_force_N" (k, 3)}`` per converged increment, and the run info."""
    mesh = hinge_mesh(spec, h)
    tables, info = ccx.run(bending_deck(spec, mesh, angle_deg, increments, held), "hinge_bend", timeout_s)
    rows = _end_table(tables, "hinge_bend")
    out = {"time": np.array([r[0] for r in rows]), "angle_rad": np.array([r[3][2] for r in rows]),
           "moment_Nmm": np.array([r[4][2] for r in rows]), "end_u_mm": np.array([r[1] for r in rows]),
           "end_force_N": np.array([r[2] for r in rows])}
    info.update({"h_mm": h, "nodes": mesh.n_nodes, "elements": mesh.n_elements, "dofs": 3 * mesh.n_nodes,
                 "held": bool(held), "increments": len(rows), **element_sizes(spec, h)})
    return out, info


def lattice_bending(spec, angles, held=False, hinge_elements=1):
    """What the lattice's hinge law says for the same loading: moment and end displacement at every angle
    (``core/lattice`` mechanics: ``hinge_elements`` corotational Timoshenko elements, the end frame turned by
    ``angle`` about ``e3``; translations free (pure bending) or held at the rest chord)."""
    from metamaterial_wb.core.lattice.refine import hinge_end_response
    return hinge_end_response(spec.L, spec.w, spec.t, spec.E, spec.nu, angles, held=held, n=hinge_elements)


def mesh_study(spec, sizes=(0.4, 0.27, 0.2), timeout_s=900.0, progress=None):
    """FE stiffness at every nominal mesh size, and the Richardson estimate of the converged diagonal over the
    meshes' own sizes (``h_eff_mm``, ``element_sizes``; ``core.extrapolation.extrapolate``: observed order from the three
    finest, flagged where clipped)."""
    rows = []
    for h in sizes:
        t0 = time.perf_counter()
        K, info = stiffness(spec, h, timeout_s)
        rows.append({"h_mm": h, "K": K, "wall_s": info["wall_s"], "dofs": info["dofs"],
                     "elements": info["elements"], "h_eff_mm": info["h_eff_mm"], "element_mm": info["element_mm"]})
        if progress:
            progress(f"FE hinge stiffness h = {h:g} mm: {info['dofs']} DOFs, {time.perf_counter() - t0:.1f} s")
    return rows, extrapolate([r["h_eff_mm"] for r in rows], [np.diag(r["K"]) for r in rows])


def richardson(h, values):
    """``(extrapolated, error estimate, order)`` of ``values`` (arrays, coarse to fine) at the element sizes ``h``
    (the meshes' own, any ratios: ``core.extrapolation.extrapolate``, whose result also says which orders were clipped or
    assumed); with two values, order 2 is assumed."""
    res = extrapolate(h, values)
    return res["value"], res["error"], res["order"]
