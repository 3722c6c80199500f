"""Motion profiles of actuators over time (the seed's sinusoidal worm / fish / butterfly gaits).

A profile is a small dict stored on an actuator (``"profile"``):

* ``{"shape": "sine", "amplitude": 0.8, "frequency_hz": 0.5, "phase_deg": 90, "offset": 0}``:
  ``value(t) = offset + amplitude * sin(2 pi f t + phase)``;
* ``{"shape": "constant", "value": 0.3}``;
* ``{"shape": "steps", "times_s": [0, 1, 2], "values": [0, 1, -1], "period_s": 3}``: piecewise
  constant (the second seed's tau_on / tau_off sequences), repeating when ``period_s`` is given;
* ``{"shape": "keyframes", "times_s": [...], "values": [...], "period_s": ...}``: linear in between.

Every value is checked to stay within [-1, 1] over the whole profile (no silent clamping).
"""
import math

import numpy as np

from metamaterial_wb.core.errors import SceneError, check_number

SHAPES = ("sine", "constant", "steps", "keyframes")
# closed ranges of a sine profile's fields (the GUI's spin boxes read them); keyframe times are >= 0 s
PROFILE_RANGES = {"amplitude": (0.0, 1.0), "frequency_hz": (0.0, 50.0), "phase_deg": (-3600.0, 3600.0)}


def validate_profile(p, field_name="profile"):
    """Check a motion profile (``sine``, ``constant``, ``steps`` or ``keyframes``) and its fields.

    Parameters
    ----------
    p : dict
        The profile.
    field_name : str, optional
        The field path used in error messages.

    Returns
    -------
    dict
        ``p`` itself, when valid.

    Raises
    ------
    SceneError
        Naming the bad field, its value and the allowed range.
    """
    if not isinstance(p, dict):
        raise SceneError(field_name, f"expected an object with \"shape\", got {p!r}")
    shape = p.get("shape", "sine")
    if shape not in SHAPES:
        raise SceneError(f"{field_name}.shape", f"{shape!r}; allowed: {', '.join(SHAPES)}")
    allowed = {"sine": {"shape", "amplitude", "frequency_hz", "phase_deg", "offset"},
               "constant": {"shape", "value"},
               "steps": {"shape", "times_s", "values", "period_s"},
               "keyframes": {"shape", "times_s", "values", "period_s"}}[shape]
    for k in p:
        if k not in allowed:
            raise SceneError(f"{field_name}.{k}", f"unknown field for a {shape} profile; allowed: {sorted(allowed)}")
    if shape == "sine":
        a = check_number(f"{field_name}.amplitude", p.get("amplitude", 1.0), *PROFILE_RANGES["amplitude"])
        check_number(f"{field_name}.frequency_hz", p.get("frequency_hz", 1.0), *PROFILE_RANGES["frequency_hz"], "Hz")
        check_number(f"{field_name}.phase_deg", p.get("phase_deg", 0.0), *PROFILE_RANGES["phase_deg"], "deg")
        off = check_number(f"{field_name}.offset", p.get("offset", 0.0), -1.0, 1.0)
        if abs(off) + a > 1.0 + 1e-12:
            raise SceneError(f"{field_name}", f"offset {off} plus amplitude {a} reaches {abs(off) + a}; "
                                              f"|offset| + amplitude must stay <= 1")
    elif shape == "constant":
        check_number(f"{field_name}.value", p.get("value", 0.0), -1.0, 1.0)
    else:
        t = p.get("times_s")
        v = p.get("values")
        if not isinstance(t, list) or not isinstance(v, list) or len(t) != len(v) or not t:
            raise SceneError(field_name, "times_s and values must be lists of the same, non-zero length")
        prev = -math.inf
        for k, (tk, vk) in enumerate(zip(t, v)):
            tk = check_number(f"{field_name}.times_s[{k}]", tk, 0.0, None, "s")
            if tk <= prev:
                raise SceneError(f"{field_name}.times_s[{k}]", f"{tk} s: times must increase strictly")
            prev = tk
            check_number(f"{field_name}.values[{k}]", vk, -1.0, 1.0, exact=True)
        if "period_s" in p:
            per = check_number(f"{field_name}.period_s", p["period_s"], 0.0, None, "s", low_open=True)
            if per <= t[-1]:
                raise SceneError(f"{field_name}.period_s", f"{per} s must be longer than the last time {t[-1]} s")
    return p


def profile_value(p, t, default=0.0):
    """Value of a profile at time ``t`` (seconds; scalar or array). ``None`` -> ``default``.

    Parameters
    ----------
    p : dict or None
        A validated profile.
    t : float or array_like
        Time (s).
    default : float, optional
        Returned when ``p`` is None.

    Returns
    -------
    float or numpy.ndarray
        Shaped like ``t``.
    """
    t = np.asarray(t, dtype=float)
    if p is None:
        return np.full(t.shape, float(default)) if t.ndim else float(default)
    shape = p.get("shape", "sine")
    if shape == "sine":
        out = p.get("offset", 0.0) + p.get("amplitude", 1.0) * np.sin(
            2 * math.pi * p.get("frequency_hz", 1.0) * t + math.radians(p.get("phase_deg", 0.0)))
    elif shape == "constant":
        out = np.full(t.shape, float(p.get("value", 0.0)))
    else:
        times = np.asarray(p["times_s"], dtype=float)
        vals = np.asarray(p["values"], dtype=float)
        tt = np.mod(t, p["period_s"]) if "period_s" in p else t
        if shape == "steps":
            idx = np.clip(np.searchsorted(times, tt, side="right") - 1, 0, len(vals) - 1)
            out = vals[idx]
        else:
            if "period_s" in p:  # wrap linearly back to the first key
                times = np.append(times, p["period_s"])
                vals = np.append(vals, vals[0])
            out = np.interp(tt, times, vals)
    return float(out) if np.ndim(out) == 0 else out


def scene_values_at(scene, t):
    """``{name: value}`` for every actuator at time ``t`` (actuators without a profile keep their value).

    Parameters
    ----------
    scene : Scene
    t : float
        Time (s).

    Returns
    -------
    dict
    """
    return {a.name: float(profile_value(a.profile, t, a.value)) for a in scene.actuators}
