"""channel_map's cross-field errors named a default as if someone had given it: the fish (no ``servo`` objects)
with ``--channels {"tail": {"limits_deg": [10, 60]}}`` said ``actuators[1].servo.park_deg: 0.0 deg is outside
the limits`` (park_deg 0 is the default: nobody gave it, there is no such field to fix), and two actuators on one
channel gave ``actuators 'head' and 'tail' both use channel 1`` with neither where each channel came from nor
which channels are free. The errors now say which value is a default, where each value came from, where to set
it and the allowed values."""
import json
import os

import pytest

from clihelpers import one_line_error, run_cli

from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.core.scene import Scene
from metamaterial_wb.hardware.mapping import channel_map

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
FISH = os.path.join(REPO, "examples", "fish.json")


def fish(**servo):
    with open(FISH, encoding="utf-8") as f:
        d = json.load(f)
    for a in d["actuators"]:
        assert "servo" not in a   # the fish gives no servo fields: every one is a default
        if a["name"] in servo:
            a["servo"] = servo[a["name"]]
    return Scene.from_dict(d)


def message(*args, **kw):
    with pytest.raises(SceneError) as e:
        channel_map(*args, **kw)
    return str(e.value)


def test_default_park_outside_limits_from_channels_file_cli(tmp_path):
    p = tmp_path / "p1.json"
    p.write_text(json.dumps({"tail": {"limits_deg": [10, 60]}}), encoding="utf-8")
    r = run_cli("stream", FISH, "--dry-run", "--channels", p)
    one_line_error(r, "actuators[1] (tail)")
    err = r.stderr
    assert "servo.park_deg: 0" not in err   # not named as a field someone gave
    assert "the default park angle 0 deg (no park_deg given)" in err
    assert "outside the limits [10, 60] deg (limits_deg from --channels tail)" in err
    assert "allowed: a park angle within [10, 60] deg" in err
    assert "park_deg in --channels for tail, or the scene's actuators[1].servo.park_deg" in err


def test_default_park_outside_limits_from_the_scene():
    err = message(fish(tail={"limits_deg": [10, 60]}))
    assert err.startswith("actuators[1] (tail): the default park angle 0 deg (no park_deg given) is outside the "
                          "limits [10, 60] deg (limits_deg from actuators[1].servo)"), err
    # no --channels file (the GUI, or the CLI without one): the scene is the place to set it
    assert "set park_deg in the scene's actuators[1].servo.park_deg" in err and "--channels" not in err
    # the same limits with a park angle inside them: accepted
    assert channel_map(fish(tail={"limits_deg": [10, 60], "park_deg": 10}))[1].park_deg == 10


def test_given_park_still_names_its_field():
    err = message(fish(), overrides={"head": {"park_deg": 80}})
    assert err.startswith("--channels head.park_deg: 80"), err
    assert "(limits_deg from actuators[0].joint's kinematic range)" in err


def test_min_us_against_the_default_max_us_says_it_is_the_default():
    err = message(fish(head={"min_us": 2550}))
    assert err.startswith("actuators[0].servo.min_us: 2550 us must be below max_us 2500 us"), err
    assert "max_us: the default 2500 us, not given" in err


def test_max_us_against_the_default_min_us_names_max_us():
    # min_us was never given: the error named actuators[0].servo.min_us
    err = message(fish(), overrides={"head": {"max_us": 450}})
    assert err.startswith("--channels head.max_us: 450 us must be above min_us 500 us"), err
    assert "min_us: the default 500 us, not given" in err and ".min_us:" not in err


def test_park_past_the_servo_end_names_where_trim_came_from():
    err = message(fish(tail={"trim_deg": 12}), overrides={"tail": {"park_deg": 85, "limits_deg": [-90, 90]}})
    assert err.startswith("--channels tail.park_deg: 85 deg: the servo would park at 97.00 deg"), err
    assert "trim_deg 12 from actuators[1].servo" in err


def test_shared_channel_names_both_origins_and_the_free_channels_cli():
    r = run_cli("stream", FISH, "--dry-run", "--map", "head=1")
    one_line_error(r, "channels")
    assert ("actuators 'head' and 'tail' both use channel 1 (head: --map head=1; tail: default, its position in "
            "the scene); free channels: 0, 2, 3, 4, 5, 6, 7 (allowed: 0..7, one actuator each)") in r.stderr, r.stderr


def test_shared_channel_from_channels_file_and_scene():
    err = message(fish(), overrides={"tail": {"channel": 0}})
    assert ("both use channel 0 (head: default, its position in the scene; tail: --channels tail.channel); free "
            "channels: 1, 2, 3, 4, 5, 6, 7") in err, err
    err = message(fish(head={"channel": 3}, tail={"channel": 3}))
    assert "(head: actuators[0].servo.channel; tail: actuators[1].servo.channel)" in err, err
    assert "free channels: 0, 1, 2, 4, 5, 6, 7" in err
    # --map overrides the scene's channel; --channels may give the same channel as --map (a different one is
    # refused: tests/hardware/test_map_channels_conflict.py), and is then named
    err = message(fish(tail={"channel": 6}), {"tail": 0})
    assert "(head: default, its position in the scene; tail: --map tail=0)" in err, err
    err = message(fish(), {"tail": 0}, {"tail": {"channel": 0}})
    assert "tail: --channels tail.channel)" in err, err
    # a smaller board: the free channels are those it has
    err = message(fish(), {"head": 1}, n_channels=3)
    assert "free channels: 0, 2 (allowed: 0..2, one actuator each)" in err, err
