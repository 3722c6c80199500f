"""Hinges of ``n`` corotational Timoshenko elements (the nonlinear model's option ``hinge_elements``).

The one-element hinge measures each hinge by one corotational element between the two plates: exact for
pure bending (the arc correction of ``core/lattice/mechanics``) and for the linear response to end loads
(the tip stiffness of the Timoshenko beam), but only approximate once a hinge that also carries end forces
turns through tens of degrees. :func:`refine` splits every hinge into ``n`` elements of length ``L/n``
joined by ``n - 1`` hinge-internal nodes (each a point with a frame: 3 DOFs in a planar scene, 6 otherwise),
so the hinge's deformed shape is resolved and the model converges to the geometrically exact
(Reissner-Timoshenko) beam as ``n`` grows; ``docs/fidelity.md`` gives the convergence study.

The refined geometry keeps the plates as nodes ``0 .. n_plates - 1`` (so supports, actuators and results
read as before) and lists the elements as:

* ``0 .. m - 1``: one *whole-hinge* element per joint, from plate A's hinge corner to plate B's, with zero
  stiffness. It carries what belongs to the hinge as a whole: the actuator constraints (relative rotation
  of the two plates about the soft axis) and the plate-contact penalty (closing rotation of the hinge);
* ``m ..``: the ``n m`` stiff sub-elements, hinge by hinge, from plate A through the internal nodes to
  plate B.

Everything the element mechanics reads (``a``, ``b``, ``rA``, ``rB``, ``Q0``, ``K``, ``rest``, ``tilt``, ``dofs``)
is per element, so :class:`~metamaterial_wb.core.lattice.mechanics.ElementState` and the nonlinear solver run
unchanged on it.
"""
import numpy as np

from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.core.lattice.geometry import beam_tip_stiffness

MAX_HINGE_ELEMENTS = 64


def check_hinge_elements(value):
    """The option's value as an int in [1, MAX_HINGE_ELEMENTS], or a SceneError naming it (a boolean is refused:
    ``hinge_elements=true`` is not a count, though Python's ``int(True)`` is 1)."""
    if isinstance(value, bool):
        raise SceneError("--option hinge_elements", f"{value!r}; allowed: an integer in [1, {MAX_HINGE_ELEMENTS}] "
                                                    "(a count of elements, not a boolean)")
    try:
        n = int(value)
        ok = float(value) == n
    except (TypeError, ValueError):
        ok = False
    if not ok or not (1 <= n <= MAX_HINGE_ELEMENTS):
        raise SceneError("--option hinge_elements", f"{value!r}: expected an integer in [1, {MAX_HINGE_ELEMENTS}]")
    return n


class RefinedGeometry:
    """A :class:`~metamaterial_wb.core.lattice.geometry.LatticeGeometry` with ``n`` elements per hinge."""

    def __init__(self, base, n):
        self.base = base
        self.hinge_elements = n
        m, np_ = base.m, base.n
        self.scene = base.scene
        self.n_plates = np_
        self.m_hinges = m
        self.n = np_ + m * (n - 1)
        self.m = m * (n + 1)
        for k in ("plate_side_mm", "cell_size_mm", "gap_mm", "E", "nu", "contact_rad", "closing_rad",
                  "opening_rad", "arc_correction", "is_h", "joint_parity"):
            setattr(self, k, getattr(base, k))
        self.planar = base.planar
        e1 = base.Q0[:, :, 0]
        # internal nodes of hinge k: np_ + k (n - 1) + (0 .. n - 2), spaced along the hinge chord
        start = base.X0[base.a] + base.rA                      # plate A's hinge corner (flat sheet)
        frac = np.arange(1, n) / n
        Xi = start[:, None, :] + frac[None, :, None] * (base.rest * e1)[:, None, :]
        self.X0 = np.concatenate([base.X0, Xi.reshape(-1, 3)], axis=0)
        self.parity = np.concatenate([base.parity, np.ones(m * (n - 1))])
        # sub-element chains: node sequence a, i_1 .. i_{n-1}, b for every hinge
        internal = np_ + np.arange(m * (n - 1)).reshape(m, n - 1)
        chain = np.concatenate([base.a[:, None], internal, base.b[:, None]], axis=1)     # (m, n + 1)
        sa = chain[:, :-1].ravel()
        sb = chain[:, 1:].ravel()
        zero = np.zeros((m, n, 3))
        rA = zero.copy()
        rA[:, 0, :] = base.rA
        rB = zero.copy()
        rB[:, -1, :] = base.rB
        rep = np.repeat(np.arange(m), n)                      # hinge of every sub-element
        self.hinge_of = np.concatenate([np.arange(m), rep])
        self.a = np.concatenate([base.a, sa])
        self.b = np.concatenate([base.b, sb])
        self.rA = np.concatenate([base.rA, rA.reshape(-1, 3)])
        self.rB = np.concatenate([base.rB, rB.reshape(-1, 3)])
        self.Q0 = base.Q0[self.hinge_of]
        self.tilt = base.tilt[self.hinge_of]
        self.L = np.concatenate([base.L, base.L[rep] / n])
        self.w, self.t = base.w[self.hinge_of], base.t[self.hinge_of]
        Ksub = beam_tip_stiffness(base.L[rep] / n, base.w[rep], base.t[rep], base.E, base.nu)
        f = getattr(base, "hinge_law_factors", None)
        if f is not None:                                  # the FE-calibrated law, per hinge (geometry.apply_hinge_law)
            sq = np.sqrt(f[rep])
            Ksub = Ksub * sq[:, :, None] * sq[:, None, :]
        self.hinge_law = getattr(base, "hinge_law", "beam")
        self.K = np.concatenate([np.zeros((m, 6, 6)), Ksub])
        self.rest = np.concatenate([np.full(m, float(base.rest)), np.full(m * n, float(base.rest) / n)])
        # contact acts on the whole-hinge elements only, with the one-element hinge's penalty stiffness
        self.contact_k = np.concatenate([base.K[:, 5, 5], np.zeros(m * n)])
        self.contact_mask = np.concatenate([np.ones(m, bool), np.zeros(m * n, bool)])
        self.dofs = np.concatenate([6 * self.a[:, None] + np.arange(6), 6 * self.b[:, None] + np.arange(6)], axis=1)

    def phi_max(self, D):
        return self.base.phi_max(D)

    def D_from_phi(self, phi):
        return self.base.D_from_phi(phi)

    def phi_from_D(self, D):
        return self.base.phi_from_D(D)

    def plates(self, X, R):
        """The plate nodes' part of a refined state."""
        return X[:self.n_plates], R[:self.n_plates]

    def chord_stretch(self, X, R):
        """(m,) relative change of every hinge's end-to-end chord against its rest length (the gap)."""
        return chord_stretch(self.base, X, R)


