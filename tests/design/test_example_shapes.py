"""The bundled folded examples take the shape their descriptions and docs/design.md give them: grid_fold is a
step (the outer parts parallel, the middle a 45 deg ramp); the docs called it a channel with both walls raised,
which its folds (-45, +45) are not (an audit, session 26)."""
import json

import numpy as np

from metamaterial_wb import example_path
from metamaterial_wb.cli import main


def test_grid_fold_is_a_step(tmp_path, capsys):
    out = tmp_path / "r.json"
    assert main(["solve", example_path("grid_fold"), "--global", "1", "--out", str(out)]) == 0, capsys.readouterr()
    nodes = json.loads(out.read_text())["nodes"]
    normal = {}
    for n in nodes:
        i, j = map(int, n["name"][1:].split(","))
        normal.setdefault(j, []).append(np.asarray(n["rotation"], float)[2])   # the plate normal (third row)
    first, mid, last = (np.mean(normal[j], axis=0) for j in (0, 3, 5))
    first, mid, last = (v / np.linalg.norm(v) for v in (first, mid, last))
    assert abs(float(first @ last)) > 0.99                                       # outer parts parallel
    assert abs(np.degrees(np.arccos(np.clip(first @ mid, -1, 1))) - 45.0) < 3.0  # a 45 deg ramp between
    with open(example_path("grid_fold")) as f:
        assert "step" in json.load(f)["description"]
