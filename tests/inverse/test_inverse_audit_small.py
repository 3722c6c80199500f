"""Small defects of a user audit: a kept ``--hinges`` answer says so in ``warnings`` (docs/inverse.md), and an
unknown joint name (``--forbid``, a target fold's ``joint``) is refused with the scene's joint names."""
import os
from types import SimpleNamespace

import pytest

from metamaterial_wb import REPO_DIR
from metamaterial_wb.core.errors import MetamaterialError
from metamaterial_wb.core.inverse import pipeline
from metamaterial_wb.core.inverse.search import PlacementSearch
from metamaterial_wb.core.inverse.targets import parse_target
from metamaterial_wb.core.scene import Scene

FISH = os.path.join(REPO_DIR, "examples", "fish_axes.json")


def _fish():
    return Scene.load(FISH)


def test_unknown_forbidden_joint_names_the_scene_joints():
    s = _fish()
    pb = SimpleNamespace(topo=s.topology, fixed_nodes=set(), _joint_nodes=lambda j: ())
    with pytest.raises(MetamaterialError) as e:
        PlacementSearch(pb, 2, forbidden=["V4,0"])
    msg = str(e.value)
    assert "'V4,0'" in msg and "32 joints" in msg
    assert "H0,0 .. H2,5" in msg and "V0,0 .. V1,6" in msg, msg


def test_unknown_target_fold_joint_names_the_scene_joints():
    with pytest.raises(MetamaterialError) as e:
        parse_target(_fish(), {"folds": [{"joint": "V4,0", "fold_deg": 10}]})
    msg = str(e.value)
    assert "folds[0].joint" in msg and "'V4,0'" in msg
    assert "H0,0 .. H2,5" in msg and "V0,0 .. V1,6" in msg, msg


def test_a_kept_hinge_answer_has_a_line_in_warnings():
    from inverse_helpers import planted_result, scene_with
    s = scene_with(Scene.grid(6, 6, hinge={"length_mm": 8, "width_mm": 0.8, "thickness_mm": 7}),
                   [("H1,1", 0.6), ("V3,4", 0.7)])
    d = s.to_dict()
    d["joints"] = [{"joint": j, "length_mm": 4.0} for j in s.topology.joint_names]
    target = parse_target(s, {"nodes": planted_result(Scene.from_dict(d))["nodes"]})
    run = pipeline.solve(s, target, values_only=True, hinge_regions=(1, 1), evaluate=("quadratic",))
    assert run.scene.joint_overrides                        # the hinge answer was kept ...
    kept = [w for w in run.info["warnings"] if w.startswith("--hinges")]
    assert len(kept) == 1 and "kept" in kept[0] and "mm^2" in kept[0], run.info["warnings"]   # ... and says so
