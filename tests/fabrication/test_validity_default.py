"""Validity by default (issue 16): every build checks collisions and walls; colliding set-ups are
refused naming both modules and where; walls are at least two nozzle widths; examples build or say why
they are simulation-only."""
import glob
import json
import math
import os
import subprocess
import sys

import pytest

from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.core.numbers import inward_g

from fabhelpers import EXAMPLES, REPO, make_scene


def _cli(*args, timeout=300):
    return subprocess.run([sys.executable, "-m", "metamaterial_wb", *args], cwd=REPO, capture_output=True,
                          encoding="utf-8", errors="replace", timeout=timeout)


def _params_and_modules(scene, **kw):
    from metamaterial_wb.geometry.modules import parse_modules
    from metamaterial_wb.core.design import effective_tilts_deg
    from metamaterial_wb.core.fabrication import fabrication_params
    p = fabrication_params(scene, effective_tilts_deg(scene), **kw)
    return p, parse_modules(scene, p)


def test_clip_next_to_the_fish_stable_hub_is_refused_by_default(tmp_path, fc):
    """No shared socket, but the clip's plate and the stable hub's foot overlap on N0,3: the default
    checks refuse it (exit 2, nothing written, both modules and the node named); --no-check writes."""
    d = json.load(open(os.path.join(EXAMPLES, "fish_modules.json")))
    d["modules"].append({"type": "constraint_clip", "name": "clip", "joint": "V0,3", "angle_deg": 5})
    src = tmp_path / "fish_clip.json"
    src.write_text(json.dumps(d))
    out = tmp_path / "out"
    r = _cli("build", str(src), "--out", str(out), "--modules", "--3mf", "--quiet")
    assert r.returncode == 2, r.stderr
    assert "'fin_mount_top' and 'clip' collide on node N0,3" in r.stderr, r.stderr
    assert not out.exists() or not os.listdir(out)
    r = _cli("build", str(src), "--out", str(out), "--modules", "--3mf", "--quiet", "--no-check")
    assert r.returncode == 0, r.stderr
    assert any(f.endswith("_clip.3mf") for f in os.listdir(out))


def test_shared_export_function_checks(fc):
    """export_result (what the GUI's export calls) runs the checks itself."""
    from metamaterial_wb.export.package import export_result
    from metamaterial_wb.core.errors import MetamaterialError
    from metamaterial_wb.geometry.build import build_scene
    sc = make_scene({"grid": [2, 3]}, modules=[{"type": "stable_hub", "name": "hub", "joint": "H0,0"},
                                               {"type": "constraint_clip", "name": "clip", "joint": "V0,0",
                                                "angle_deg": 0.0}])
    r = build_scene(sc, progress=False)
    import tempfile
    d = tempfile.mkdtemp()
    with pytest.raises(MetamaterialError, match="'hub' and 'clip' collide on node N0,0"):
        export_result(r, d, step=False, progress=False)
    assert os.listdir(d) == []


@pytest.mark.parametrize("typ,key,extra", [
    ("servo_housing", "wall_mm", {"joint": "H0,0"}),
    ("servo_housing", "floor_mm", {"joint": "H0,0"}),
    ("stable_hub", "beam_width_mm", {"joint": "H0,0"}),
    ("connection_hub", "thickness_mm", {"node": "N0,0"}),
    ("constraint_clip", "thickness_mm", {"joint": "H0,0", "angle_deg": 3}),
])
def test_module_walls_below_two_nozzle_widths_are_refused(typ, key, extra):
    sc = make_scene({"grid": [1, 2]}, modules=[dict({"type": typ, "name": "m", key: 0.1}, **extra)])
    with pytest.raises(SceneError) as e:
        _params_and_modules(sc)
    assert e.value.field.startswith(f"modules[0].{key}")
    assert "two nozzle widths" in str(e.value) and "[0.8, 200]" in str(e.value)
    # a finer nozzle allows finer walls
    with pytest.raises(SceneError, match=r"\[0.5, 200\]"):
        _params_and_modules(sc, nozzle_mm=0.25)


