"""Mesh-convergence error bars use the element sizes the meshes have, not the nominal ``h`` asked for.

``mesh.graded`` rounds element counts up, so the "h = 0.283 mm" hinge mesh has 0.25 mm bricks along the hinge, 0.267
across and 0.538 through: its size ratios to the 0.4 and 0.2 meshes are not 1.414. Richardson extrapolation must use
the recorded sizes, solve for the order with unequal ratios (Roache / Celik: ``f = f0 + C h^p`` at three sizes), and
flag an order it clips or assumes instead of clipping it silently. No ccx is run (the stiffness run reads a fake
``ccx``'s tables).
"""
import json
import os
import stat

import numpy as np
import pytest

from metamaterial_wb.fe import hinge, patch

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


@pytest.mark.parametrize("p", [0.8, 1.7, 2.0, 3.3])
def test_unequal_ratios_recover_the_limit_and_the_order(p):
    """f(h) = f0 + C h^p at three sizes in unequal ratios (the hinge's true sizes, ratios 1.51 and 1.32): the
    closed form's f0 and p come back, through the studies' own call (``hinge.richardson``) too."""
    from metamaterial_wb.core.extrapolation import extrapolate
    f0, C = np.array([3.0, -1.5]), np.array([-2.0, 0.7])
    h = [0.4993, 0.3298, 0.2497]
    vals = [f0 + C * x ** p for x in h]
    res = extrapolate(h, vals)
    assert res["value"] == pytest.approx(f0, abs=1e-10)
    assert res["order"] == pytest.approx([p, p], abs=1e-8)
    assert res["error"] == pytest.approx(np.abs(C) * h[-1] ** p, rel=1e-7)
    assert not res["clipped"].any() and not res["assumed"].any()
    assert res["ratios"] == pytest.approx([h[0] / h[1], h[1] / h[2]])
    ext, err, order = hinge.richardson(h, vals)
    assert ext == pytest.approx(f0, abs=1e-10) and order == pytest.approx([p, p], abs=1e-8)


def test_an_order_outside_the_range_is_clipped_and_flagged():
    from metamaterial_wb.core.extrapolation import extrapolate, summary
    h = [0.5, 0.333, 0.25]
    res = extrapolate(h, [1.0 + x ** 5.5 for x in h])
    assert res["clipped"].all() and res["order"] == pytest.approx(4.0)
    assert res["order_observed"] == pytest.approx(5.5, abs=1e-8)
    assert "1 of 1 observed orders outside [0.5, 4] and clipped" in summary(res)
    res = extrapolate(h, [1.0, 1.2, 1.1])                     # oscillating: no order observed
    assert res["assumed"].all() and res["order"] == pytest.approx(2.0) and "order 2 assumed" in summary(res)
    res = extrapolate([0.4, 0.2], [1.16, 1.04])               # two meshes: order 2 assumed, true ratio used
    assert res["assumed"].all() and res["value"] == pytest.approx(1.0)
    with pytest.raises(ValueError, match="strictly decreasing"):
        extrapolate([0.2, 0.4, 0.1], [1.0, 2.0, 3.0])


def _hinge_spacing(spec, h):
    """The hinge bricks' edge lengths (along, across, through) read off the mesh itself."""
    m = hinge.hinge_mesh(spec, h)
    corners = m.nodes[m.elements[m.part == 0][:, [0, 6]]]           # (E, 2, 3): opposite corners of each brick
    size = corners[:, 1] - corners[:, 0]
    assert np.allclose(size, size[0])                               # a uniform grid in the hinge
    return size[0]


@pytest.mark.parametrize("h", [0.4, 0.283, 0.2])
def test_the_hinge_mesh_records_its_own_element_size(h):
    spec = hinge.HingeSpec()
    got = hinge.element_sizes(spec, h)
    assert got["element_mm"] == pytest.approx(_hinge_spacing(spec, h), rel=1e-12)
    assert got["h_eff_mm"] == pytest.approx(float(np.prod(got["element_mm"])) ** (1 / 3), rel=1e-12)
    if h == 0.283:                               # the auditor's figures: not the nominal 0.283 in any direction
        assert got["element_mm"] == pytest.approx([0.25, 0.8 / 3, 7 / 13], rel=1e-12)


FAKE_DAT = """#!/bin/sh
for t in 1 2 3 4 5 6; do
  for q in displacements forces; do
    for s in NREF NROT; do
      n=900001; [ $s = NROT ] && n=900002
      printf ' %s (vx,vy,vz) for set %s and time  %s.0000000E+00\\n\\n  %s 1.0E+00 0.0E+00 0.0E+00\\n\\n' \
        $q $s $t $n >> "$2.dat"
    done
  done
done
exit 0
"""


