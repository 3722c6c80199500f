"""``build`` writes DIR/manifest.json; module print poses are checked on the exported meshes."""
import json
import math
import os
import subprocess
import sys
import xml.etree.ElementTree as ET
import zipfile

import numpy as np
import pytest

from fabhelpers import REPO, make_scene

NS = {"m": "http://schemas.microsoft.com/3dmanufacturing/core/2015/02"}
MODULES = [{"type": "servo_housing", "name": "servo", "joint": "V0,0",
            "profile_note": None}, {"type": "friction_pad", "name": "pad", "node": "N0,2"},
           {"type": "connection_hub", "name": "hub", "node": "N1,3"},
           {"type": "stable_hub", "name": "stable", "joint": "H0,4"},
           {"type": "constraint_clip", "name": "clip", "joint": "V0,6", "angle_deg": 6.0}]


def read_3mf_meshes(path):
    """``{object name: (V, T)}`` of every mesh object (plain zip + XML: an independent reader)."""
    with zipfile.ZipFile(path) as z:
        root = ET.fromstring(z.read("3D/3dmodel.model"))
    out = {}
    for obj in root.iter(f"{{{NS['m']}}}object"):
        mesh = obj.find("m:mesh", NS)
        if mesh is None:
            continue
        V = np.array([[float(v.get(k)) for k in "xyz"] for v in mesh.find("m:vertices", NS)])
        T = np.array([[int(t.get(k)) for k in ("v1", "v2", "v3")] for t in mesh.find("m:triangles", NS)])
        out[obj.get("name")] = (V, T)
    return out


@pytest.fixture(scope="module")
def built(tmp_path_factory, fc):
    d = tmp_path_factory.mktemp("manifest")
    sc = {"format": "metamaterial-scene", "version": 1, "name": "w", "cell_size_mm": 20,
          "hinge": {"length_mm": 2, "width_mm": 0.8, "thickness_mm": 7}, "layout": {"chain": 6},
          "actuators": [{"name": "m", "joint": "V0,0", "value": 0.0,
                         "profile": {"shape": "sine", "amplitude": 0.5, "frequency_hz": 1.0}}],
          "modules": [{k: v for k, v in m.items() if k != "profile_note"} for m in MODULES]}
    src = d / "w.json"
    src.write_text(json.dumps(sc))
    out = d / "out"
    r = subprocess.run([sys.executable, "-m", "metamaterial_wb", "build", str(src), "--out", str(out), "--modules",
                        "--quiet"], cwd=REPO, capture_output=True, encoding="utf-8", errors="replace", timeout=600)
    assert r.returncode == 0, r.stderr
    return out, json.load(open(out / "manifest.json"))


def test_manifest_lists_every_part_file_and_check(built):
    out, m = built
    assert m["format"] == "metamaterial-build-manifest" and m["units"] == "mm"
    assert sorted(m["files"] + ["manifest.json"]) == sorted(os.listdir(out))
    names = [p["name"] for p in m["parts"]]
    # chain of 6 cells: 2 x 7 nodes; every node and hinge, then the module parts
    assert sum(1 for p in m["parts"] if p["role"] == "node") == 14
    assert {"servo_housing", "servo_horn_adapter", "pad_pad", "hub_hub_lower", "hub_hub_upper"} <= set(names)
    node = [p for p in m["parts"] if p["name"] == "node_1_3"][0]
    assert node["placement"]["base_mm"] == [60.0, -20.0, 0.0] and "w_sheet.3mf" in node["files"]
    assert m["checks"]["ran"] == ["solids", "modules"] and m["checks"]["parameters"] is True
    assert m["min_wall_mm"] == 0.8


def test_manifest_servo_shaft_is_the_built_shaft(built, fc):
    """The shaft point in the manifest lies on the axis of the horn-hub pocket read back from the
    module's STEP file (sheet coordinates), and it is the joint's pivot."""
    import Part
    out, m = built
    servo = [x for x in m["modules"] if x["name"] == "servo"][0]
    sx, sy, _ = servo["servo"]["shaft_point_mm"]
    assert servo["joint_pivot"]["point_mm"][:2] == pytest.approx([sx, sy], abs=1e-6)
    shape = Part.read(str(out / "w_servo.step"))
    r_hub = 0.5 * 7.0 + 0.2
    cyl = [f for f in shape.Faces if f.Surface.__class__.__name__ == "Cylinder" and abs(f.Surface.Radius - r_hub) < 1e-6]
    assert cyl
    c = cyl[0].Surface.Center
    assert (c.x, c.y) == pytest.approx((sx, sy), abs=1e-5)
    assert servo["servo"]["hinge_length_error"] <= 0.02
    assert servo["servo"]["range_deg"][0] < 0 < servo["servo"]["range_deg"][1]


def test_manifest_snap_fit_strain_within_limit(built):
    _, m = built
    for mod in m["modules"]:
        sf = mod["snap_fit"]
        assert sf["strain"] == pytest.approx(1.5 * sf["thickness_mm"] * sf["deflection_mm"] / sf["length_mm"] ** 2,
                                             rel=1e-6)
        assert sf["strain"] <= sf["limit"] and sf["material"] == mod["material"]


