"""Snap-fit pins designed from the cantilever formula (no FreeCAD import).

Every module plugs into a node socket with a split pin: two half-round prongs separated by a slot,
a barb at the tip that must pass the socket's hole and latches under its bottom ledge. Inserting it
bends each prong inward by the barb's interference ``y`` like a cantilever clamped where the slot
ends (the module's underside) and loaded at the barb. For a constant section the peak strain is

    strain = 1.5 * t * y / L**2        (t: prong thickness in the bending direction, L: free length)

(the standard beam formula of snap-fit design guides: ``y = 2 eps L^2 / (3 t)``). The design takes
the longest prong the sheet allows (``L = T - barb top``), the interference the socket sets
(``y = socket_lip_mm - clearance_mm``) and the thickest prong whose strain stays within the module
material's allowable strain, so that the slot closes by ``2 y`` without the prongs touching. It
refuses (SceneError naming the material, the strain and what to change) when no prong of at least two
nozzle widths fits.

Allowable strains (design values for repeated assembly of FDM parts, a little under the 1.5-2.5 %
that data sheets give for moulded parts in the same polymers; edit ``ALLOWABLE_STRAIN`` or give a
module another "material" if your filament differs).
"""
from dataclasses import asdict, dataclass

from metamaterial_wb.core.errors import SceneError

ALLOWABLE_STRAIN = {"PLA": 0.015, "ABS": 0.02, "PETG": 0.025, "TPU": 0.10}
SLOT_MARGIN_MM = 0.1          # the prongs stay this far apart when the barb passes the hole


@dataclass(frozen=True)
class SnapFit:
    material: str
    thickness_mm: float       # t: prong thickness across the slot (the bending direction)
    deflection_mm: float      # y: barb interference each prong bends by
    length_mm: float          # L: free prong length (barb to the slot's end)
    slot_mm: float            # slot width between the prongs
    slot_top_mm: float        # z of the slot's end above the pin tip's side of the sheet (module frame)
    strain: float             # 1.5 t y / L^2
    limit: float              # allowable strain of the material
    bending: str = "across the layers (pins printed upright)"

    def key(self):
        return (round(self.thickness_mm, 6), round(self.slot_mm, 6), round(self.slot_top_mm, 6))

    def as_dict(self):
        return asdict(self)


def cantilever_strain(t, y, L):
    """Peak bending strain of a constant-section cantilever of thickness t deflected by y at length L."""
    return 1.5 * t * y / (L * L)


def clearance_origin(p):
    """The setting the clearance of ``p`` was chosen in, as its maker names it (``p.clearance_origin``: the
    workbench's modules set it to the preference as its page shows it, ``objects.module``), or None: the scene's
    ``fabrication.clearance_mm`` or the command line's ``--clearance``, which the messages do not name."""
    return getattr(p, "clearance_origin", None)


def no_latch_error(p):
    """The SceneError of a clearance at or above the socket lip of ``p`` (the barb has no interference): naming the
    clearance's origin (:func:`clearance_origin`) with its value, the lip and the allowed range, else the lip."""
    clr, lip, origin = p.clearance_mm, p.socket_lip_mm, clearance_origin(p)
    if origin:
        return SceneError(origin, f"{clr:g} mm is not below the {lip:g} mm socket lip (fabrication.socket_lip_mm): "
                                  f"the snap pins' barbs would have nothing to latch on; allowed range [0, {lip:g}) "
                                  f"mm; set it there")
    return SceneError("fabrication.socket_lip_mm", f"{lip} mm with a clearance of {clr} mm leaves the barb no "
                                                   f"interference to latch; allowed range ({clr}, ...) mm")


def design_snap_fit(p, material, field_name="modules"):
    """The :class:`SnapFit` of a module pin in ``material`` for the fabrication parameters ``p``."""
    mat = material.upper()
    if mat not in ALLOWABLE_STRAIN:
        raise SceneError(field_name, f"no allowable strain known for {material!r}; known: {sorted(ALLOWABLE_STRAIN)}")
    limit = ALLOWABLE_STRAIN[mat]
    T = p.sheet_thickness_mm
    clr = p.clearance_mm
    origin = clearance_origin(p)
    r = p.socket_radius_mm - clr                 # prong pair's outer radius
    y = p.socket_lip_mm - clr                    # barb radius (counterbore - clearance) minus the hole radius
    z_barb = p.socket_lip_height_mm - clr        # the barb's widest section (its latch face)
    L = T - z_barb                               # clamped at the module's underside (z = T)
    if y <= 0:
        raise no_latch_error(p)
    if L <= 0:
        raise SceneError("fabrication.socket_lip_height_mm", f"the barb at {z_barb:.3g} mm leaves no prong in a "
                                                             f"{T} mm sheet")
    t_strain = limit * L * L / (1.5 * y)
    half_slot = max(y + 0.5 * SLOT_MARGIN_MM, 0.5 * max(0.6, 1.5 * p.nozzle_mm))
    t_slot = r - half_slot
    t = min(t_strain, t_slot)
    if t < p.min_wall_mm - 1e-9:
        t_need = p.min_wall_mm
        if t_strain >= t_need - 1e-9:        # the strain allows the prong: the pin is too thin for its slot
            # the barb sets the slot (a smaller lip narrows it), else the narrowest slot a nozzle cuts does (the
            # lip does not matter then; a smaller clearance widens the pin)
            barb_sets = half_slot > 0.5 * max(0.6, 1.5 * p.nozzle_mm)
            smaller = "fabrication.socket_lip_mm" if barb_sets else (
                f"{origin} (now {clr:g} mm; allowed range [0, {p.socket_lip_mm:g}) mm, below the "
                f"{p.socket_lip_mm:g} mm socket lip fabrication.socket_lip_mm)" if origin else "clearance")
            of = f" of {origin}" if origin and barb_sets else ""
            raise SceneError("fabrication.socket_diameter_mm",
                             f"{p.socket_diameter_mm} mm: the {2 * r:.3g} mm pin (after the {clr} mm clearance{of}) "
                             f"has no room for its {2 * (r - t_need):.3g} mm slot between two prongs of two nozzle "
                             f"widths ({t_need:.3g} mm) and the barb's {y:.3g} mm; use a larger socket_diameter_mm or "
                             f"a smaller {smaller}")
        L_need = (1.5 * t_need * y / limit) ** 0.5
        softer = [k for k, v in ALLOWABLE_STRAIN.items() if v > limit and k != "TPU"]
        raise SceneError(f"{field_name}.material",
                         f"no snap pin fits {mat} (allowable strain {100 * limit:.3g} %): a prong of two nozzle widths "
                         f"({t_need:.3g} mm) bent by the barb's {y:.3g} mm over the {L:.3g} mm the sheet allows is "
                         f"strained {100 * cantilever_strain(t_need, y, L):.3g} %"
                         + (f" and the {2 * r:.3g} mm pin leaves no room for the slot" if t_slot < t_need else "")
                         + "; use " + (f"a more flexible material ({', '.join(softer)}), " if softer else "")
                         + f"a thicker sheet (prong length at least {L_need:.3g} mm), a smaller "
                           f"fabrication.socket_lip_mm or a larger socket_diameter_mm"
                         + (f" (the barb's {y:.3g} mm is the {p.socket_lip_mm:g} mm socket lip less the {clr:g} mm "
                            f"clearance of {origin}, allowed range [0, {p.socket_lip_mm:g}) mm: a larger clearance "
                            f"bends the prongs less)" if origin else ""))
    slot = 2.0 * (r - t)
    return SnapFit(mat, t, y, L, slot, T, cantilever_strain(t, y, L), limit)
