"""Separate push-rivet snap pins that print lying down, so that the prongs bend along the layers.

A fused pin (geometry/solids.make_pin) prints standing up with its module: its prongs bend across the
layer lines, where FDM parts are weakest. The rivet is the same designed pin (geometry/snapfit.py:
shaft, barb, slot, prong thickness ``t``, interference ``y``, free length ``L``) made as a part of its
own: a shank that runs on through a hole of ``foot_mm`` in the module's foot and a head that traps the
foot from above. It prints on its side: the round section is cut by a flat at ``-FLAT_FRACTION * r``
(every surface below that would overhang by more than 45 deg; above it the round faces look up) and
the slot plane stands upright, so the two prongs lie side by side on the bed and bend in the bed
plane -- along the layers. The flat leaves the prongs' thickness across the slot (their bending
thickness) untouched, so the strain is the designed ``1.5 t y / L^2``.

Assembly frame (as placed in a socket): the axis is ``z``, the tip at ``z = clearance`` (the bed side
of the sheet), the sheet's top face at ``z = T``, the module foot from ``T`` to ``T + foot_mm``, the
head above it; the slot is the plane ``x = 0`` (the prongs bend along ``x``), the flat faces ``-y``.
Print frame: :data:`PRINT_POSE` (export/printpose.POSES) turns ``-y`` onto the bed.

Used by the friction pad, stable hub and constraint clip (:func:`make_rivet`, head on the module), the
connection hub (:func:`make_double_rivet`, barbed at both ends) and the servo housing and its horn adapter
(:func:`make_blind_rivet`: pushed in from the sheet's underside, head in the socket's bottom counterbore,
the barb latching in a blind socket inside the module, so that nothing of it reaches the servo's cavity).
"""
from dataclasses import replace

from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.geometry.snapfit import design_snap_fit

FLAT_FRACTION = 0.70          # the flat at -0.70 r: just inside the 45 deg limit (sin 45 = 0.707)
HEAD_RIM_MM = 1.0             # the head reaches this far beyond the shank
HEAD_HEIGHT_MM = 1.2          # head thickness along the axis
PRINT_POSE = "-y down"        # export/printpose.POSES name: the flat on the bed
BENDING = "along the layers (separate pin printed lying on a flat, slot upright)"


def rivet_snap_fit(p, material):
    """The designed :class:`~metamaterial_wb.geometry.snapfit.SnapFit` of a rivet pin, marked as bending
    along the layers."""
    return replace(design_snap_fit(p, material), bending=BENDING)


def rivet_dimensions(p, foot_mm, snap):
    """Dict of the rivet's dimensions (mm) for a module foot of ``foot_mm``."""
    if not foot_mm > 0:
        raise SceneError("modules", f"a rivet pin needs a module foot to trap; foot thickness {foot_mm} mm, "
                                    f"allowed range (0, ...) mm")
    r = p.socket_radius_mm - p.clearance_mm
    T = p.sheet_thickness_mm
    return {"shank_radius_mm": r, "barb_radius_mm": p.counterbore_radius_mm - p.clearance_mm,
            "tip_z_mm": p.clearance_mm, "barb_top_z_mm": p.socket_lip_height_mm - p.clearance_mm,
            "slot_mm": snap.slot_mm, "slot_top_z_mm": snap.slot_top_mm, "foot_mm": foot_mm,
            "head_z_mm": T + foot_mm, "head_radius_mm": r + HEAD_RIM_MM, "head_height_mm": HEAD_HEIGHT_MM,
            "flat_mm": FLAT_FRACTION * r,
            "foot_hole_radius_mm": r + p.clearance_mm,
            "length_mm": T + foot_mm + HEAD_HEIGHT_MM - p.clearance_mm,
            # the prongs (as blind_rivet_dimensions names them): barb latch face and the slot's end
            "latch_z_mm": p.socket_lip_height_mm - p.clearance_mm, "slot_end_z_mm": snap.slot_top_mm}


