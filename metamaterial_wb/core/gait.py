"""Distributed closed-loop gait rule of the soft belt (seed 001, Algorithm 1).

Each cell ``i`` of a chain of ``N`` cells reads its own ground sensor and the
sensors of the cells ``n1`` ahead and ``n2`` behind it. With the seed's sign
convention ``c_i = 1`` means *in the air* (light sensor sees light) and
``c_i = 0`` means *touching the ground*. Algorithm 1 ("gait generation for
forward motion with increased torque") inflates cell ``i`` iff::

    c_i == 1  and  (c_{i+n1} == 0  or  c_{i-n2} == 0)

and vents it otherwise.

* ``n1`` selects the cells at most ``n1`` cells *before* an air -> ground
  ('1' -> '0') transition (the cells that pull the centre of mass forward);
  ``n2`` selects the cells at most ``n2`` cells *after* a ground -> air
  ('0' -> '1') transition (the high-torque "opposite" cells).
* ``n = 0`` switches a term off (``c_{i+0} = c_i = 1`` never reads "ground"),
  so ``n2 = 0`` is the seed's normal-torque rule "inflate i if it is in the air
  and cell i+n is on the ground".
* ``closed=True`` (the belt, a circular structure as in the seed): indices wrap
  modulo ``N``. ``closed=False`` (an open strip): a neighbour index outside
  ``0..N-1`` does not exist and its term is false (it never reads "ground").

The rule is a pure function of the sensor vector: no time, no state. The same
rule is implemented in C by the firmware's gait mode; both are checked against
``tests/vectors/gait_rule.json``.
"""
from __future__ import annotations

from typing import Sequence

import numpy as np

from .errors import MetamaterialError

__all__ = ["gait_rule_step", "gait_rule_array", "check_gait_params"]


def check_gait_params(n_cells: int, n1: int, n2: int) -> None:
    """Raise MetamaterialError unless n_cells >= 1 and 0 <= n1, n2 < n_cells."""
    for name, val in (("n_cells", n_cells), ("n1", n1), ("n2", n2)):
        if isinstance(val, bool) or not isinstance(val, (int, np.integer)):
            raise MetamaterialError(f"gait: {name} = {val!r} must be an integer")
    if n_cells < 1:
        raise MetamaterialError(f"gait: n_cells = {n_cells} must be >= 1")
    for name, val in (("n1", n1), ("n2", n2)):
        if not 0 <= val < max(n_cells, 1):
            raise MetamaterialError(
                f"gait: {name} = {val} is out of range 0..{n_cells - 1} for {n_cells} cells")


def gait_rule_array(c_air, n1: int, n2: int, closed: bool = True) -> np.ndarray:
    """Vectorised Algorithm 1. ``c_air``: array (..., N) of 0/1 or bool, 1 = in the air.

    Returns a bool array of the same shape: True = inflate, False = vent.
    """
    c = np.asarray(c_air)
    if c.ndim < 1 or c.shape[-1] < 1:
        raise MetamaterialError("gait: the sensor vector must hold at least one cell")
    if not np.all((c == 0) | (c == 1)):
        raise MetamaterialError("gait: sensor values must be 0 (ground) or 1 (air)")
    c = c.astype(bool)
    n = c.shape[-1]
    check_gait_params(n, int(n1), int(n2))
    idx = np.arange(n)
    ground = ~c

    def ground_at(offset: int) -> np.ndarray:
        j = idx + offset
        if closed:
            return ground[..., j % n]
        ok = (j >= 0) & (j < n)
        out = np.zeros_like(ground)
        out[..., ok] = ground[..., j[ok]]
        return out

    return c & (ground_at(int(n1)) | ground_at(-int(n2)))


def gait_rule_step(c_air: Sequence[int], n1: int, n2: int, closed: bool = True) -> list[int]:
    """Algorithm 1 for one sensor snapshot; returns a list of 0/1 (1 = inflate)."""
    return [int(v) for v in gait_rule_array(c_air, n1, n2, closed)]
