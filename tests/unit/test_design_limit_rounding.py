"""Every limit `design` prints can be typed back: the maximum fold of the report ("max +-X deg"), the allowed range
of a refusal ("allowed range [-X, X] deg") and the printable fold of the report and its warning ("printable
fold <= X deg") are rounded inwards to the digits printed, so the printed value is accepted and the refused value
lies outside the printed range (an audit: `--fold tail=97.63` on the fish was refused with "allowed range
[-97.63, 97.63] deg", the true maximum being 2 atan(8/7) = 97.628 deg; the report printed "max +-97.63 deg").
Checked on every bundled example with axes, in both directions."""
import glob
import json
import os
import re

import pytest

from metamaterial_wb import EXAMPLES_DIR
from metamaterial_wb.cli import main
from metamaterial_wb.core import design
from metamaterial_wb.core.scene import Scene

NUM = r"(-?\d+(?:\.\d+)?)"


def _examples():
    out = []
    for path in sorted(glob.glob(os.path.join(EXAMPLES_DIR, "*.json"))):
        with open(path, encoding="utf-8") as f:
            d = json.load(f)
        if isinstance(d, dict) and d.get("format") == "metamaterial-scene" and d.get("axes"):
            out.append(os.path.basename(path))
    return out


EXAMPLES = _examples()


def run(capsys, tmp_path, src, *folds):
    argv = ["design", src, "--out", str(tmp_path / "o.json")]
    for k, v in folds:
        argv += ["--fold", f"{k}={v}"]
    rc = main(argv)
    cap = capsys.readouterr()
    return rc, cap.out, cap.err


def report_limits(out, n):
    """Per axis (scene order) the printed ``(max, printable)`` of the report lines."""
    rows = re.findall(rf"^axis .*? fold .*?\(max \+-{NUM} deg, .*?; printable \+-{NUM} deg\)", out, re.M)
    assert len(rows) == n, out
    return [(float(a), float(b)) for a, b in rows]


def printable_warnings(text):
    """``{axis name: (needed tilt, printable tilt, printable fold)}`` of the printability warnings."""
    pat = (rf"warning: axis (.+?): fold \S+ deg needs hinge tilts up to {NUM} deg, but a \S+ mm wide hinge fits "
           rf"its node plate only up to {NUM} deg \(printable fold <= {NUM} deg\)")
    return {m[0]: (float(m[1]), float(m[2]), float(m[3])) for m in re.findall(pat, text)}


def scene_of(src):
    with open(src, encoding="utf-8") as f:
        return Scene.from_dict(json.load(f))


def names(scene):
    return [p.label_name for p in design.plan_axes(scene)]


def check_refusals(capsys, tmp_path, src, k, true_max, shown_max):
    """A fold just beyond the maximum is refused with a range that excludes it, and both ends typed back load."""
    beyond = {round(shown_max + 0.01, 2), float(f"{true_max:.2f}")}
    for v in sorted(x for x in beyond if x > true_max + 1e-9):
        for s in (v, -v):
            rc, _out, err = run(capsys, tmp_path, src, (k, s))
            assert rc == 2, (src, k, s, err)
            m = re.search(rf"allowed range \[{NUM}, {NUM}\] deg", err)
            assert m, err
            lo, hi = float(m[1]), float(m[2])
            assert not lo <= s <= hi, f"{s} refused but inside the printed range [{lo}, {hi}]: {err}"
            for back in (lo, hi):
                rc, _out, err2 = run(capsys, tmp_path, src, (k, back))
                assert rc == 0, f"the printed bound {back} of '{err.strip()}' typed back is refused: {err2}"


@pytest.mark.parametrize("name", EXAMPLES)
def test_printed_limits_type_back(name, tmp_path, capsys):
    src = os.path.join(EXAMPLES_DIR, name)
    scene = scene_of(src)
    axes = names(scene)
    true_max = design.max_folds_deg(scene)
    rc, out, err = run(capsys, tmp_path, src)
    assert rc == 0, err
    shown = report_limits(out, len(axes))
    for k, ((mx, pmx), tm) in enumerate(zip(shown, true_max)):
        assert mx <= tm + 1e-9, f"{name} axis {axes[k]}: report says max +-{mx} deg, the maximum is {tm!r}"
    # every printed maximum (and its negative) typed back is accepted, all axes at once
    for sign in (1, -1):
        rc, _out, err = run(capsys, tmp_path, src, *((k, sign * mx) for k, (mx, _p) in enumerate(shown)))
        assert rc == 0, f"{name}: the report's maxima typed back ({sign:+d}) are refused: {err}"
    # every printed printable fold typed back gives no printability warning
    for sign in (1, -1):
        rc, out2, err = run(capsys, tmp_path, src, *((k, sign * p) for k, (_m, p) in enumerate(shown)))
        assert rc == 0, err
        assert printable_warnings(out2 + err) == {}, f"{name}: the report's printable folds typed back warn"
    # just beyond the printable fold: the warning's numbers say so, and its bound typed back does not warn
    beyond = [(k, round(p + 0.01, 2)) for k, (_m, p) in enumerate(shown)]
    rc, out2, err = run(capsys, tmp_path, src, *beyond)
    assert rc == 0, err
    warned = printable_warnings(out2 + err)
    assert sorted(warned) == sorted(axes), out2 + err
    for k, v in beyond:
        need, fits, pf = warned[axes[k]]
        assert v > pf, f"{name} axis {axes[k]}: fold {v} warned with printable fold <= {pf}"
        assert need > fits, f"{name} axis {axes[k]}: needs tilts up to {need} deg but fits only up to {fits} deg"
    rc, out2, err = run(capsys, tmp_path, src, *((k, warned[axes[k]][2]) for k, _v in beyond))
    assert rc == 0, err
    assert printable_warnings(out2 + err) == {}, f"{name}: the warnings' printable folds typed back warn: {out2}"
    # refusals
    for k, ((mx, _p), tm) in enumerate(zip(shown, true_max)):
        check_refusals(capsys, tmp_path, src, k, tm, mx)


def test_printable_hard_limit_types_back(tmp_path, capsys):
    """With fabrication.limit_design_tilt the printable fold is the maximum: its refusal's range types back too."""
    with open(os.path.join(EXAMPLES_DIR, "fish_axes.json"), encoding="utf-8") as f:
        d = json.load(f)
    d.setdefault("fabrication", {})["limit_design_tilt"] = True
    src = tmp_path / "fish_limited.json"
    src.write_text(json.dumps(d), encoding="utf-8")
    scene = scene_of(str(src))
    true_max = design.max_folds_deg(scene)
    rc, out, err = run(capsys, tmp_path, str(src))
    assert rc == 0, err
    shown = report_limits(out, len(true_max))
    for k, ((mx, _p), tm) in enumerate(zip(shown, true_max)):
        assert "fabrication:" in design.axis_limits(scene, design.plan_axes(scene)[k])[1]
        rc, _o, err = run(capsys, tmp_path, str(src), (k, mx))
        assert rc == 0, err
        check_refusals(capsys, tmp_path, str(src), k, tm, mx)