def make_rivet(p, foot_mm, snap=None):
    """The rivet pin solid in its assembly frame (module docstring)."""
    if snap is None:
        snap = rivet_snap_fit(p, p.module_material)
    from metamaterial_wb.geometry.fc import freecad
    App, Part = freecad()
    V = App.Vector
    d = rivet_dimensions(p, foot_mm, snap)
    r, rb, z_tip, z_sh = d["shank_radius_mm"], d["barb_radius_mm"], d["tip_z_mm"], d["barb_top_z_mm"]
    z_head = d["head_z_mm"]
    shank = Part.makeCylinder(r, z_head - z_sh, V(0, 0, z_sh))
    barb = Part.makeCone(r, rb, z_sh - z_tip, V(0, 0, z_tip))
    head = Part.makeCylinder(d["head_radius_mm"], HEAD_HEIGHT_MM, V(0, 0, z_head))
    pin = shank.fuse([barb, head])
    w = d["slot_mm"]
    big = d["head_radius_mm"] + 1.0
    slot = Part.makeBox(w, 2 * big, snap.slot_top_mm - (z_tip - 1.0), V(-0.5 * w, -big, z_tip - 1.0))
    flat = Part.makeBox(2 * big, big, z_head + HEAD_HEIGHT_MM + 2.0, V(-big, -big - d["flat_mm"], z_tip - 1.0))
    pin = pin.cut([slot, flat]).removeSplitter()
    if len(pin.Solids) != 1:
        from metamaterial_wb.core.errors import MetamaterialError
        raise MetamaterialError(f"rivet pin came out as {len(pin.Solids)} solids")
    return pin.Solids[0]


def make_double_rivet(p, span_mm, snap=None):
    """A headless rivet with a barbed, slotted end at each side: it joins two sheets through a module
    ``span_mm`` thick between them (the connection hub). Assembly frame as :func:`make_rivet`: the lower
    end in the sheet below (tip at ``z = clearance``), the upper end its mirror about the module's
    mid-plane ``z = T + span_mm / 2``, in the sheet that lies upside down on the module's top face. It
    prints lying on the same flat, both slots upright, so both pairs of prongs bend along the layers."""
    if snap is None:
        snap = rivet_snap_fit(p, p.module_material)
    if not span_mm > 0:
        raise SceneError("modules", f"a double rivet needs a module between the sheets; thickness {span_mm} mm, "
                                    f"allowed range (0, ...) mm")
    from metamaterial_wb.geometry.fc import freecad
    App, Part = freecad()
    V = App.Vector
    d = rivet_dimensions(p, span_mm, snap)
    r, rb, z_tip, z_sh = d["shank_radius_mm"], d["barb_radius_mm"], d["tip_z_mm"], d["barb_top_z_mm"]
    zm = p.sheet_thickness_mm + 0.5 * span_mm
    w = d["slot_mm"]
    big = r + HEAD_RIM_MM + 1.0

    def end():
        e = Part.makeCylinder(r, zm - z_sh + 0.01, V(0, 0, z_sh)).fuse(Part.makeCone(r, rb, z_sh - z_tip, V(0, 0, z_tip)))
        slot = Part.makeBox(w, 2 * big, snap.slot_top_mm - (z_tip - 1.0), V(-0.5 * w, -big, z_tip - 1.0))
        return e.cut(slot)

    lo = end()
    pin = lo.fuse(lo.mirror(V(0, 0, zm), V(0, 0, 1)))
    flat = Part.makeBox(2 * big, big, 2 * zm + 2.0, V(-big, -big - d["flat_mm"], -1.0))
    pin = pin.cut(flat).removeSplitter()
    if len(pin.Solids) != 1:
        from metamaterial_wb.core.errors import MetamaterialError
        raise MetamaterialError(f"double rivet pin came out as {len(pin.Solids)} solids")
    return pin.Solids[0]


