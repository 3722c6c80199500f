"""How ``Simulator.choose`` resolves the integrator ``"auto"``: the cheaper run on the path that will actually run.

The explicit integrator (semi-implicit Euler) runs in numpy only, at its stability guard (or a requested step within
its limit); the implicit one (BDF2 + Newton) at the requested step, else the scene's converged default step, on the
compiled kernel when there is one (fastkernel.py; runs of steps in one C call each, burst.py), else in numpy. Each
runs at the step it is trusted at, so the choice is about run time only; the dt study and the energy ledger check the
result either way (simulate.py).
"""
from __future__ import annotations

from .system import DynamicsError

# The cost of one implicit step in explicit steps, by the implicit integrator's path, as ``a + dofs / b``: at or above
# what ``benchmarks/bench_dynamics.py auto --costs`` measured on the sheet examples and the 1000-cell belt, on a shared
# 2-core machine (docs/benchmarks.md, "What auto runs"; single figures vary by up to 2x with the load). Compiled, runs
# of steps in one C call each (burst.py): 0.003-0.07 on the sheet examples (6-27 dofs; their time-only servo actuation
# runs blocks of steps per call), 0.1-0.23 on the 8-cell belt (48 dofs; its closed-loop controller is one Python call
# per step), 0.09-0.7 on belts of 30-300 cells (90-900 dofs), 2.0-2.6 on the 1000-cell belt (3000 dofs); the compiled
# Newton loop called once per step from Python: 0.2-0.8 on the sheets and the 8-cell belt, 2.3-3.2 at 3000 dofs;
# numpy: 1.3-2.5 on the sheets, 2.4-4.4 on the 8-cell belt, 1.3-9.0 at 90-900 dofs (dense LU up to 300 dofs), 19-24
# at 3000 dofs. (The former rule, "an implicit step costs 4-8 explicit steps" whatever the path, made the explicit
# integrator the default of every sheet example without dynamics.integrator: the fish's 0.2 s took 3241 numpy steps
# in 5.3 s against 800 compiled implicit steps in 0.05 s, with the same answer.)
IMPLICIT_STEP_COST = {"compiled": (0.3, 1000.0), "compiled_per_step": (1.0, 1000.0), "numpy": (2.5, 100.0)}


def implicit_step_cost(path, dofs):
    """The modelled cost of one implicit step on ``path`` (a key of ``IMPLICIT_STEP_COST``), in explicit steps, for a
    system of ``dofs`` degrees of freedom."""
    if path not in IMPLICIT_STEP_COST:
        raise ValueError(f"implicit path {path!r}; allowed: {', '.join(IMPLICIT_STEP_COST)}")
    a, b = IMPLICIT_STEP_COST[path]
    return a + float(dofs) / b


def auto_method(dt_symplectic, dt_implicit, implicit_cost):
    """``"symplectic"`` when its run is the cheaper one (``1 / dt_symplectic`` explicit steps against
    ``1 / dt_implicit`` implicit steps of ``implicit_cost`` explicit steps each), else ``"implicit"`` (also on a tie:
    the implicit step is the scene's converged one)."""
    return "symplectic" if implicit_cost * dt_symplectic > dt_implicit else "implicit"


def implicit_path(sim):
    """The path an implicit run of the simulator ``sim`` takes: ``"compiled"`` (runs of steps in one C call each,
    burst.py), ``"compiled_per_step"`` (``sim.burst`` off: the compiled Newton loop, one call per step) or ``"numpy"``
    (no compiler, a failed build, ``sim.kernel = "numpy"`` or ``METAMATERIAL_DYNAMICS_KERNEL=numpy``, a layout
    without band structure, a non-default Newton option). Builds the kernel as the first implicit step would
    (compiling it at its first use); ``sim.stats`` is left as it was."""
    dense, banded = sim._layout()    # as the implicit step solves
    keep = {k: sim.stats[k] for k in ("kernel", "kernel_note") if k in sim.stats}
    try:
        k = sim._kernel_for(dense, banded)
    except DynamicsError:           # kernel = "c" and not usable: an implicit run says so itself
        k = None
    finally:
        for key in ("kernel", "kernel_note"):
            sim.stats.pop(key, None)
        sim.stats.update(keep)
    if k is None:
        return "numpy"
    return "compiled" if sim.burst else "compiled_per_step"
