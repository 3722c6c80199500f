"""Issue 18: ``sleeve SPEC --fe-check`` measures the beam model against the curved CalculiX solid for the user's own
cells. On the seed's cell it must give the ratio the accuracy table quotes (a second path to the same number:
the CLI, the spec's model settings and ``fe/sleeve_check.py`` against ``bench_sleeve_ring3d.py --cells``); without
CalculiX it refuses before any work and writes nothing."""
import json
import os
import subprocess
import sys

import pytest

from metamaterial_wb.core.sleeve import accuracy as acc
from metamaterial_wb.fe import ccx, sleeve_check

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SEED = {"format": "metamaterial-sleeve", "version": 1, "L_mm": 18, "c_mm": 4, "delta_mm": 0.5, "T_mm": 1.8,
        "shear_modulus_MPa": 1, "cell_types": [{"t_mm": 1.0, "h_mm": 7.5}], "ring": [0, 0, 0, 0],
        "model": {"elements_cell": 6, "steps": 60}}


def _run(tmp_path, spec, *extra, env=None):
    p = tmp_path / "spec.json"
    p.write_text(json.dumps(spec))
    out = tmp_path / "out"
    r = subprocess.run([sys.executable, "-m", "metamaterial_wb", "sleeve", str(p), "--out", str(out), "--quiet",
                        "--no-plots", *extra], cwd=REPO, capture_output=True, text=True, timeout=900, env=env)
    return r, out


@pytest.mark.skipif(not ccx.available()[0], reason="CalculiX (ccx) not installed")
def test_fe_check_of_the_seed_cell_gives_the_quoted_ratio(tmp_path):
    """``--fe-check converged`` on the seed's cell: the coarse solid gives the table's coarse ratio, and the solid
    extrapolated over r = 1, 2, 3 gives the ratio (and error) the accuracy notes quote, by a second path (the CLI,
    the spec's model settings, ``fe/sleeve_check.py``) to the same CalculiX runs (about 2 min)."""
    r, out = _run(tmp_path, SEED, "--fe-check", "converged")
    assert r.returncode == 0, r.stderr
    s = json.loads((out / "summary.json").read_text())
    a = s["accuracy"]
    (row,) = a["fe_check"]["types"]
    assert row["type"] == 0 and row["fe_stiffness"] > 0
    assert row["stiffness_ratio"] == pytest.approx(row["model_stiffness"] / row["fe_stiffness"])
    # the same solid and the same model as the measured table's coarse mesh: the same ratio (documented, four
    # cells); the quoted ratio is against the solid extrapolated in its mesh, lower by the coarse mesh's excess
    cells = json.load(open(os.path.join(REPO, "benchmarks", "results", "fe-ring3d-comparison.json")))["cells"]
    coarse = cells["4"]["model_curved_documented"] / cells["4"]["fe_curved"]
    assert row["stiffness_ratio"] == pytest.approx(coarse, abs=0.01)
    quoted = acc.CURVED_RING_STIFFNESS["documented"][4]
    assert a["ring_initial_stiffness"] == list(quoted)
    lo, hi = sleeve_check.COARSE_STIFFNESS_OVER
    assert 1 + lo / 100 - 0.005 < quoted[0] / row["stiffness_ratio"] < 1 + hi / 100 + 0.005
    assert row["stiffness_ratio_extrapolated"] == pytest.approx(quoted[0], abs=0.01)
    assert row["stiffness_ratio_error"] == pytest.approx(quoted[1], abs=0.01)
    assert any(f"(model / solid {quoted[0]:.2f} +- {quoted[1]:.2f})" in n for n in a["notes"])
    assert any(n.startswith("fe check, type 0") and f"{row['stiffness_ratio']:.2f}" in n for n in a["notes"])


def test_fe_check_without_calculix_refuses_before_any_work(tmp_path):
    env = dict(os.environ, PATH=str(tmp_path))                    # no ccx on this PATH
    r, out = _run(tmp_path, SEED, "--fe-check", "peak", env=env)
    assert r.returncode == 2, r.stderr
    assert "--fe-check" in r.stderr and "calculix-ccx" in r.stderr
    assert not out.exists()


