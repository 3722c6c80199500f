"""GUI tests (FreeCAD under Xvfb, tests/run_gui_pytest.py): the Animate panel plays a simulated
dynamics trajectory (issue 8) and the Sleeve actuator command builds a sleeve and predicts it (issue 9).

References are independent of the panels: the trajectory comes from the ``simulate`` CLI run in a
separate /usr/bin/python3 process, the prediction from ``core.sleeve.pipeline.analyse`` called here.
"""
import json
import math
import os
import subprocess
import sys
import time

import numpy as np
import pytest

FreeCAD = pytest.importorskip("FreeCAD")
if not getattr(FreeCAD, "GuiUp", False):
    pytest.skip("needs the FreeCAD GUI (run tests/run_gui_pytest.py under xvfb-run)", allow_module_level=True)

import FreeCADGui  # noqa: E402
from PySide import QtGui  # noqa: E402

import metamaterial_wb  # noqa: E402
from metamaterial_wb.gui import panels  # noqa: E402
from metamaterial_wb.objects import structure  # noqa: E402
from guihelpers import click, doc, run_panel, shown_placements, type_into, workbench  # noqa: E402,F401

PY = "/usr/bin/python3" if os.path.exists("/usr/bin/python3") else sys.executable
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(metamaterial_wb.__file__)))


def node_state(arr):
    """(n, 3) positions and (n, 3) images of the x axis of every node placement."""
    shown = shown_placements(arr)
    pos = np.array([[q.Base.x, q.Base.y, q.Base.z] for q in shown])
    ex = np.array([list(q.Rotation.multVec(FreeCAD.Vector(1, 0, 0))) for q in shown])
    return pos, ex


