"""Two sleeve rings stacked in series as one curved CalculiX solid (issue 18): two hysterons that share only their
force.

The seed's combination 2 (two cell types that differ in h) snaps asymmetrically in the seed's Abaqus ring; the
mixed solid ring (``sleeve3d``, one ring of both types under one plate) snaps symmetrically on every mesh, by
implicit dynamics and without the bias, and so does the frame's mixed ring. On the frame, the same two types as
two rings stacked, a free plate between them, give the seed's order (``bench/fe_frame3d_stack.py``). Here that
stack is a solid too:

* each ring is ``sleeve3d.ring_mesh`` of one cell type (uniform, ``n_cells`` around, the same radius: the
  types share their width), the first from ``Z = 0`` to its height ``H0``, the second from ``H0`` to
  ``H0 + H1``; their node and element ids follow one another (the second ring's offset by the first's counts);
* the first ring's top edge and the second ring's bottom edge are one rigid plate (``*RIGID BODY``, reference
  node ``MREF`` on the axis at ``H0``, rotation node ``MROT``): free to rise, tilt and twist, its in-plane
  translation fixed (as the top plate's; ``sleeve3d``'s module docstring);
* the bottom is clamped; the top plate rises by ``d`` (and back with ``unload``), tilts and twists freely under
  the same small bias moment (``bias`` in ``G L^2`` times ``R``) as a single ring's - the frame's stack biases
  its free top plate alone, so does this one;
* implicit dynamics by default (``*DYNAMIC``, the small ``DENSITY``): rings in series snap under displacement
  control dynamically (when one ring snaps its force falls and the other springs back, a jump static Newton
  cannot follow), as the seed's FE ran.

The force is the clamped bottom's axial reaction; each ring's rise is the middle plate's (the first ring) and the
top's over it (the second); the hysterons are each ring's beam halves (``sleeve3d.hysterons``).
"""
import math

import numpy as np

from metamaterial_wb.fe import ccx, checks, sleeve3d
from metamaterial_wb.fe.sleeve3d import REF, ROT

MREF, MROT = 9000003, 9000004
DAMPING_MAX = 1000.0     # 1/s: a damping ratio of 1 at 500 rad/s; its drag on the rising ring stays under 1 % of P1


class StackMesh:
    """Two rings of ``sleeve3d.ring_mesh``, the second on the first: ``nodes``, ``elements`` (0-based, the
    second's offset by ``offset``, the first's node count), ``rings`` (the two ``RingMesh``, each in its own
    coordinates), ``heights`` (each ring's height) and ``height`` (the stack's)."""

    def __init__(self, rings):
        self.rings = rings
        self.offset = rings[0].n_nodes
        self.heights = [m.height for m in rings]
        self.height = sum(self.heights)
        upper = rings[1].nodes + np.array([0.0, 0.0, self.heights[0]])
        self.nodes = np.vstack([rings[0].nodes, upper])
        self.elements = np.vstack([rings[0].elements, rings[1].elements + self.offset])
        self.radius = rings[0].radius

    @property
    def n_nodes(self):
        return len(self.nodes)

    @property
    def n_elements(self):
        return len(self.elements)

    def volume(self):
        return sum(m.volume() for m in self.rings)

    def beam_ends(self):
        """Both rings' ``RingMesh.beam_ends`` in the stack's node ids: ``[first's, second's]``."""
        out = []
        for k, m in enumerate(self.rings):
            e = m.beam_ends()
            shift = k * self.offset
            out.append(dict(e, outer=e["outer"] + shift, inner=e["inner"] + shift))
        return out


def stack_mesh(cells, n_cells=4, r=1, n_layers=1):
    """The stack of two uniform rings of the cell types ``cells`` (``(lower, upper)``, each a ``CellGeometry``) on
    mesh ``r``: a ``StackMesh``. The types must share their width (one radius)."""
    if len(cells) != 2:
        raise ValueError(f"cells: {len(cells)} cell types; allowed: 2 (the lower ring's, the upper ring's)")
    if not math.isclose(cells[0].width, cells[1].width, rel_tol=1e-12):
        raise ValueError(f"cells: widths {cells[0].width:g} and {cells[1].width:g} mm; allowed: equal widths "
                         "(the stacked rings share one radius)")
    return StackMesh([sleeve3d.ring_mesh(g, n_cells, r, n_layers) for g in cells])


