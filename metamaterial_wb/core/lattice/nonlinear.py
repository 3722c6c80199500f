"""The nonlinear corotational lattice model (R2): Newton with a backtracking line search on an
exact-penalty merit function, adaptive load stepping, plate contact by a one-sided penalty, dynamic
relaxation as the fallback (docs/fidelity-models.md)."""

import numpy as np

from metamaterial_wb.core.lattice.geometry import LatticeGeometry, fixed_items
from metamaterial_wb.core.lattice.linalg import _dofmap, _kkt_solve, kkt_regularisation
from metamaterial_wb.core.lattice.linear import LinearLattice
from metamaterial_wb.core.lattice.mechanics import ElementState, Pattern
from metamaterial_wb.core.lattice.poses import _apply

_ROT_DOFS = np.array([3, 4, 5, 9, 10, 11])


def _check_predictor(geo, planar, method):
    """Refuse ``predictor=true`` where the linear predictor cannot run (it would be skipped silently): refined
    hinges (``hinge_elements`` >= 2), a ``planar`` override that differs from the scene's own (the one-element
    linear lattice has other unknowns), ``method=dynamic_relaxation`` (no Newton start to predict)."""
    from metamaterial_wb.core.errors import SceneError
    n = getattr(geo, "hinge_elements", 1)
    if n != 1:
        raise SceneError("--option predictor", f"true with --option hinge_elements={n}; allowed: predictor only with "
                                               "hinge_elements=1 (the linear predictor has one element per hinge)")
    own = getattr(geo, "base", geo).planar
    if bool(planar) != bool(own):
        raise SceneError("--option predictor", f"true with --option planar={str(bool(planar)).lower()} on a scene "
                                               f"whose own is planar={str(bool(own)).lower()}; allowed: predictor "
                                               "with the scene's own planar setting (omit planar)")
    if method != "newton":
        raise SceneError("--option predictor", f"true with --option method={method}; allowed: predictor only with "
                                               "method=newton (it is Newton's starting point)")