def test_the_stiffness_run_records_the_sizes_it_ran_on(tmp_path, monkeypatch):
    d = tmp_path / "bin"
    d.mkdir()
    exe = d / "ccx"
    exe.write_text(FAKE_DAT)
    exe.chmod(exe.stat().st_mode | stat.S_IXUSR)
    monkeypatch.setenv("PATH", str(d) + os.pathsep + os.environ.get("PATH", ""))
    spec = hinge.HingeSpec()
    _K, info = hinge.stiffness(spec, 0.283, 30)
    assert info["h_mm"] == 0.283
    assert info["element_mm"] == pytest.approx(_hinge_spacing(spec, 0.283), rel=1e-12)
    assert info["h_eff_mm"] == pytest.approx(hinge.element_sizes(spec, 0.283)["h_eff_mm"])


def test_the_patch_deck_records_its_own_element_size():
    scene = patch.patch_scene(0.05)
    for h, nz in ((0.5, 2), (0.35, 3), (0.25, 4)):
        _deck, meta = patch.patch_deck(scene, h, nz, 2)
        geo = meta["geo"]
        xs, ys, zs = patch.hinge_lines(float(geo.rest), float(geo.w[0]), float(geo.t[0]), h, nz)
        own = [np.diff(xs).max(), np.diff(ys).max(), np.diff(zs).max()]
        assert meta["element_mm"] == pytest.approx(own, rel=1e-12)
        assert meta["h_eff_mm"] == pytest.approx(float(np.prod(own)) ** (1 / 3), rel=1e-12)
    assert meta["element_mm"][0] != pytest.approx(0.25) or meta["element_mm"][1] != pytest.approx(0.25)


def test_the_stored_study_is_extrapolated_with_its_meshes_own_sizes():
    """benchmarks/results/fe-study.json: every mesh row records its sizes, and the hinge stiffness' extrapolation is
    the one those sizes give (recomputed here from its per-mesh stiffness, without ccx)."""
    from metamaterial_wb.core.extrapolation import extrapolate
    with open(os.path.join(REPO, "benchmarks", "results", "fe-study.json")) as f:
        st = json.load(f)
    spec = hinge.HingeSpec(**{k: v for k, v in st["spec"].items() if k not in ("L", "w", "t")},
                           length=st["spec"]["L"], width=st["spec"]["w"], thickness=st["spec"]["t"])
    rows = st["stiffness"]
    for r in rows + st["bending"]:
        assert r["h_eff_mm"] == pytest.approx(hinge.element_sizes(spec, r["h_mm"])["h_eff_mm"], rel=1e-9)
    vals = [np.concatenate([np.diag(r["K"]), [r["bending_condensed"]]]) for r in rows]
    res = extrapolate([r["h_eff_mm"] for r in rows], vals)
    ext = st["stiffness_extrapolated"]
    assert ext["diag"] == pytest.approx(res["value"][:6].tolist(), rel=1e-12)
    assert ext["diag_err"] == pytest.approx(res["error"][:6].tolist(), rel=1e-9)
    assert ext["bending_condensed_err"] == pytest.approx(float(res["error"][6]), rel=1e-9)
    assert ext["order_clipped"] == res["clipped"][:6].tolist()
    for a in st["aspect"]:
        s = hinge.HingeSpec(length=a["length_mm"])
        for m in a["meshes"]:
            assert m["h_eff_mm"] == pytest.approx(hinge.element_sizes(s, m["h_mm"])["h_eff_mm"], rel=1e-9)
    for row in st["patch"]:
        assert all("h_eff_mm" in f and len(f["element_mm"]) == 3 for f in row["fe"])


def test_the_sleeve_studies_extrapolate_with_the_same_computation():
    """``richardson3`` (the sleeve studies, per column) is ``extrapolate`` with its flags: one implementation. A
    column with a non-finite value keeps its finest value with NaN error and order; a clipped order is reported by
    ``richardson3_flags``."""
    from metamaterial_wb.core.extrapolation import extrapolate, richardson3, richardson3_flags
    h = [1.0, 0.5, 1.0 / 3.0]
    rows = [[2.0 + x ** 1.7, 1.0 + x ** 5.5, 3.0 + (np.nan if x == 1.0 else x)] for x in h]
    ext, err, order = richardson3(h, rows)
    ref = extrapolate(h, [np.array(r[:2]) for r in rows])
    assert ext[:2] == pytest.approx(ref["value"]) and err[:2] == pytest.approx(ref["error"])
    assert order[:2] == pytest.approx(ref["order"]) and order[0] == pytest.approx(1.7)
    assert ext[2] == rows[-1][2] and np.isnan(err[2]) and np.isnan(order[2])
    assert richardson3_flags(h, rows) == "1 of 3 observed orders outside [0.5, 4] and clipped to it (0 to 0.5, 1 to 4)"