def stack_deck3d(cells, n_cells=4, r=1, d_max=None, increments=70, bias=1e-5, bias_angle=0.5, method="dynamic",
                 unload=True, element="C3D20", watch=None, damping=0.0):
    """``(deck, meta)``: the stack (module docstring) under its top plate, raised to ``d_max`` mm (default 0.5 L:
    twice a single ring's default) and, with ``unload``, lowered back along one step of time 2 (the single
    ring's amplitudes, ``sleeve3d.amplitudes``); ``increments`` per unit of time at most; ``watch``: 0-based node
    ids printed at every increment, or ``"ends"``: every beam end of both rings (``StackMesh.beam_ends``, kept in
    ``meta["ends"]`` for ``read_stack``'s hysterons; ``meta["watch"]`` the ids printed). ``damping`` (1/s, implicit dynamics only): the rubber's
    mass-proportional Rayleigh damping (``sleeve3d.material_text``). Without it, when the second ring's snap
    drops the force to the first ring's valley, the first ring and the middle plate swing across that ring's
    snap-back threshold for a long time at tiny increments (the integrator's dissipation acts on high frequencies
    only; measured on combination 2); a real rubber's own damping ends that swing."""
    mesh = stack_mesh(cells, n_cells, r)
    L = cells[0].L
    sleeve3d.check_procedure(element, method)
    if not 0.0 <= damping <= DAMPING_MAX:
        raise ValueError(f"damping: {damping!r} 1/s; allowed: 0 to {DAMPING_MAX:g} 1/s")
    if damping and method != "dynamic":
        raise ValueError(f"damping: {damping!r} 1/s damps implicit dynamics; method {method!r} has no time")
    increments = checks.integer("increments", increments, 1)
    sleeve3d.sleeve2d.check_bias(bias, bias_angle, "a moment bias L^2 R")
    d_max = 0.5 * L if d_max is None else float(d_max)
    if not 0 < d_max <= 3.0 * L:
        raise ValueError(f"d_max: {d_max!r} mm; allowed: 0 < d_max <= 3 L = {3.0 * L:g} mm (1.5 L per ring)")
    ends = mesh.beam_ends() if isinstance(watch, str) and watch == "ends" else None
    if ends is not None:
        watch = np.unique(np.concatenate([np.concatenate([e["outer"].ravel(), e["inner"].ravel()]) for e in ends]))
    elif watch is not None:
        watch = sleeve3d.checked_watch(watch, mesh.n_nodes)
    X = mesh.nodes
    tol = 1e-7 * L
    H0 = mesh.heights[0]
    bottom = np.flatnonzero(np.abs(X[:, 2]) < tol)
    middle = np.flatnonzero(np.abs(X[:, 2] - H0) < tol)
    top = np.flatnonzero(np.abs(X[:, 2] - mesh.height) < tol)
    if not (np.any(middle < mesh.offset) and np.any(middle >= mesh.offset)):
        raise AssertionError("the middle plate does not hold both rings")
    amp, amp_text = sleeve3d.amplitudes(method, unload)
    ids = np.arange(1, mesh.n_elements + 1)
    out = [f"*HEADING\nmetamaterial_wb: two sleeve rings stacked, curved 3-D solid ({element}), free middle plate\n",
           "*NODE\n", ccx.fmt_nodes(X),
           f"{REF},0,0,{mesh.height:.9g}\n{ROT},0,0,{mesh.height:.9g}\n{MREF},0,0,{H0:.9g}\n{MROT},0,0,{H0:.9g}\n",
           f"*ELEMENT, TYPE={element}, ELSET=SOLID\n", ccx.fmt_elements(mesh.elements, ids),
           "*NSET, NSET=BOTTOM\n", ccx.fmt_set(bottom + 1), "*NSET, NSET=TOP\n", ccx.fmt_set(top + 1),
           "*NSET, NSET=MID\n", ccx.fmt_set(middle + 1),
           f"*NSET, NSET=NROT\n{ROT}\n*NSET, NSET=NMID\n{MREF}\n*NSET, NSET=NMROT\n{MROT}\n",
           ("*NSET, NSET=WATCH\n" + ccx.fmt_set(watch + 1) if watch is not None else ""),
           sleeve3d.material_text(method == "dynamic", damping),
           f"*RIGID BODY, NSET=TOP, REF NODE={REF}, ROT NODE={ROT}\n",
           f"*RIGID BODY, NSET=MID, REF NODE={MREF}, ROT NODE={MROT}\n", amp_text]
    bc = (f"*BOUNDARY\n{MREF},1,2,0\n*BOUNDARY{amp}\nBOTTOM,1,3,0\n{REF},1,2,0\n{REF},3,3,{d_max:.12g}\n"
          + sleeve3d.bias_text(bias * L ** 2 * mesh.radius, bias_angle * math.pi / n_cells, amp, unload))
    prints = ("*NODE PRINT, NSET=BOTTOM\nRF\n*NODE PRINT, NSET=NROT\nU\n*NODE PRINT, NSET=NMID\nU\n"
              "*NODE PRINT, NSET=NMROT\nU\n" + ("*NODE PRINT, NSET=WATCH\nU\n" if watch is not None else ""))
    out.append(sleeve3d.step_text(method, unload, increments, False, bc + prints))
    meta = {"mesh": mesh, "radius_mm": mesh.radius, "d_max_mm": d_max, "r": int(r), "n_cells": int(n_cells),
            "dofs": 3 * mesh.n_nodes, "elements": mesh.n_elements, "increments": int(increments), "bias": bias,
            "bias_angle": bias_angle, "method": method, "element": element, "unload": bool(unload),
            "heights_mm": list(mesh.heights), "damping": float(damping), "watch": watch, "ends": ends}
    return "".join(out), meta


