"""``calibrate measured`` counts the measured plates after dropping those a constraint holds: a CSV that lists
one free plate and one held by the clip is refused with the "at least 2 are needed" error naming the held plate
and its clip (not with a misleading search-bound error of the k1 fit); nothing is written (docs/calibration.md)."""
import json

import pytest

from clihelpers import one_line_error, run_cli

PIECE = {"format": "metamaterial-scene", "version": 1, "name": "calibration-test-piece", "cell_size_mm": 20.0,
         "hinge": {"length_mm": 4.0, "width_mm": 0.8, "thickness_mm": 7.0}, "layout": {"grid": [3, 3]},
         "actuators": [], "constraints": [{"name": "clip", "joint": "H1,1", "value": 0.3}]}


@pytest.mark.parametrize("rows,left", [
    ('"N0,0",1.3\n"N1,1",0.5\n', 1),              # N1,1 is held by the clip on H1,1 (with N1,2)
    ('"N1,2",-0.4\n"N1,1",0.5\n', 0),
])
def test_held_plates_do_not_count_towards_the_two_needed(tmp_path, rows, left):
    piece = tmp_path / "piece.json"
    piece.write_text(json.dumps(PIECE), encoding="utf-8")
    csv = tmp_path / "clipped.csv"
    csv.write_text("node,angle_deg\n" + rows, encoding="utf-8")
    out = tmp_path / "cal.json"
    r = run_cli("calibrate", "measured", piece, csv, "--out", out)
    one_line_error(r, str(csv))
    assert f"{left} measured node(s) left" in r.stderr and "at least 2 are needed" in r.stderr, r.stderr
    assert "N1,1 held by the constraint 'clip' on H1,1" in r.stderr, r.stderr
    assert "search bound" not in r.stderr and not out.exists()


def test_one_free_node_without_held_ones_is_refused_plainly():
    """Called directly with one measured node and none held (the CLI's CSV reader refuses that first), the message
    named an empty list of dropped plates ("left after dropping  (a plate ..."); review of the above."""
    from metamaterial_wb.core.calibrate import fit_measured
    from metamaterial_wb.core.errors import SceneError
    from metamaterial_wb.core.scene import Scene
    scene = Scene.from_dict(PIECE)
    with pytest.raises(SceneError) as e:
        fit_measured(scene, [0], [0.02], source="angles.csv")
    assert str(e.value).startswith("angles.csv: 1 measured node(s); at least 2 are needed for a fit"), str(e.value)
    assert "dropping" not in str(e.value)
