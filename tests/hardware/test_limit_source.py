"""A motion leaving a channel's limits names where the limits came from: ``--channels FILE NAME.limits_deg`` when
the ``--channels`` file set them (not the scene file, which the error used to blame: ``... widen
servo.limits_deg, or pass --clamp (in fish.json)``), the scene's actuator when the scene's ``servo`` object set
them. For ``stream`` (check_motion) and ``--mode osc`` (onboard.osc_params), through the command line too."""
import json
import os

import pytest

from clihelpers import one_line_error, run_cli
from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.core.scene import Scene
from metamaterial_wb.hardware import channel_map, check_motion
from metamaterial_wb.hardware.onboard import osc_params

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
FISH = os.path.join(ROOT, "examples", "fish.json")
LIM = {"tail": {"limits_deg": [-60, 60]}}


def _write(path, data):
    with open(path, "w", encoding="utf-8") as f:
        json.dump(data, f)
    return str(path)


def test_check_motion_names_the_channels_file():
    scene = Scene.load(FISH)
    chans = channel_map(scene, overrides=LIM, overrides_from="lim.json")
    with pytest.raises(SceneError) as e:
        check_motion(scene, chans, 2.0)
    assert e.value.field == "--channels lim.json tail.limits_deg", e.value.field
    msg = e.value.message
    assert msg.startswith("[-60, 60] deg: the motion of actuators[1] (tail) reaches 60.1 deg at t = 0.383 s"), msg
    assert "servo.limits_deg" not in msg and "--clamp" in msg
    # without the file's name (an API caller): still --channels, not the scene
    with pytest.raises(SceneError) as e:
        check_motion(scene, channel_map(scene, overrides=LIM), 2.0)
    assert e.value.field == "--channels tail.limits_deg", e.value.field


def test_osc_params_names_the_channels_file():
    scene = Scene.load(FISH)
    chans = channel_map(scene, overrides=LIM, overrides_from="lim.json")
    with pytest.raises(SceneError) as e:
        osc_params(scene, chans)
    assert e.value.field == "--channels lim.json tail.limits_deg", e.value.field
    assert "actuators[1] (tail).profile swings over [-21.88, 81.00] deg" in e.value.message, e.value.message
    assert "--clamp" not in e.value.message   # refused with --mode osc


def test_osc_params_linear_names_the_channels_file():
    scene = Scene.load(FISH)
    lim = {"tail": {"limits_deg": [-60, 60], "scale_deg": 80}}
    with pytest.raises(SceneError) as e:
        osc_params(scene, channel_map(scene, overrides=lim, overrides_from="lim.json"))
    assert e.value.field == "--channels lim.json tail.limits_deg", e.value.field
    assert "swings over [-72.0, 72.0] deg" in e.value.message, e.value.message


@pytest.mark.parametrize("mode", ["stream", "osc"])
def test_cli_names_the_channels_file_not_the_scene(tmp_path, mode):
    lim = _write(tmp_path / "lim.json", LIM)
    r = run_cli("stream", FISH, "--dry-run", "--seconds", 2, "--channels", lim, "--mode", mode)
    one_line_error(r, f"--channels {lim} tail.limits_deg")
    assert "(in " not in r.stderr and "fish.json" not in r.stderr, r.stderr


def test_limits_from_the_scene_still_name_the_scene(tmp_path):
    with open(FISH, encoding="utf-8") as f:
        data = json.load(f)
    data["actuators"][1]["servo"] = {"limits_deg": [-60, 60]}
    scene_path = _write(tmp_path / "fish.json", data)
    r = run_cli("stream", scene_path, "--dry-run", "--seconds", 2)
    one_line_error(r, "actuators[1] (tail)")
    assert "widen servo.limits_deg" in r.stderr and f"(in {scene_path})" in r.stderr, r.stderr
