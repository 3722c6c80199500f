"""FreeCAD GUI layer: the only package that imports FreeCADGui / Qt."""
