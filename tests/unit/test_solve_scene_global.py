"""``solve`` with a global deformation stored in the scene: model options and --backend would be ignored (the
closed form runs, no model), so they are refused as with ``--global`` (audit of the simulation core, defect 2)."""
import json

import pytest

from metamaterial_wb import example_path
from metamaterial_wb.cli import main


def _scene_with_global(tmp_path, g=0.3):
    with open(example_path("grid_fold")) as f:
        d = json.load(f)
    d["global_deformation"] = g
    p = tmp_path / "scene_global.json"
    p.write_text(json.dumps(d))
    return str(p)


@pytest.mark.parametrize("args, needle", [
    (["--model", "nonlinear", "--option", "tol=1e-10", "--option", "hinge_elements=8"], "--option tol=1e-10"),
    (["--model", "linear", "--option", "about=flat"], "--option about=flat"),
    (["--backend", "superlu"], "--backend superlu"),
])
def test_scene_global_with_options_is_refused(tmp_path, capsys, args, needle):
    scene = _scene_with_global(tmp_path)
    out = tmp_path / "o.json"
    rc = main(["solve", scene, "--out", str(out), *args])
    err = capsys.readouterr().err
    assert rc == 2, err
    assert err.startswith("error: ") and err.count("\n") == 1, err
    assert "global_deformation" in err and needle in err, err
    assert not out.exists()


def test_scene_global_without_options_still_solves(tmp_path, capsys):
    scene = _scene_with_global(tmp_path)
    out = tmp_path / "o.json"
    assert main(["solve", scene, "--out", str(out)]) == 0, capsys.readouterr().err
    res = json.loads(out.read_text())
    assert res["global_deformation"] == 0.3 and all(n["D"] == 0.3 for n in res["nodes"])


def test_set_overrides_the_scene_global_so_options_apply(tmp_path, capsys):
    scene = _scene_with_global(tmp_path)
    with open(scene) as f:
        name = json.load(f)["actuators"][0]["name"]
    out = tmp_path / "o.json"
    rc = main(["solve", scene, "--out", str(out), "--set", f"{name}=0.2", "--model", "linear",
               "--option", "about=flat"])
    assert rc == 0, capsys.readouterr().err
    res = json.loads(out.read_text())
    assert res["global_deformation"] is None and res["info"]["about"] == "flat"
