"""Distributed gait rule (seed 001, Algorithm 1) against the shared vectors and closed-form properties."""
import json
import os

import numpy as np
import pytest

from metamaterial_wb.core.errors import MetamaterialError
from metamaterial_wb.core.gait import gait_rule_array, gait_rule_step

VEC = os.path.join(os.path.dirname(__file__), "..", "vectors", "gait_rule.json")


def load():
    with open(VEC) as f:
        return json.load(f)


def test_vector_file_is_documented_and_well_formed():
    d = load()
    assert "format" in d and "c_air" in d["format"] and "act" in d["format"]
    assert sum(v["hand_checked"] for v in d["vectors"]) >= 8
    for v in d["vectors"]:
        n = len(v["c_air"])
        assert 1 <= n <= d["max_cells"]
        assert len(v["act"]) == n
        assert 0 <= v["n1"] < n and 0 <= v["n2"] < n


@pytest.mark.parametrize("v", load()["vectors"], ids=lambda v: v["name"])
def test_rule_matches_vector(v):
    assert gait_rule_step(v["c_air"], v["n1"], v["n2"], v["closed"]) == v["act"]


def test_batch_form_equals_single_form():
    d = load()
    vs = [v for v in d["vectors"] if len(v["c_air"]) == 8 and v["closed"] and v["n1"] == 1 and v["n2"] == 1]
    c = np.array([v["c_air"] for v in vs])
    out = gait_rule_array(c, 1, 1, True)
    assert out.astype(int).tolist() == [v["act"] for v in vs]


@pytest.mark.parametrize("n", [8, 20, 1000])
@pytest.mark.parametrize("n1", [1, 2, 3])
def test_normal_torque_fires_exactly_n1_cells_before_touchdown(n, n1):
    # one contiguous ground arc longer than n1: exactly the n1 air cells just before it fire
    c = np.ones(n, int)
    g0 = n // 3
    c[g0:g0 + n1 + 2] = 0
    act = gait_rule_array(c, n1, 0)
    assert act.sum() == n1
    assert np.flatnonzero(act).tolist() == sorted(i % n for i in range(g0 - n1, g0))


def test_never_fires_on_ground_and_rotation_equivariant():
    rng = np.random.default_rng(1)
    for _ in range(50):
        n = int(rng.integers(2, 40))
        c = rng.integers(0, 2, n)
        n1, n2 = int(rng.integers(0, n)), int(rng.integers(0, n))
        a = gait_rule_array(c, n1, n2, True)
        assert not np.any(a & (c == 0))
        s = int(rng.integers(0, n))
        assert np.array_equal(gait_rule_array(np.roll(c, s), n1, n2, True), np.roll(a, s))


def test_bad_parameters_raise():
    with pytest.raises(MetamaterialError, match="n1"):
        gait_rule_step([0, 1, 1], 3, 0)
    with pytest.raises(MetamaterialError, match="0 \\(ground\\) or 1"):
        gait_rule_step([0, 2, 1], 1, 0)
    with pytest.raises(MetamaterialError, match="n2"):
        gait_rule_step([0, 1, 1], 1, -1)
