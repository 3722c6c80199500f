"""The slew check without a Python loop per 10 ms tick (hardware/rates.py: ``slew_ticks``, ``_check_slew``).

``slew_ticks`` moved the servo towards each tick's target in a Python loop (60 000 ticks for a 600 s stream: 1.25 s
of the stream command's check, the rest of it 0.33 s); it now runs one numpy pass per phase of the limit. The old
loop is kept here, word for word, as the reference: the new function must give its angles within 1e-9 deg on
random targets (sines, random walks, steps, whole centidegrees), from random start angles and over leading axes,
and ``_check_slew`` (also kept here as it was) must accept and refuse the same motions (sine and steps profiles,
random limits) with the same message. ``check_slew(..., speed=s)``, the Animate panel's check at s times wall
time, is the same motion played faster: its refusals match the sped-up motion checked at 1x.
"""
import copy
import json
import math
import os

import numpy as np
import pytest

from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.core.scene import Scene
from metamaterial_wb.hardware import channel_map
from metamaterial_wb.hardware import mapping, rates

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
with open(os.path.join(REPO, "examples", "fish.json"), encoding="utf-8") as _f:
    FISH = json.load(_f)


# --- the reference: the loop as it was (mapping.py before the split) ---------------------------------------------

def old_slew_ticks(target_deg, max_slew_dps, start_deg=None):
    y = np.asarray(target_deg, dtype=float)
    if not max_slew_dps:
        return y.copy()
    step = max_slew_dps * rates.SLEW_PERIOD_MS / 1000.0
    out = np.empty_like(y)
    cur = y[..., 0].copy() if start_deg is None else np.broadcast_to(np.asarray(start_deg, float), y[..., 0].shape)
    for i in range(y.shape[-1]):
        cur = cur + np.clip(y[..., i] - cur, -step, step)
        out[..., i] = cur
    return out


def old_check_slew(c, angles, duration_s, rate_hz, tol, steps=False):
    _DENSE_S, _WINDOW, SLEW_PERIOD_MS = rates._DENSE_S, rates._WINDOW, rates.SLEW_PERIOD_MS
    if not c.max_slew_dps:
        return
    cur, peak = None, 0.0
    n = int(math.floor(duration_s / _DENSE_S + 1e-9)) + 1
    for i0 in range(0, n, _WINDOW):
        td = np.arange(i0, min(n, i0 + _WINDOW)) * _DENSE_S
        peak = max(peak, float(np.max(np.abs(np.diff(angles(np.append(td, td[-1] + _DENSE_S)))))) / _DENSE_S)
        tt = td[(np.round(td / _DENSE_S).astype(int) % SLEW_PERIOD_MS) == 0]
        k = np.arange(max(0, int(math.floor(tt[0] * rate_hz)) - 1), int(math.ceil(tt[-1] * rate_hz)) + 2)
        path = np.interp(tt, k / rate_hz, np.round(angles(k / rate_hz) * 100.0) / 100.0)
        slewed = old_slew_ticks(path, c.max_slew_dps, cur)
        cur = slewed[-1]
        held = np.abs(slewed - path) > 0.005
        dev = np.where(held, np.abs(slewed - (path if steps else angles(tt))), 0.0)
        i = int(np.argmax(dev))
        if dev[i] > tol:
            raise SceneError(f"channel {c.channel} ({c.name}).max_slew_dps",
                             f"{c.max_slew_dps} deg/s: the firmware turns {c.name}'s servo at most {c.max_slew_dps} "
                             f"deg/s, but the motion moves at up to {peak:.0f} deg/s: the servo would be "
                             f"{dev[i]:.2f} deg off it at t = {tt[i]:.3f} s (at {slewed[i]:.2f} deg where the "
                             f"motion is at {float(angles(tt[i:i + 1])[0]):.2f} deg); allowed: at most {tol:g} deg "
                             f"(--rate-tolerance); " + rates.slew_advice(c.max_slew_dps, "the motion"))


# --- slew_ticks ------------------------------------------------------------------------------------------------

