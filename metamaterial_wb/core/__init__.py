"""Pure core: scene model, solver, kinematics. Never imports FreeCAD."""
