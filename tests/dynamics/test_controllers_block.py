"""A sheet's servo actuation for a block of steps at once (SheetController.gap_D, controllers.py) and set by the
compiled kernel before each step (block_actuation; mm_sheet_steps / mm_sheet_actuate, _kernel.c; Simulator._burst):
the same numbers as ``SheetController.__call__`` step by step, bit for bit, and the same runs as
``Simulator.burst = False``."""
from __future__ import annotations

import math
import os
import types

import numpy as np
import pytest

from metamaterial_wb.core.dynamics import Simulator, fastkernel
from metamaterial_wb.core.dynamics.builders import BeltController as BeltFromBuilders
from metamaterial_wb.core.dynamics.builders import SheetController as SheetFromBuilders
from metamaterial_wb.core.dynamics.builders import build, dynamics_config
from metamaterial_wb.core.dynamics.controllers import BeltController, SheetController
from metamaterial_wb.core.motion import validate_profile
from metamaterial_wb.core.scene import Scene

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
COUNTS = ("steps", "force_evaluations", "jacobians", "newton_iterations", "newton_unconverged_steps", "bdf2_steps",
          "max_penetration_mm", "rejected_checks")

PROFILES = [
    {"shape": "keyframes", "times_s": [0.0, 0.13, 0.4], "values": [0.2, -0.9, 0.5], "period_s": 0.55},
    {"shape": "steps", "times_s": [0.0, 0.07, 0.21], "values": [0.0, 1.0, -0.6], "period_s": 0.3},
    {"shape": "constant", "value": -0.35},
    None,
    {"shape": "sine", "amplitude": 0.7, "frequency_hz": 3.3, "phase_deg": -47.0, "offset": 0.2},
]


def worm(profiles=None):
    sc = Scene.load(os.path.join(ROOT, "examples", "worm_crawl.json"))
    cfg = dynamics_config(sc)
    model = build(sc, cfg)
    if profiles is not None:
        for act, p in zip(model.actuate.acts, profiles):
            act.profile = validate_profile(p) if p is not None else None
    return model, cfg


def lib_or_skip():
    if fastkernel.load() is None:
        pytest.skip(f"no compiled kernel here: {fastkernel.note()}")


def test_moved_classes_are_still_imported_from_builders():
    assert SheetFromBuilders is SheetController and BeltFromBuilders is BeltController
    assert SheetController.time_only and not getattr(BeltController, "time_only", False)


@pytest.mark.parametrize("profiles", [None, PROFILES[:2], PROFILES[2:4], PROFILES[4:] + PROFILES[:1]],
                         ids=["scene", "keyframes+steps", "constant+none", "sine+keyframes"])
def test_gap_D_is_call_s_D_row_for_row(profiles):
    """D for many times at once equals ``d_const + d_basis @ values(t)`` of ``__call__`` at each time, bitwise
    (times accumulated by addition as a run does, across the profiles' periods and key times)."""
    model, _ = worm(profiles)
    c = model.actuate
    times, t = [], 0.0
    for _ in range(3000):
        t += 2.5e-4
        times.append(t)
    times += [0.0, 0.07, 0.13, 0.21, 0.3, 0.55, 1.1, 123.456789]
    D = c.gap_D(times)
    assert D.shape == (len(times), c.d_const.size)
    ref = np.array([c.d_const + c.d_basis @ c.values(t) for t in times])
    assert np.array_equal(D, ref)
    empty = SheetController([], c.d_const, c.d_basis[:, :0], c.P0, c.s, c.lh, c.closing, c.opening,
                            np.zeros(c.d_const.size), c.sys)
    assert np.array_equal(empty.gap_D([0.1, 0.2]), np.vstack([c.d_const, c.d_const]))


def test_compiled_actuation_is_call_s_actuation_bitwise():
    """The block's actuation (``block_actuation``: numpy on the block, copied in by mm_sheet_actuate) against
    ``__call__`` on the same D: pitch -> anchors and fold -> rest angles, with tilted hinges, D beyond +-1 (clipped),
    +-0, tiny values and a NaN. (The cosine and sine are numpy's in both: on AVX-512 numpy's may be SVML's, whose
    last bit can differ from the C library's, so the kernel does not compute them.)"""
    lib_or_skip()
    model, _ = worm()
    s = model.system
    c0 = model.actuate
    m = s.ha.size
    rng = np.random.default_rng(7)
    tilt = rng.uniform(-0.6, 0.6, m)
    k = fastkernel.Kernel(fastkernel.load(), s, fastkernel.layout_for(s, band_max=s.band_max))
    rows = [rng.uniform(-1.3, 1.3, m) for _ in range(300)]
    special = np.array([0.0, -0.0, 1.0, -1.0, 5e-324, -5e-324, 1e-17, -1e-17])
    rows.append(np.resize(special, m))
    rows.append(np.resize([np.nan, 0.5, -0.5], m))
    for closing, opening in ((c0.closing, c0.opening), (rng.uniform(0.01, 0.9, m), rng.uniform(0.01, 0.9, m))):
        for D in rows:
            ctrl = SheetController([], D.copy(), np.zeros((m, 0)), c0.P0, c0.s, c0.lh, closing, opening, tilt, s)
            ctrl(0.0, None)
            ref = (s.theta0.copy(), s.ra.copy(), s.rb.copy())
            s.theta0[:] = 7.0
            s.ra[:, 0] = 7.0
            s.rb[:, 0] = 7.0
            k.sheet_actuate(ctrl.block_actuation([0.0]))
            for a, b in zip(ref, (s.theta0, s.ra, s.rb)):
                assert np.array_equal(a, b, equal_nan=True)
                ok = ~np.isnan(a)          # (a NaN's sign bit is not a number's: not compared)
                assert np.array_equal(np.signbit(a[ok]), np.signbit(b[ok]))


