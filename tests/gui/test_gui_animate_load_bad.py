"""Animate's Load... of a malformed ``trajectory.json`` says why in the panel's red line (the field and the bad
value), with no traceback, and keeps what was playing (an audit on FreeCAD 1.0, session 34): body_of_node values as
strings or as a list, poses holding strings, an incline "steep" raised ValueError / TypeError into sys.excepthook
and the panel said nothing; NaN times were "played" ("46 frames, nan s", duration silently 0.1 s); a body index 1.7
was truncated to body 1. The file dialog is patched to answer the file; the button is clicked for real."""
import json
import os

import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

from PySide import QtGui  # noqa: E402

import metamaterial_wb  # noqa: E402
from metamaterial_wb.objects import structure  # noqa: E402
from guihelpers import click, doc, process, run_panel, tracebacks, workbench  # noqa: E402,F401

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(metamaterial_wb.__file__)))
NAN, INF = float("nan"), float("inf")


def good(scene):
    """A valid sheet trajectory of ``scene``: one body per column, moving 1 mm a frame."""
    cols = sorted({j for _, j in scene.topology.nodes})
    poses = [[[20.0 * b + f, 3.5, 0.5 * f] for b in range(len(cols))] for f in range(4)]
    return {"format": "metamaterial-trajectory", "version": 1, "model": "sheet", "incline_deg": 0.0,
            "times_s": [0.0, 0.1, 0.2, 0.3], "bodies": len(cols), "poses": poses,
            "body_of_node": {f"N{i},{j}": cols.index(j) for (i, j) in scene.topology.nodes}}


def set_first_body(value):
    def edit(d):
        d["body_of_node"][next(iter(d["body_of_node"]))] = value
    return edit


def set_pose(value):
    def edit(d):
        d["poses"][1][2][0] = value
    return edit


# (file name, edit, the field the red line names, the value it quotes)
BAD = [
    ("strbody", set_first_body("x"), "trajectory.body_of_node.N", "'x'"),
    ("listbody", lambda d: d.__setitem__("body_of_node", list(d["body_of_node"])), "trajectory.body_of_node:",
     "expected an object mapping each node"),
    ("strposes", set_pose("a"), "trajectory.poses[1][2][0]", "'a'"),
    ("strincline", lambda d: d.__setitem__("incline_deg", "steep"), "trajectory.incline_deg", "'steep'"),
    ("nantimes", lambda d: d.__setitem__("times_s", [NAN] * 4), "trajectory.times_s[0]", "nan"),
    ("infpose", set_pose(INF), "trajectory.poses[1][2][0]", "inf"),
    ("floatbody", set_first_body(1.7), "trajectory.body_of_node.N", "1.7"),
]


def write(tmp_path, name, data):
    path = tmp_path / name / "trajectory.json"
    path.parent.mkdir()
    path.write_text(json.dumps(data), encoding="utf-8")      # NaN / Infinity as Python's JSON writes them
    return str(path)


def load_with_button(p, path, monkeypatch):
    """Click Load... with the file dialog answering ``path``."""
    monkeypatch.setattr(QtGui.QFileDialog, "getOpenFileName", staticmethod(lambda *a, **k: (path, "")))
    try:
        click(p.traj_load_btn)
        process(50)
    finally:
        monkeypatch.undo()


@pytest.mark.parametrize("name,edit,field,value", BAD, ids=[b[0] for b in BAD])
def test_load_of_a_bad_trajectory_says_why_in_the_panel(doc, tmp_path, monkeypatch, tracebacks, name, edit, field,
                                                        value):
    sc = structure.load_scene_file(doc, os.path.join(ROOT, "examples", "worm.json"))
    doc.recompute()
    scene = structure.compose_scene(sc)
    p = run_panel("MM_Animate")
    # a good file first: it plays; the refusal after it keeps it playing
    load_with_button(p, write(tmp_path, "good", good(scene)), monkeypatch)
    assert p.trajectory is not None, p.error.text()
    playing, duration = p.traj_label.text(), p.duration.value()
    assert "good/trajectory.json, 4 frames, 0.30 s" in playing, playing
    assert duration == pytest.approx(0.3)
    kept = p.trajectory
    d = good(scene)
    edit(d)
    bad = write(tmp_path, name, d)
    load_with_button(p, bad, monkeypatch)
    text = p.error.text()
    assert not tracebacks, tracebacks[-1]
    assert p.error.isVisible() and field in text and value in text, text
    assert os.path.basename(os.path.dirname(str(bad))) in text and "(in " in text, text   # names the file
    assert p.trajectory is kept
    assert p.traj_label.text() == playing and p.duration.value() == pytest.approx(duration)
    p.reject()
