"""Solid finite elements with CalculiX (``ccx``): the top rung of the fidelity ladder (issue 18).

Imports only ``core``. Decks are written in the Abaqus input format CalculiX reads, run by
:func:`metamaterial_wb.fe.ccx.run` as a subprocess with a time limit, and read back from ``.dat``.

* :mod:`.mesh`: structured 20-node brick meshes (C3D20R) of unions of boxes (plates and hinges);
* :mod:`.ccx`: the solver runner and the ``.dat`` parser; ``available()`` says whether ccx is installed,
  ``table()`` reads one printed table or raises ``FEError`` naming the job and the table;
* :mod:`.checks`: the entry points' input checks (``"<field>: <value>; allowed: ..."``);
* :mod:`.patch`: a small patch of rigid plates and solid hinges with actuated joints;
* :mod:`.hinge`: one TPU hinge between two PLA plates: its 6 x 6 stiffness and its large-rotation
  moment-rotation curve, against the lattice's beam law.
* :mod:`.sleeve2d`: the sleeve's unit cell and an N-cell ring in 2-D plane strain (CPE8R on our own mapped
  mesh of the printed outline), force-displacement curves against ``core.sleeve``'s beam model.
* :mod:`.sleeve3d`: the N-cell ring as a curved 3-D solid (that mesh wrapped onto the cylinder, C3D20R bricks
  through the wall, rigid tilting top plate): the curvature the flat ring cannot have.
"""
from metamaterial_wb.fe.ccx import FEError, available  # noqa: F401