def test_peak_check_reads_the_solid_s_first_peak_or_says_it_was_not_reached(monkeypatch):
    """The ``peak`` path's logic on a stand-in solid (the real one takes minutes): a curve with a known peak gives
    that peak and the ratio; a curve still rising when the run stopped gives no number and says why."""
    import numpy as np

    from metamaterial_wb.core.sleeve.spec import SleeveSpec
    from metamaterial_wb.fe import sleeve3d, sleeve_check
    spec = SleeveSpec(SEED)
    calls = []

    def fake(g, n, r, layers, d_max=None, increments=2, timeout_s=0, partial=True, **kw):
        calls.append((n, r, layers, d_max / g.L, increments))
        d = np.linspace(0, d_max / g.L, increments + 1)
        F = 1e-3 * np.sin(np.pi * d / 0.24) if rising is False else 1e-2 * d
        return {"d": d, "F": F, "tilt_rad": np.zeros((len(d), 2))}, {"wall_s": 1.0, "d_reached": float(d[-1])}

    monkeypatch.setattr(sleeve3d, "solve_ring3d", fake)
    monkeypatch.setattr(ccx, "available", lambda: (True, "ccx"))
    rising = False
    out = sleeve_check.check_sleeve(spec, peak=True)
    (row,) = out["types"]
    assert row["fe_p1"] == pytest.approx(1e-3, rel=1e-3) and row["fe_p1_d"] == pytest.approx(0.12, abs=2e-3)
    assert row["p1_ratio"] == pytest.approx(row["model_p1"] / row["fe_p1"])
    # the stiffness run (two increments to d/L 0.01), then the peak run to 1.4 x the model's peak, 0.01 per increment
    assert calls[0] == (4, 1, 2, pytest.approx(0.01), 2)
    assert calls[1][3] == pytest.approx(max(0.15, 1.4 * row["model_p1_d"])) and calls[1][4] == round(100 * calls[1][3])
    assert "first peak model" in sleeve_check.notes(out)[0]
    rising = True
    row = sleeve_check.check_sleeve(spec, peak=True)["types"][0]
    assert row["fe_p1"] is None and "no peak" in row["fe_stopped"]
    assert "not reached" in sleeve_check.notes({"types": [row]})[0]


def test_a_stalled_run_s_last_wobble_is_no_peak():
    """A static run that stalls near a bifurcation ends with its force wobbling by 1e-4 of itself: no peak; one
    that descends after its maximum by more than 1 % has its peak."""
    import numpy as np

    from metamaterial_wb.fe.sleeve_check import first_peak
    d = np.linspace(0, 0.08, 17)
    F = 0.04 * d
    F[-2:] = F[-3] * np.array([1.0001, 0.99995])                   # ccx cutting back: force flat to 1e-4
    assert all(np.isnan(first_peak(d, F)))
    d = np.linspace(0, 0.2, 41)
    F = np.sin(np.pi * d / 0.26)
    dp, Fp = first_peak(d, F)
    assert dp == pytest.approx(0.13, abs=1e-3) and Fp == pytest.approx(1.0, abs=1e-4)


def test_the_coarse_solids_quoted_excess_is_the_stored_mesh_studys():
    """``COARSE_STIFFNESS_OVER`` (in every fe-check note) is how far the stored coarse solid (the check's mesh) lies
    above the solid extrapolated over three meshes, over the seed's rings of 4-12 cells (no ccx needed)."""
    from metamaterial_wb.bench import fe_frame3d
    cells = json.load(open(os.path.join(REPO, "benchmarks", "results", "fe-ring3d-comparison.json")))["cells"]
    x = fe_frame3d.summary(fe_frame3d.study(cells, (0.0, 0.63)))["extrapolated"]
    assert sleeve_check.COARSE_STIFFNESS_OVER == tuple(round(v) for v in x["coarse"]) and x["sizes"] == 4
    lo, hi = sleeve_check.COARSE_STIFFNESS_OVER
    assert f"its stiffness {lo}-{hi} %" in sleeve_check.MESH_NOTE


