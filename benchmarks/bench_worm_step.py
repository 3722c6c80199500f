"""Per-step cost of the implicit integrator on the compiled kernel (worm, belts).

    /usr/bin/python3 benchmarks/bench_worm_step.py [--scene worm_crawl.json] [--seconds 10] [--repeat 3]
                                                   [--no-burst] [--split] [--lean-actuator]

Times ``Simulator.run`` (model building excluded, as benchmarks/bench_dynamics.py) at the scene's own
integrator settings, best of ``--repeat``, and prints the step, force-evaluation, Jacobian and Newton counts
and the final centre of mass, so that two versions of the code can be compared run for run (A/B). Each
invocation times run's default path (``Simulator.burst``: runs of steps in one C call each, burst.py) and the
step-by-step baseline (``Simulator.burst = False``: every step through ``step_implicit``) one after the other,
and prints their ratio and whether their final states, ledgers and counts are bitwise the same.

``--no-burst``: the baseline only. ``--split``: also the time spent in the scene's actuator callback
(``model.actuate``), in the sheet's block actuation (``SheetController.block_actuation``) and in the C calls
(``mm_step`` per step, or ``Kernel.sheet_steps`` per block). ``--lean-actuator``: a prototype, for measuring only, of the
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
from metamaterial_wb.core.dynamics.builders import build, dynamics_config  # noqa: E402
from metamaterial_wb.core.dynamics.controllers import SheetController  # noqa: E402
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


def _timed(acc, i, f):
    def g(*args):
        t0 = time.perf_counter()
        try:
            return f(*args)
        finally:
            acc[i] += time.perf_counter() - t0
    return g


def run_once(sc, seconds, burst=True, split=False):
    cfg = dynamics_config(sc)
    model = build(sc, cfg)
    acc = [0.0, 0.0, 0.0, 0.0]   # actuator callback, C step, block actuation (block_actuation), C block (mm_sheet_steps)
    patched = []
    lib = fastkernel.load()

    def patch(owner, name, i):
        raw = getattr(owner, name, None)      # (absent in older code: not timed)
        if raw is not None:
            patched.append((owner, name, raw))
            setattr(owner, name, _timed(acc, i, raw))
    if split:
        patch(type(model.actuate), "__call__", 0)
        patch(lib, "mm_step", 1)
        patch(SheetController, "block_actuation", 2)
        patch(fastkernel.Kernel, "sheet_steps", 3)
    sim = Simulator(model.system, model.q0, actuate=model.actuate)
    sim.energy_scale = float(model.system.mass.sum() * 9.81 * 0.05)
    sim.kernel = "c"
    sim.burst = burst
    try:
        sim.run(seconds, method=cfg["integrator"]["method"], dt=cfg["integrator"]["dt_s"], record_dt=seconds / 200,
                on_record=lambda S: None)
    finally:
        for owner, name, raw in reversed(patched):
            setattr(owner, name, raw)
    st = sim.stats
    return {"wall_s": st["wall_s"], "steps": st["steps"], "force_evaluations": st["force_evaluations"],
            "jacobians": st.get("jacobians", 0), "newton_iterations": st.get("newton_iterations", 0),
            "unconverged": st.get("newton_unconverged_steps", 0), "com_mm": model.com_x(sim.q) * 1e3,
            "actuator_s": acc[0], "c_step_s": acc[1], "block_act_s": acc[2], "c_block_s": acc[3],
            "q": sim.q.copy(), "ledger": dict(sim.ledger)}


def report(label, a, runs, r, split):
    print(f"  {label}: wall best {r['wall_s']:.3f} s of {[round(x['wall_s'], 3) for x in runs]} "
          f"({a.seconds / r['wall_s']:.2f}x real time, {r['wall_s'] / r['steps'] * 1e6:.1f} us/step); "
          f"steps {r['steps']}, force evaluations {r['force_evaluations']}, Jacobians {r['jacobians']}, "
          f"Newton iterations {r['newton_iterations']}, unconverged {r['unconverged']}, com {r['com_mm']!r} mm")
    if split:
        n = r["steps"]
        c_s = r["c_step_s"] if not r["c_block_s"] else r["c_block_s"]
        rest = r["wall_s"] - r["actuator_s"] - r["block_act_s"] - c_s
        print(f"    actuator callback {r['actuator_s'] / n * 1e6:.1f} us/step, block actuation (block_actuation) "
              f"{r['block_act_s'] / n * 1e6:.1f} us/step, C {'block' if r['c_block_s'] else 'step'} "
              f"{c_s / n * 1e6:.1f} us/step, rest {rest / n * 1e6:.1f} us/step")


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
    modes = [False] if a.no_burst else [True, False]
    runs = {m: [] for m in modes}
    for _ in range(a.repeat):              # the two paths one after the other, run for run
        for m in modes:
            runs[m].append(run_once(sc, a.seconds, burst=m, split=a.split))
    best = {m: min(runs[m], key=lambda r: r["wall_s"]) for m in modes}
    print(f"{a.scene} {a.seconds:g} s (best of {a.repeat}):")
    for m in modes:
        report("burst (run's default)" if m else "step by step (burst = False, the reference)", a, runs[m], best[m],
               a.split)
    if len(modes) == 2:
        b, s_ = best[True], best[False]
        same = (np.array_equal(b["q"], s_["q"]) and b["ledger"] == s_["ledger"]
                and all(b[k] == s_[k] for k in ("steps", "force_evaluations", "jacobians", "newton_iterations")))
        print(f"  ratio step by step / burst: x{s_['wall_s'] / b['wall_s']:.2f}; final states, ledger and counts "
              f"{'bitwise the same' if same else 'DIFFER'}")


if __name__ == "__main__":
    main()
