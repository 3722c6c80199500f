"""The two lattice models: "linear" (R1, one sparse solve) and "nonlinear" (R2, Newton), and what they share.

Both share :class:`~metamaterial_wb.core.lattice.geometry.LatticeGeometry` and the vectorised hinge
mechanics of :mod:`~metamaterial_wb.core.lattice.mechanics`. One role per file:

* :mod:`.linalg`: KKT solves (sparse LU, CHOLMOD + Schur complement), the held plate, the DOF map and the
  fast-path / reference-path switch (:func:`reference_paths`);
* :mod:`.poses`: Kabsch alignment, plate twist and D, hinge-chain positions, state updates;
* :mod:`.predictor`: the quadratic model as predictor (:func:`quadratic_D`, :func:`quadratic_state`);
* :mod:`.linear`: :class:`LinearLattice`; :mod:`.nonlinear`: :class:`NonlinearLattice`.

Model summary:

* Actuators and angular constraints are exact constraints on the relative rotation of the two plates
  of their joint about the hinge's soft axis (Lagrange multipliers, a symmetric KKT system).
* Rigid motions: one node near the centre is held (all its DOFs); the result is then aligned to the
  flat sheet by a best-fit rigid motion (Kabsch), so positions are comparable across models.
* Planar scenes (no tilted hinge) keep 3 DOFs per node (x, y, rotation about z): out-of-plane DOFs
  are left out because in-plane actuation cannot excite them.
* Plate contact (nonlinear model): a one-sided penalty on the closing relative rotation of each hinge
  once it passes ``contact_fraction`` of the contact rotation ``2 asin(lh / 2s)``.
* Newton with a backtracking line search on an exact-penalty merit function, adaptive load stepping;
  dynamic relaxation (kinetic damping) as the fallback, followed by a Newton polish. A result that
  did not reach the tolerance has ``converged = False`` and a warning.

This module re-exports the public names from where callers have always imported them.
"""
from metamaterial_wb.core.lattice.linalg import (SCHUR_MAX_CONSTRAINTS, SchurKKT, _dofmap,  # noqa: F401
                                                 _kkt_solve, _support_node, kkt_regularisation, reference_paths)
from metamaterial_wb.core.lattice.linear import LinearLattice  # noqa: F401
from metamaterial_wb.core.lattice.nonlinear import NonlinearLattice  # noqa: F401
from metamaterial_wb.core.lattice.poses import ChainPositions, _apply, finish, kabsch, node_twist  # noqa: F401
from metamaterial_wb.core.lattice.predictor import quadratic_D, quadratic_state  # noqa: F401