def test_actuation_of_a_block_is_that_of_each_row():
    """``actuation`` on a (n, m) block row by row equals it on each row alone, bitwise: the ufuncs' results do not
    depend on an element's place in the array (SIMD lanes, the tail of a vector loop)."""
    model, _ = worm()
    c, m = model.actuate, model.system.ha.size
    rng = np.random.default_rng(11)
    for n in (1, 2, 3, 7, 8, 9, 17, 64, 301):
        D = rng.uniform(-1.3, 1.3, (n, m))
        block = c.actuation(D)
        for i in range(n):
            for a, b in zip(block, c.actuation(D[i])):
                assert np.array_equal(a[i], b), (n, i)


def _run(model, cfg, burst, seconds, record=None, check_every=100, dt=None):
    sim = Simulator(model.system, model.q0, actuate=model.actuate)
    sim.energy_scale = float(model.system.mass.sum() * 9.81 * 0.05)
    sim.kernel = "c"
    sim.burst = burst
    frames = []
    sim.run(seconds, method="implicit", dt=dt or cfg["integrator"]["dt_s"], record_dt=record, check_every=check_every,
            on_record=(lambda S: frames.append((S.t, S.q.copy(), S.v.copy(), S.anchors.copy(), dict(S.ledger))))
            if record else None)
    return sim, frames


@pytest.mark.parametrize("profiles,seconds,record,check_every", [
    (None, 0.4, 0.0371, 100), (PROFILES[:2], 0.3, 0.05, 37), (PROFILES[2:4], 0.2, None, 100),
    (PROFILES[4:] + PROFILES[:1], 0.25, 0.0013, 250)], ids=["scene", "keyframes+steps", "constant+none", "sine"])
def test_block_runs_match_step_by_step(monkeypatch, profiles, seconds, record, check_every):
    """Runs whose steps go through mm_sheet_steps in blocks (between checks and records) against the same run
    step by step (``burst = False``): the same states at every frame, ledger and counts, bit for bit."""
    lib_or_skip()
    calls = []
    real = fastkernel.Kernel.sheet_steps

    def counting(self, n, block):
        calls.append(n)
        return real(self, n, block)
    monkeypatch.setattr(fastkernel.Kernel, "sheet_steps", counting)
    model, cfg = worm(profiles)
    a, fa = _run(model, cfg, False, seconds, record, check_every)
    assert not calls
    model, cfg = worm(profiles)
    b, fb = _run(model, cfg, True, seconds, record, check_every)
    assert calls and max(calls) > 1 and sum(calls) < b.stats["steps"] + 2
    assert a.stats["kernel"] == b.stats["kernel"] == "c"
    for key in COUNTS:
        assert a.stats.get(key, 0) == b.stats.get(key, 0), key
    for key in ("com_x_min_m", "com_x_max_m"):
        assert b.stats[key] == pytest.approx(a.stats[key], rel=1e-13, abs=1e-15)
    assert a.t == b.t and a.ledger == b.ledger
    for x, y in ((a.q, b.q), (a.v, b.v), (a.anchors, b.anchors), (a.inside, b.inside),
                 (a.sys.theta0, b.sys.theta0), (a.sys.ra, b.sys.ra), (a.sys.rb, b.sys.rb)):
        assert np.array_equal(x, y)
    assert len(fa) == len(fb)
    for x, y in zip(fa, fb):
        assert x[0] == y[0] and x[4] == y[4]
        assert all(np.array_equal(p, r) for p, r in zip(x[1:4], y[1:4]))


def test_a_wrapped_controller_runs_per_step():
    """An actuator that is not a time-only controller (here a plain function around one) keeps the per-step
    callback: it is called once per step, at the step's end time."""
    lib_or_skip()
    model, cfg = worm()
    inner = model.actuate
    seen = []

    def act(t, sim):
        seen.append(t)
        inner(t, sim)
    sim = Simulator(model.system, model.q0, actuate=act)
    sim.kernel = "c"
    sim.run(0.01, method="implicit", dt=2.5e-4)
    assert len(seen) == 1 + sim.stats["steps"] == 41
    assert math.isclose(seen[-1], 0.01)


def test_controller_of_another_system_is_called_per_step():
    """A time-only controller bound to another system than the simulated one is not run by the kernel."""
    lib_or_skip()
    model, cfg = worm()
    other, _ = worm()
    c = model.actuate
    wrong = SheetController(c.acts, c.d_const, c.d_basis, c.P0, c.s, c.lh, c.closing, c.opening,
                            np.zeros(c.d_const.size), other.system)
    calls = types.SimpleNamespace(n=0)
    orig = SheetController.__call__

    def counted(self, t, sim):
        calls.n += 1
        orig(self, t, sim)
    try:
        SheetController.__call__ = counted
        sim = Simulator(model.system, model.q0, actuate=wrong)
        sim.kernel = "c"
        sim.run(0.01, method="implicit", dt=2.5e-4)
    finally:
        SheetController.__call__ = orig
    assert calls.n == 41
