"""A live frame of a lattice model carries that model's warnings for the state and whether it converged (the GUI
showed only the warnings from when the model was chosen: the slider drove the gripper's hinges past the scene's
limits without a word)."""
import json
import os

from metamaterial_wb.core.live import LiveSolver
from metamaterial_wb.core.models import run_model
from metamaterial_wb.core.scene import Scene

EX = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))), "examples")


def test_lattice_frame_carries_the_models_warnings_for_its_state():
    scene = Scene.from_dict(json.load(open(os.path.join(EX, "gripper.json"))))
    live = LiveSolver(scene, model="nonlinear")
    low = {a.name: -1.0 for a in scene.actuators}
    f = live.frame(values=low)
    sc = scene.copy()
    for k, v in low.items():
        sc.set_value(k, v)
    ref = run_model("nonlinear", sc)
    assert f.warnings == list(ref.warnings) and f.converged == ref.converged
    assert any("turn past the scene's rotation limits" in w for w in f.warnings)
    assert live.frame(values={a.name: 0.2 for a in scene.actuators}).warnings == []


def test_quadratic_frames_have_no_state_warnings():
    scene = Scene.from_dict(json.load(open(os.path.join(EX, "fish.json"))))
    f = LiveSolver(scene).frame(values={})
    assert f.warnings == [] and f.converged is True
