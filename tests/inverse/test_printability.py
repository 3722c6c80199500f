"""The inverse answer goes through build's checks: printable or not, said in report.json (issue 17)."""
import json
import os
import subprocess
import sys

import pytest

from inverse_helpers import planted_result
from metamaterial_wb import REPO_DIR
from metamaterial_wb.core import design
from metamaterial_wb.core.inverse import pipeline
from metamaterial_wb.core.inverse.targets import parse_target
from metamaterial_wb.core.scene import Scene
from metamaterial_wb.export.printability import check_printable


def _folded(fold_deg, acts=(("H1,1", 0.6),)):
    d = Scene.grid(5, 5).to_dict()
    d["axes"] = [{"name": "x", "direction": "vertical", "line": 2, "fold_deg": fold_deg}]
    d["actuators"] = [{"name": f"m{k}", "joint": j, "value": v} for k, (j, v) in enumerate(acts)]
    s = Scene.from_dict(d)
    design.ensure_configured(s)
    return s


def _bare(s):
    d = s.to_dict()
    d["actuators"] = []
    return Scene.from_dict(d)


def test_a_planted_answer_folding_beyond_the_printable_limit_is_reported_not_printable():
    planted = _folded(20.0)                 # 20 deg needs hinge tilts of ~72 deg: a 0.8 mm hinge fits ~30
    scene = _bare(planted)
    target = parse_target(scene, planted_result(planted))
    run = pipeline.solve(scene, target, servos=1, evaluate=("quadratic",),
                         fab_check=lambda s: check_printable(s, geometry="off"))
    assert run.errors["quadratic"]["max_mm"] < 1e-6              # the shape is reached ...
    rep = pipeline.report_dict(run)
    assert rep["printable"] is False                              # ... but it cannot be printed
    assert "tilt" in rep["fabrication"]["problems"][0] and "parameters" in rep["fabrication"]["checks_run"]
    assert any("printable: NO" in line for line in pipeline.summary_lines(run))


def test_the_same_check_function_as_build_passes_a_printable_fold():
    ok = _folded(3.0)
    assert check_printable(ok, geometry="off")["printable"] is None          # parameters only: not a yes
    assert check_printable(ok, geometry="off")["checks_run"] == ["parameters"]
    assert check_printable(_folded(20.0), geometry="off")["printable"] is False


@pytest.mark.skipif(not os.path.isdir("/usr/lib/freecad-python3/lib"), reason="needs FreeCAD for the geometry checks")
def test_cli_report_says_printable_after_builds_geometry_checks(tmp_path):
    planted = _folded(3.0)
    (tmp_path / "t.json").write_text(json.dumps(planted_result(planted)))
    (tmp_path / "s.json").write_text(_bare(planted).to_json())
    env = dict(os.environ, PYTHONPATH=REPO_DIR)
    p = subprocess.run([sys.executable, "-m", "metamaterial_wb", "inverse", str(tmp_path / "s.json"), "--target",
                        str(tmp_path / "t.json"), "--servos", "1", "--out", str(tmp_path / "o"), "--no-picture",
                        "--evaluate", "quadratic"], capture_output=True, text=True, env=env, timeout=600)
    assert p.returncode == 0, p.stderr
    rep = json.loads((tmp_path / "o" / "report.json").read_text())
    assert rep["printable"] is True, rep["fabrication"]
    assert rep["fabrication"]["checks_run"][:2] == ["parameters", "solids"]
    assert "printable: yes" in p.stderr
