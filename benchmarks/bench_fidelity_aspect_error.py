"""The FE mesh error of docs/fidelity.md's "Beam law against FE by hinge aspect ratio" table (issue 18).

    /usr/bin/python3 benchmarks/bench_fidelity_aspect_error.py [--h 0.4] [--fe-json benchmarks/results/fe-study.json]

The table came from one mesh (h = 0.283 mm) per hinge length. This script runs each length on a second mesh
(``--h``, default 0.4 mm, the hinge study's coarsest) with CalculiX, stores it in the aspect rows of the FE
study JSON (``meshes``), and rewrites the table in docs/fidelity.md from
:func:`metamaterial_wb.bench.fe_study.aspect_markdown`: every ratio then carries the correction Richardson
extrapolation makes to the finest mesh. ``bench fidelity --fe`` runs both meshes itself; this script adds
the missing one to an existing study without re-running the rest. Needs ``ccx``.
"""
import argparse
import json
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, ROOT)

from metamaterial_wb.bench import fe_study  # noqa: E402
from metamaterial_wb.fe import ccx, hinge  # noqa: E402

HEADING = "### Beam law against FE by hinge aspect ratio"


def splice(doc_text, section):
    """``doc_text`` with the aspect section (from its heading to the next heading) replaced by ``section``."""
    i = doc_text.index(HEADING)
    j = doc_text.find("\n#", i + len(HEADING))
    j = len(doc_text) if j < 0 else j + 1
    return doc_text[:i] + section.rstrip("\n") + "\n\n\n" + doc_text[j:]


def add_mesh(rows, h, timeout_s=1800.0, progress=print):
    """Run mesh ``h`` for every row that lacks it (the row's own top-level figures count as its first mesh)."""
    for r in rows:
        meshes = r.setdefault("meshes", [{"h_mm": r["h_mm"], "wall_s": r["wall_s"], "fe_diag": r["fe_diag"],
                                          "fe_bending": r["fe_bending"]}])
        if any(abs(m["h_mm"] - h) < 1e-9 for m in meshes):
            continue
        m = fe_study.aspect_mesh_row(hinge.HingeSpec(length=r["length_mm"]), h, timeout_s)
        progress(f"L = {r['length_mm']:g} mm, h = {h:g} mm: {m['wall_s']:.1f} s")
        meshes.append(m)
        meshes.sort(key=lambda x: -x["h_mm"])
    for r in rows:                      # the row's top-level figures are the finest mesh's (as run_aspect_study)
        fine = r["meshes"][-1]
        r.update({"h_mm": fine["h_mm"], "wall_s": fine["wall_s"], "fe_diag": fine["fe_diag"],
                  "fe_bending": fine["fe_bending"]})
    return rows


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--h", type=float, default=0.4, help="the added mesh size (mm)")
    ap.add_argument("--fe-json", default=os.path.join(ROOT, "benchmarks", "results", "fe-study.json"))
    ap.add_argument("--doc", default=os.path.join(ROOT, "docs", "fidelity.md"))
    a = ap.parse_args(argv)
    ok, why = ccx.available()
    if not ok:
        sys.exit(f"CalculiX not available: {why}")
    with open(a.fe_json) as f:
        study = json.load(f)
    add_mesh(study["aspect"], a.h)
    with open(a.fe_json + ".tmp", "w") as f:
        json.dump(study, f, indent=1)
    os.replace(a.fe_json + ".tmp", a.fe_json)
    section = fe_study.aspect_markdown(study["aspect"])
    with open(a.doc) as f:
        text = f.read()
    with open(a.doc + ".tmp", "w") as f:
        f.write(splice(text, section))
    os.replace(a.doc + ".tmp", a.doc)
    print(section)


if __name__ == "__main__":
    main()
