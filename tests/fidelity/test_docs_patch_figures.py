"""The 3 x 3 patch figures the README and docs/fidelity-models.md quote come from the stored CalculiX study
(benchmarks/results/fe-study.json, the same file docs/fidelity.md is rendered from): a regenerated study whose
numbers moved leaves this test failing until the prose follows (the README kept 1.6 % / 8.5 % after the study's
mesh error bars were redone and gave 2.1 % / 8.2 %)."""
import json
import os
import re

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def _read(rel):
    with open(os.path.join(ROOT, rel), encoding="utf-8") as fh:
        return fh.read()


def _patch(amplitude):
    study = json.loads(_read("benchmarks/results/fe-study.json"))
    (case,) = [c for c in study["patch"] if abs(c["amplitude"] - amplitude) < 1e-12]
    models = {m["label"]: m["rms_D"] for m in case["models"]}
    return case, models


def _flat(text):
    return re.sub(r"\s+", " ", text)


def test_the_readme_quotes_the_stored_patch_study():
    case, models = _patch(0.05)
    amp = case["amplitude"]
    text = _flat(_read("README.md"))
    m = re.search(r"at amplitude 0\.05 the nonlinear lattice is within ([\d.]+) % of the amplitude, the linear one "
                  r"([\d.]+) %, the quadratic model ([\d.]+) x \(FE uncertainty ([\d.]+) %\)", text)
    assert m, "the README's CalculiX patch sentence is gone or reworded"
    nonlinear, linear, quadratic, unc = map(float, m.groups())
    assert nonlinear == round(100 * models["nonlinear (R2), 1 element/hinge, no contact"] / amp, 1)
    assert linear == round(100 * models["linear lattice (R1), no contact"] / amp, 1)
    assert quadratic == round(models["quadratic (R0)"] / amp, 1)
    assert unc == round(100 * case["fe_uncertainty"]["rms_D"] / amp, 1)


def test_the_model_guide_quotes_the_stored_patch_study():
    text = _flat(_read("docs/fidelity-models.md"))
    small, models = _patch(0.05)
    m = re.search(r"uncertainty ([\d.e-]+) RMS dD at amplitude 0\.05\): at 0\.05 the nonlinear lattice is "
                  r"([\d.]+)-([\d.e-]+) RMS dD \(([\d.]+)-([\d.]+) % of the amplitude\).*?the linear lattice "
                  r"([\d.e-]+) \(([\d.]+) %\), the quadratic model ([\d.]+) ", text)
    assert m, "docs/fidelity-models.md's 3 x 3 patch paragraph is gone or reworded"
    unc, lo, hi, plo, phi, lin, plin, quad = (float(g) for g in m.groups())
    nl = [v for k, v in models.items() if k.startswith("nonlinear (R2),") and "elements/hinge" in k
          or k == "nonlinear (R2), 1 element/hinge, no contact"]
    assert unc == float(f"{small['fe_uncertainty']['rms_D']:.1e}")
    assert lo == round(min(nl) * 1e3, 1) and hi == float(f"{max(nl):.2e}")
    assert (plo, phi) == (round(100 * min(nl) / 0.05, 1), round(100 * max(nl) / 0.05, 1))
    assert lin == float(f"{models['linear lattice (R1), no contact']:.1e}")
    assert plin == round(100 * models["linear lattice (R1), no contact"] / 0.05, 1)
    assert quad == round(models["quadratic (R0)"], 2)
    large, models5 = _patch(0.5)
    m = re.search(r"uncertainty ([\d.e-]+)\): the nonlinear lattice ([\d.]+) with one element per hinge and "
                  r"([\d.]+)-([\d.]+) with 2-8", text)
    assert m, "the amplitude 0.5 sentence is gone or reworded"
    unc5, one, lo5, hi5 = (float(g) for g in m.groups())
    assert unc5 == float(f"{large['fe_uncertainty']['rms_D']:.1e}")
    assert one == round(models5["nonlinear (R2), 1 element/hinge, no contact"], 3)
    more = [models5[f"nonlinear (R2), {n} elements/hinge, no contact"] for n in (2, 4, 8)]
    assert (lo5, hi5) == (round(min(more), 3), round(max(more), 3))
