"""Child process of the Export panel: ``python -m metamaterial_wb.gui.export_job JOB.json``.

JOB.json: ``{"scene": {...scene dict...}, "out_dir": DIR, "step": bool, "threemf": bool, "modules": bool,
"sockets": bool, "overrides": {...}, "stem": NAME}``; ``overrides`` are the fabrication parameters the workbench
preferences supply (``exporting.preference_overrides``: a clearance there is named as the preference in the snap pins'
errors, ``exporting.export_scene``). Progress lines go to stderr; the last stdout line
is ``{"files": [...], "warnings": [...], "seconds": s}``. A problem prints ``error: MESSAGE`` on stderr
and exits with status 2 (nothing written). No Qt, no FreeCAD document.
"""
import json
import sys
import time


def main(argv):
    t0 = time.perf_counter()
    with open(argv[0], encoding="utf-8") as f:
        job = json.load(f)
    from metamaterial_wb.core.errors import MetamaterialError
    from metamaterial_wb.core.scene import Scene
    from metamaterial_wb.gui.exporting import export_scene
    warnings = []
    try:
        scene = Scene.from_dict(job["scene"])
        files = export_scene(scene, job["out_dir"], step=job.get("step", True), threemf=job.get("threemf", True),
                             modules=job.get("modules", True), sockets=job.get("sockets", True),
                             overrides=job.get("overrides"), stem=job.get("stem"), warnings=warnings, progress=True)
    except (MetamaterialError, OSError, ValueError) as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    print(json.dumps({"files": files, "warnings": warnings, "seconds": time.perf_counter() - t0}))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
