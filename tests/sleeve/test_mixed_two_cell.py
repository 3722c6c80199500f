"""Combination 2 as a mixed two-cell ring ([0, 1], the default seed) stopped with a bare "sleeve model: no equilibrium
found at d/L = 0.9418" (8 elements per half; 0.9432 on 6, 0.9408 on 12, 0.947 on 4: the stop converges with the mesh).
Not the solver: past d/L ~0.904 the ring leaves its symmetric state (the tangent's smallest eigenvalue 2.4e-6 there) and
cell 1's beam slides along its central pillar's tip, which leans 20 deg; the ring-curvature end spring on one side (the
soft axial link of ``add_row_single``, its stiffness ~R^2: soft on a ring of two cells) shortens from 72% of its length at
d/L 0.904 to 1.7% at 0.940, while the tangent stays positive definite (smallest eigenvalue 6.4e-5) but its largest
diagonal entry grows from 515 to 3.5e5 (the link's chord turning about a vanishing length), the residual's round-off
floor with it (47 tolerances). At zero length the link degenerates: the model has no equilibrium past it. The error now
says so and what to do (docs/sleeves.md, "A perfect ring")."""
import re

import numpy as np
import pytest

from metamaterial_wb.bench.fe_ring3d_combinations import combination_cells
from metamaterial_wb.core.errors import MetamaterialError
from metamaterial_wb.core.sleeve.model import SleeveModel, default_stroke


def test_the_mixed_two_cell_ring_says_why_its_path_ends():
    cells = combination_cells("2")
    # the smallest model that shows it: 4 elements per half, 40 steps to the default stroke (stops at d/L 0.947)
    m = SleeveModel(cells, [[0, 1]], 4, imperfection=1e-4)
    with pytest.raises(MetamaterialError) as err:
        m.trace(np.linspace(0.0, default_stroke(cells), 41))
    msg = str(err.value)
    assert msg.startswith("sleeve model: no equilibrium found at d/L = ")
    # which spring collapsed, how far, where, and what to do
    assert "end spring between cell 1's beam and its central pillar" in msg
    ratio = float(re.search(r"compressed to ([0-9.e+-]+) of its length", msg).group(1))
    assert 0.0 <= ratio < 0.1
    stop = float(re.search(r"at d/L = ([0-9.]+) \(the beam", msg).group(1))
    assert 0.9 < stop < default_stroke(cells)
    assert "model.ring_curvature false" in msg and "shorter stroke" in msg
