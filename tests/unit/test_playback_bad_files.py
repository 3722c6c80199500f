"""A malformed ``trajectory.json`` (Animate's Load..., ``core.playback.TrajectoryPlayer``) is refused with a
SceneError naming the field, the value and what is allowed, and the file when it is given (an audit on FreeCAD 1.0,
session 34): body_of_node values as strings or as a list, poses holding strings and an incline "steep" raised
ValueError / TypeError (a traceback in the GUI, nothing in the panel); NaN times and infinite poses were accepted
and "played" (label "46 frames, nan s"); a body index 1.7 was truncated to body 1."""
import json
import os

import numpy as np
import pytest

from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.core.playback import TrajectoryPlayer
from metamaterial_wb.core.scene import Scene

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
WORM = os.path.join(ROOT, "examples", "worm.json")
NAN, INF = float("nan"), float("inf")


@pytest.fixture(scope="module")
def scene():
    return Scene.load(WORM)


def good(scene):
    """A valid sheet trajectory of ``scene``: one body per column, three frames moving 1 mm a frame."""
    cols = sorted({j for _, j in scene.topology.nodes})
    nb = len(cols)
    poses = [[[20.0 * b + f, 3.5, 0.5 * f] for b in range(nb)] for f in range(3)]
    return {"format": "metamaterial-trajectory", "version": 1, "model": "sheet", "incline_deg": 0.0,
            "times_s": [0.0, 0.1, 0.2], "bodies": nb, "poses": poses,
            "body_of_node": {f"N{i},{j}": cols.index(j) for (i, j) in scene.topology.nodes}}


def player(scene, data, source=None):
    flat = np.zeros((scene.topology.n_nodes, 3))
    if source is None:
        return TrajectoryPlayer(data, scene, flat)      # the call the Animate panel makes
    return TrajectoryPlayer(data, scene, flat, source=source)


def first_node(scene):
    i, j = scene.topology.nodes[0]
    return f"N{i},{j}"


def edit_body(value, key=None):
    def edit(d):
        d["body_of_node"][key or next(iter(d["body_of_node"]))] = value
    return edit


def edit_pose(f, b, c, value):
    def edit(d):
        d["poses"][f][b][c] = value
    return edit


def edit_time(k, value):
    def edit(d):
        d["times_s"][k] = value
    return edit


def put(key, value):
    return lambda d: d.__setitem__(key, value)



# (name, edit, field named, words in the message)
CASES = [
    ("string body", edit_body("x"), "trajectory.body_of_node.{node}", ["'x'", "allowed: an integer 0..{last}"]),
    ("fractional body", edit_body(1.7), "trajectory.body_of_node.{node}", ["1.7", "allowed: an integer 0..{last}"]),
    ("body out of range", edit_body(99), "trajectory.body_of_node.{node}", ["99", "0..{last}", "which has {nb}"]),
    ("negative body", edit_body(-1), "trajectory.body_of_node.{node}", ["-1", "0..{last}"]),
    ("boolean body", edit_body(True), "trajectory.body_of_node.{node}", ["True", "an integer"]),
    ("body_of_node a list", lambda d: d.__setitem__("body_of_node", list(d["body_of_node"])),
     "trajectory.body_of_node", ["expected an object mapping each node"]),
    ("string pose", edit_pose(1, 2, 0, "a"), "trajectory.poses[1][2][0]", ["'a'", "a finite number"]),
    ("infinite pose", edit_pose(2, 0, 1, INF), "trajectory.poses[2][0][1]", ["inf is not a finite number"]),
    ("NaN pose", edit_pose(0, 1, 2, NAN), "trajectory.poses[0][1][2]", ["nan is not a finite number"]),
    ("null pose", edit_pose(1, 0, 0, None), "trajectory.poses[1][0][0]", ["None", "a finite number"]),
    ("boolean pose", edit_pose(1, 0, 0, False), "trajectory.poses[1][0][0]", ["False", "a finite number"]),
    ("two columns", lambda d: d["poses"][0].__setitem__(0, [1.0, 2.0]), "trajectory.poses[0][0]",
     ["[1.0, 2.0]", "expected [x, y, angle]"]),
    ("ragged frame", lambda d: d["poses"][2].pop(), "trajectory.poses[2]", ["{lastc} bodies", "the {nb} bodies"]),
    ("frames not times", lambda d: d["poses"].pop(), "trajectory.poses", ["2 frames", "one frame per time", "(3)"]),
    ("poses not a list", put("poses", "lots"), "trajectory.poses", ["'lots'", "one frame per time"]),
    ("NaN time", edit_time(1, NAN), "trajectory.times_s[1]", ["nan is not a finite number"]),
    ("all NaN times", put("times_s", [NAN, NAN, NAN]), "trajectory.times_s[0]", ["nan is not a finite number"]),
    ("infinite time", edit_time(2, INF), "trajectory.times_s[2]", ["inf is not a finite number"]),
    ("string time", edit_time(1, "0.1"), "trajectory.times_s[1]", ["'0.1'", "a finite number of seconds"]),
    ("null times", put("times_s", None), "trajectory.times_s", ["None", "expected a list of the recorded times"]),
    ("no times", put("times_s", []), "trajectory.times_s", ["[]", "expected a list"]),
    ("times back", edit_time(2, 0.05), "trajectory.times_s[2]", ["0.05 after 0.1", "times must increase"]),
    ("string incline", put("incline_deg", "steep"), "trajectory.incline_deg", ["'steep'", "[-60, 60]"]),
    ("NaN incline", put("incline_deg", NAN), "trajectory.incline_deg", ["nan is not a finite number"]),
    ("incline too steep", put("incline_deg", 99.0), "trajectory.incline_deg", ["99.0 deg", "[-60.0, 60.0]"]),
    ("boolean incline", put("incline_deg", True), "trajectory.incline_deg", ["True", "degrees"]),
    ("bodies disagree", put("bodies", 4), "trajectory.bodies", ["4", "expected {nb}"]),
]


