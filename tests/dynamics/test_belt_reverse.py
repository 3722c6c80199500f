"""The open-loop belt's ``direction: -1`` is the mirror of ``direction: 1`` (an audit of the dynamics journey,
session 26): with the default start cell 0 the reversed belt rolled -195 mm where the forward one rolls +329 mm in
10 s; the mirror of cell 0 in the released ring is cell N - 1, the reversed gait's default start."""
import copy
import json

import pytest

from metamaterial_wb import example_path
from metamaterial_wb.core.dynamics.builders import dynamics_config
from metamaterial_wb.core.dynamics.simulate import simulate
from metamaterial_wb.core.scene import Scene


def belt(**gait):
    with open(example_path("belt8_open_loop")) as f:
        d = copy.deepcopy(json.load(f))
    del d["dynamics"]["gait"]["start_cell"]          # (the example gives 0 explicitly)
    d["dynamics"]["gait"].update(gait)
    return Scene.from_dict(d)


def test_the_reversed_open_loop_belt_is_the_mirror_of_the_forward_one():
    fwd, *_ = simulate(belt(), 2.0)
    rev, *_ = simulate(belt(direction=-1), 2.0)
    assert abs(fwd["displacement_mm"]) > 10.0
    assert rev["displacement_mm"] == pytest.approx(-fwd["displacement_mm"], rel=1e-6, abs=1e-6)


def test_the_start_cell_defaults_by_direction_and_a_given_one_is_kept():
    n = 8
    assert dynamics_config(belt())["gait"]["start_cell"] == 0
    assert dynamics_config(belt(direction=-1))["gait"]["start_cell"] == n - 1
    assert dynamics_config(belt(direction=-1, start_cell=0))["gait"]["start_cell"] == 0