def test_converged_check_runs_three_meshes_and_extrapolates(monkeypatch):
    """The ``converged`` path on a stand-in solid whose stiffness converges as k + a h^1.3 (h = 1 / r): the three
    meshes of ``CONVERGED_MESHES`` run with every brick C3D20 after the coarse run, and the ratio is against k
    (1e-9) with the finest mesh's distance as its error."""
    import numpy as np

    from metamaterial_wb.core.sleeve.spec import SleeveSpec
    from metamaterial_wb.fe import sleeve3d
    spec = SleeveSpec(SEED)
    calls, k, a = [], 0.0143, 0.0027

    def fake(g, n, r, layers, d_max=None, increments=2, timeout_s=0, partial=True, element="C3D20R", **kw):
        calls.append((r, layers, element))
        d = np.linspace(0, d_max / g.L, increments + 1)
        return {"d": d, "F": (k + a * r ** -1.3) * d, "tilt_rad": np.zeros((len(d), 2))}, {"wall_s": 1.0}

    monkeypatch.setattr(sleeve3d, "solve_ring3d", fake)
    monkeypatch.setattr(ccx, "available", lambda: (True, "ccx"))
    (row,) = sleeve_check.check_sleeve(spec, converged=True)["types"]
    assert calls == [(1, 2, "C3D20R"), (1, 1, "C3D20"), (2, 1, "C3D20"), (3, 1, "C3D20")]
    assert row["fe_stiffness_extrapolated"] == pytest.approx(k, rel=1e-9)
    assert row["fe_stiffness_order"] == pytest.approx(1.3, rel=1e-6)
    assert row["stiffness_ratio_extrapolated"] == pytest.approx(row["model_stiffness"] / k, rel=1e-9)
    assert row["fe_stiffness_error"] == pytest.approx(a * 3 ** -1.3, rel=1e-6) and row["fe_seconds"] == 4.0
    assert "extrapolated over meshes r = 1, 2, 3" in sleeve_check.notes({"types": [row]})[0]


def test_converged_check_says_when_the_order_was_clipped(monkeypatch):
    """A solid converging as k + a h^5.5: the observed order lies above the range [0.5, 4]; the check uses 4 and
    says so in its row and its note (the sleeve studies' Richardson clipped orders silently)."""
    import numpy as np

    from metamaterial_wb.core.sleeve.spec import SleeveSpec
    from metamaterial_wb.fe import sleeve3d
    k, a = 0.0143, 0.0027

    def fake(g, n, r, layers, d_max=None, increments=2, timeout_s=0, partial=True, element="C3D20R", **kw):
        d = np.linspace(0, d_max / g.L, increments + 1)
        return {"d": d, "F": (k + a * r ** -5.5) * d, "tilt_rad": np.zeros((len(d), 2))}, {"wall_s": 1.0}

    monkeypatch.setattr(sleeve3d, "solve_ring3d", fake)
    monkeypatch.setattr(ccx, "available", lambda: (True, "ccx"))
    (row,) = sleeve_check.check_sleeve(SleeveSpec(SEED), converged=True)["types"]
    assert row["fe_stiffness_order"] == pytest.approx(4.0)
    assert "1 of 1 observed orders outside [0.5, 4] and clipped to it (0 to 0.5, 1 to 4)" in row[
        "fe_stiffness_order_note"]
    assert "order 4.00: 1 of 1 observed orders outside" in sleeve_check.notes({"types": [row]})[0]


def test_secant_refuses_a_curve_that_stops_short_of_its_rise():
    """A traced curve that stops before d/L ``SECANT_AT`` (a partial ccx run) has no secant there: ``np.interp``
    would hold its last force and report a stiffness the ring does not have. The error names the rise reached."""
    at = sleeve_check.SECANT_AT
    assert sleeve_check.secant([0.0, at, 2 * at], [0.0, 3.0 * at, 5.0 * at]) == pytest.approx(3.0)
    with pytest.raises(ValueError, match=r"the curve reaches d/L 0.0025; the secant needs it to reach 0.005"):
        sleeve_check.secant([0.0, 0.5 * at], [0.0, 1.0])