class NonlinearLattice:
    """Nonlinear corotational lattice: ``solve()`` returns ``(X, R, converged)``; ``stats`` says how.

    Options are those of the "nonlinear" model (core/lattice/__init__.py, docs/fidelity-models.md).

    Parameters
    ----------
    scene : Scene
    geo : LatticeGeometry, optional
    contact : bool
    contact_fraction, contact_stiffness : float
    tol : float
        Newton tolerance.
    max_iter, load_steps, dr_max_iter : int
    min_step : float
        Smallest load step.
    fallback : bool
        Dynamic relaxation when Newton fails.
    predictor : bool
        Start from the linear model with contact; only with one element per hinge, the scene's own ``planar``
        and Newton (elsewhere the linear lattice's unknowns are not the model's: refused with a SceneError).
        ``stats["predictor_used"]`` records whether it ran.
    planar : bool, optional
    method : {"newton", "dynamic_relaxation"}
    """

    def __init__(self, scene, geo=None, contact=True, contact_fraction=0.98, contact_stiffness=1e4,
                 tol=1e-8, max_iter=40, load_steps=1, min_step=1.0 / 64, fallback=True, dr_max_iter=5000,
                 predictor=False, planar=None, method="newton"):
        from metamaterial_wb.core.errors import SceneError
        if method not in ("newton", "dynamic_relaxation"):
            raise SceneError("--option method", f"{method!r}; allowed: newton, dynamic_relaxation")
        self.method = method
        self.geo = geo or LatticeGeometry(scene)
        geo = self.geo
        self.joints, self.values, self.psi, self.names = fixed_items(scene, geo)
        self.planar = geo.planar if planar is None else bool(planar)
        self.dofmap, self.na = _dofmap(geo, self.planar)
        self.pattern = Pattern(geo.dofs, self.dofmap, self.na, self.joints, None)
        self.reg = kkt_regularisation(geo)
        # rounding floor of the force residual: forces are differences of positions ~ the cell size
        self.force_floor = 100.0 * np.finfo(float).eps * float(geo.K[:, 0, 0].max()) * geo.cell_size_mm
        self.contact = contact
        self.contact_fraction = contact_fraction
        # contact penalty per hinge: a multiple of its soft bending stiffness, acting on the closing rotation
        # refined hinges (core/lattice/refine): contact on the whole-hinge elements only
        self.kc = contact_stiffness * getattr(geo, "contact_k", geo.K[:, 5, 5])
        self.kappa0 = np.where(getattr(geo, "contact_mask", True),
                               contact_fraction * 2.0 * geo.contact_rad / np.cos(geo.tilt), np.inf)
        self.close_sign = -geo.parity[geo.a]                 # closing measure = close_sign * Theta_3
        self.tol = float(tol)
        self.max_iter = int(max_iter)
        self.load_steps = max(1, int(load_steps))
        self.min_step = float(min_step)
        self.fallback = fallback
        self.dr_max_iter = int(dr_max_iter)
        self.predictor = bool(predictor)
        if self.predictor:
            _check_predictor(geo, self.planar, method)
        self.stats = {"newton_iterations": 0, "load_steps": 0, "line_search_backtracks": 0,
                      "dr_iterations": 0, "method": "newton", "predictor_used": False}

    # -- energy pieces ------------------------------------------------------------------------------
    def _state(self, X, R, tangent=True):
        """``(element state, energy incl. contact, element gradients, element tangents or None)``."""
        st = ElementState(self.geo, X, R, tangent=False)
        E, ge = self._energy_grad(st)
        return st, E, ge, (self._tangent(st) if tangent else None)

    def _contact_terms(self, st):
        if not self.contact:
            return None
        over = self.close_sign * st.eps[:, 5] - self.kappa0
        idx = np.flatnonzero(over > 0)
        if not idx.size:
            return None
        return idx, over[idx], st.J[idx, 5, :] * self.close_sign[idx, None]

    def _energy_grad(self, st):
        E = float(st.energy.sum())
        ge = st.grad
        ct = self._contact_terms(st)
        if ct is not None:
            idx, over, Jr = ct
            f = self.kc[idx] * over
            E += 0.5 * float(np.sum(f * over))
            ge = ge.copy()
            ge[idx] += f[:, None] * Jr
        return E, ge

    def _tangent(self, st, mu=None):
        """Element tangents of the Lagrangian: hinges, contact springs and, away from the plane, the
        curvature of the soft-axis rotation weighted by the contact forces and actuator multipliers."""
        He = st.tangent()
        ct = self._contact_terms(st)
        spatial = not self.geo.planar and getattr(self.geo, "exact_tangent", True)
        if ct is not None:
            idx, over, Jr = ct
            He = He.copy()
            He[idx] += self.kc[idx, None, None] * Jr[:, :, None] * Jr[:, None, :]
            if spatial:
                He[np.ix_(idx, _ROT_DOFS, _ROT_DOFS)] += st.soft_axis_curvature(idx, self.kc[idx] * over *
                                                                                 self.close_sign[idx])
        if spatial and mu is not None and mu.size and np.any(mu):
            He = He.copy() if ct is None else He
            # constraints share joints only once (fixed_items), so the fancy-index update is safe
            He[np.ix_(self.joints, _ROT_DOFS, _ROT_DOFS)] += st.soft_axis_curvature(self.joints, mu)
        return He

    def _kkt_norm(self, r_f, c, scale_f):
        """Scaled KKT residual: forces relative to the actuator load, constraints relative to the rotations."""
        rc = np.abs(c).max(initial=0.0) / max(1e-3, np.abs(self.psi).max(initial=0.0))
        return max(np.abs(r_f).max(initial=0.0) / scale_f, rc)

    def _constraint(self, st, lam):
        return st.eps[self.joints, 5] - lam * self.psi

    # -- Newton on one load level -------------------------------------------------------------------
    def _newton(self, X, R, lam, mu, scale_f):
        pat = self.pattern
        nu = None
        carried = None
        for it in range(self.max_iter):
            if carried is None:
                st, E, ge, _ = self._state(X, R, tangent=False)
            else:
                st, E, ge = carried
            g = pat.vector(ge)
            c = self._constraint(st, lam)
            A = st.J[self.joints, 5, :]
            Ag = pat.vector(A * mu[:, None], self.joints) if mu.size else 0.0
            r_f = np.abs(g + Ag).max() if g.size else 0.0
            r_c = np.abs(c).max() if c.size else 0.0
            self.last_residual = (r_f / scale_f, r_c)
            if r_f <= max(self.tol * scale_f, self.force_floor) and \
                    r_c <= self.tol * max(1e-3, np.abs(self.psi).max(initial=0.0)):
                return X, R, mu, True, it
            He = self._tangent(st, mu)
            rhs = np.concatenate([-(g + Ag), -c])      # increments of the state and of the multipliers
            try:
                sol = _kkt_solve(pat, He, A, self.reg, rhs)
            except RuntimeError:
                return X, R, mu, False, it
            if not np.all(np.isfinite(sol)):
                return X, R, mu, False, it
            dq = sol[:self.na]
            mu_new = mu + sol[self.na:]
            nu = max(nu or 0.0, 2.0 * (np.abs(mu_new).max(initial=0.0)) + 1e-30)
            merit0 = E + nu * np.abs(c).sum()
            slope = float(g @ dq) - nu * np.abs(c).sum()
            alpha = 1.0
            ok = False
            res0 = self._kkt_norm(g + Ag, c, scale_f)
            for _ in range(12):
                X2, R2 = _apply(X, R, alpha * dq, self.dofmap, self.geo.n)
                st2, E2, g2, _H2 = self._state(X2, R2, tangent=False)
                c2 = self._constraint(st2, lam)
                merit = E2 + nu * np.abs(c2).sum()
                if merit <= merit0 + 1e-4 * alpha * min(slope, 0.0) + 1e-13 * abs(merit0):
                    ok = True
                    break
                # close to the solution the energy changes drown in rounding: there, accept a step that
                # reduces the KKT residual instead (far from it, the energy decides: it keeps Newton on the
                # branch it started on)
                if res0 > 1e-5:
                    alpha *= 0.5
                    self.stats["line_search_backtracks"] += 1
                    continue
                mu_t = mu + alpha * (mu_new - mu)
                A2 = st2.J[self.joints, 5, :]
                Ag2 = pat.vector(A2 * mu_t[:, None], self.joints) if mu.size else 0.0
                if self._kkt_norm(pat.vector(g2) + Ag2, c2, scale_f) <= (1.0 - 1e-4 * alpha) * res0:
                    ok = True
                    break
                alpha *= 0.5
                self.stats["line_search_backtracks"] += 1
            self.stats["newton_iterations"] += 1
            if not ok:
                return X, R, mu, False, it
            X, R = X2, R2
            carried = (st2, E2, g2)
            mu = mu + alpha * (mu_new - mu)
        st, E, ge, He = self._state(X, R, tangent=False)
        g = pat.vector(ge)
        c = self._constraint(st, lam)
        Ag = pat.vector(st.J[self.joints, 5, :] * mu[:, None], self.joints) if mu.size else 0.0
        self.last_residual = ((np.abs(g + Ag).max() if g.size else 0.0) / scale_f,
                              np.abs(c).max() if c.size else 0.0)
        return X, R, mu, False, self.max_iter

    # -- dynamic relaxation fallback -----------------------------------------------------------------
    def _dr_masses(self, X, R, kp):
        """Fictitious masses: Gershgorin row sums of the penalised tangent, contact penalties included
        whether active or not (so that a contact that closes cannot destabilise the explicit steps)."""
        pat = self.pattern
        st = ElementState(self.geo, X, R, tangent=True)
        He = np.abs(st.H)
        Jr = np.abs(st.J[:, 5, :])
        if self.contact:
            He = He + self.kc[:, None, None] * Jr[:, :, None] * Jr[:, None, :]
        gersh = pat.vector(He.sum(axis=2))
        if self.joints.size:
            A = np.abs(st.J[self.joints, 5, :])
            gersh = gersh + kp * pat.vector(A * A.sum(axis=1, keepdims=True), self.joints)
        return np.maximum(gersh, 1e-12 * max(gersh.max(initial=0.0), 1e-300))

    def _dynamic_relaxation(self, X, R, tol_f, scale_f):
        """Kinetic-damping dynamic relaxation on the penalised energy (constraints as stiff springs).

        Explicit pseudo-dynamics with unit time step and Gershgorin masses (refreshed every 100 steps);
        the velocities restart from zero at every kinetic-energy peak. No linear solves: it gets through
        states where Newton's tangent is singular or the line search stalls, and Newton then polishes.
        """
        pat = self.pattern
        st = ElementState(self.geo, X, R, tangent=True)
        kp = 10.0 * float(np.abs(st.H[:, :, :]).max())
        psi_scale = max(np.abs(self.psi).max(initial=0.0), 1e-12)
        v = np.zeros(self.na)
        ke_old = 0.0
        mass = None
        for it in range(self.dr_max_iter):
            if it % 100 == 0:
                mass = self._dr_masses(X, R, kp)
            st, E, ge, _ = self._state(X, R, tangent=False)
            c = self._constraint(st, 1.0)
            if self.joints.size:
                ge = ge.copy()
                np.add.at(ge, self.joints, (kp * c)[:, None] * st.J[self.joints, 5, :])
            f = -pat.vector(ge)
            if np.abs(f).max() <= tol_f * scale_f and (not c.size or np.abs(c).max() <= 1e-3 * psi_scale):
                self.stats["dr_iterations"] += it
                return X, R, True
            v = v + f / mass
            ke = float(v @ (mass * v))
            if ke < ke_old:          # kinetic damping: restart from rest at a kinetic-energy peak
                v = np.zeros_like(v)
                ke = 0.0
            ke_old = ke
            X, R = _apply(X, R, v, self.dofmap, self.geo.n)
        self.stats["dr_iterations"] += self.dr_max_iter
        return X, R, False

    # -- driver ---------------------------------------------------------------------------------------
    def solve(self, linear=None):
        """Solve for the equilibrium under the scene's actuators and constraints.

        Parameters
        ----------
        linear : LinearLattice, optional
            A linear model to reuse for the force scale and predictor.

        Returns
        -------
        tuple
            ``(X, R, converged)``.
        """
        geo = self.geo
        I3 = np.broadcast_to(np.eye(3), (geo.n, 3, 3)).copy()
        X, R = geo.X0.copy(), I3
        if not self.joints.size or not np.any(self.psi):
            self.stats["method"] = "no load (nothing to solve)"
            return X, R, True
        # refined hinges: the force scale from the one-element lattice (the same loads on the plates)
        lin = linear or LinearLattice(self.geo.scene, getattr(geo, "base", geo), contact=False)
        q0 = lin.solve(self.psi)[2]
        # force scale: the largest generalised force the actuators apply in the linear solution
        Klin_q = lin.H @ q0
        scale_f = max(float(np.abs(Klin_q).max()), 1e-30)
        q_lin = None
        if self.predictor and lin.na == self.na:
            # predictor: the linearised lattice with plate contact (piecewise linear)
            lin.contact = self.contact
            lin.kappa_c, lin.kc = self.kappa0, self.kc
            q_lin = lin.solve(self.psi)[2]
            self.stats["predictor_used"] = True
        self.scale_f = scale_f
        if self.method == "dynamic_relaxation":
            # dynamic relaxation alone (for comparison; the default uses it only as Newton's fallback)
            self.stats["method"] = "dynamic relaxation"
            X, R, ok = self._dynamic_relaxation(X, R, self.tol, scale_f)
            st = ElementState(geo, X, R, tangent=False)
            g = self.pattern.vector(self._energy_grad(st)[1])
            self.last_residual = (float(np.abs(g).max()) / scale_f, float(np.abs(self._constraint(st, 1.0)).max()))
            self.mu = np.zeros(self.joints.size)
            return X, R, ok
        mu = np.zeros(self.joints.size)
        lam = 0.0
        dl = 1.0 / self.load_steps
        converged = False
        while lam < 1.0 - 1e-15:
            step = min(dl, 1.0 - lam)
            target = lam + step
            X1, R1 = X, R
            if q_lin is not None and lam == 0.0:
                X1, R1 = _apply(X, R, step * q_lin, self.dofmap, geo.n)
            X2, R2, mu2, ok, _ = self._newton(X1, R1, target, mu.copy(), scale_f)
            if not ok and (X1 is not X):
                X2, R2, mu2, ok, _ = self._newton(X, R, target, mu.copy(), scale_f)
            if ok:
                X, R, mu, lam = X2, R2, mu2, target
                self.stats["load_steps"] += 1
                if step == dl and dl < 1.0:
                    dl = min(1.0, 2.0 * dl)
                continue
            if step / 2 >= self.min_step:
                dl = step / 2
                continue
            break
        converged = lam >= 1.0 - 1e-15
        if not converged and self.fallback:
            self.stats["method"] = "dynamic relaxation + Newton"
            Xd, Rd, ok = self._dynamic_relaxation(X, R, 1e-2, scale_f)
            X3, R3, mu3, ok2, _ = self._newton(Xd, Rd, 1.0, np.zeros(self.joints.size), scale_f)
            if ok2:
                X, R, converged = X3, R3, True
            else:
                X, R = (X3, R3) if np.all(np.isfinite(X3)) else (Xd, Rd)
        self.mu = mu
        return X, R, converged
