"""``stream --map head=2 --channels F`` with F = ``{"head": {"channel": 3}}`` streamed head on channel 3: the file
silently won over the flag (user audit, session 35), where every other contradictory pair of flags is refused.
A disagreement is refused, one line naming the actuator and both values (and the file); nothing is streamed and
no report written. The same channel in both stays accepted, and either alone still works."""
import json
import os

import pytest

from clihelpers import REPO, one_line_error, run_cli

pytest.importorskip("serial")

from metamaterial_wb.core.errors import SceneError  # noqa: E402
from metamaterial_wb.core.scene import Scene  # noqa: E402
from metamaterial_wb.hardware import channel_map  # noqa: E402

FISH = os.path.join(REPO, "examples", "fish.json")


def _chans(tmp_path, spec):
    p = tmp_path / "ch9.json"
    p.write_text(json.dumps(spec), encoding="utf-8")
    return p


def _streamed(report):
    with open(report, encoding="utf-8") as f:
        return {c["name"]: c["channel"] for c in json.load(f)["channels"]}


def test_map_contradicting_channels_file_is_refused(tmp_path):
    ch = _chans(tmp_path, {"head": {"channel": 3}})
    report = tmp_path / "r.json"
    r = run_cli("stream", FISH, "--dry-run", "--seconds", "0.1", "--channels", ch, "--map", "head=2",
                "--report", report)
    one_line_error(r, "--map head")
    assert f"2 contradicts --channels {ch} head.channel 3" in r.stderr, r.stderr
    assert "one of them, or the same channel" in r.stderr, r.stderr
    assert not report.exists() and r.stdout == "", r.stdout


def test_map_agreeing_with_channels_file_is_accepted(tmp_path):
    ch = _chans(tmp_path, {"head": {"channel": 3, "trim_deg": 1}})
    report = tmp_path / "r.json"
    r = run_cli("stream", FISH, "--dry-run", "--seconds", "0.1", "--channels", ch, "--map", "head=3,tail=0",
                "--report", report)
    assert r.returncode == 0, r.stderr
    assert _streamed(report) == {"head": 3, "tail": 0}


def test_the_function_names_the_file_and_both_values():
    scene = Scene.load(FISH)
    with pytest.raises(SceneError) as e:
        channel_map(scene, {"tail": 5}, {"tail": {"channel": 4}}, overrides_from="c.json")
    assert e.value.field == "--map tail"
    assert e.value.message.startswith("5 contradicts --channels c.json tail.channel 4"), e.value.message
    # without a file name (a caller's own dict) the values are still both named
    with pytest.raises(SceneError) as e:
        channel_map(scene, {"tail": 5}, {"tail": {"channel": 4}})
    assert "5 contradicts --channels tail.channel 4" in e.value.message, e.value.message
    assert {c.name: c.channel for c in channel_map(scene, {"tail": 4}, {"tail": {"channel": 4}})}["tail"] == 4
    # a file that sets other fields of the actuator, not its channel, leaves --map in charge
    assert {c.name: c.channel for c in channel_map(scene, {"tail": 5}, {"tail": {"trim_deg": 2}})}["tail"] == 5
