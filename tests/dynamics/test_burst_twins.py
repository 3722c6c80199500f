"""``Simulator._burst`` (burst.py) against the step-by-step path (``Simulator.burst = False``) where an actuator
rebinds the simulator's contact arrays (``sim.anchors``, ``sim.inside``) in the middle of a burst, and the
helpers both paths share (``Simulator._track_com``, ``EnergyLedger._book_actuation``)."""
import os

import numpy as np
import pytest

from metamaterial_wb.core.dynamics import Simulator
from metamaterial_wb.core.dynamics import fastkernel
from metamaterial_wb.core.dynamics.builders import build, dynamics_config
from metamaterial_wb.core.scene import Scene

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
COUNTS = ("steps", "force_evaluations", "jacobians", "newton_iterations", "newton_unconverged_steps", "bdf2_steps",
          "max_penetration_mm", "rejected_checks")


def _lib_or_skip():
    if fastkernel.load() is None:
        pytest.skip(f"no compiled kernel here: {fastkernel.note()}")


def _run(burst, wrap, seconds=0.1, spy=None):
    sc = Scene.load(os.path.join(ROOT, "examples", "worm_crawl.json"))
    cfg = dynamics_config(sc)
    model = build(sc, cfg)
    sim = Simulator(model.system, model.q0, actuate=wrap(model.actuate))
    sim.energy_scale = float(model.system.mass.sum() * 9.81 * 0.05)
    sim.kernel, sim.burst = "c", burst
    if spy is not None:
        spy(sim)
    frames = []
    sim.run(seconds, method="implicit", dt=cfg["integrator"]["dt_s"], record_dt=seconds / 7,
            on_record=lambda S: frames.append((S.t, S.q.copy(), S.v.copy(), S.anchors.copy(), S.inside.copy(),
                                               dict(S.ledger))))
    return sim, frames


def _assert_same(a, b):
    (sa, fa), (sb, fb) = a, b
    assert sa.stats["kernel"] == sb.stats["kernel"] == "c"
    for key in COUNTS:
        assert sa.stats.get(key, 0) == sb.stats.get(key, 0), key
    for key in ("com_x_min_m", "com_x_max_m"):      # summed in C in the burst, by numpy's dot step by step
        assert sb.stats[key] == pytest.approx(sa.stats[key], rel=1e-13, abs=1e-15), key
    assert sa.t == sb.t
    for name in ("q", "v", "anchors", "inside"):
        assert np.array_equal(getattr(sa, name), getattr(sb, name)), name
    assert sa.ledger == sb.ledger
    assert len(fa) == len(fb)
    for i, (x, y) in enumerate(zip(fa, fb)):
        assert x[0] == y[0] and x[5] == y[5], i
        for name, p, r in zip(("q", "v", "anchors", "inside"), x[1:5], y[1:5]):
            assert np.array_equal(p, r), (i, name)


def _rebinding(what):
    """A stand-in actuator: the scene's, and every 37th step a new array bound to ``sim.anchors`` (moved by
    0.1 um: a slip the actuator imposes) or to ``sim.inside`` (a copy)."""
    def wrap(inner):
        def act(t, sim):
            inner(t, sim)
            if int(round(t / 2.5e-4)) % 37 == 0:
                if what == "anchors":
                    sim.anchors = sim.anchors + 1e-7
                else:
                    sim.inside = sim.inside.copy()
        return act
    return wrap


@pytest.mark.parametrize("what", ["anchors", "inside"])
def test_burst_sees_an_actuator_that_rebinds_the_contact_arrays(what):
    """The burst's kernel writes the contact anchors and flags in place; an actuator that binds a new array to
    ``sim.anchors`` / ``sim.inside`` mid-burst must not leave the burst updating the old one: the same run,
    states at every frame, ledger and counts bit for bit, as step by step."""
    _lib_or_skip()
    a = _run(False, _rebinding(what))
    b = _run(True, _rebinding(what))
    _assert_same(a, b)
    assert b[0].stats["steps"] == 400
    assert np.any(b[0].inside)      # the worm touches the ground: the anchors matter


def _counting(sim, calls):
    for name in ("_track_com", "_book_actuation"):
        inner = getattr(sim, name)

        def counted(*args, _inner=inner, _name=name):
            calls[_name] += 1
            return _inner(*args)
        setattr(sim, name, counted)


def test_step_by_step_and_burst_fallback_share_the_bookkeeping():
    """``_track_com`` (the centre of mass's extremes) and ``_book_actuation`` (the first half of the actuators'
    work) serve ``run``'s step by step path and the burst's numpy fallback step alike."""
    _lib_or_skip()
    calls = {"_track_com": 0, "_book_actuation": 0}
    a = _run(False, _rebinding("anchors"), spy=lambda s: _counting(s, calls))
    assert calls == {"_track_com": 400, "_book_actuation": 400}
    calls.update(_track_com=0, _book_actuation=0)
    b = _run(True, _rebinding("anchors"), spy=lambda s: _counting(s, calls))
    # in the burst: the steps whose actuator rebinds the anchors (and the last step, run()'s own) only
    assert 0 < calls["_track_com"] == calls["_book_actuation"] < 400
    _assert_same(a, b)
