"""Child process of test_module_recompute.py: one module document object on an example structure.

    MM_PROBE='[REPO, EXAMPLE, TYPE, TARGET, DATA_JSON, OUT_JSON]' python3 _module_probe.py

Makes the example's structure, adds one module of TYPE at TARGET, recomputes, and writes to OUT_JSON
whether every object is valid, the module's state, its volume and where its shape came from. Run in a
child process because a crash inside OpenCASCADE kills the whole interpreter (FreeCAD with it).
Arguments come in the environment so that ``freecadcmd _module_probe.py`` runs it the same way.
"""
import json
import os
import sys


def main():
    repo, example, mtype, target, data, out = json.loads(os.environ["MM_PROBE"])
    sys.path.append("/usr/lib/freecad-python3/lib")
    import FreeCAD  # noqa: F401
    if sys.path[0] != repo:
        sys.path.insert(0, repo)
    import metamaterial_wb
    from metamaterial_wb.core.scene import Scene
    from metamaterial_wb.objects import structure

    doc = FreeCAD.newDocument("Probe")
    sc = structure.make_structure(doc, Scene.load(metamaterial_wb.example_path(example)))
    m = structure.make_module(doc, sc, mtype, target, json.loads(data) or None)
    doc.recompute()
    res = {"valid": all(o.isValid() for o in doc.Objects), "module_state": list(m.State),
           "invalid": [o.Name for o in doc.Objects if not o.isValid()],
           "volume": m.Shape.Volume if not m.Shape.isNull() else 0.0, "source": m.GeometrySource}
    FreeCAD.closeDocument(doc.Name)
    with open(out, "w") as f:
        json.dump(res, f)


if __name__ in ("__main__", "_module_probe"):   # freecadcmd runs a file under its own module name
    main()
