# FreeCAD exec()s this file at start-up (no __file__): keep it tiny.
import FreeCAD
FreeCAD.__unit_test__ += ["TestMetamaterialApp"]
