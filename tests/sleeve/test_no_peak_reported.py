"""A curve without a peak is not reported as having one (audit): a monostable cell (t 3, h 1.5 on L 18) rises to
the stroke's end, and a stroke shorter than any peak (``model.max_displacement_mm`` 0.001) ends on the rise. The
stroke's last point is no peak or valley: null with a note; a sequence in which nothing snapped is neither
symmetric nor asymmetric."""
import json
import os
import subprocess
import sys

from metamaterial_wb.core.sleeve.cell import CellGeometry
from metamaterial_wb.core.sleeve.pipeline import analyse, unit_cell_result
from metamaterial_wb.core.sleeve.spec import SleeveSpec

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
COARSE = {"elements_cell": 6, "elements_ring": 6, "steps": 40}


def test_a_monostable_cell_has_no_peak_or_valley():
    res, up, _ = unit_cell_result(CellGeometry(t=3.0, h=1.5), 8, 80)
    assert res["peak_force"] is None and res["peak_displacement"] is None
    assert res["valley_force"] is None and res["valley_displacement"] is None
    assert res["bistable"] is False
    assert "no peak within the stroke" in res["note"]
    # the seed's cell still has both
    seed, _, _ = unit_cell_result(CellGeometry(), 8, 80)
    assert seed["peak_force"] > 0 > seed["valley_force"] and "note" not in seed


def test_a_stroke_shorter_than_the_peak_reports_no_peak_and_no_symmetry(tmp_path):
    spec = SleeveSpec({"format": "metamaterial-sleeve", "cell_types": [{"t_mm": 1.098, "h_mm": 7.092},
                                                                        {"t_mm": 1.098, "h_mm": 7.488}],
                       "ring": [0, 0, 1, 1], "model": dict(COARSE, max_displacement_mm=0.001)})
    s, _ = analyse(spec)
    for u in s["unit_cells"]:
        assert u["peak_force"] is None and u["peak_force_N"] is None and "no peak within the stroke" in u["note"]
    for u in s["uniform_rings"]:
        assert u["P1"] is None and "no peak within the stroke" in u["note"]
    seq = s["sequence"]
    assert seq["loading"] == [] and seq["unloading"] == []
    assert seq["symmetric"] is None and "nothing snapped" in seq["note"]
    assert seq["two_hysteron"]["loading"] is None and seq["two_hysteron"]["symmetric"] is None
    assert seq["agrees_with_two_hysteron"] is None


def test_cli_writes_and_prints_a_peakless_sleeve(tmp_path):
    spec = {"format": "metamaterial-sleeve", "cell_types": [{"t_mm": 3.0, "h_mm": 1.5}], "ring": [0, 0, 0, 0],
            "model": COARSE}
    p = tmp_path / "mono.json"
    p.write_text(json.dumps(spec))
    out = tmp_path / "o"
    r = subprocess.run([sys.executable, "-m", "metamaterial_wb", "sleeve", str(p), "--out", str(out)], cwd=REPO,
                       capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr
    s = json.loads((out / "summary.json").read_text())
    assert s["unit_cells"][0]["peak_force"] is None
    assert "unit cell of type 0: no peak within the stroke" in r.stderr
    assert (out / "fd_cells.png").stat().st_size > 1000
