"""Child process of the Sleeve panel's export: ``python -m metamaterial_wb.gui.sleeve_export_job JOB.json``.

JOB.json: ``{"spec": {...sleeve spec...}, "out_dir": DIR}``. The sleeve's B-rep is built, checked and
written as ``sleeve.step`` and meshed into ``sleeve.3mf`` here (OpenCASCADE holds the GIL, so a thread in
FreeCAD would still freeze the GUI); progress lines go to stderr, the last stdout line is
``{"files": [...], "seconds": s}``. A problem prints ``error: MESSAGE`` on stderr and exits with status 2.
No Qt, no FreeCAD document.
"""
import json
import sys
import time


def main(argv):
    t0 = time.perf_counter()
    with open(argv[0], encoding="utf-8") as f:
        job = json.load(f)
    from metamaterial_wb.core.errors import MetamaterialError
    from metamaterial_wb.core.sleeve.spec import SleeveSpec
    from metamaterial_wb.export.sleeve import export_sleeve
    try:
        spec = SleeveSpec(job["spec"], "panel")
        print(f"building the sleeve ({spec.M} x {spec.N} cells), writing STEP and 3MF ...", file=sys.stderr,
              flush=True)
        files = export_sleeve(spec, job["out_dir"], step=job.get("step", True), threemf=job.get("threemf", True))
    except (MetamaterialError, OSError, ValueError) as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    print(json.dumps({"files": files, "seconds": time.perf_counter() - t0}))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
