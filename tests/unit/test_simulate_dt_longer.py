"""``simulate --dt 0.5 --seconds 0.1`` ran one step of 0.1 s without a word (summary dt_s 0.1; session 35 audit):
the integrator shortens a step longer than the run to the run. ``--dt`` is the step the run takes (the explicit
integrator may only reduce it to its stability guard, and says so), so a ``--dt`` longer than ``--seconds`` on
the same command line is refused naming both, nothing written. A step the user did not type on the command line
(the scene's ``dynamics.integrator.dt_s``, or the automatic one) that is longer than the run is still shortened
to one step of the run, and a note on stderr says so. belt8 (dt_s 2 ms), implicit, a millisecond: fast."""
import json
import os

from clihelpers import REPO, one_line_error, run_cli

BELT = os.path.join(REPO, "examples", "belt8.json")


def test_a_dt_longer_than_seconds_is_refused(tmp_path):
    out = tmp_path / "o"
    r = run_cli("simulate", BELT, "--dt", "0.5", "--seconds", "0.1", "--out", out, "--no-dt-check")
    one_line_error(r, "--dt")
    assert "0.5 s" in r.stderr and "--seconds 0.1" in r.stderr
    assert not out.exists()


def test_a_dt_equal_to_seconds_runs_one_step_without_a_note(tmp_path):
    out = tmp_path / "o"
    r = run_cli("simulate", BELT, "--dt", "0.001", "--seconds", "0.001", "--method", "implicit", "--out", out,
                "--no-dt-check")
    assert r.returncode == 0, r.stderr
    s = json.loads((out / "summary.json").read_text(encoding="utf-8"))
    assert s["integrator"]["dt_s"] == 0.001 and s["integrator"]["steps"] == 1
    assert "longer than the run" not in r.stderr


def test_the_scenes_step_longer_than_the_run_is_said(tmp_path):
    out = tmp_path / "o"
    r = run_cli("simulate", BELT, "--seconds", "0.001", "--method", "implicit", "--out", out, "--no-dt-check")
    assert r.returncode == 0, r.stderr
    s = json.loads((out / "summary.json").read_text(encoding="utf-8"))
    assert s["integrator"]["dt_s"] == 0.001
    notes = [ln for ln in r.stderr.splitlines() if ln.startswith("note: ") and "longer than the run" in ln]
    assert len(notes) == 1 and "0.002 s" in notes[0] and "0.001 s" in notes[0], r.stderr
