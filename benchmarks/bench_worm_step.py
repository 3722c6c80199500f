"""Per-step cost of the implicit integrator on the compiled kernel (worm, belts).

    /usr/bin/python3 benchmarks/bench_worm_step.py [--scene worm_crawl.json] [--seconds 10] [--repeat 3]
                                                   [--no-burst] [--split] [--lean-actuator]

Times ``Simulator.run`` (model building excluded, as benchmarks/bench_dynamics.py) at the scene's own
integrator settings, best of ``--repeat``, and prints the step, force-evaluation, Jacobian and Newton counts
and the final centre of mass, so that two versions of the code can be compared run for run (A/B).

``--no-burst``: ``Simulator.burst = False`` (every step through ``step_implicit``, the code before the
one-call-per-step path). ``--split``: also the time spent in the scene's actuator callback
(``model.actuate``) and in the C step call. ``--lean-actuator``: a prototype, for measuring only, of the
sheet controller's ``__call__`` (builders.py) with fewer numpy calls and the same operations on the same
values (``np.clip`` -> ``np.minimum(np.maximum(...))``, the cosine and sine taken once).
"""
from __future__ import annotations

import argparse
import os
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, ROOT)

from metamaterial_wb.core.dynamics import Simulator, fastkernel  # noqa: E402
from metamaterial_wb.core.dynamics.builders import SheetController, build, dynamics_config  # noqa: E402
from metamaterial_wb.core.scene import Scene  # noqa: E402


def lean_sheet_call(self, t, sim):
    """SheetController.__call__ with the same ufuncs on the same values (bitwise the same actuation)."""
    D = self.d_const + self.d_basis @ self.values(t) if self.acts else self.d_const
    D = np.minimum(np.maximum(D, -1.0), 1.0)
    pos = D >= 0
    phi = np.where(pos, D * self.closing, -D * self.opening)
    c, s = np.cos(phi), np.sin(phi)
    pitch = np.where(pos, self.lh + self.s * (c - s), self.lh + self.s * (c + s))
    self.sys.ra[:, 0] = pitch / 2
    self.sys.rb[:, 0] = -pitch / 2
    self.sys.theta0[:] = 2.0 * np.sign(D) * phi * self.tilt_tan


def run_once(sc, seconds, burst=True, split=False):
    cfg = dynamics_config(sc)
    model = build(sc, cfg)
    act = model.actuate
    acc = [0.0, 0.0]
    if split and act is not None:
        real = act

        def act(t, sim, real=real):
            t0 = time.perf_counter()
            real(t, sim)
            acc[0] += time.perf_counter() - t0
    sim = Simulator(model.system, model.q0, actuate=act)
    sim.energy_scale = float(model.system.mass.sum() * 9.81 * 0.05)
    sim.kernel = "c"
    sim.burst = burst
    lib = fastkernel.load()
    raw = getattr(lib, "mm_step", None)     # (absent in the code before the one-call-per-step path)
    if split and raw is not None:
        def timed(a, b):
            t0 = time.perf_counter()
            raw(a, b)
            acc[1] += time.perf_counter() - t0
        lib.mm_step = timed
    try:
        sim.run(seconds, method=cfg["integrator"]["method"], dt=cfg["integrator"]["dt_s"], record_dt=seconds / 200,
                on_record=lambda S: None)
    finally:
        if raw is not None:
            lib.mm_step = raw
    st = sim.stats
    return {"wall_s": st["wall_s"], "steps": st["steps"], "force_evaluations": st["force_evaluations"],
            "jacobians": st.get("jacobians", 0), "newton_iterations": st.get("newton_iterations", 0),
            "unconverged": st.get("newton_unconverged_steps", 0), "com_mm": model.com_x(sim.q) * 1e3,
            "actuator_s": acc[0], "c_step_s": acc[1]}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--scene", default="worm_crawl.json")
    ap.add_argument("--seconds", type=float, default=10.0)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--no-burst", action="store_true")
    ap.add_argument("--split", action="store_true")
    ap.add_argument("--lean-actuator", action="store_true")
    a = ap.parse_args(argv)
    if fastkernel.load() is None:
        sys.exit(f"no compiled kernel: {fastkernel.note()}")
    if a.lean_actuator:
        SheetController.__call__ = lean_sheet_call
    sc = Scene.load(os.path.join(ROOT, "examples", a.scene))
    runs = [run_once(sc, a.seconds, burst=not a.no_burst, split=a.split) for _ in range(a.repeat)]
    best = min(runs, key=lambda r: r["wall_s"])
    r = best
    print(f"{a.scene} {a.seconds:g} s: wall best {r['wall_s']:.3f} s of {[round(x['wall_s'], 3) for x in runs]} "
          f"({a.seconds / r['wall_s']:.2f}x real time, {r['wall_s'] / r['steps'] * 1e6:.1f} us/step); "
          f"steps {r['steps']}, force evaluations {r['force_evaluations']}, Jacobians {r['jacobians']}, "
          f"Newton iterations {r['newton_iterations']}, unconverged {r['unconverged']}, com {r['com_mm']!r} mm")
    if a.split:
        print(f"  actuator {r['actuator_s']:.3f} s ({r['actuator_s'] / r['steps'] * 1e6:.1f} us/step), "
              f"C step {r['c_step_s']:.3f} s ({r['c_step_s'] / r['steps'] * 1e6:.1f} us/step), rest "
              f"{(r['wall_s'] - r['actuator_s'] - r['c_step_s']) / r['steps'] * 1e6:.1f} us/step")


if __name__ == "__main__":
    main()