def test_thin_hinge_sheet_blames_the_hinge_not_the_socket_lip():
    sc = make_scene({"grid": [1, 2]}, hinge={"length_mm": 2, "width_mm": 0.8, "thickness_mm": 1.0})
    with pytest.raises(SceneError) as e:
        _params_and_modules(sc)
    assert e.value.field == "hinge.thickness_mm"
    assert "3.8" in str(e.value) and "fabrication.sheet_thickness_mm" in str(e.value)
    # with the plates given their own thickness the socket lip is what is checked
    with pytest.raises(SceneError) as e:
        _params_and_modules(sc, sheet_thickness_mm=3.0)
    assert e.value.field == "fabrication.socket_lip_height_mm" and "(0, 1.1] mm" in str(e.value)


def test_unprintable_fold_error_gives_the_allowed_range():
    """The old grid_fold (5 mm hinges, 20 mm cells, 7 mm sheet): 74 deg tilts; the error gives the
    allowed tilt and the fold it makes, computed independently here from the closed forms."""
    from metamaterial_wb.core.design import rotation_limits   # the tilts of the axes, configured on the fly
    sc = make_scene({"grid": [4, 6]}, cell_size_mm=20, hinge={"length_mm": 5, "width_mm": 0.8, "thickness_mm": 7},
                    axes=[{"name": "w", "direction": "vertical", "line": 1, "fold_deg": -60}])
    with pytest.raises(SceneError) as e:
        _params_and_modules(sc)
    msg = str(e.value)
    # room along the edge: s/2 - (counterbore 2.1 + wall 0.8) = 4.6; reach = 0.8/cos t + 1.2 + 7 tan t
    t = 0.0
    for _ in range(60):
        t_hi = t + 0.5 ** (_ + 1) * 90
        if 0.8 / math.cos(math.radians(t_hi)) + 1.2 + 7 * math.tan(math.radians(t_hi)) <= 4.6:
            t = t_hi
    assert f"allowed tilt range [-{inward_g(t)}, {inward_g(t)}] deg" in msg
    closing, _ = rotation_limits(sc)
    fold = math.degrees(2 * math.atan(math.tan(math.radians(t)) * math.sin(closing)))
    assert f"fold of at most {inward_g(fold)} deg" in msg


def _edge_fit_error(**kw):
    """The edge-fit error of an 18 mm plate (20 mm cell, 2 mm hinges, 7 mm sheet) whose hinge V0,1 has
    the width and tilt given in ``kw`` (other keywords: fabrication overrides)."""
    h = {k: kw.pop(k) for k in ("width_mm", "tilt_deg")}
    sc = make_scene({"chain": 2}, cell_size_mm=20, hinge={"length_mm": 2, "width_mm": 0.8, "thickness_mm": 7},
                    joints=[{"joint": "V0,1", **h}])
    with pytest.raises(SceneError) as e:
        _params_and_modules(sc, **kw)
    return e.value


@pytest.mark.parametrize("bad", [{"width_mm": 0.8, "tilt_deg": 40.5},
                                 {"width_mm": 4.5, "tilt_deg": 0.0, "anchor_margin_mm": 4.0}])
def test_edge_fit_error_without_sockets_names_the_wall_not_a_socket(bad):
    """Without sockets (``build --no-sockets``) the anchor may reach along its plate edge up to half the side
    less a wall of two nozzle widths (18 / 2 - 0.8 = 8.2 mm): the error says so and names no socket; with
    sockets the room ends before the socket's ledge (9 - (2.1 + 0.8) = 6.1 mm)."""
    e = _edge_fit_error(sockets=False, **bad)
    msg = str(e)
    assert e.field == ("joints V0,1.tilt_deg" if bad["tilt_deg"] else "joints V0,1.width_mm"), msg
    assert "before the socket" not in msg and "no sockets" in msg, msg
    assert "has 8.2 mm" in msg and "half its side" in msg and "0.8 mm wall (two nozzle widths)" in msg, msg
    msg = str(_edge_fit_error(**bad))
    assert "has 6.1 mm before the socket" in msg, msg


