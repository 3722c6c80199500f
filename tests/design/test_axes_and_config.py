"""Rotary axes (seed 4.1 rules), maximum fold, joint configuration, global deformation."""
import json
import math

import numpy as np
import pytest

from metamaterial_wb.core import design, kinematics as K
from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.core.scene import Scene


def scene(layout, axes, lh=5.0, t=7.0, w=0.8, **kw):
    d = {"layout": layout, "hinge": {"length_mm": lh, "width_mm": w, "thickness_mm": t}, "axes": axes}
    d.update(kw)
    return Scene.from_dict(d)


def V(line, fold=0.0, **kw):
    return dict({"direction": "vertical", "line": line, "fold_deg": fold}, **kw)


def H(line, fold=0.0, **kw):
    return dict({"direction": "horizontal", "line": line, "fold_deg": fold}, **kw)


# ------------------------------------------------------------------------------------------------
# crossed joints
# ------------------------------------------------------------------------------------------------
def test_axis_crosses_every_joint_on_its_line():
    s = scene({"grid": [3, 4]}, [V(1)])
    (p,) = design.plan_axes(s)
    assert p.joint_names == ["H0,1", "H1,1", "H2,1", "H3,1"]
    s2 = scene({"grid": [3, 4]}, [H(2)])
    (p2,) = design.plan_axes(s2)
    assert p2.joint_names == ["V2,0", "V2,1", "V2,2", "V2,3", "V2,4"]


# ------------------------------------------------------------------------------------------------
# rule violations, each naming the axes
# ------------------------------------------------------------------------------------------------
def test_crossing_axes_are_rejected_naming_both():
    s = scene({"grid": [3, 3]}, [V(1, name="spine"), H(1, name="rib")])
    with pytest.raises(SceneError) as e:
        design.plan_axes(s)
    msg = str(e.value)
    assert "spine" in msg and "rib" in msg and "cross" in msg and "[1, 1]" in msg


def test_perpendicular_axes_that_do_not_meet_are_accepted():
    s = scene({"rows": ["####", "...#", "...#"]}, [V(1, 30), H(1, -20)])
    plans = design.plan_axes(s)
    assert [p.direction for p in plans] == ["vertical", "horizontal"]


def test_axis_that_stops_short_is_rejected():
    s = scene({"grid": [4, 3]}, [V(1, 20, **{"from": 0, "to": 2})])
    with pytest.raises(SceneError) as e:
        design.plan_axes(s)
    msg = str(e.value)
    assert "axes[0]" in msg and "stops short" in msg and "[3, 1]" in msg
    s = scene({"grid": [4, 3]}, [V(1, 20, **{"from": 1})])
    with pytest.raises(SceneError, match="stops short"):
        design.plan_axes(s)
    # covering the whole line with from/to is fine
    s = scene({"grid": [4, 3]}, [V(1, 20, **{"from": 0, "to": 3})])
    assert len(design.plan_axes(s)[0].joints) == 5


def test_axis_on_a_line_without_cells_is_rejected():
    s = scene({"grid": [2, 3]}, [V(7, 10)])
    with pytest.raises(SceneError, match=r"axes\[0\].*runs through no cell.*0\.\.2"):
        design.plan_axes(s)


def test_two_axes_on_one_line_are_rejected():
    s = scene({"grid": [2, 3]}, [V(1, 10), V(1, 20)])
    with pytest.raises(SceneError, match=r"axes\[0\].*axes\[1\].*same line"):
        design.plan_axes(s)


def test_u_shape_stretch_may_be_covered_whole_but_not_cut_inside():
    # a U: arms at columns 0 and 2 joined by the bottom row; horizontal line 0 meets both arms
    rows = ["#.#", "#.#", "###"]
    s = scene({"rows": rows}, [H(0, 20)])
    p = design.plan_axes(s)[0]
    assert p.segments == [(0, 0), (2, 2)]
    # covering one arm only (a whole stretch, boundary to boundary) is allowed and cuts it off
    s = scene({"rows": rows}, [H(0, 20, **{"from": 2, "to": 2})])
    assert design.plan_axes(s)[0].segments == [(2, 2)]


# ------------------------------------------------------------------------------------------------
# maximum fold: computed independently per binding criterion
# ------------------------------------------------------------------------------------------------
def _phi_c(lh, cell=20.0):
    return math.asin(lh / (2 * (cell - lh)))


def test_max_fold_bound_by_plate_contact_across_the_fold():
    s = scene({"chain": 4}, [V(1, 10)], lh=5.0, t=7.0)
    mx, why = design.axis_limits(s, design.plan_axes(s)[0])
    assert mx == pytest.approx(math.degrees(2 * math.atan(5.0 / 7.0)))
    assert "plate contact across the fold" in why


