"""``bench fidelity`` on a subset (``--scenes`` / ``--amplitudes`` / ``--repeats 1``): the report describes
what ran, not the default run.

Before the fix a chain-only run at amplitude 0.05 still said "Two actuator amplitudes: 0.05 (...) and 0.5
(...)", left "## Targets and reading" without its targets (they need grid10 / grid30) and without a word on
why, and credited its single timing run as "best of up to 1 runs". The default run's text (docs/fidelity.md,
generated) must not change: the Reference paragraph and the trust table's introduction rendered from a
synthetic full run (every scene, both amplitudes, 3 repeats) are compared with the stored docs line by line.

Fast: the inputs are small JSON files written here, rendered with ``--from-json`` (no model runs).
"""
import json
import os

from metamaterial_wb.cli import main

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SCENES = ("chain", "grid10", "grid30", "bending", "mixed")


def _row(model, label, time_s, rms_d, **options):
    return {"model": model, "label": label, "options": options, "time_s": time_s, "converged": True,
            "rms_D": rms_d, "max_D": 3 * rms_d, "rms_pos": rms_d, "max_pos": 2 * rms_d, "rigid_rotation_deg": 1e-4,
            "worst5_share": 0.5, "max_turn_deg": 2.0, "reference_max_turn_deg": 2.0, "ref_rms_D": 2e-06,
            "ref_max_D": 6e-06, "ref_max_pos": 4e-06, "info": {}}


def _result(key, amp):
    return {"key": key, "title": f"{key} scene", "amplitude": amp, "n_nodes": 42, "n_joints": 61,
            "reference_time_s": 0.5, "reference_converged": True,
            "reference_info": {"newton_iterations": 14, "load_steps": 3, "method": "newton"},
            "rows": [_row("quadratic", "quadratic (R0)", 0.0128, 0.3 * amp),
                     _row("linear", "linear lattice (R1)", 0.00693, 0.02 * amp),
                     _row("linear_flat", "linear lattice at the flat sheet (R1, about=flat)", 0.004, 0.03 * amp,
                          about="flat"),
                     _row("nonlinear", "nonlinear (R2), tol 1e-8 (default)", 0.0255, 0.002 * amp)]}


def _render(tmp_path, scenes, amps, repeats):
    raw = {"format": "metamaterial-fidelity", "version": 1,
           "measured": {"date": "2001-02-03", "cores": 2, "python": "3.11.2", "arch": "x86_64",
                        "load_average": 1.0, "repeats": repeats,
                        "command": "python3 -m metamaterial_wb bench fidelity"},
           "results": [_result(k, a) for a in amps for k in scenes]}
    src = tmp_path / "run.json"
    src.write_text(json.dumps(raw), encoding="utf-8")
    out = tmp_path / "r.md"
    rc = main(["bench", "fidelity", "--quiet", "--from-json", str(src), "--out", str(out),
               "--img", str(tmp_path / "r.png")])
    assert rc == 0
    return out.read_text(encoding="utf-8")


def _line(text, start):
    (line,) = [ln for ln in text.splitlines() if ln.startswith(start)]
    return line


def _section(text, heading):
    return text.split(heading + "\n", 1)[1].split("\n## ", 1)[0]


def test_one_scene_one_amplitude_one_repeat_says_what_ran(tmp_path):
    text = _render(tmp_path, ("chain",), (0.05,), 1)
    ref = _line(text, "Reference: ")
    assert "Two actuator amplitudes" not in ref and "0.5 (" not in ref
    assert "One actuator amplitude: 0.05 (small, where the linearised lattice is accurate)." in ref
    assert "best of 1 run," in ref and "best of up to" not in ref and "1 runs" not in ref
    targets = _section(text, "## Targets and reading")
    # the targets' scenes were not run: said so, and how to run them; no target figures invented
    assert "grid10" in targets and "grid30" in targets and "not run" in targets and "--scenes" in targets
    assert "ms (met)" not in targets and "ms (not met)" not in targets
    # the trust table does not promise a mixed-scene column that was not run
    trust = _section(text, "## Where each model can be trusted (measured)")
    assert "is listed apart:" not in trust and "mixed, RMS dD" not in trust and "`mixed`" in trust
    assert "not run" in trust


def test_other_amplitude_and_several_repeats(tmp_path):
    text = _render(tmp_path, ("chain", "grid10"), (0.3, 0.5), 4)
    ref = _line(text, "Reference: ")
    assert "best of up to 4 runs," in ref
    assert "Two actuator amplitudes: 0.3 and 0.5 (working range, where plate contact and large hinge rotations " \
           "matter)." in ref and "0.05" not in ref
    targets = _section(text, "## Targets and reading")
    assert "* Linear model on 10 x 10 <= 5 ms:" in targets       # grid10's targets are there
    assert "grid30" in targets and "not run" in targets and "grid10" not in targets.split("grid30")[1]


def test_full_default_run_text_is_unchanged(tmp_path):
    """The sentences a full default run renders are those of the stored docs/fidelity.md, byte for byte."""
    text = _render(tmp_path, SCENES, (0.05, 0.5), 3)
    with open(os.path.join(REPO, "docs", "fidelity.md"), encoding="utf-8") as f:
        docs = f.read()
    assert _line(text, "Reference: ") == _line(docs, "Reference: ")
    assert _line(text, "Worst case over the standard scenes") == _line(docs, "Worst case over the standard scenes")
    assert _line(text, "| model | RMS dD / amplitude") == _line(docs, "| model | RMS dD / amplitude")
    targets = _section(text, "## Targets and reading")
    assert "not run" not in targets
    heads = [ln.split(":")[0] for ln in targets.splitlines() if ln.startswith("* ")]
    assert heads == [ln.split(":")[0] for ln in _section(docs, "## Targets and reading").splitlines()
                     if ln.startswith("* ")]
