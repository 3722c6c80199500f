"""One owner per quantity (issue 14): the plate side, the hinge sizes of a joint, the material colours
and their hex -> RGB conversion, the preference path and the tilt range are each defined in one place;
a second definition anywhere in the package fails here."""
import pathlib
import ast
import os
import re

import pytest

from metamaterial_wb import PACKAGE_DIR, PREFS_PATH, REPO_DIR
from metamaterial_wb.core.materials import MATERIALS, hex_to_rgb, material_rgb
from metamaterial_wb.core.errors import MetamaterialError
from metamaterial_wb.core.scene import Scene


def _files():
    for d, dirs, files in os.walk(PACKAGE_DIR):
        dirs[:] = [x for x in dirs if x != "__pycache__"]
        for f in files:
            if f.endswith(".py"):
                p = os.path.join(d, f)
                text = pathlib.Path(p).read_text(encoding="utf-8")
                yield os.path.relpath(p, REPO_DIR).replace(os.sep, "/"), text, ast.parse(text, p)


def _offenders(pred, owner):
    bad = []
    for rel, text, tree in _files():
        if rel == owner:
            continue
        for node in ast.walk(tree):
            if pred(node, text):
                bad.append(f"{rel}:{node.lineno}: {ast.get_source_segment(text, node)}")
    return bad


def test_plate_side_is_computed_in_one_place():
    """``cell - hinge length`` only in core/scene/names.py (Scene.plate_side_mm calls it)."""
    def pred(node, text):
        if not (isinstance(node, ast.BinOp) and isinstance(node.op, ast.Sub)):
            return False
        left, right = ast.get_source_segment(text, node.left) or "", ast.get_source_segment(text, node.right) or ""
        return bool(re.search(r"cell", left, re.I) and re.search(r"length|\blh\b|\blh0\b|hinge", right))
    assert _offenders(pred, "metamaterial_wb/core/scene/names.py") == []


def test_plate_side_and_hinge_sizes_agree_everywhere():
    from metamaterial_wb.core import kinematics
    from metamaterial_wb.core.fabrication import fabrication_params
    from metamaterial_wb.core.lattice.geometry import LatticeGeometry
    sc = Scene.from_dict({"layout": {"chain": 3}, "cell_size_mm": 25.0,
                          "hinge": {"length_mm": 5.0, "width_mm": 0.8, "thickness_mm": 7.0},
                          "joints": [{"joint": "H0,1", "length_mm": 3.0, "width_mm": 1.1}]})
    assert sc.plate_side_mm == 20.0
    assert kinematics.plate_side_mm(sc) == 20.0
    assert LatticeGeometry(sc).plate_side_mm == 20.0
    p = fabrication_params(sc)
    assert p.plate_side_mm_global == 20.0
    assert sc.hinge_sizes("H0,1") == {"length_mm": 3.0, "width_mm": 1.1, "thickness_mm": 7.0}
    assert sc.hinge_sizes("H0,0") == {"length_mm": 5.0, "width_mm": 0.8, "thickness_mm": 7.0}
    # the solver's arrays, the B-rep's specs and the scene agree joint by joint
    lh, wh, th = kinematics.joint_hinge_arrays(sc)
    for k, name in enumerate(sc.topology.joint_names):
        h = sc.hinge_sizes(name)
        assert (lh[k], wh[k], th[k]) == (h["length_mm"], h["width_mm"], h["thickness_mm"])
        spec = p.hinges[name]
        assert (spec.length_mm, spec.width_mm, spec.thickness_mm) == (h["length_mm"], h["width_mm"], h["thickness_mm"])


def test_material_colours_and_hex_parsing_have_one_owner():
    colours = {v.upper() for v in MATERIALS.values()}

    def colour_literal(node, text):
        return isinstance(node, ast.Constant) and isinstance(node.value, str) and node.value.upper() in colours

    def hex_parse(node, text):      # int(x, 16): parsing hex digits by hand
        return (isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id == "int"
                and len(node.args) == 2 and isinstance(node.args[1], ast.Constant) and node.args[1].value == 16)
    assert _offenders(colour_literal, "metamaterial_wb/core/materials.py") == []
    assert _offenders(hex_parse, "metamaterial_wb/core/materials.py") == []


def test_hex_to_rgb():
    assert hex_to_rgb("#1E64FF") == pytest.approx((30 / 255, 100 / 255, 1.0))
    assert hex_to_rgb("#000000ff") == (0.0, 0.0, 0.0)
    assert material_rgb("tpu") == hex_to_rgb(MATERIALS["TPU"])
    for bad in ("1E64FF", "#12345", "#GG0000", None):
        with pytest.raises(MetamaterialError, match="RRGGBB"):
            hex_to_rgb(bad)


def test_preference_path_and_tilt_range_have_one_owner():
    def pref_literal(node, text):
        return isinstance(node, ast.Constant) and node.value == PREFS_PATH

    def tilt_literal(node, text):   # the +-80 deg tilt range as a float literal
        return isinstance(node, ast.Constant) and type(node.value) is float and node.value == 80.0
    assert _offenders(pref_literal, "metamaterial_wb/__init__.py") == []
    assert _offenders(tilt_literal, "metamaterial_wb/core/scene/names.py") == []


def test_tilt_range_error_names_the_constant_range():
    from metamaterial_wb.core.errors import SceneError
    from metamaterial_wb.core.scene.names import MAX_TILT_DEG
    with pytest.raises(SceneError, match=re.escape(f"[-{MAX_TILT_DEG!r}, {MAX_TILT_DEG!r}]")):
        Scene.from_dict({"layout": {"chain": 2}, "joints": [{"joint": "H0,0", "tilt_deg": MAX_TILT_DEG + 1}]})
