"""A surface target in other units than mm is refused, as node positions are (docs/inverse.md): the diagonal of
the surface's bounding box must be 0.05 to 200 times that of the flat plates of the nodes matched to it (metres
give about 0.001). Through the CLI a bare .stl / .obj is named as --target with the file, nothing is written;
``align: similarity`` fits the scale and is not checked."""
import json

import numpy as np
import pytest

from clihelpers import one_line_error, run_cli
from metamaterial_wb.core.errors import MetamaterialError
from metamaterial_wb.core.inverse.targets import load_target, parse_target
from metamaterial_wb.core.scene import Scene

SCENE = {"format": "metamaterial-scene", "version": 1, "name": "scale-probe", "cell_size_mm": 20.0,
         "layout": {"grid": [3, 3]}, "actuators": [{"name": "a", "joint": "H1,1", "value": 0.0}]}


def _box(scale):
    """Triangles of a 60 x 60 x 100 box's four sides (a 30 mm radius, 100 mm cylinder's extent) times ``scale``."""
    c = np.array([[x, y, z] for x in (-30, 30) for y in (-30, 30) for z in (0, 100)], float) * scale
    quads = [(0, 1, 3, 2), (4, 5, 7, 6), (0, 1, 5, 4), (2, 3, 7, 6)]
    return [[c[a], c[b], c[d]] for a, b, d, _ in quads] + [[c[a], c[d], c[e]] for a, _, d, e in quads]


def _stl(path, tri):
    with open(path, "w", encoding="utf-8") as f:
        f.write("solid s\n")
        for t in tri:
            f.write(" facet normal 0 0 0\n  outer loop\n")
            f.writelines(f"   vertex {p[0]:.9g} {p[1]:.9g} {p[2]:.9g}\n" for p in t)
            f.write("  endloop\n endfacet\n")
        f.write("endsolid s\n")
    return path


@pytest.fixture
def scene_file(tmp_path):
    p = tmp_path / "scene.json"
    p.write_text(json.dumps(SCENE), encoding="utf-8")
    return p


def _inverse(scene_file, target, out):
    return run_cli("inverse", scene_file, "--target", target, "--servos", 1, "--out", out, "--no-picture",
                   "--evaluate", "quadratic", "--fab-checks", "off")


def test_metre_stl_is_refused_at_target_naming_file_scale_and_range(tmp_path, scene_file):
    stl = _stl(tmp_path / "cyl_m.stl", _box(0.001))           # a 30 mm / 100 mm shape exported in metres
    out = tmp_path / "out"
    r = _inverse(scene_file, stl, out)
    one_line_error(r, "--target")
    assert "cyl_m.stl" in r.stderr and "mm across" in r.stderr, r.stderr
    assert "allowed: 0.05 to 200 times" in r.stderr and "metres? give mm" in r.stderr, r.stderr
    assert not out.exists()


def test_tenth_mm_obj_triangle_is_refused(tmp_path, scene_file):
    obj = tmp_path / "tri.obj"
    obj.write_text("v 0 0 0\nv 0.1 0 0\nv 0 0.1 0\nf 1 2 3\n", encoding="utf-8")
    out = tmp_path / "out"
    r = _inverse(scene_file, obj, out)
    one_line_error(r, "--target")
    assert "tri.obj" in r.stderr and "0.05 to 200" in r.stderr, r.stderr
    assert not out.exists()


def test_scale_range_in_core_mm_accepted_similarity_unchecked(tmp_path):
    scene = Scene.from_dict(SCENE)
    assert load_target(scene, str(_stl(tmp_path / "mm.stl", _box(1.0)))).frames[0].surface is not None
    for scale in (0.001, 1000.0):                              # metres, micrometres
        path = str(_stl(tmp_path / f"s{scale:g}.stl", _box(scale)))
        with pytest.raises(MetamaterialError) as e:
            parse_target(scene, {"surface": {"file": path}})
        assert e.value.field == "surface" and "allowed: 0.05 to 200 times" in e.value.message
        assert parse_target(scene, {"surface": {"file": path}, "align": "similarity"}).frames[0].surface is not None
    with pytest.raises(MetamaterialError) as e:                # the nodes matched to it set the reference
        parse_target(scene, {"keyframes": [{"surface": {"triangles": [[[0, 0, 0], [0.5, 0, 0], [0, 0.5, 0]]],
                                                        "nodes": ["N0,0", "N0,1"]}}]})
    assert e.value.field == "keyframes[0].surface" and "2 sheet node(s)" in e.value.message