def simulate_cli(seconds, out):
    r = subprocess.run([PY, "-m", "metamaterial_wb", "simulate", os.path.join(ROOT, "examples", "worm_crawl.json"),
                        "--seconds", str(seconds), "--out", str(out), "--fps", "30"],
                       cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    with open(os.path.join(out, "trajectory.json")) as f:
        return json.load(f)


def expected_pose(data, body, t):
    T = np.asarray(data["times_s"])
    P = np.asarray(data["poses"])[:, body, :]
    return np.array([np.interp(t, T, P[:, k]) for k in range(3)])


def test_animate_plays_a_simulated_trajectory_and_restores(doc, tmp_path):
    sc = structure.load_scene_file(doc, os.path.join(ROOT, "examples", "worm_crawl.json"))
    doc.recompute()
    scene = structure.compose_scene(sc)
    pos0, ex0 = node_state(sc.NodeArray)
    hinges0 = [FreeCAD.Placement(p) for p in sc.HingeArray.PlacementList]
    builds = doc.getObject("NodeShape").BuildCount
    data = simulate_cli(1.0, tmp_path / "sim")
    assert data["incline_deg"] == 0.0 and data["model"] == "sheet"

    p = run_panel("MM_Animate")
    assert p.load_trajectory(str(tmp_path / "sim" / "trajectory.json")) is True
    assert p.duration.value() == pytest.approx(data["times_s"][-1], abs=1e-3)
    graph = FreeCADGui.getDocument(doc.Name).ActiveView.getSceneGraph()
    assert p.floor is not None and graph.findChild(p.floor.root) >= 0, "the floor is shown"
    floor_root = p.floor.root
    p.loop.setChecked(False)
    p.speed.setValue(1.0)
    n = 17
    p.step(n)
    t = p.t
    assert t == pytest.approx(n * p.dt)
    nodes = scene.topology.nodes
    moved = 0.0
    for (mode, tt) in (("played", t), ("recorded frame", data["times_s"][7])):
        if mode == "recorded frame":
            p.show_time(tt)
        pos, ex = node_state(sc.NodeArray)
        # the trajectory starts from a settled state (not the flat layout): the view places the bodies as
        # simulated, shifted by one offset (the nodes' mean position kept where the flat structure is)
        bodies = [data["body_of_node"][f"N{i},{j}"] for (i, j) in nodes]
        first = np.asarray(data["poses"][0])[bodies]
        off_x = float(np.mean(pos0[:, 0] - first[:, 0]))
        off_z = float(np.mean(first[:, 1]))
        for k, b in enumerate(bodies):
            x, y, a = expected_pose(data, b, tt)
            x0, y0, _a0 = np.asarray(data["poses"][0][b])
            # side view (x, y up) -> the 3D view's x-z plane; the row coordinate is kept
            assert pos[k, 0] == pytest.approx(x + off_x, abs=1e-6), (mode, k)
            assert pos[k, 2] - pos0[k, 2] == pytest.approx(y - off_z, abs=1e-6), (mode, k)
            assert pos[k, 1] == pytest.approx(pos0[k, 1], abs=1e-9)
            # the plate's x axis turns counter-clockwise in the side view by the body angle
            ar = math.radians(a)
            np.testing.assert_allclose(ex[k], [math.cos(ar), 0.0, math.sin(ar)], atol=1e-9)
            moved = max(moved, abs(x - x0))
    assert moved > 1.0, "the worm should have moved: the comparison would be empty otherwise"
    # hinges follow their nodes (not left at the flat layout)
    hp = [FreeCAD.Placement(q) for q in shown_placements(sc.HingeArray)]
    assert max((a.Base - b.Base).Length for a, b in zip(hp, hinges0)) > 1.0
    # no recompute: shapes untouched, arrays not touched
    assert doc.getObject("NodeShape").BuildCount == builds
    assert "Touched" not in sc.NodeArray.State
    # no loop: playing past the end stops at the last frame
    p.step(int(2.0 / p.dt))
    assert p.t == pytest.approx(p.duration.value())
    p.reject()
    assert graph.findChild(floor_root) < 0, "the floor is removed on close"
    pos, ex = node_state(sc.NodeArray)
    np.testing.assert_allclose(pos, pos0, atol=1e-9)
    np.testing.assert_allclose(ex, ex0, atol=1e-9)
    assert all((a.Base - b.Base).Length < 1e-9 for a, b in
               zip(sc.HingeArray.PlacementList, hinges0))


def test_animate_simulates_in_the_background_like_the_cli(doc, tmp_path):
    sc = structure.load_scene_file(doc, os.path.join(ROOT, "examples", "worm_crawl.json"))
    doc.recompute()
    pos0, _ = node_state(sc.NodeArray)
    p = run_panel("MM_Animate")
    assert p.dt == pytest.approx(1.0 / 30.0)     # the test preferences' frame rate = the CLI's --fps 30
    assert p.simulate_trajectory(0.4) is True
    assert p.traj_progress.isVisible()
    assert p.wait_simulation(60.0)
    assert not p.traj_progress.isVisible()
    assert p.trajectory is not None, p.error.text()
    ref = simulate_cli(0.4, tmp_path / "ref")
    assert p.trajectory_data["times_s"] == pytest.approx(ref["times_s"])
    np.testing.assert_allclose(np.asarray(p.trajectory_data["poses"]), np.asarray(ref["poses"]), atol=1e-3)
    assert "moved" in p.traj_label.text()
    # back to the motion profiles, then close: placements restored
    p.clear_trajectory()
    assert p.trajectory is None and p.table.isEnabled()
    p.reject()
    np.testing.assert_allclose(node_state(sc.NodeArray)[0], pos0, atol=1e-9)


def test_animate_shows_the_simulations_warnings(doc):
    """The summary's warnings (here: implicit steps accepted with Newton unconverged) reached no GUI user: the panel
    showed only the displacement (an audit of the dynamics journey, session 26)."""
    structure.load_scene_file(doc, os.path.join(ROOT, "examples", "worm_crawl.json"))
    doc.recompute()
    p = run_panel("MM_Animate")
    assert p.simulate_trajectory(2.0) is True
    assert p.wait_simulation(300.0)
    assert p.trajectory is not None, p.error.text()
    warnings = p.last_simulation["warnings"]
    assert warnings, "precondition: the worm's 2 s accept a few unconverged Newton steps"
    assert all(w in p.error.text() for w in warnings), p.error.text()
    p.reject()


def test_trajectory_of_another_layout_is_refused(doc, tmp_path):
    structure.load_scene_file(doc, os.path.join(ROOT, "examples", "fish.json"))
    doc.recompute()
    data = simulate_cli(0.1, tmp_path / "sim")
    p = run_panel("MM_Animate")
    assert p.load_trajectory(str(tmp_path / "sim")) is False          # the --out folder works too
    assert "not in the trajectory" in p.error.text() or "different layout" in p.error.text()
    assert p.trajectory is None
    p.reject()


def test_sleeve_command_builds_a_valid_sleeve_and_predicts_like_the_core(doc, tmp_path):
    from metamaterial_wb.core.sleeve.pipeline import analyse
    from metamaterial_wb.core.sleeve.spec import SleeveSpec

    p = run_panel("MM_Sleeve")
    assert p.ring.text().replace(" ", "") == "0,0,1,1"          # examples/sleeve.json is the default
    spec = json.load(open(os.path.join(ROOT, "examples", "sleeve.json")))
    spec["model"] = {"elements_cell": 6, "elements_ring": 6, "steps": 60}   # coarse: keeps the test short
    path = tmp_path / "coarse.json"
    path.write_text(json.dumps(spec))
    assert p.load_spec(str(path)) is True
    assert p.dims["L_mm"].value() == pytest.approx(spec["L_mm"])
    assert p.types.rowCount() == 2
    # edit through the widgets: thicker wall, two rings
    p.dims["T_mm"].setValue(2.0)
    p.rings.setValue(2)
    d = p.spec_dict()
    assert d["T_mm"] == 2.0 and d["rings"] == 2 and d["ring"] == [0, 0, 1, 1] and d["model"] == spec["model"]
    # a bad pattern is reported, not built
    p.ring.setText("0, 0, 5")
    lab = p.problem_label("spec")          # shown at once, next to the pattern, and OK refused
    assert "ring[2]" in lab.text() and "an integer 0..1" in lab.text() and "spec" in p.problems
    assert p.accept() is False and "an integer 0..1" in p.error.text()
    p.ring.setText("0, 0, 1, 1")
    p.rings.setValue(1)

    assert p.predict() is True
    assert p.wait_prediction(120.0)
    assert p.summary is not None, p.error.text()
    ref, _ = analyse(SleeveSpec(p.spec_dict()))
    for a, b in zip(p.summary["unit_cells"], ref["unit_cells"]):
        assert a["peak_force"] == pytest.approx(b["peak_force"]) and a["valley_force"] == pytest.approx(b["valley_force"])
    assert p.summary["ring"]["peaks"] == pytest.approx(ref["ring"]["peaks"])
    assert p.summary["ring"]["valleys"] == pytest.approx(ref["ring"]["valleys"])
    for k in ("loading", "unloading", "symmetric"):
        assert p.summary["sequence"][k] == ref["sequence"][k]
    text = p.result.text()
    word = "symmetric" if ref["sequence"]["symmetric"] else "asymmetric"
    assert f"-> {word}" in text and f"loading {ref['sequence']['loading']}" in text
    # the model's measured error against the solid is shown with the prediction (core/sleeve/accuracy.py)
    assert ref["accuracy"]["notes"] and all(f"accuracy: {n}" in text for n in ref["accuracy"]["notes"])

    # export: STEP that re-imports as the five printed parts, 3MF with TPU and PLA
    import zipfile

    import Part
    # the export runs in a child process: the GUI's event loop keeps running (a QTimer ticks throughout)
    from PySide import QtCore
    ticks = []
    timer = QtCore.QTimer()
    timer.timeout.connect(lambda: ticks.append(time.perf_counter()))
    timer.start(20)
    t0 = time.perf_counter()
    type_into(p.export_dir, str(tmp_path / "exp"))
    click(p.export_btn)
    assert p.export_job.running, p.error.text()
    assert p.jobbox.progress.isVisible() and p.jobbox.cancel_btn.isVisible(), "progress + Cancel while it runs"
    assert p.wait_export(600), "sleeve export did not finish"
    timer.stop()
    took = time.perf_counter() - t0
    gaps = [b - a for a, b in zip([t0] + ticks, ticks + [time.perf_counter()])]
    assert p.export_job.outcome == "done", p.error.text()
    assert len(ticks) > 5 and max(gaps) < max(2.0, 0.25 * took) and took > 2 * max(gaps), \
        f"the GUI froze: longest pause {max(gaps):.2f} s of a {took:.1f} s export"
    assert "wrote 2 file(s)" in p.jobbox.summary.text(), p.jobbox.summary.text()
    paths = p.exported
    assert sorted(os.path.basename(x) for x in paths) == ["sleeve.3mf", "sleeve.step"], p.error.text()
    shp = Part.read(str(tmp_path / "exp" / "sleeve.step"))
    assert shp.isValid() and len(shp.Solids) == 5
    with zipfile.ZipFile(tmp_path / "exp" / "sleeve.3mf") as z:
        text = " ".join(z.read(n).decode("utf-8", "replace") for n in z.namelist() if n.endswith((".model", ".config")))
    assert "TPU" in text and "PLA" in text
    assert not [n for n in os.listdir(tmp_path) if n.startswith(".sleeve-export-")], "temporary folder left"

    n0, undo0 = len(doc.Objects), doc.UndoCount
    assert p.accept() is True, p.error.text()
    assert doc.UndoCount == undo0 + 1, "building the sleeve is one undo step"
    made = doc.Objects[n0:]
    sleeve = [o for o in made if o.Name.startswith("sleeve")]
    assert len(sleeve) == 1
    s = sleeve[0].Shape
    assert s.isValid() and len(s.Solids) == 1 and s.Volume > 0 and all(sh.isClosed() for sh in s.Shells)
    # the circumference holds N cell widths at the mid radius; the wall is T thick
    bb = s.BoundBox
    Rm = 4 * (spec["L_mm"] + spec["c_mm"]) / (2 * math.pi)
    assert bb.XLength == pytest.approx(2 * (Rm + 2.0 / 2), rel=1e-3)     # outer radius = mid + T / 2
    part = [o for o in made if o.TypeId == "App::Part"][0]
    assert json.loads(part.SleeveSpec)["T_mm"] == 2.0
    assert {o.Name for o in part.Group} >= {sleeve[0].Name}
    doc.undo()
    assert len(doc.Objects) == n0


def test_sleeve_export_cancel_leaves_nothing(doc, tmp_path):
    p = run_panel("MM_Sleeve")
    type_into(p.export_dir, str(tmp_path / "exp"))
    click(p.export_btn)
    assert p.export_job.running and p.jobbox.cancel_btn.isVisible(), p.error.text()
    assert not p.export_btn.isEnabled(), "a second export cannot start while one runs"
    click(p.jobbox.cancel_btn)
    assert p.export_job.outcome == "cancelled" and not p.export_job.running
    assert "cancelled" in p.jobbox.summary.text() and p.export_btn.isEnabled()
    assert not os.path.exists(tmp_path / "exp") or not os.listdir(tmp_path / "exp")
    assert not [n for n in os.listdir(tmp_path) if n.startswith(".sleeve-export-")], "staging folder left"


def test_sleeve_panel_checks_the_first_peak_on_the_3d_frame_when_asked(doc, tmp_path):
    """The panel's 3-D frame box, ticked by a click, adds the nonlinear frame's first peak of each uniform ring
    to the prediction (the same figures as ``analyse`` on the spec the panel describes, shown as accuracy lines);
    a spec whose ring is modelled flat greys the box out and never asks for it."""
    from metamaterial_wb.core.sleeve.pipeline import analyse
    from metamaterial_wb.core.sleeve.spec import SleeveSpec

    p = run_panel("MM_Sleeve")
    spec = json.load(open(os.path.join(ROOT, "examples", "sleeve.json")))
    spec["model"] = {"elements_cell": 6, "elements_ring": 6, "steps": 60, "frame_elements": 4}
    path = tmp_path / "coarse.json"
    path.write_text(json.dumps(spec))
    assert p.load_spec(str(path)) is True
    assert p.frame_nl.isEnabled() and not p.frame_nl.isChecked() and "frame_nonlinear" not in p.spec_dict()["model"]
    click(p.frame_nl)
    assert p.frame_nl.isChecked() and p.spec_dict()["model"]["frame_nonlinear"] is True
    assert p.predict() is True
    assert p.wait_prediction(120.0)
    assert p.summary is not None, p.error.text()
    ref, _ = analyse(SleeveSpec(p.spec_dict()))
    for a, b in zip(p.summary["uniform_rings"], ref["uniform_rings"]):
        assert a["frame3d_nl"]["P1"] == pytest.approx(b["frame3d_nl"]["P1"], rel=1e-9)
        assert a["frame3d_nl"]["elements"] == 4 and a["frame3d_nl"]["ratio"] > 1.2
    notes = [n for n in ref["accuracy"]["notes"] if n.startswith("nonlinear frame")]
    assert len(notes) == 2 and all(f"accuracy: {n.split(';')[0]}" in p.result.text() for n in notes)
    flat = dict(spec, model=dict(spec["model"], ring_curvature=False))
    path.write_text(json.dumps(flat))
    assert p.load_spec(str(path)) is True
    assert not p.frame_nl.isEnabled() and "frame_nonlinear" not in p.spec_dict()["model"]
    p.reject()