def test_max_fold_bound_by_tilt_limit():
    s = scene({"chain": 4}, [V(1, 10)], lh=5.0, t=2.0)
    mx, why = design.axis_limits(s, design.plan_axes(s)[0])
    assert mx == pytest.approx(math.degrees(2 * math.atan(math.tan(math.radians(80)) * math.sin(_phi_c(5.0)))))
    assert "tilt limit" in why


def test_max_fold_bound_by_hinge_strain():
    s = scene({"chain": 4}, [V(1, 10)], lh=5.0, t=2.0, w=3.0, material={"hinge_strain_limit": 0.2})
    mx, why = design.axis_limits(s, design.plan_axes(s)[0])
    psi_max = 2 * 5.0 * 0.2 / 3.0
    gamma = 2 * math.acos(math.cos(psi_max / 2) / math.cos(_phi_c(5.0)))
    assert mx == pytest.approx(math.degrees(gamma))
    assert "hinge strain" in why
    # at that fold the strain at D = +1 is exactly the limit (independent: w psi / 2 lh)
    s2 = scene({"chain": 4}, [V(1, mx - 1e-9)], lh=5.0, t=2.0, w=3.0, material={"hinge_strain_limit": 0.2})
    design.configure(s2)
    R = K.node_poses(s2, np.ones(s2.topology.n_nodes))[1]
    a, b = s2.topology.joint_pairs[s2.topology.joint_id("H", 0, 1)]
    psi = np.linalg.norm(K.rotation_log((R[a].T @ R[b])[None])[0])
    assert 3.0 * psi / (2 * 5.0) == pytest.approx(0.2, rel=1e-6)


def test_max_fold_bound_by_fabrication():
    """With fabrication.limit_design_tilt the design keeps every tilt printable: at the reported
    maximum the build's own fit check passes, just beyond it the build rejects the hinge. Without
    it (the default) the printable fold is reported and exceeding it is a warning."""
    from metamaterial_wb.core.fabrication import fabrication_params, max_fabricable_tilt_deg
    d = {"layout": {"chain": 4}, "hinge": {"length_mm": 5.0, "width_mm": 0.8, "thickness_mm": 7.0},
         "axes": [V(1, 1.0)], "fabrication": {"limit_design_tilt": True}}
    s = Scene.from_dict(d)
    mx, why = design.axis_limits(s, design.plan_axes(s)[0])
    assert "fabrication" in why
    assert mx == pytest.approx(design.printable_fold_deg(s, design.plan_axes(s)[0])[0])
    # independent check of the fit criterion at the limit tilt: anchor + shear == room before the socket
    tilt = math.radians(max_fabricable_tilt_deg(s, 0.8))
    s1 = Scene.from_dict(d)
    p = fabrication_params(s1, design.effective_tilts_deg(s1))
    room = 0.5 * (20 - 5) - (p.counterbore_radius_mm + p.min_wall_mm)   # wall: two nozzle widths
    assert 0.8 / math.cos(tilt) + p.anchor_margin_mm + 7.0 * math.tan(tilt) == pytest.approx(room, abs=1e-9)
    for fold, ok in ((mx - 1e-6, True), (mx * 1.02, False)):
        s2 = Scene.from_dict(dict(d, axes=[V(1, fold)]))
        design.configure(s2, strict=False)
        if ok:
            fabrication_params(s2)
        else:
            with pytest.raises(SceneError, match="tilt"):
                fabrication_params(s2)
    # default: not a hard limit, but a warning that names the axis and the printable fold
    free = Scene.from_dict(dict(d, axes=[V(1, mx * 1.5, name="spine")], fabrication={}))
    rep = design.configure(free)
    assert any("spine" in w and "printable" in w for w in rep["warnings"])
    ok = Scene.from_dict(dict(d, axes=[V(1, mx * 0.5, name="spine")], fabrication={}))
    assert not any("printable" in w for w in design.configure(ok)["warnings"])


def test_fold_beyond_the_maximum_is_an_error_that_gives_the_maximum():
    s = scene({"chain": 4}, [V(1, 75.0)], lh=5.0, t=7.0)
    mx = design.max_fold_deg(s, 0)
    with pytest.raises(SceneError) as e:
        design.configure(s)
    assert design.inward(mx) in str(e.value) and "axes[0].fold_deg" in str(e.value)
    assert s.joint_config == {}                      # nothing configured half-way
    assert design.max_folds_deg(s) == [pytest.approx(mx)]


