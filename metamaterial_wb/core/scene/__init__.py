"""The scene: plain data that describes one metamaterial design (JSON round trip).

Naming follows the seed paper (000, section 3.2):

* cell ``(i, j)``: i = row (grows downwards), j = column. Its four corners are rigid nodes, its four
  edges are hinges (joints). ``R x C`` cells have ``(R+1) x (C+1)`` nodes.
* node ``N(i,j)`` is the top-left corner of cell ``(i, j)``.
* joint ``H(i,j)`` joins ``N(i,j)``-``N(i,j+1)`` (horizontal edge); ``V(i,j)`` joins
  ``N(i,j)``-``N(i+1,j)`` (vertical edge). Written as strings ``"H1,2"`` and ``"V0,3"``.

The format is documented in ``docs/scene-format.md``. Unknown top-level keys are kept (other tools
may add their own) and written back unchanged.

The package: ``names`` (constants, joint and node names), ``topology`` (nodes and joints of a layout),
``layout`` (layout section, size budget, the seed's layout rules), ``items`` (actuators, constraints,
axes), ``sections`` (one parser per scene section), ``model`` (the :class:`Scene`).
"""
from metamaterial_wb.core.scene.items import Actuator, Axis, Constraint  # noqa: F401
from metamaterial_wb.core.scene.layout import (MAX_BOX, MAX_CELLS, MAX_INDEX, cells_from_layout,  # noqa: F401
                                               validate_layout)
from metamaterial_wb.core.scene.model import Scene  # noqa: F401
from metamaterial_wb.core.scene.names import (DEFAULT_CELL_SIZE_MM, DEFAULT_HINGE, FORMAT,  # noqa: F401
                                              JOINT_OVERRIDE_KEYS, KNOWN_KEYS, VERSION, joint_name, joint_nodes,
                                              node_name, parse_joint)
from metamaterial_wb.core.scene.sections import K2_RANGE, check_hinge_sizes  # noqa: F401
from metamaterial_wb.core.scene.topology import Topology  # noqa: F401