def refusal(scene, edit, source=None):
    d = good(scene)
    edit(d)
    with pytest.raises(SceneError) as e:
        player(scene, d, source)
    return e.value


@pytest.mark.parametrize("name,edit,field,words", CASES, ids=[c[0] for c in CASES])
def test_a_bad_field_is_refused_naming_field_and_value(scene, name, edit, field, words):
    nb = len(good(scene)["poses"][0])
    fill = dict(node=first_node(scene), last=nb - 1, nb=nb, lastc=nb - 1)
    exc = refusal(scene, edit)
    assert exc.field == field.format(**fill), str(exc)
    assert str(exc).startswith(field.format(**fill) + ": "), str(exc)
    for w in words:
        assert w.format(**fill) in str(exc), (w, str(exc))


def test_the_good_trajectory_plays(scene):
    """The reference of the cases above: unedited, it is accepted, with what it says."""
    p = player(scene, good(scene))
    assert p.duration == pytest.approx(0.2)
    assert p.poses.shape == (3, len(good(scene)["poses"][0]), 3)
    cols = sorted({j for _, j in scene.topology.nodes})
    assert list(p.node_body) == [cols.index(j) for _, j in scene.topology.nodes]
    # an integer body index is kept as it is (the one change of the fractional case is the .7)
    d = good(scene)
    d["body_of_node"][first_node(scene)] = 1
    assert player(scene, d).node_body[0] == 1


def test_a_file_read_from_disk_is_named_once(scene, tmp_path):
    """The JSON reader takes NaN / Infinity: written by json.dumps, a file of NaN times is read and refused,
    naming the file."""
    d = good(scene)
    d["times_s"] = [NAN, NAN, NAN]
    path = tmp_path / "run dir" / "trajectory.json"
    path.parent.mkdir()
    path.write_text(json.dumps(d), encoding="utf-8")
    with open(path, encoding="utf-8") as f:
        data = json.load(f)
    with pytest.raises(SceneError) as e:
        player(scene, data, source=str(path))
    msg = str(e.value)
    assert msg.startswith("trajectory.times_s[0]: nan is not a finite number"), msg
    assert msg.endswith(f"(in {path})") and msg.count(str(path)) == 1, msg


def test_every_refusal_names_the_source(scene):
    for name, edit, field, _w in CASES:
        exc = refusal(scene, edit, source="some/trajectory.json")
        assert str(exc).endswith("(in some/trajectory.json)"), (name, str(exc))
        assert exc.field.startswith("trajectory"), (name, exc.field)