def random_targets(rng, kind, n):
    t = np.arange(n) * 0.01
    if kind == "walk":
        return np.cumsum(rng.normal(0.0, rng.uniform(0.1, 10.0), n))
    if kind == "sine":
        return rng.uniform(5, 80) * np.sin(2 * math.pi * rng.uniform(0.1, 8.0) * t + rng.uniform(0, 6.3))
    if kind == "steps":
        return np.repeat(rng.uniform(-60, 60, n // 20 + 1), 20)[:n]
    return np.round(rng.uniform(-90, 90, n) * 100.0) / 100.0     # whole centidegrees, any jump


@pytest.mark.parametrize("kind", ["walk", "sine", "steps", "noise"])
def test_slew_ticks_equals_the_tick_loop(kind):
    rng = np.random.default_rng(sum(map(ord, kind)))
    held = 0
    for trial in range(60):
        n = int(rng.integers(1, 2500))
        y = random_targets(rng, kind, n)
        dps = int(rng.choice([1, 10, 100, 300, 480, 1000, 3600, int(rng.integers(1, 3601))]))
        start = None if trial % 3 == 0 else float(rng.uniform(-90, 90))
        want, got = old_slew_ticks(y, dps, start), rates.slew_ticks(y, dps, start)
        assert got.shape == want.shape
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-9, err_msg=f"{kind} trial {trial}: {dps} deg/s")
        held += bool(np.any(np.abs(want - y) > 1e-6))
    assert held > 10          # the limit acted in many of them (not only the trivial follow-the-target case)


def test_slew_ticks_over_leading_axes_and_no_limit():
    rng = np.random.default_rng(7)
    y = np.cumsum(rng.normal(0, 3, (4, 3, 700)), axis=-1)
    for start in (None, 5.0, rng.uniform(-50, 50, (4, 3))):
        np.testing.assert_allclose(rates.slew_ticks(y, 200, start), old_slew_ticks(y, 200, start), rtol=0, atol=1e-9)
    short = np.cumsum(rng.normal(0, 3, (50, 8)), axis=-1)    # more rows than ticks
    np.testing.assert_allclose(rates.slew_ticks(short, 100, 1.0), old_slew_ticks(short, 100, 1.0), rtol=0, atol=1e-9)
    assert rates.slew_ticks(y, 0).tolist() == y.tolist()
    assert mapping.slew_ticks is rates.slew_ticks      # still importable where its callers look for it


# --- _check_slew ------------------------------------------------------------------------------------------------

def tail_scene(profile, slew):
    d = copy.deepcopy(FISH)
    d["actuators"][1]["profile"] = profile
    d["actuators"][1]["servo"] = {"max_slew_dps": slew}
    return Scene.from_dict(d)


def random_profile(rng):
    if rng.random() < 0.5:
        return {"shape": "sine", "amplitude": float(rng.uniform(0.05, 0.9)),
                "frequency_hz": float(rng.uniform(0.2, 3.0)), "phase_deg": float(rng.uniform(0, 360))}
    n = int(rng.integers(2, 6))
    times = np.sort(rng.uniform(0.05, 2.9, n - 1)).round(3)
    return {"shape": "steps", "times_s": [0.0] + times.tolist(), "values": rng.uniform(-0.8, 0.8, n).round(3).tolist(),
            "period_s": 3.0}


def outcome(check):
    try:
        check()
    except SceneError as exc:
        return str(exc)
    return None


def test_check_slew_accepts_and_refuses_as_the_loop_did():
    rng = np.random.default_rng(2024)
    said = {"sine": [0, 0], "steps": [0, 0]}
    for trial in range(40):
        profile = random_profile(rng)
        s = tail_scene(profile, int(rng.choice([30, 100, 200, 300, 480, 800, 3600])))
        ch = channel_map(s)
        (c, angles, steps), = [tr for tr in rates._rate_tracks(s, ch, False) if tr[0].name == "tail"]
        assert steps == (profile["shape"] == "steps")
        dur, rate = float(rng.uniform(0.5, 6.0)), float(rng.choice([20.0, 50.0, 100.0]))
        want = outcome(lambda: old_check_slew(c, angles, dur, rate, 3.0, steps))
        got = outcome(lambda: rates._check_slew(c, angles, dur, rate, 3.0, steps))
        assert got == want, (trial, profile, c.max_slew_dps, dur, rate)
        said[profile["shape"]][want is None] += 1
    assert all(refused and passed for refused, passed in said.values()), said   # both outcomes, both shapes


def test_check_slew_in_blocks_equals_the_loop(monkeypatch):
    """Long streams go block by block (rates._WINDOW samples): the servo's angle carries over from one block to
    the next as in the loop."""
    monkeypatch.setattr(rates, "_WINDOW", 730)          # 0.73 s blocks, not a whole number of ticks
    at = []
    for f, slew in ((0.3, 80), (0.5, 150)):             # refused in the first block, and past it
        s = tail_scene({"shape": "sine", "amplitude": 0.8, "frequency_hz": f, "phase_deg": 90}, slew)
        (c, angles, steps), = [tr for tr in rates._rate_tracks(s, channel_map(s), False) if tr[0].name == "tail"]
        want = outcome(lambda: old_check_slew(c, angles, 5.0, 50.0, 3.0, steps))
        assert want is not None
        assert outcome(lambda: rates._check_slew(c, angles, 5.0, 50.0, 3.0, steps)) == want
        at.append(float(want.split(" at t = ")[1].split(" s")[0]))
    assert min(at) < 0.73 < max(at), at


@pytest.mark.parametrize("speed", [2.0, 0.5])
def test_check_slew_at_a_speed_is_the_motion_played_that_fast(speed):
    """The Animate panel at ``speed``: frames 50 a wall second, the firmware's ticks every 10 ms of wall time. The
    same as the motion ``speed`` times faster checked at 1x, its times those of the timeline."""
    for f, slew in ((1.0, 300), (1.0, 900), (0.4, 120)):
        played = tail_scene({"shape": "sine", "amplitude": 0.8, "frequency_hz": f * speed}, slew)
        timeline = tail_scene({"shape": "sine", "amplitude": 0.8, "frequency_hz": f}, slew)
        at_1x = outcome(lambda: rates.check_slew(played, channel_map(played), 4.0 / speed, 50.0))
        at_speed = outcome(lambda: rates.check_slew(timeline, channel_map(timeline), 4.0, 50.0 / speed, speed=speed))
        assert (at_1x is None) == (at_speed is None), (f, slew, at_1x, at_speed)
        if at_1x is not None:
            t1 = float(at_1x.split(" at t = ")[1].split(" s")[0])
            ts = float(at_speed.split(" at t = ")[1].split(" s")[0])
            assert ts == pytest.approx(t1 * speed, abs=1e-3), (at_1x, at_speed)
            assert at_1x.split(" off it")[0].split("the servo would be ")[1] == \
                at_speed.split(" off it")[0].split("the servo would be ")[1]
