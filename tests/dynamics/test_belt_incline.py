"""The 8-cell belt on an incline (seed 2, section 5, figures 10-11): start-up with the controller's pressures,
viscoelastic silicone (loss factor), and the closed loop holding at the seed's limit of 10 degrees."""
import json
import math
import os

import numpy as np
import pytest

from metamaterial_wb.core.dynamics.builders import build, dynamics_config
from metamaterial_wb.core.dynamics.simulate import simulate
from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.core.scene import Scene


def _trapezoid(y, x):
    """Trapezoidal integral (numpy 2.x removed ``np.trapz``; ``np.trapezoid`` is new in 2.0)."""
    y, x = np.asarray(y, float), np.asarray(x, float)
    return float(np.sum(0.5 * (y[1:] + y[:-1]) * np.diff(x)))


ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CELL_MM = 38.0


def scene(name="belt8.json", belt=None, **dyn):
    with open(os.path.join(ROOT, "examples", name)) as f:
        d = json.load(f)
    d["dynamics"].update(dyn)
    d["dynamics"]["belt"].update(belt or {})
    return Scene.from_dict(d)


def test_initial_pressure_gait_starts_with_the_closed_loops_own_decision():
    vented = build(scene(belt={"initial_pressure": "vented"}))
    filled = build(scene(belt={"initial_pressure": "gait"}))
    assert np.all(vented.actuate.p == 0.0)
    # the seed's rule written out here (not core/gait.py): inflate i iff i is in the air and i + 1 is on the
    # ground; the sensor is read from the contact points of the released ring directly
    ctrl = filled.actuate
    pts = filled.system.contact_points(filled.q0)
    cells = np.repeat(filled.seg_cell, 2)
    ground = np.array([np.any(pts[cells == c, 1] < ctrl.thr) for c in range(8)])
    expect = [(not ground[i]) and ground[(i + 1) % 8] for i in range(8)]
    assert any(expect)
    p_on = dynamics_config(scene())["belt"]["pressure_kpa"]
    assert ctrl.p.tolist() == [p_on if e else 0.0 for e in expect]
    # ... and the rest curvature already belongs to those pressures (nothing left to fill at t = 0)
    assert np.any(filled.system.theta0 != vented.system.theta0)
    # the open loop starts with its first cell filled
    ol = build(scene("belt8_open_loop.json", belt={"initial_pressure": "gait"}))
    assert np.flatnonzero(ol.actuate.p).tolist() == [0]


def test_loss_factor_dissipates_pi_eta_k_a2_per_cycle():
    # definition of the loss factor: a hinge bent harmonically, theta = A sin(w t) at the matched frequency,
    # dissipates pi * eta * kr * A^2 per cycle. Measured through the force routine (damper torque x rate):
    # one segment rocks, which bends its two hinges (an inner and a stiffer inter-cell one) by A sin(w t).
    eta, f = 0.2, 1.5
    sc = scene(belt={"loss_factor": eta, "loss_frequency_hz": f}, damping_ratio=0.0)
    m = build(sc)
    s = m.system
    w, A = 2 * math.pi * f, 0.05
    h = 3
    q = m.q0.copy()
    anchors = s.contact_points(q)[:, 0] + 1.0
    q[:, 1] += 1.0                                   # lifted: no contact forces
    ts = np.linspace(0.0, 1.0 / f, 401)
    power = []
    for t in ts:
        v = np.zeros_like(q)
        v[s.hb[h], 2] = A * w * math.cos(w * t)        # the relative rotation rate of hinge h only
        Q1, _ = s.forces(q, v, anchors)
        Q0, _ = s.forces(q, np.zeros_like(q), anchors)
        tau = Q1[s.hb[h], 2] - Q0[s.hb[h], 2]            # damper torques on the segment (the pin damper is off)
        power.append(-tau * v[s.hb[h], 2])
    dissipated = _trapezoid(power, ts)
    both = (s.ha == s.hb[h]) | (s.hb == s.hb[h])
    assert both.sum() == 2 and len(set(s.kr[both])) == 2
    assert dissipated == pytest.approx(math.pi * eta * s.kr[both].sum() * A * A, rel=2e-3)


def test_viscoelastic_belt_rolls_back_less_when_vented():
    # rolling resistance: the vented ring (no gait) rolls down 4 degrees; hysteresis in the bending cells
    # slows it (the perfectly elastic ring only has its hinge damping)
    out = {}
    for eta in (0.0, 0.1):
        s, *_ = simulate(scene(belt={"initial_pressure": "vented", "loss_factor": eta}, gait={"type": "none"},
                               incline_deg=4.0), 3.0)
        out[eta] = s["displacement_mm"]
    assert out[0.0] < -CELL_MM
    assert out[0.1] > 0.5 * out[0.0]


def _runs(name, incline, seconds, starts=8):
    res = []
    for k in range(starts):
        s, *_ = simulate(scene(name, belt={"start_rotation_deg": 45.0 * k / starts}, incline_deg=incline), seconds)
        res.append((s["displacement_mm"], s["min_com_displacement_mm"]))
    return np.array(res)


def test_closed_loop_holds_at_ten_degrees_from_the_start_where_the_open_loop_rolls_back():
    # seed 2: the closed loop handles inclines up to 10 degrees and "does not fall back, but rather gets stuck
    # at a rolling step"; the open-loop normal-torque gait fails after 5 degrees "by rolling backward".
    # Released at 8 positions (turned by 1/8 of a cell each); the result of a nearly stuck belt depends on
    # where it first touches, so the statement is about most starts, not every one.
    closed = _runs("belt8.json", 10.0, 5.0)
    opened = _runs("belt8_open_loop.json", 10.0, 5.0)
    assert np.all(opened[:, 0] < -4 * CELL_MM)                    # every open-loop start rolls far back
    held = closed[:, 1] > -1.5 * CELL_MM                           # never more than 1.5 cells downhill
    assert held.sum() >= 4
    assert np.median(closed[:, 0]) > -1.5 * CELL_MM
    assert np.median(closed[:, 0]) > 0.2 * np.median(opened[:, 0])


def test_bad_belt_start_fields_are_named():
    with pytest.raises(SceneError, match=r"dynamics\.belt\.initial_pressure.*vented"):
        dynamics_config(scene(belt={"initial_pressure": "full"}))
    with pytest.raises(SceneError, match=r"dynamics\.belt\.loss_factor"):
        dynamics_config(scene(belt={"loss_factor": -0.1}))
    with pytest.raises(SceneError, match=r"dynamics\.belt\.loss_frequency_hz"):
        dynamics_config(scene(belt={"loss_frequency_hz": 0}))