def chord_stretch(geo, X, R):
    """(m,) relative change of every hinge's end-to-end chord (plate corner to plate corner) against its rest
    length (the gap), for a one-element geometry ``geo`` and a state whose first nodes are its plates."""
    pA = X[geo.a] + np.einsum("mij,mj->mi", R[geo.a], geo.rA)
    pB = X[geo.b] + np.einsum("mij,mj->mi", R[geo.b], geo.rB)
    return np.linalg.norm(pB - pA, axis=1) / geo.rest - 1.0


def refine(geo, n):
    """``geo`` itself for ``n = 1``, else its :class:`RefinedGeometry` with ``n`` elements per hinge."""
    n = check_hinge_elements(n)
    return geo if n == 1 else RefinedGeometry(geo, n)


def hinge_end_response(L, w, t, E, nu, angles, held=False, n=1):
    """One hinge alone, as the lattice models it: ``n`` corotational Timoshenko elements clamped at plate
    A's end, the far end turned about the sheet normal ``e3`` by each of ``angles`` (radians, in order), its
    translations free (``held=False``: pure bending) or held at the rest chord. Returns
    ``{"angle_rad", "moment_Nmm", "end_u_mm" (k, 3), "end_force_N" (k, 3)}``: the end moment about ``e3``,
    the end's displacement and the force on it (the reaction where it is held). For the comparison with
    the solid FE hinge (``metamaterial_wb/fe/hinge``)."""
    import types

    from metamaterial_wb.core.lattice.mechanics import ElementState

    n = check_hinge_elements(n)
    geo = types.SimpleNamespace(
        a=np.arange(n), b=np.arange(1, n + 1), rA=np.zeros((n, 3)), rB=np.zeros((n, 3)),
        Q0=np.broadcast_to(np.eye(3), (n, 3, 3)).copy(), rest=L / n, arc_correction=True, planar=True,
        K=beam_tip_stiffness(np.full(n, L / n), np.full(n, w), np.full(n, t), E, nu))
    X = np.column_stack([np.linspace(0.0, L, n + 1), np.zeros(n + 1), np.zeros(n + 1)])
    phi = np.zeros(n + 1)
    loc = [0, 1, 5, 6, 7, 11]                        # planar DOFs of both element ends

    def rot(p):
        c, s = np.cos(p), np.sin(p)
        R = np.zeros((p.size, 3, 3))
        R[:, 0, 0], R[:, 0, 1], R[:, 1, 0], R[:, 1, 1], R[:, 2, 2] = c, -s, s, c, 1.0
        return R

    def assemble(X, phi):
        st = ElementState(geo, X, rot(phi), tangent=True)
        g = np.zeros(3 * (n + 1))
        H = np.zeros((3 * (n + 1),) * 2)
        for e in range(n):
            idx = np.arange(3 * e, 3 * e + 6)
            g[idx] += st.grad[e, loc]
            H[np.ix_(idx, idx)] += st.H[e][np.ix_(loc, loc)]
        return g, H

    last = 3 * n
    free = [k for k in range(3, 3 * (n + 1)) if k != last + 2 and not (held and k in (last, last + 1))]
    free = np.array(free, dtype=np.int64)
    out = {"angle_rad": [], "moment_Nmm": [], "end_u_mm": [], "end_force_N": []}
    scale = float(geo.K[0, 5, 5]) / L
    prev = 0.0
    for th in np.asarray(angles, float):
        sub = max(1, int(np.ceil(abs(th - prev) / 0.05)))
        for target in np.linspace(prev, th, sub + 1)[1:]:
            phi[-1] = target
            for _ in range(50):
                g, H = assemble(X, phi)
                if not free.size or np.abs(g[free]).max() <= 1e-11 * scale:
                    break
                dq = np.linalg.solve(H[np.ix_(free, free)], -g[free])
                full = np.zeros(3 * (n + 1))
                full[free] = dq
                full = full.reshape(n + 1, 3)
                X[:, :2] += full[:, :2]
                phi += full[:, 2]
            else:
                raise RuntimeError(f"hinge_end_response: Newton did not converge at {target:.3f} rad")
        prev = th
        g, _ = assemble(X, phi)
        out["angle_rad"].append(th)
        out["moment_Nmm"].append(g[last + 2])
        out["end_u_mm"].append([X[-1, 0] - L, X[-1, 1], 0.0])
        out["end_force_N"].append([g[last], g[last + 1], 0.0])
    return {k: np.asarray(v, float) for k, v in out.items()}