def blind_rivet_dimensions(p, ledge_mm, snap):
    """Dict of a blind rivet's dimensions (mm, assembly frame: the sheet's bottom face at ``z = 0``) for a
    blind socket whose ledge (the module material the barb latches over) is ``ledge_mm`` thick."""
    if not ledge_mm > 0:
        raise SceneError("modules", f"a blind rivet needs a ledge in the module to latch over; ledge {ledge_mm} mm, "
                                    f"allowed range (0, ...) mm")
    clr, lip, T = p.clearance_mm, p.socket_lip_height_mm, p.sheet_thickness_mm
    z_latch = T + ledge_mm + clr                  # the barb's latch face, just above the module's ledge
    z_tip = z_latch + lip - 2 * clr               # the barb as long as the standard pin's
    return {"shank_radius_mm": p.socket_radius_mm - clr, "barb_radius_mm": p.counterbore_radius_mm - clr,
            "head_radius_mm": p.counterbore_radius_mm - clr, "head_z_mm": clr, "head_height_mm": lip - clr,
            "latch_z_mm": z_latch, "tip_z_mm": z_tip, "slot_mm": snap.slot_mm,
            "slot_end_z_mm": z_latch - snap.length_mm, "ledge_mm": ledge_mm,
            "undercut_mm": lip, "undercut_radius_mm": p.counterbore_radius_mm,
            "flat_mm": FLAT_FRACTION * (p.socket_radius_mm - clr), "length_mm": z_tip - clr}


def make_blind_rivet(p, ledge_mm, snap=None):
    """A rivet pushed in from the sheet's underside (the servo housing and its horn adapter, whose
    sockets lie under the servo): its head sits in the socket's bottom counterbore (flush with the
    sheet's face, bearing on the socket's ledge), the shank runs up through the sheet, and the slotted,
    barbed end snaps over a ledge ``ledge_mm`` thick inside a blind socket of the module
    (:func:`metamaterial_wb.geometry.solids.blind_riveted`). The prongs are as long as the standard
    pin's (``snap.length_mm`` from the latch face, ending inside the sheet's hole), so the strain is the
    designed ``1.5 t y / L^2``; it prints lying on the same flat, slot upright."""
    if snap is None:
        snap = rivet_snap_fit(p, p.module_material)
    from metamaterial_wb.geometry.fc import freecad
    App, Part = freecad()
    V = App.Vector
    d = blind_rivet_dimensions(p, ledge_mm, snap)
    r, rb = d["shank_radius_mm"], d["barb_radius_mm"]
    z0, zh, zl, zt = d["head_z_mm"], d["head_z_mm"] + d["head_height_mm"], d["latch_z_mm"], d["tip_z_mm"]
    if d["slot_end_z_mm"] < zh:
        from metamaterial_wb.core.errors import MetamaterialError
        raise MetamaterialError(f"blind rivet: prongs of {snap.length_mm:.3g} mm reach into its head")
    head = Part.makeCylinder(d["head_radius_mm"], zh - z0, V(0, 0, z0))
    shank = Part.makeCylinder(r, zl - zh + 0.01, V(0, 0, zh - 0.01))
    barb = Part.makeCone(rb, r, zt - zl, V(0, 0, zl))
    pin = head.fuse([shank, barb])
    big = rb + 1.0
    slot = Part.makeBox(d["slot_mm"], 2 * big, zt - d["slot_end_z_mm"] + 1.0,
                        V(-0.5 * d["slot_mm"], -big, d["slot_end_z_mm"]))
    flat = Part.makeBox(2 * big, big, zt + 2.0, V(-big, -big - d["flat_mm"], -1.0))
    pin = pin.cut([slot, flat]).removeSplitter()
    if len(pin.Solids) != 1:
        from metamaterial_wb.core.errors import MetamaterialError
        raise MetamaterialError(f"blind rivet pin came out as {len(pin.Solids)} solids")
    return pin.Solids[0]
