"""Transition re-export: the fabrication parameters moved to :mod:`metamaterial_wb.core.fabrication`
(pure, below the design stage). Import from there; this module goes once no branch imports it."""
from metamaterial_wb.core.design import effective_tilts_deg as _effective_tilts_deg
from metamaterial_wb.core.fabrication import *  # noqa: F401,F403
from metamaterial_wb.core.fabrication import (FAB_DEFAULTS, MATERIALS, MIN_WALL_MM, FabParams,  # noqa: F401
                                              HingeSpec, anchor_width_mm, joint_pivot, max_fabricable_tilt_deg,
                                              neck_width_mm, pin_slot_width_mm)
from metamaterial_wb.core.fabrication import fabrication_params as _fabrication_params


def fabrication_params(scene, **overrides):
    """:func:`core.fabrication.fabrication_params` with the design stage's effective tilts."""
    return _fabrication_params(scene, _effective_tilts_deg(scene), **overrides)
