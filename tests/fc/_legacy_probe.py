"""Child process of test_fc_legacy_document.py: open a document saved before the split of objects/structure.py
*before* the package is imported (FreeCAD then imports ``metamaterial_wb.objects.structure`` itself, or on
0.20.2 blocks that and leaves the proxies None until the package's guard re-attaches them from ``ProxyClass``),
then import the package, recompute, and write what happened to a JSON file.

    MM_PROBE='[REPO, FCSTD, OUT_JSON]' python3 _legacy_probe.py     (or freecadcmd _legacy_probe.py)
"""
import json
import os
import sys


def main():
    repo, path, out = json.loads(os.environ["MM_PROBE"])
    sys.path.append("/usr/lib/freecad-python3/lib")
    import FreeCAD
    if sys.path[0] != repo:
        sys.path.insert(0, repo)
    doc = FreeCAD.openDocument(path)
    import metamaterial_wb.objects  # noqa: F401  (the guard repairs documents already open)
    from metamaterial_wb.objects.common import repair_report
    report = repair_report(doc) or {}
    file_name = doc.FileName     # a document the guard took for damaged is locked: its FileName is cleared
    for o in doc.Objects:
        o.touch()
    doc.recompute()
    res = {"proxies": {o.Name: (f"{type(o.Proxy).__module__}.{type(o.Proxy).__name__}"
                                if getattr(o, "Proxy", None) is not None else None)
                       for o in doc.Objects if "ProxyClass" in o.PropertiesList},
           "invalid": [o.Name for o in doc.Objects if not o.isValid()],
           "nodes": len(doc.getObject("Nodes").PlacementList), "locked": bool(report.get("locked")),
           "lost": report.get("lost", []), "file_name": file_name}
    FreeCAD.closeDocument(doc.Name)
    with open(out, "w") as f:
        json.dump(res, f)


if __name__ in ("__main__", "_legacy_probe"):   # freecadcmd runs a file under its own module name
    main()