# ------------------------------------------------------------------------------------------------
# joint configuration
# ------------------------------------------------------------------------------------------------
def test_joint_configuration_tilts_and_round_trip():
    s = scene({"grid": [3, 5]}, [V(2, 40.0, name="a"), V(4, -25.0, name="b")])
    report = design.configure(s)
    assert sorted(s.joint_config) == sorted([f"H{i},2" for i in range(4)] + [f"H{i},4" for i in range(4)])
    phi_c = _phi_c(5.0)
    for name, cfg in s.joint_config.items():
        i, j = (int(x) for x in name[1:].split(","))
        fold = 40.0 if j == 2 else -25.0
        # independent: tan(alpha) = -(-1)^(i+j) tan(fold/2) / sin(phi_c)
        expect = math.degrees(math.atan(-(-1) ** (i + j) * math.tan(math.radians(fold) / 2) / math.sin(phi_c)))
        assert cfg["tilt_deg"] == pytest.approx(expect, abs=1e-7)
        assert s.joint_tilt_deg(name) == pytest.approx(expect, abs=1e-7)
    # contracting joints stay untilted
    assert s.joint_tilt_deg("V1,2") == 0.0 and s.joint_tilt_deg("H0,1") == 0.0
    # JSON round trip keeps the configuration
    s2 = Scene.from_json(s.to_json())
    assert s2.joint_config == s.joint_config
    assert [r["axis"] for r in report["axes"]] == ["a", "b"]
    assert report["axes"][0]["fold_at_D1_deg"] == pytest.approx(40.0)


def test_override_tilt_wins_and_is_reported():
    s = scene({"grid": [2, 3]}, [V(1, 30.0)], joints=[{"joint": "H0,1", "tilt_deg": 5.0}])
    report = design.configure(s)
    assert s.joint_tilt_deg("H0,1") == 5.0
    assert any("H0,1" in w for w in report["warnings"])


def test_unconfigured_scene_with_axes_is_configured_on_the_fly_without_changing_it():
    s = scene({"chain": 5}, [V(2, 45.0)])
    R = K.node_poses(s, np.ones(s.topology.n_nodes), kin=design.kinematics_for(s))[1]
    assert s.joint_config == {}
    # the kinematics itself never configures (it sits below the design stage): a clear error instead
    with pytest.raises(SceneError, match="joint configuration"):
        K.Kinematics(s)
    a, b = 0, s.topology.n_nodes - 1
    assert math.degrees(math.acos(R[a][:, 2] @ R[b][:, 2])) == pytest.approx(45.0)


def test_global_deformation_between_flat_and_folded():
    s = scene({"grid": [2, 4]}, [V(1, 50.0), V(2, 20.0)])
    design.configure(s)
    kin = K.Kinematics(s)
    a, b = s.topology.node_id(0, 0), s.topology.node_id(0, 4)
    angles = []
    for g in np.linspace(0, 1, 6):
        R = kin.poses(design.global_D(s, g))[1]
        angles.append(math.degrees(math.acos(np.clip(R[a][:, 2] @ R[b][:, 2], -1, 1))))
    assert angles[0] == pytest.approx(0.0, abs=1e-9)
    assert angles[-1] == pytest.approx(70.0, abs=1e-7)
    assert all(x < y for x, y in zip(angles, angles[1:]))       # monotonic between flat and folded
    with pytest.raises(SceneError, match="global_deformation"):
        design.global_D(s, 1.5)


def test_stale_design_configuration_is_recomputed_but_hand_written_one_is_kept():
    s = scene({"chain": 4}, [V(1, 30.0)])
    design.configure(s)
    s.axes[0].fold_deg = 45.0                       # the user changed the fold after designing
    rep = design.ensure_configured(s)
    assert rep is not None and "stale" in rep["warnings"][0]
    assert s.joint_config["H0,1"]["fold_deg"] == 45.0
    assert design.ensure_configured(s) is None      # now consistent
    # a hand-written tilt on one of the axis' two joints is kept; the other joint (H1,1) was solved flat, silently:
    # it is configured now, with the stale-design warning
    hand = scene({"chain": 4}, [V(1, 30.0)], joint_config={"H0,1": {"tilt_deg": 10.0}})
    rep = design.ensure_configured(hand)
    assert rep is not None and "stale" in rep["warnings"][0] and hand.joint_tilt_deg("H0,1") == 10.0
    assert hand.joint_config["H1,1"]["axis"] == "v1" and design.ensure_configured(hand) is None
    both = scene({"chain": 4}, [V(1, 30.0)], joint_config={"H0,1": {"tilt_deg": 10.0}, "H1,1": {"tilt_deg": -10.0}})
    assert design.ensure_configured(both) is None and both.joint_tilt_deg("H1,1") == -10.0
