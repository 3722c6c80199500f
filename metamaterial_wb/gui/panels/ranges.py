"""Spin-box ranges read from the validators (one owner per quantity): no panel re-types a range.

``bind(spin, field)`` gives a spin box the range the validator allows for ``field`` (a key of
:data:`FIELDS`) and tags it, so ``tests/gui/test_gui_ranges.py`` can walk every panel's spin boxes and
compare them with the validators. A bound that depends on other values (a hinge length below half the
cell, a cell type's t below a quarter of L) is given its widest value here and checked in words by the
validator when the panel applies. Spin boxes that edit no validated quantity (playback speed, the
number of servos a fit searches) are tagged with ``ui_only(spin, reason)``.
"""
from metamaterial_wb.core import motion
from metamaterial_wb.core.scene import sections
from metamaterial_wb.core.sleeve import spec as sleeve_spec

KEYFRAME_T_MAX_S = 1e6       # the validator has no upper bound on a keyframe time; a spin box needs one


def _sleeve_fields():
    out = {k: (lo, hi, lo_open) for k, (lo, hi, _unit, lo_open) in sleeve_spec.RANGES.items()}
    l_max = sleeve_spec.RANGES["L_mm"][1]
    for k, (lo, ratio, lo_open) in sleeve_spec.CELL_TYPE_RANGES.items():
        out["cell_types." + k] = (lo, ratio * l_max, lo_open)
    out["rings"] = (sleeve_spec.RINGS_RANGE[0], sleeve_spec.RINGS_RANGE[1], False)
    return out


def fields():
    """``{field: (low, high, low_open)}`` from the validators' own constants."""
    cell_max = sections.CELL_SIZE_RANGE[1]
    out = {
        "cell_size_mm": (sections.CELL_SIZE_RANGE[0], cell_max, False),
        "axes.fold_deg": (sections.FOLD_RANGE[0], sections.FOLD_RANGE[1], False),
        "value": (sections.VALUE_RANGE[0], sections.VALUE_RANGE[1], False),
        "hinge.length_mm": (0.0, 0.5 * cell_max, True),
        "hinge.width_mm": (0.0, 0.25 * cell_max, True),
        "hinge.thickness_mm": (0.0, sections.THICKNESS_MAX_MM, True),
        "profile.times_s": (0.0, KEYFRAME_T_MAX_S, False),
        "profile.values": (sections.VALUE_RANGE[0], sections.VALUE_RANGE[1], False),
    }
    out.update({"profile." + k: (lo, hi, False) for k, (lo, hi) in motion.PROFILE_RANGES.items()})
    out.update({"sleeve." + k: v for k, v in _sleeve_fields().items()})
    return out


FIELDS = fields()


def spin_range(spin, field):
    """The ``(minimum, maximum)`` a spin box must have for ``field`` (an open low bound becomes the
    smallest positive step the box can show)."""
    lo, hi, low_open = FIELDS[field]
    if low_open:
        lo = lo + (10.0 ** -spin.decimals() if hasattr(spin, "decimals") else 1)
    return lo, hi


def bind(spin, field):
    lo, hi = spin_range(spin, field)
    spin.setRange(lo, hi)
    spin.setProperty("validator_field", field)
    return spin


def ui_only(spin, reason):
    spin.setProperty("ui_only", reason)
    return spin
