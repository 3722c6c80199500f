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


def _print_mesh(p, foot_mm, material, blind=False):
    """The rivet (``blind``: the servo modules' blind rivet, ``foot_mm`` its ledge) tessellated, its
    dimensions, and the mesh turned into its print pose."""
    from metamaterial_wb.export.mesh import tessellate
    from metamaterial_wb.export.printpose import POSES
    from metamaterial_wb.geometry.rivet import (PRINT_POSE, blind_rivet_dimensions, make_blind_rivet, make_rivet,
                                                rivet_dimensions, rivet_snap_fit)
    snap = rivet_snap_fit(p, material)
    make, dims = (make_blind_rivet, blind_rivet_dimensions) if blind else (make_rivet, rivet_dimensions)
    V, T = tessellate(make(p, foot_mm, snap), name="rivet")
    R = POSES[PRINT_POSE]
    off = np.array([0.0, 0.0, (V @ R.T)[:, 2].min()])
    W = V @ R.T - off
    return snap, dims(p, foot_mm, snap), V, W, T, (lambda a: np.asarray(a, dtype=float) @ R.T - off)


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


@pytest.mark.parametrize("material,foot_mm,blind", [("ABS", 1.5, False), ("PLA", 3.0, False), ("PETG", 2.0, False),
                                                    ("ABS", 1.5, True), ("PLA", 1.5, True), ("PETG", 2.0, True)])
def test_rivet_lies_flat_bends_in_the_bed_plane_within_the_strain(fc, material, foot_mm, blind):
    """Both kinds: the push rivet (head on the module) and the blind rivet of the servo modules (pushed in
    from the sheet's underside, its barb in a blind socket of the module; ``foot_mm`` its ledge)."""
    from metamaterial_wb.export.printpose import pose_report
    from metamaterial_wb.geometry.rivet import BENDING
    from metamaterial_wb.geometry.snapfit import ALLOWABLE_STRAIN
    p = _params()
    snap, d, V, W, T, to_print = _print_mesh(p, foot_mm, material, blind)
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
    y_sec = to_y(0.5 * (d["latch_z_mm"] + d["slot_end_z_mm"]))
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


def test_blind_rivets_hold_the_servo_modules_and_stay_out_of_the_cavity(fc):
    """The seed's worm set-up: the housing and the horn adapter each take two blind rivets pushed in
    from the sheet's underside. At rest each rivet is clear of its node and its module part (clearance
    only); it is trapped along its axis: pushed on by 0.1 mm its head hits the socket's ledge in the
    node, pulled back by the clearance + 0.1 mm its barb hits the module's ledge (so it clamps the part
    to the sheet); its head lies inside the node's bottom counterbore (nothing below the sheet) and
    its tip under the module's material (nothing reaches the servo's cavity)."""
    from test_done_when import _setup
    from metamaterial_wb.core.scene import Scene
    from metamaterial_wb.geometry.build import build_scene
    r = build_scene(Scene.from_dict(_setup("worm")), progress=False)
    p = r.params
    App = fc
    spec = [m for m in r.modules if m.type == "servo_housing"][0]
    nodes = {q.info["node"]: r.placed_shape(q) for q in r.parts if q.role == "node"}
    seen = 0
    for part, node in (("housing", spec.a), ("horn_adapter", spec.b)):
        body = r.placed_shape(r.by_name(f"{spec.name}_{part}"))
        sheet = nodes[f"N{node[0]},{node[1]}"]
        rivets = [q for q in r.groups()[spec.name] if q.name.startswith(f"{spec.name}_{part}_rivet_")]
        assert len(rivets) == 2, [q.name for q in rivets]
        for q in rivets:
            assert q.info["inserted_from"] == "sheet" and "along the layers" in q.info["bending"]
            rv = r.placed_shape(q)
            bb = rv.BoundBox
            assert bb.ZMin == pytest.approx(p.clearance_mm) and bb.ZMax < body.BoundBox.ZMax
            assert rv.common(sheet).Volume < 1e-4 and rv.common(body).Volume < 1e-4, q.name
            # a vertical line above the rivet's tip meets module material (the blind socket's roof)
            c = App.Vector(bb.Center.x, bb.Center.y, 0)
            top = App.Vector(c.x, c.y, bb.ZMax + 0.3)
            assert body.isInside(top, 1e-6, True), q.name

            def moved(dz):
                m = App.Matrix()
                m.move(App.Vector(0, 0, dz))
                return rv.transformed(m)
            assert moved(0.1).common(sheet).Volume > 1e-3, q.name                          # head on the ledge
            assert moved(-(p.clearance_mm + 0.1)).common(body).Volume > 1e-3, q.name       # barb on the ledge
            seen += 1
    assert seen == 4


def test_servo_modules_fall_back_to_fused_pins_and_say_why(fc):
    """Where a blind socket does not fit (a 0.8 mm floor: feet and floor 3.0 mm under the servo, a blind
    socket needs 3.8 mm) the housing and adapter fuse upright pins as before, and the spec (the manifest's
    module "note") and the snap-fit's bending say so instead of claiming rivets."""
    import copy
    from test_done_when import _setup, _specs
    from metamaterial_wb.core.scene import Scene
    from metamaterial_wb.export.manifest import build_manifest
    from metamaterial_wb.geometry.build import build_scene
    from metamaterial_wb.geometry.modules import is_riveted
    d = copy.deepcopy(_setup("worm"))
    d["modules"][0]["floor_mm"] = 0.8
    spec = [s for s in _specs(d) if s.type == "servo_housing"][0]
    assert not is_riveted(spec) and "across the layers" in spec.snap.bending
    assert "floor_mm" in spec.note and "3 mm" in spec.note and "3.8 mm" in spec.note, spec.note
    r = build_scene(Scene.from_dict(d), progress=False)
    names = [q.name for q in r.groups()[spec.name]]
    assert names == [f"{spec.name}_housing", f"{spec.name}_horn_adapter"]
    assert r.placed_shape(r.by_name(f"{spec.name}_housing")).BoundBox.ZMin == pytest.approx(r.params.clearance_mm)
    m = [x for x in build_manifest(r, {}, "w", ["solids"])["modules"] if x["name"] == spec.name][0]
    assert m["note"] == spec.note and "rivets" not in m
