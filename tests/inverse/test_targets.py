"""Bad targets get a clear error naming the field and the value (exit 2 from the CLI, no output)."""
import json
import math
import os

import numpy as np
import pytest

from inverse_helpers import grid_surface, planted_result, scene_with, write_stl
from metamaterial_wb import REPO_DIR
from metamaterial_wb.core.errors import MetamaterialError
from metamaterial_wb.core.inverse.surface import Surface, load_mesh
from metamaterial_wb.core.inverse.targets import load_target, parse_target
from metamaterial_wb.core.scene import Scene

GRID_FOLD = os.path.join(REPO_DIR, "examples", "grid_fold.json")


@pytest.fixture
def scene():
    return scene_with(Scene.grid(4, 4), [("H0,0", 0.5)])


@pytest.mark.parametrize("doc,words", [
    ({}, "empty"),
    ({"nodes": []}, "non-empty"),
    ({"keyframes": []}, "non-empty"),
    ({"nodes": [{"name": "N0,0", "position_mm": [0, float("nan"), 0]}]}, "NaN"),
    ({"nodes": [{"name": "N9,0", "position_mm": [0, 0, 0]}]}, "N9,0"),
    ({"nodes": [{"name": "N0,0", "position_mm": [0, 0]}]}, "position_mm"),
    ({"nodes": [{"name": "N0,0", "position_mm": [0, 0, 0]}, {"name": "N0,0", "position_mm": [1, 0, 0]}]},
     "already given"),
    ({"folds": [{"joint": "H9,9", "fold_deg": 10}]}, "H9,9"),
    ({"folds": [{"joint": "H0,0", "fold_deg": 10}]}, "unreachable"),
    ({"folds": [{"axis": "nope", "fold_deg": 10}]}, "not an axis"),
    ({"nodes": [{"name": "N0,0", "position_mm": [0, 0, 0]}], "align": "affine"}, "affine"),
    ({"format": "metamaterial-scene"}, "format"),
    ({"keyframes": [{"time_s": 1, "folds": [{"joint": "H0,0", "fold_deg": 0}]},
                    {"time_s": 1, "folds": [{"joint": "H0,0", "fold_deg": 0}]}]}, "increase"),
])
def test_bad_target_documents(scene, doc, words):
    with pytest.raises(MetamaterialError) as e:
        parse_target(scene, doc)
    assert words in str(e.value)


def test_keyframes_shared_align_is_named_where_it_is_written(scene):
    """A bad top-level ``align`` shared by every keyframe is named as ``align``, not as keyframes[0]'s own."""
    doc = {"align": "affine", "keyframes": [{"time_s": 0, "nodes": [{"name": "N0,0", "position_mm": [0, 0, 0]}]}]}
    with pytest.raises(MetamaterialError) as e:
        parse_target(scene, doc)
    assert e.value.field == "align" and "'affine'; allowed:" in str(e.value)


def test_unreachable_fold_names_the_range():
    s = scene_with(GRID_FOLD, [("V1,0", 0.5)])
    with pytest.raises(MetamaterialError) as e:
        parse_target(s, {"folds": [{"axis": "left_wall", "fold_deg": -150}]})
    msg = str(e.value)
    assert "unreachable" in msg and "-150" in msg and "reachable range" in msg


@pytest.mark.parametrize("where,wrap", [("surface", lambda f: f),
                                        ("keyframes[0].surface", lambda f: {"keyframes": [dict(f, time_s=0)]})])
def test_a_node_repeated_in_a_surface_target_is_refused_like_a_repeated_target_node(where, wrap):
    """docs/inverse.md: repeated node names are errors. A node listed twice in ``surface.nodes`` was counted twice
    (double weight, twice in the report's per_node); it is refused with the words of a repeated ``nodes[]`` entry."""
    s = Scene.load(GRID_FOLD)
    frame = {"surface": {"triangles": [[[0, 0, 0], [300, 0, 0], [0, 300, 0]]], "nodes": ["N0,0", "N0,0", "N1,1"]}}
    with pytest.raises(MetamaterialError) as e:
        parse_target(s, wrap(frame))
    assert e.value.field == f"{where}.nodes[1]"
    assert e.value.message == f"node 'N0,0' is already given by {where}.nodes[0]"
    frame["surface"]["nodes"] = ["N0,0", [0, 0]]                  # the same node by its [i, j]
    with pytest.raises(MetamaterialError, match=r"node \[0, 0\] is already given by .*surface\.nodes\[0\]"):
        parse_target(s, wrap(frame))
    frame["surface"]["nodes"] = ["N0,0", "N1,1"]
    tgt = parse_target(s, wrap(frame))
    assert len(tgt.frames[0].surface.idx) == 2


