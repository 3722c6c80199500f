"""Separate push-rivet snap pins printed lying down (issue 16 item 4, "printed in the orientation that
bends along the layers"): measured on the tessellated mesh in its print pose -- it lies on a flat without
supports, the slot stands upright so the prongs bend in the bed plane, and the strain computed from the
prong dimensions measured on the mesh stays within the material's allowable strain."""
import numpy as np
import pytest

from fabhelpers import make_scene


def _params(**kw):
    from metamaterial_wb.core.design import effective_tilts_deg
    from metamaterial_wb.core.fabrication import fabrication_params
    sc = make_scene({"chain": 2}, **kw)
    return fabrication_params(sc, effective_tilts_deg(sc))


def _print_mesh(p, foot_mm, material):
    from metamaterial_wb.export.mesh import tessellate
    from metamaterial_wb.export.printpose import POSES
    from metamaterial_wb.geometry.rivet import PRINT_POSE, make_rivet, rivet_snap_fit
    snap = rivet_snap_fit(p, material)
    V, T = tessellate(make_rivet(p, foot_mm, snap), name="rivet")
    R = POSES[PRINT_POSE]
    off = np.array([0.0, 0.0, (V @ R.T)[:, 2].min()])
    W = V @ R.T - off
    return snap, V, W, T, (lambda a: np.asarray(a, dtype=float) @ R.T - off)


def _intervals(W, T, points, coord):
    """Inside runs along a line of sample points: list of (start, end) of ``points[:, coord]``."""
    from metamaterial_wb.export.printpose import inside
    ins = inside(W, T, points)
    runs, start = [], None
    for k, flag in enumerate(ins):
        if flag and start is None:
            start = points[k, coord]
        if not flag and start is not None:
            runs.append((start, points[k - 1, coord]))
            start = None
    if start is not None:
        runs.append((start, points[-1, coord]))
    return runs


@pytest.mark.parametrize("material,foot_mm", [("ABS", 1.5), ("PLA", 3.0), ("PETG", 2.0)])
def test_rivet_lies_flat_bends_in_the_bed_plane_within_the_strain(fc, material, foot_mm):
    from metamaterial_wb.export.printpose import pose_report
    from metamaterial_wb.geometry.rivet import BENDING, rivet_dimensions
    from metamaterial_wb.geometry.snapfit import ALLOWABLE_STRAIN
    p = _params()
    snap, V, W, T, to_print = _print_mesh(p, foot_mm, material)
    d = rivet_dimensions(p, foot_mm, snap)
    rep = pose_report(W, T)
    assert rep["supports_free"], rep
    # it lies: the pin's axis (assembly z) is horizontal in the print frame, its length along print y
    ext = np.ptp(W, axis=0)
    assert ext[1] == pytest.approx(d["length_mm"], abs=0.05)
    assert ext[2] < 2 * d["head_radius_mm"] and ext[2] < ext[1] / 2
    # the flat is on the bed under the whole length (tip, barb, shank and head all touch it)
    on_bed = W[:, 2] < 1e-6
    assert W[on_bed, 1].min() == pytest.approx(W[:, 1].min(), abs=0.05)
    assert W[on_bed, 1].max() == pytest.approx(W[:, 1].max(), abs=0.05)

    # the pin's centre line in the print frame (assembly z -> print y, centre height = the flat's depth)
    zc = d["flat_mm"]
    assert to_print([0, 0, 0])[2] == pytest.approx(zc)
    to_y = lambda z_assembly: to_print([0, 0, z_assembly])[1]  # noqa: E731
    # a section through the prongs: across the bed (print x) inside-slot-inside, straight up (print z)
    # through the slot's middle all empty -> the slot plane is upright and the prongs bend along x,
    # in the bed plane
    y_sec = to_y(0.5 * (d["barb_top_z_mm"] + d["slot_top_z_mm"]))
    xs = np.linspace(-d["head_radius_mm"], d["head_radius_mm"], 801)
    runs = _intervals(W, T, np.c_[xs, np.full_like(xs, y_sec), np.full_like(xs, zc)], 0)
    assert len(runs) == 2, runs
    zs = np.linspace(0.01, ext[2] - 0.01, 200)
    from metamaterial_wb.export.printpose import inside
    assert not inside(W, T, np.c_[np.zeros_like(zs), np.full_like(zs, y_sec), zs]).any()
    # the same section in the vertical direction is one solid run per prong: nothing splits it
    # across the layers
    x_prong = 0.5 * (runs[1][0] + runs[1][1])
    assert len(_intervals(W, T, np.c_[np.full_like(zs, x_prong), np.full_like(zs, y_sec), zs], 2)) == 1

    # strain from the mesh: t = prong width across the slot, L = slot end - barb's widest section,
    # y = barb radius - the socket hole's radius
    step = xs[1] - xs[0]
    t = np.mean([b - a for a, b in runs]) + step
    # along the centre line from the tip: empty (slot) until the slot's end
    ys = np.linspace(to_y(d["tip_z_mm"]), to_y(d["head_z_mm"]), 1201)
    slot_runs = _intervals(W, T, np.c_[np.zeros_like(ys), ys, np.full_like(ys, zc)], 1)
    slot_end = slot_runs[0][0]
    # the barb: the print-frame vertices standing out of the shank's radius in the tip's half
    near_tip = np.abs(W[:, 1] - to_y(d["tip_z_mm"])) < np.abs(W[:, 1] - to_y(d["head_z_mm"]))
    barb = W[near_tip & (np.abs(W[:, 0]) > d["shank_radius_mm"] + 0.5 * snap.deflection_mm)]
    barb_top = barb[np.argmin(np.abs(barb[:, 1] - slot_end)), 1]
    L = abs(slot_end - barb_top)
    y = np.abs(barb[:, 0]).max() - p.socket_radius_mm
    strain = 1.5 * t * y / L ** 2
    assert t == pytest.approx(snap.thickness_mm, abs=2 * step)
    assert L == pytest.approx(snap.length_mm, abs=0.05)
    assert y == pytest.approx(snap.deflection_mm, abs=0.02)
    assert strain <= ALLOWABLE_STRAIN[material] * 1.03, (t, y, L, strain)
    assert strain == pytest.approx(snap.strain, rel=0.05)
    assert t >= p.min_wall_mm - 1e-9
    assert snap.bending == BENDING and "along the layers" in snap.bending


def test_rivet_needs_a_foot(fc):
    from metamaterial_wb.core.errors import SceneError
    from metamaterial_wb.geometry.rivet import make_rivet
    with pytest.raises(SceneError, match=r"foot thickness 0 mm, allowed range \(0"):
        make_rivet(_params(), 0)


def test_upright_fused_pin_bends_across_the_layers(fc):
    """The reference the rivet replaces: the fused pin's slot plane, in the module's pins-up print pose,
    stands upright but the prongs run vertically, so each prong's bending strain lies along z, across
    the layer lines (the slot splits a vertical line through a prong into no run at all: the prong's
    length is vertical)."""
    from metamaterial_wb.export.mesh import tessellate
    from metamaterial_wb.geometry.solids import make_pin
    p = _params()
    V, T = tessellate(make_pin(p, up=True), name="pin")
    ext = np.ptp(V, axis=0)
    assert ext[2] > max(ext[0], ext[1])          # the pin's length is vertical: layers cut the prongs
