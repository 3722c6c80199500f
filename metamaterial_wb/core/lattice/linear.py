"""The linear lattice model (R1): one sparse solve of the flat sheet's (or the predicted state's) tangent
stiffness with exact linearised actuator constraints, contact by an active set (docs/fidelity-models.md)."""
import time

import numpy as np
import scipy.sparse.linalg as spla

from metamaterial_wb.core.lattice import linalg
from metamaterial_wb.core.lattice.geometry import LatticeGeometry, fixed_items
from metamaterial_wb.core.lattice.linalg import _SPLU, SchurKKT, _dofmap, kkt_regularisation
from metamaterial_wb.core.lattice.mechanics import ElementState, Pattern, PlanarElementState, _cross_e1, hinge_strains
from metamaterial_wb.core.lattice.poses import ChainPositions, _apply


class LinearLattice:
    """Linearised lattice: tangent stiffness of the flat sheet, exact linearised actuator constraints.

    Factor once per scene structure and placement, re-solve per set of values (the response without
    contact is linear in the actuator values). Plate contact (``contact=True``): hinges whose linearised
    closing rotation passes ``contact_fraction`` of the contact rotation get the nonlinear model's stiff
    one-sided spring; the set of such hinges is found by re-solving until it stops changing (semismooth
    Newton on a piecewise-quadratic energy), so the answer is piecewise linear. When no hinge reaches
    contact (small amplitudes) this costs nothing extra.

    Poses: the plate rotations are ``exp`` of the solved rotation increments; the positions come from those
    rotations through the hinge chain (:class:`ChainPositions`, ``poses="chain"``, the default) rather than
    from adding the solved displacements to the flat sheet (``poses="linear"``), which stretches every hinge
    by the second-order motion of the plate corners. Both agree to first order; ``q`` is the same.

    ``base=(X, R)`` linearises about that state instead of the flat sheet (the ``about=quadratic`` option:
    the quadratic model's predicted state, :func:`quadratic_state`): the corotational strains and hinge
    forces of the state enter the right-hand side, the actuator constraints and the contact onset are
    measured from it, and ``q`` is the increment from it. ``tangent="material"`` keeps only ``J^T K J``
    (positive semi-definite; the state's non-equilibrium stress terms mislead the step,
    docs/fidelity-models.md); ``"full"`` is the exact tangent. :meth:`line_search` then picks the step
    length along ``q`` from the nonlinear energy.

    Parameters
    ----------
    scene : Scene
    geo : LatticeGeometry, optional
    contact : bool
        Plate contact by an active set.
    contact_fraction, contact_stiffness : float
        Onset (fraction of the contact rotation) and stiffness of the one-sided spring.
    poses : {"chain", "linear"}
    base : tuple, optional
        ``(X, R)`` to linearise about (default the flat sheet).
    tangent : {"full", "material"}
    chain : ChainPositions, optional
    """

    def __init__(self, scene, geo=None, contact=True, contact_fraction=0.98, contact_stiffness=1e4, poses="chain",
                 base=None, tangent="full", chain=None):
        t0 = time.perf_counter()
        if poses not in ("chain", "linear"):
            from metamaterial_wb.core.errors import SceneError
            raise SceneError("--option poses", f"{poses!r}; allowed: chain, linear")
        self.poses = poses
        self._chain = chain          # the hinge-chain position rule of geo (built on first use if None)
        self.geo = geo or LatticeGeometry(scene)
        geo = self.geo
        self.joints, self.values, self.psi, self.names = fixed_items(scene, geo)
        self.dofmap, self.na = _dofmap(geo, geo.planar)
        self.pattern = Pattern(geo.dofs, self.dofmap, self.na, self.joints, None)
        if base is None:
            # at the flat sheet the arc correction and its first derivative vanish: leave it out
            self.base = (geo.X0, np.broadcast_to(np.eye(3), (geo.n, 3, 3)).copy())
            if linalg._FAST and PlanarElementState.applies(geo, self.base[1]):
                st = PlanarElementState(geo, self.base[0], self.base[1], arc=False)
            else:
                st = ElementState(geo, self.base[0], self.base[1], tangent=True, arc=False)
            self.g0 = None                  # no force, no strain at the flat sheet
            self.eps0 = None
        else:
            # linearised about a deformed state (X, R): corotational strains, forces and tangent there
            self.base = (np.asarray(base[0], float), np.asarray(base[1], float))
            if linalg._FAST and tangent != "full" and PlanarElementState.applies(geo, self.base[1]):
                st = PlanarElementState(geo, self.base[0], self.base[1])      # material tangent included
            else:
                st = ElementState(geo, self.base[0], self.base[1], tangent=(tangent == "full"))
                if tangent != "full":        # material (Gauss-Newton) part J^T K J only: no stress terms
                    st.H = np.transpose(st.J, (0, 2, 1)) @ (geo.K @ st.J)
            self.g0 = self.pattern.vector(st.grad)
            self.eps0 = st.eps
        self.He = st.H
        self.J5 = st.J[:, 5, :].copy()
        self.J6 = st.J                      # strains (u, Theta) of the flat sheet per element DOF
        Acon = self.J5[self.joints] if self.joints.size else None
        self._Acon = Acon
        self.reg = kkt_regularisation(geo)
        self._KKT = None
        self._schur_ok = base is None or tangent != "full"      # positive definite tangents only
        self.contact = bool(contact)
        self.close_sign = -geo.parity[geo.a]
        self.kappa_c = contact_fraction * 2.0 * geo.contact_rad / np.cos(geo.tilt)
        self.kappa_onset = self.kappa_c
        if self.eps0 is not None:        # closing rotation measured from the base state
            self.kappa_c = self.kappa_c - self.close_sign * self.eps0[:, 5]
        self.kc = contact_stiffness * geo.K[:, 5, 5]
        self.contact_info = {"contact_hinges": 0, "active_set_iterations": 0}
        self._zcol = None            # column of each hinge's cached back-substitution in self._Z (-1: none yet)
        self._Z = None
        self._nz = 0
        self._Jc = None
        self.timings = {"assemble_s": time.perf_counter() - t0}
        t1 = time.perf_counter()
        self.lu = None
        self.H = self.pattern.stiffness(st.H)        # (na, na) CSC stiffness block
        if self.joints.size:
            if self._schur_ok:
                self.lu = SchurKKT.build(self.H, self.pattern.rows(Acon, self.joints))
            if self.lu is None:
                try:
                    self.lu = spla.splu(self.KKT, **_SPLU)
                except RuntimeError:     # redundant constraints (e.g. clips on every joint around a cell)
                    self._KKT = self.pattern.matrix(st.H, Acon, self.reg)
                    self.lu = spla.splu(self._KKT, **_SPLU)
        self.timings["factor_s"] = time.perf_counter() - t1

    @property
    def KKT(self):
        """The KKT matrix ``[[H, A^T], [A, 0]]`` (sparse; built on first use: the factorisation does not
        need it when the Schur-complement solver applies)."""
        if self._KKT is None:
            if linalg._FAST:           # from the assembled stiffness block and the constraint rows (no pattern sort)
                import scipy.sparse as sp
                H = self.H.tocoo()
                na = self.na
                Ad = self.pattern.rows(self._Acon, self.joints) if self.joints.size else np.zeros((0, na))
                nc = Ad.shape[0]
                r, c = np.nonzero(Ad)
                v = Ad[r, c]
                d = na + np.arange(nc)
                rows = np.concatenate([H.row, na + r, c, d])
                cols = np.concatenate([H.col, c, na + r, d])
                self._KKT = sp.csc_matrix((np.concatenate([H.data, v, v, np.zeros(nc)]), (rows, cols)),
                                          shape=(na + nc, na + nc))
            else:
                self._KKT = self.pattern.matrix(self.He, self._Acon, 0.0)
        return self._KKT

    def _energy(self, q):
        """Elastic energy ``q.H q / 2`` (H = the factored KKT matrix's stiffness block) plus the contact
        penalty; sparse products (this is evaluated in every active-set line search)."""
        e = 0.5 * float(q @ (self.H @ q))
        if self.g0 is not None:
            e += float(self.g0 @ q)
        over = self._closing(q) - self.kappa_c
        return float(e + 0.5 * np.sum(self.kc * np.maximum(over, 0.0) ** 2))

    def _closing(self, q):
        """Closing rotation of every hinge (linearised): a sparse (m, na) matrix built on first use."""
        if self._Jc is None:
            import scipy.sparse as sp
            ed = self.pattern.ed
            J = self.close_sign[:, None] * self.J5
            keep = (ed >= 0) & (J != 0.0)
            rows = np.broadcast_to(np.arange(ed.shape[0])[:, None], ed.shape)[keep]
            self._Jc = sp.csr_matrix((J[keep], (rows, ed[keep])), shape=(ed.shape[0], self.na))
        return self._Jc @ q

    def _U(self, active):
        """Sparse (k, N) rows: the closing-rotation gradient of each active hinge on the KKT unknowns."""
        import scipy.sparse as sp
        ed = self.pattern.ed[active]                                  # (k, 12) active DOF indices or -1
        Jr = self.close_sign[active, None] * self.J5[active]
        keep = ed >= 0
        rows = np.repeat(np.arange(active.size), 12).reshape(-1, 12)[keep]
        return sp.csr_matrix((Jr[keep], (rows, ed[keep])), shape=(active.size, self.pattern.N))

    def _rows(self, active, V):
        """``U @ V`` for the active hinges' closing-gradient rows U, V of shape (N,) or (N, c)."""
        ed = self.pattern.ed[active]                                   # (k, 12), -1 = no DOF
        Vp = np.concatenate([V[:self.na], np.zeros((1,) + V.shape[1:])])
        Jr = self.close_sign[active, None] * self.J5[active]
        if V.ndim == 1:
            return np.einsum("ki,ki->k", Jr, Vp[ed])
        return np.einsum("ki,kic->kc", Jr, Vp[ed])

    def _solve_with_contacts(self, y_free, active):
        """KKT solve with stiff one-sided springs (the nonlinear model's contact penalty) on ``active``:
        a low-rank (Woodbury) update of the cached base factorisation, no new factorisation:
        ``x = y - Z (C^-1 + U Z)^-1 U y`` with ``Z = M^-1 U^T`` (one cached back-substitution per hinge)
        and ``y = y_free + Z C kappa_c`` (the springs' preload)."""
        if active.size == 0:
            return y_free[:self.na], y_free[self.na:]
        kc = self.kc[active]
        if self._zcol is None:
            self._zcol = -np.ones(self.geo.m, dtype=np.int64)
            self._Z = np.zeros((self.pattern.N, 0))
            self._nz = 0
        missing = active[self._zcol[active] < 0]
        if missing.size:
            Ut = np.zeros((self.pattern.N, missing.size))
            Jm = self.close_sign[missing, None] * self.J5[missing]
            edm = self.pattern.ed[missing]
            cols = np.broadcast_to(np.arange(missing.size)[:, None], edm.shape)
            ok = edm >= 0
            Ut[edm[ok], cols[ok]] = Jm[ok]        # one hinge per column, its DOFs distinct: no repeats
            used = self._nz
            self._zcol[missing] = used + np.arange(missing.size)
            if not linalg._FAST:
                self._Z = np.hstack([self._Z[:, :used], self.lu.solve(Ut)])
            else:                   # column-major buffer with spare room: no copy per update, contiguous columns
                if used + missing.size > self._Z.shape[1]:
                    Zn = np.empty((self.pattern.N, max(2 * (used + missing.size), 16)), order="F")
                    Zn[:, :used] = self._Z[:, :used]
                    self._Z = Zn
                self._Z[:, used:used + missing.size] = self.lu.solve(Ut)
            self._nz = used + missing.size
        Z = self._Z[:, self._zcol[active]]
        y = y_free + Z @ (kc * self.kappa_c[active])
        S = np.diag(1.0 / kc) + self._rows(active, Z)
        x = y - Z @ np.linalg.solve(S, self._rows(active, y))
        return x[:self.na], x[self.na:]

    def solve(self, psi=None):
        """Solve the linearised system for constraint values ``psi`` (contact by the active set).

        Parameters
        ----------
        psi : numpy.ndarray, optional
            Constraint values (default the scene's).

        Returns
        -------
        tuple
            ``(X, R, q, mu)``: positions, rotations, DOF increments, multipliers.
        """
        geo = self.geo
        psi = self.psi if psi is None else psi
        I3 = np.broadcast_to(np.eye(3), (geo.n, 3, 3)).copy()
        self.contact_info = {"contact_hinges": 0, "active_set_iterations": 0}
        if self.lu is None or not np.any(psi):
            return geo.X0.copy(), I3, np.zeros(self.na), np.zeros(self.joints.size)
        rhs = np.zeros(self.pattern.N)
        rhs[self.na:] = psi
        if self.eps0 is not None:        # residual forces and constraint offsets of the base state
            rhs[:self.na] = -self.g0
            rhs[self.na:] -= self.eps0[self.joints, 5]
        sol = self.lu.solve(rhs)
        q = sol[:self.na]
        mu = sol[self.na:]
        if self.contact:
            # semismooth Newton on the penalised piecewise-quadratic (convex) energy: solve with the hinges
            # past the contact onset penalised, then a backtracking line search on the energy (both
            # iterates satisfy the linear actuator constraints, so every point between them does too)
            active = None
            e_old = self._energy(q)
            for it in range(100):
                new = np.flatnonzero(self._closing(q) > self.kappa_c)
                if (active is None and new.size == 0) or (active is not None and np.array_equal(new, active)):
                    break
                active = new
                q_new, mu_new = self._solve_with_contacts(sol, active)
                alpha = 1.0
                for _ in range(30):
                    q_try = q + alpha * (q_new - q)
                    e_try = self._energy(q_try)
                    if e_try <= e_old + 1e-14 * abs(e_old):
                        break
                    alpha *= 0.5
                q, e_old = q_try, e_try
                mu = mu + alpha * (mu_new - mu)
                self.contact_info = {"contact_hinges": int(active.size), "active_set_iterations": it + 1}
                if alpha < 1e-8:
                    break
            else:
                self.contact_info["active_set_converged"] = False
        X, R = self.pose(q)
        return X, R, q, mu

    def pose(self, q, alpha=1.0):
        """Positions and rotations of the step ``alpha q`` from the base state: rotations ``exp`` of the
        rotation increments, positions by the pose rule (``chain``: through the hinge chain)."""
        geo = self.geo
        X, R = _apply(self.base[0], self.base[1], alpha * q, self.dofmap, geo.n)
        if self.poses == "chain":        # positions through the hinge chain from the plate rotations
            if self._chain is None:
                self._chain = ChainPositions(geo)
            if getattr(self, "_step", (None,))[0] is not q:       # linearised strains of the step (once per q)
                self._step = (q, (self.J6 @ self.pattern.gather(q)[:, :, None])[:, :, 0])
            eps = alpha * self._step[1]
            if self.eps0 is not None:
                eps = eps + self.eps0
            strain = eps[:, 0:3] - 0.5 * geo.rest * _cross_e1(eps[:, 3:6])    # beyond uniform bending
            X = self._chain(R, X, strain)
        return X, R

    def merit(self, eps, nu):
        """The nonlinear model's energy at hinge strains ``eps`` (hinges and, with contact, its penalty on the
        closing rotation past the onset) plus the exact penalty ``nu |c|_1`` of the actuator constraints."""
        e = 0.5 * float(np.einsum("mi,mij,mj->", eps, self.geo.K, eps))
        if self.contact:
            over = np.maximum(self.close_sign * eps[:, 5] - self.kappa_onset, 0.0)
            e += 0.5 * float(np.sum(self.kc * over * over))
        if self.joints.size:
            e += nu * float(np.abs(eps[self.joints, 5] - self.psi).sum())
        return e

    def merit_slope(self, q, nu):
        """d merit / d alpha at alpha = 0 along the step ``alpha q`` from the base state (analytic: hinge
        forces of the state, contact springs already past the onset, and the constraint penalty)."""
        if getattr(self, "_step", (None,))[0] is not q:
            self._step = (q, (self.J6 @ self.pattern.gather(q)[:, :, None])[:, :, 0])
        deps = self._step[1]
        slope = float(self.g0 @ q)
        if self.contact:
            over = self.close_sign * self.eps0[:, 5] - self.kappa_onset
            on = over > 0
            slope += float(np.sum(self.kc[on] * over[on] * self.close_sign[on] * deps[on, 5]))
        if self.joints.size:
            c0 = self.eps0[self.joints, 5] - self.psi
            slope += nu * float(np.sum(np.sign(c0) * deps[self.joints, 5]))
        return slope

    def line_search(self, q, mu, X1, R1):
        """Step length along the solved step that minimises the merit (the nonlinear energy plus the constraint
        penalty, at the poses the model returns): the parabola through the merit and its slope at the base
        state and the merit of the full step; its minimum is taken only if its merit is below the full
        step's. Returns ``(alpha, X, R)``. The slope at the base is exact: to first order the returned poses
        move along the solved increments (the hinge-chain positions satisfy the same linearised relations)."""
        if self.eps0 is None or not q.size:
            return 1.0, X1, R1
        nu = 2.0 * float(np.abs(mu).max(initial=0.0))
        m0 = self.merit(self.eps0, nu)
        m1 = self.merit(hinge_strains(self.geo, X1, R1), nu)
        slope = self.merit_slope(q, nu)
        curv = m1 - m0 - slope
        if not (slope < 0 and curv > 0):
            return 1.0, X1, R1
        a = min(2.0, max(1.0 / 64, -slope / (2.0 * curv)))
        if a == 1.0:
            return 1.0, X1, R1
        Xa, Ra = self.pose(q, a)
        if self.merit(hinge_strains(self.geo, Xa, Ra), nu) < m1:
            return a, Xa, Ra
        return 1.0, X1, R1