def test_print_pose_checked_on_the_exported_mesh(built):
    """The pose report in the manifest is what the exported 3MF mesh gives; the friction pad lies on
    its flat face, pins up, and prints without supports; every part stands on z = 0; every part of
    every module (servo housing and horn adapter upside down, the two-way hub as two one-way halves)
    prints without supports."""
    from metamaterial_wb.export.printpose import pose_report
    out, m = built
    for mod in m["modules"]:
        meshes = read_3mf_meshes(out / f"w_{mod['name']}.3mf")
        for part, rep in mod["print_pose"].items():
            V, T = meshes[part]
            assert V[:, 2].min() == pytest.approx(0.0, abs=1e-6)
            mine = pose_report(V, T)
            assert mine["supports_free"] == rep["supports_free"]
            assert mine["unsupported_area_mm2"] == pytest.approx(rep["unsupported_area_mm2"], abs=2e-3)
    pad = [x for x in m["modules"] if x["name"] == "pad"][0]["print_pose"]["pad_pad"]
    assert pad["supports_free"] and pad["bed_area_mm2"] > 100.0 and pad["pose"] in ("+z down", "-z down")
    rep = [x for x in m["modules"] if x["name"] == "stable"][0]["print_pose"]["stable_hub"]   # flat top on the bed
    assert rep["supports_free"] and rep["pose"] == "+z down" and rep["bed_area_mm2"] > 100.0, rep
    rep = [x for x in m["modules"] if x["name"] == "clip"][0]["print_pose"]["clip_clip"]      # a flat plate (rivets apart)
    assert rep["supports_free"] and rep["pose"] in ("+z down", "-z down") and rep["bed_area_mm2"] > 100.0, rep
    hub = [x for x in m["modules"] if x["name"] == "hub"][0]["print_pose"]
    assert set(hub) == {"hub_hub_lower", "hub_hub_upper"} | {f"hub_hub_rivet_{k}" for k in range(1, 5)}
    for mod in m["modules"]:
        for part, rep in mod["print_pose"].items():
            assert rep["supports_free"], (part, rep)


def test_pose_report_on_known_shapes(fc):
    """Independent references: a box needs nothing; a mushroom (wide cap on a thin stem) needs support
    under the cap rim; a 45.5 deg overhang passes and a 44.5 deg one (flatter) does not; a short bridge
    between two walls passes, the same span as a cantilever does not."""
    import Part
    from metamaterial_wb.export.mesh import tessellate
    from metamaterial_wb.export.printpose import pose_report
    V_ = fc.Vector

    def rep(shape):
        P, T = tessellate(shape, 0.05)
        return pose_report(P, T)

    assert rep(Part.makeBox(10, 10, 5))["supports_free"]
    cap = Part.makeBox(10, 10, 2, V_(-5, -5, 5)).fuse(Part.makeBox(2, 2, 5, V_(-1, -1, 0)))
    r = rep(cap)
    assert not r["supports_free"] and r["unsupported_area_mm2"] == pytest.approx(100 - 4, abs=1e-6)
    for ang, ok in ((45.5, True), (44.5, False)):     # angle of the underside from the horizontal
        h = 5.0
        run = h / math.tan(math.radians(ang))
        w = Part.makePolygon([V_(0, 0, 0), V_(5, 0, 0), V_(5 + run, 0, h), V_(0, 0, h), V_(0, 0, 0)])
        wedge = Part.Face(w).extrude(V_(0, 10, 0))
        assert rep(wedge)["supports_free"] is ok, ang
    bridge = Part.makeBox(12, 5, 6).cut(Part.makeBox(8, 7, 4, V_(2, -1, 0)))
    assert rep(bridge)["supports_free"] and rep(bridge)["widest_bridge_mm"] == pytest.approx(8.0)
    shelf = Part.makeBox(2, 5, 6).fuse(Part.makeBox(8, 5, 2, V_(2, 0, 4)))
    assert not rep(shelf)["supports_free"]
    long_bridge = Part.makeBox(16, 5, 6).cut(Part.makeBox(12, 7, 4, V_(2, -1, 0)))
    assert not rep(long_bridge)["supports_free"]
    # a 0.5 mm ledge ring (a snap barb) prints; a 2 mm one does not
    for rim, ok in ((0.5, True), (2.0, False)):
        pin = Part.makeCylinder(1.5, 4).fuse(Part.makeCylinder(1.5 + rim, 1, V_(0, 0, 4)))
        assert rep(pin)["supports_free"] is ok, rim


def test_manifest_rivets_print_lying(built):
    """The riveted modules (servo housing + horn adapter, friction pad, stable hub, clip, connection hub) list
    their rivet pins: one per socket, each its own
    part in the module's 3MF, in the pose the manifest names, lying (height under half its length) and
    supports-free, with the designed strain within the limit and bending along the layers."""
    out, m = built
    for name in ("servo", "pad", "stable", "clip", "hub"):
        mod = [x for x in m["modules"] if x["name"] == name][0]
        rv = mod["rivets"]
        assert rv["count"] == len(mod["sockets"]) == len(rv["parts"]) == 4
        assert rv["ends"] == (2 if name == "hub" else 1)
        assert rv["inserted_from"] == ("sheet" if name == "servo" else "module")     # servo: blind rivets
        assert "note" not in mod
        assert rv["strain"] == pytest.approx(mod["snap_fit"]["strain"], rel=1e-6) and rv["strain"] <= rv["limit"]
        assert "along the layers" in rv["bending"] == mod["snap_fit"]["bending"]
        meshes = read_3mf_meshes(out / f"w_{name}.3mf")
        for part, pose in zip(rv["parts"], rv["print_pose"]):
            rep = mod["print_pose"][part]
            assert rep["pose"] == pose and rep["supports_free"], (part, rep)
            V, _ = meshes[part]
            ext = np.ptp(V, axis=0)
            assert ext[2] < 0.5 * max(ext[0], ext[1]), (part, ext)