def test_a_surface_far_from_the_sheet_names_the_distance_and_the_allowed_one(tmp_path, scene):
    """The refusal does not claim the alignment is a local refinement (it is global: docs/inverse.md); it names
    the distance, the allowed one and what to do."""
    res = planted_result(scene)
    pos = np.array([n["position_mm"] for n in res["nodes"]])
    far = tmp_path / "far.stl"
    write_stl(far, grid_surface(scene, pos) + [5000, 0, 0])
    with pytest.raises(MetamaterialError) as e:
        load_target(scene, str(far))
    msg = str(e.value)
    assert "local" not in msg
    assert "from the flat sheet" in msg and "allowed: at most half the sheet's diagonal" in msg
    assert "place the surface over the sheet" in msg


def test_surface_far_from_the_sheet_and_empty_files(tmp_path, scene):
    res = planted_result(scene)
    pos = np.array([n["position_mm"] for n in res["nodes"]])
    far = tmp_path / "far.stl"
    write_stl(far, grid_surface(scene, pos) + [5000, 0, 0])
    with pytest.raises(MetamaterialError, match="from the flat sheet"):
        load_target(scene, str(far))
    empty = tmp_path / "empty.obj"
    empty.write_text("# nothing\n")
    with pytest.raises(MetamaterialError, match="no triangles"):
        load_target(scene, str(empty))
    with pytest.raises(MetamaterialError, match="does not exist"):
        load_target(scene, str(tmp_path / "missing.stl"))
    bad = tmp_path / "bad.json"
    bad.write_text("{nope")
    with pytest.raises(MetamaterialError, match="not valid JSON"):
        load_target(scene, str(bad))


def test_stl_binary_ascii_and_obj_read_the_same_triangles(tmp_path, scene):
    res = planted_result(scene)
    tri = grid_surface(scene, np.array([n["position_mm"] for n in res["nodes"]]))
    write_stl(tmp_path / "a.stl", tri)
    import struct
    with open(tmp_path / "b.stl", "wb") as f:
        f.write(b"\0" * 80 + struct.pack("<I", len(tri)))
        for t in tri:
            f.write(struct.pack("<12fH", 0, 0, 0, *t.ravel(), 0))
    verts = tri.reshape(-1, 3)
    with open(tmp_path / "c.obj", "w") as f:
        f.writelines(f"v {float(v[0])!r} {float(v[1])!r} {float(v[2])!r}\n" for v in verts)
        f.writelines(f"f {3 * k + 1} {3 * k + 2}/1 {3 * k + 3}//2\n" for k in range(len(tri)))
    a, b, c = (load_mesh(str(tmp_path / n)) for n in ("a.stl", "b.stl", "c.obj"))
    assert np.allclose(a, tri) and np.allclose(c, tri) and np.allclose(b, tri, atol=1e-4)


def test_closest_points_against_brute_force_sampling():
    rng = np.random.default_rng(0)
    tri = rng.normal(size=(40, 3, 3)) * 10
    surf = Surface(tri)
    q = rng.normal(size=(30, 3)) * 12
    cp, N = surf.closest(q)
    d = np.linalg.norm(q - cp, axis=1)
    # dense barycentric sampling of every triangle: no sample is closer than the exact answer
    u, v = np.meshgrid(np.linspace(0, 1, 41), np.linspace(0, 1, 41))
    keep = u + v <= 1
    u, v = u[keep], v[keep]
    samples = (tri[:, None, 0] + u[None, :, None] * (tri[:, None, 1] - tri[:, None, 0])
               + v[None, :, None] * (tri[:, None, 2] - tri[:, None, 0])).reshape(-1, 3)
    ds = np.linalg.norm(q[:, None] - samples[None], axis=2).min(axis=1)
    assert np.all(d <= ds + 1e-9) and np.all(ds - d < 0.5)
    # N is the derivative of the distance vector (central differences, generic points)
    h = 1e-6
    for i in range(5):
        for c in range(3):
            e = np.zeros(3)
            e[c] = h
            rp = q[i] + e - surf.closest(q[i] + e)[0][0]
            rm = q[i] - e - surf.closest(q[i] - e)[0][0]
            assert np.allclose((rp - rm) / (2 * h), N[i][:, c], atol=1e-6)


def test_step_surface_through_freecad(tmp_path, scene):
    """A STEP target is read through FreeCAD and tessellated (CLI mesh loader); skipped without FreeCAD."""
    import subprocess
    import sys
    code = ("import sys; sys.path.append('/usr/lib/freecad-python3/lib'); import FreeCAD, Part; "
            f"Part.makeBox(80, 80, 1, FreeCAD.Vector(-10, -70, -1)).exportStep({str(tmp_path / 'plate.step')!r})")
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    if p.returncode != 0:
        pytest.skip(f"FreeCAD not usable here: {p.stderr[-200:]}")
    from metamaterial_wb.geometry.surface import load_surface_mesh
    t = load_target(scene, str(tmp_path / "plate.step"), mesh_loader=load_surface_mesh)
    tri = t.frames[0].surface.surface.tri
    lo, hi = tri.reshape(-1, 3).min(0), tri.reshape(-1, 3).max(0)
    assert np.allclose(lo, [-10, -70, -1], atol=1e-6) and np.allclose(hi, [70, 10, 0], atol=1e-6)