def solve_stack3d(cells, n_cells=4, r=1, d_max=None, increments=70, bias=1e-5, bias_angle=0.5, method="dynamic",
                  unload=True, element="C3D20", timeout_s=7200.0, partial=True, hysterons=True, damping=0.0):
    """The stack's cycle (``stack_deck3d``): ``{"d": top rise / L, "F": F / (G L^2), "ring_rises" (k, 2): each
    ring's rise / L, "tilt_rad" (k, 2): the top plate's (psi_x, psi_y), "middle_tilt_rad" (k, 2), "unloading" (k,)
    (with ``unload``)}`` per converged increment with the unloaded start, and with ``hysterons`` ``"rises"`` (k,
    halves: the first ring's beam halves, then the second's, ``sleeve3d.hysterons``), ``"units"`` (each half's
    edge pillar, the second ring's numbered after the first's) and ``"types"`` (each half's ring: 0 lower, 1
    upper); and the run info (``info["stopped"]``, ``info["d_reached"]``: a partial run, as ``solve_ring3d``).
    ``damping``: ``stack_deck3d``'s."""
    deck, meta = stack_deck3d(cells, n_cells, r, d_max, increments, bias, bias_angle, method, unload, element,
                              "ends" if hysterons else None, damping)
    tables, info = ccx.run(deck, "sleeve_stack3d", timeout_s, partial=partial)
    out = read_stack(tables, meta, info)
    info.update({key: meta[key] for key in ("r", "dofs", "elements", "d_max_mm", "n_cells", "radius_mm", "bias",
                                            "bias_angle", "method", "element", "heights_mm", "damping")})
    info["increments"] = len(out["d"]) - 1
    info["d_reached"] = float(out["d"][-1])
    return out, info


def read_stack(tables, meta, info=None):
    """``solve_stack3d``'s curve from ccx's printed tables (``ccx.parse_dat``, also of a run still going or stopped)
    of the deck ``stack_deck3d`` wrote with ``meta``; the hysterons when it watched the beams' ends."""
    mesh, L, n_cells = meta["mesh"], meta["mesh"].rings[0].geom.L, meta["n_cells"]
    watch, ends = meta["watch"], meta["ends"]
    rows = ccx.table(tables, ("forces", "BOTTOM"), "sleeve_stack3d", info=info)
    sets = ["NROT", "NMID", "NMROT"] + (["WATCH"] if ends is not None else [])
    k = min([len(rows)] + [len(tables.get(("displacements", n), [])) for n in sets])   # a live file's last one
    rows = rows[:k]
    t = np.array([r_[0] for r_ in rows])
    F = -np.array([sum(v[2] for v in r_[1].values()) for r_ in rows])

    def node(set_name, nid):
        return np.array([r_[1][nid][:3] for r_ in tables.get(("displacements", set_name), [])[:k]]).reshape(-1, 3)
    top_rot, mid, mid_rot = node("NROT", ROT), node("NMID", MREF), node("NMROT", MROT)
    down = t > 1.0 + 1e-9
    d = np.where(down, 2.0 - t, t) * meta["d_max_mm"]
    first = mid[:, 2]
    out = {"d": np.concatenate([[0.0], d / L]), "F": np.concatenate([[0.0], F / L ** 2]),
           "ring_rises": np.vstack([[0.0, 0.0], np.column_stack([first, d - first]) / L]),
           "tilt_rad": np.vstack([[0.0, 0.0], top_rot[:, :2]]),
           "middle_tilt_rad": np.vstack([[0.0, 0.0], mid_rot[:, :2]])}
    if meta["unload"]:
        out["unloading"] = np.concatenate([[False], down])
    if ends is not None:
        rows_w = tables.get(("displacements", "WATCH"), [])[:k]
        u_watch = np.array([np.zeros((watch.size, 3))] + [[r_[1][i + 1][:3] for i in watch] for r_ in rows_w])
        rises, units, types = [], [], []
        for j, (m, e) in enumerate(zip(mesh.rings, ends)):
            rise, _ = sleeve3d.hysterons(m, e, u_watch, watch)
            rises.append(rise)
            units.append(e["units"] + j * n_cells)
            types.append(np.full(len(e["units"]), j))
        out.update(rises=np.hstack(rises), units=np.concatenate(units), types=np.concatenate(types))
    return out


__all__ = ["StackMesh", "stack_mesh", "stack_deck3d", "solve_stack3d", "read_stack", "MREF", "MROT"]