def test_gripper_thinnest_wall_is_two_nozzle_widths(fc):
    """Measured on the built solids: every tilted hinge of the gripper stays >= 0.8 mm from its nodes'
    socket counterbores (was 0.58 mm)."""
    import Part
    from metamaterial_wb.core.scene import Scene, joint_nodes, parse_joint
    from metamaterial_wb.geometry.build import build_scene
    from metamaterial_wb.geometry.sheet import socket_positions
    r = build_scene(Scene.load(os.path.join(EXAMPLES, "gripper.json")), modules=False, progress=False)
    p = r.params
    worst = 1e9
    for q in r.parts:
        if q.role != "hinge" or not q.info["tilt_deg"]:
            continue
        hs = r.placed_shape(q)
        for (i, j) in joint_nodes(*parse_joint(q.info["joint"])):
            for _, dx, dy in socket_positions(p):
                c = fc.Vector(j * p.cell_size_mm + dx, -i * p.cell_size_mm + dy, 0)
                cb = Part.makeCylinder(p.counterbore_radius_mm, p.sheet_thickness_mm, c)
                worst = min(worst, hs.distToShape(cb)[0])
    assert 0.8 - 1e-6 <= worst < 1.5


KINDS = {"metamaterial-scene": "scene", "metamaterial-sleeve": "sleeve spec",
         "metamaterial-target": "inverse-design target", "metamaterial-inverse-report": "inverse-design report"}


def _format(path):
    with open(path) as f:
        return json.load(f).get("format", "metamaterial-scene")


def _scene_files():
    return sorted(p for p in glob.glob(os.path.join(EXAMPLES, "*.json"))
                  if _format(p) in ("metamaterial-scene", "metamaterial-sleeve"))


def test_every_example_file_is_a_known_kind():
    """examples/ holds scenes, sleeve specs and inverse-design targets / reports (the last two are data
    that `inverse` reads or writes, not something to print)."""
    odd = {os.path.basename(p): _format(p) for p in glob.glob(os.path.join(EXAMPLES, "*.json"))
           if _format(p) not in KINDS}
    assert not odd, odd


@pytest.mark.parametrize("path", _scene_files(), ids=os.path.basename)
def test_every_example_builds_or_says_why_not(path):
    """Parameters and modules of every bundled scene pass the build's checks (no geometry), or the
    scene declares fabrication.simulation_only with a reason; sleeve specs are built by `sleeve`."""
    from metamaterial_wb.core.scene import Scene
    d = json.load(open(path))
    if d.get("format") == "metamaterial-sleeve":
        pytest.skip("a sleeve spec: `sleeve --step/--3mf` builds it")
    sc = Scene.load(path)
    why = (d.get("fabrication") or {}).get("simulation_only")
    if why:
        assert len(why) > 20
        with pytest.raises(SceneError, match="simulation-only"):
            _params_and_modules(sc)
        return
    _params_and_modules(sc)


def test_strip_fold_prints_its_folds(fc):
    """The strip's sheet builds with the tilts its 50/50/-60 deg folds need: valid solids, rigid and
    flexible bodies touching only at the anchors, and the tilts are what the design stage asks."""
    from metamaterial_wb.core.design import effective_tilts_deg
    from metamaterial_wb.core.scene import Scene
    from metamaterial_wb.geometry import validity
    from metamaterial_wb.geometry.build import build_scene
    sc = Scene.load(os.path.join(EXAMPLES, "strip_fold.json"))
    r = build_scene(sc, progress=False)
    assert validity.check_solids(r) == [] and validity.check_sheet(r) == []
    tilts = sorted({round(abs(q.info["tilt_deg"]), 6) for q in r.parts if q.role == "hinge"})
    want = sorted({round(abs(t), 6) for t in effective_tilts_deg(sc)})
    assert tilts == want and max(tilts) > 50.0
