"""The printing materials the workbench knows and their display colours: the one table that STEP
colours, 3MF base materials, pictures and the 3D view all read, and the one hex -> RGB conversion."""
from metamaterial_wb.core.errors import MetamaterialError

MATERIALS = {
    # name: display colour (sRGB hex) used in STEP colours, 3MF basematerials, pictures and the 3D view
    "PLA": "#D9D9D9",
    "ABS": "#F2C94C",
    "PETG": "#9AD0C2",
    "TPU": "#1E64FF",
}


def hex_to_rgb(colour):
    """``"#RRGGBB"`` (or ``"#RRGGBBAA"``, alpha ignored) -> ``(r, g, b)`` floats in [0, 1].

    Parameters
    ----------
    colour : str

    Returns
    -------
    tuple of float

    Raises
    ------
    MetamaterialError
        When ``colour`` is not a ``#`` followed by 6 or 8 hex digits.
    """
    c = colour.strip() if isinstance(colour, str) else colour
    try:
        if not isinstance(c, str) or not c.startswith("#") or len(c) not in (7, 9):
            raise ValueError
        return tuple(int(c[k:k + 2], 16) / 255.0 for k in (1, 3, 5))
    except ValueError:
        raise MetamaterialError(f"colour {colour!r} is not #RRGGBB or #RRGGBBAA") from None


def material_rgb(name, default="#888888"):
    """Display colour of material ``name`` (case-insensitive) as RGB floats; ``default`` when unknown.

    Parameters
    ----------
    name : str
    default : str

    Returns
    -------
    tuple of float
    """
    return hex_to_rgb(MATERIALS.get(str(name).upper(), default))
