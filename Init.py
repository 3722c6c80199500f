# FreeCAD exec()s this file at start-up (no __file__): keep it tiny.
import FreeCAD
FreeCAD.__unit_test__ += ["TestMetamaterialApp"]
try:  # the document guard (issue 19): files opened headless without the package keep their objects
    from metamaterial_wb.objects import docguard as _mm_docguard
    _mm_docguard.install()
except Exception as _mm_exc:  # noqa: BLE001 - never break FreeCAD's start-up
    FreeCAD.Console.PrintError(f"Metamaterial: document guard not installed: {_mm_exc}\n")
