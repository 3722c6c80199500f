"""No two parts of the assembly share material (``build --modules``: ``NAME_assembly.step`` holds every part at
its placement, the sheet flat): every module part (module bodies and their rivet pins) against every node and
hinge and every other module part, for every bundled example scene with modules.

The audit found the umbrella holder's clip rivets in its second node's sockets (``clip_clip_rivet_3`` / ``_4``)
28.4 and 12.1 mm3 inside ``node_1_0``: the clip is built holding its angle (its second plate and those rivets
turned about the joint's pivot), so they only go in once the joint is bent to it; the assembly showed them pushed
through the flat node's plate, where it has no hole. They now wait above their channels (part info
``lifted_mm``); :func:`test_clip_rivets_seat_in_the_held_state` checks that moved back by it they pass through
node B's sockets when node B is turned by the clip angle (the state the clip holds).

Each example is built and checked in a child process (a crash inside OpenCASCADE would kill the test run); a
bounding-box test skips the pairs whose boxes share less than the tolerance (an exact bound: two solids share
at most the volume their boxes share).
"""
import glob
import json
import os
import signal
import subprocess
import sys

FREECAD_LIB = "/usr/lib/freecad-python3/lib"
if __name__ == "__main__" and os.path.isdir(FREECAD_LIB) and FREECAD_LIB not in sys.path:
    sys.path.append(FREECAD_LIB)

import pytest  # noqa: E402

pytest.importorskip("FreeCAD")

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
TOL_MM3 = 1e-3              # geometry/validity.VOLUME_TOL_MM3


def _examples_with_modules():
    out = []
    for f in sorted(glob.glob(os.path.join(REPO, "examples", "*.json"))):
        with open(f, encoding="utf-8") as fh:
            d = json.load(fh)
        if d.get("format") == "metamaterial-scene" and d.get("modules"):
            out.append(os.path.basename(f)[:-5])
    return out


def _box_volume(a, b):
    """Volume the two bounding boxes share (0 when they only touch)."""
    d = [min(a.XMax, b.XMax) - max(a.XMin, b.XMin), min(a.YMax, b.YMax) - max(a.YMin, b.YMin),
         min(a.ZMax, b.ZMax) - max(a.ZMin, b.ZMin)]
    return max(d[0], 0.0) * max(d[1], 0.0) * max(d[2], 0.0)


def _overlaps(pairs):
    """``(checked, [(a, b, mm3)])`` of the ``[(name, shape, name, shape)]`` that share more than TOL_MM3."""
    checked, bad = 0, []
    for an, a, bn, b in pairs:
        if _box_volume(a.BoundBox, b.BoundBox) <= TOL_MM3:
            continue
        checked += 1
        v = a.common(b).Volume
        if v > TOL_MM3:
            bad.append((an, bn, round(v, 4)))
    return checked, bad


def probe(example):
    """Build ``example`` with its modules and check the assembled state and the clips' held state."""
    import FreeCAD
    import Part
    import metamaterial_wb
    from metamaterial_wb.core.scene import Scene
    from metamaterial_wb.geometry.build import build_scene

    V = FreeCAD.Vector
    res = build_scene(Scene.load(metamaterial_wb.example_path(example)), modules=True, progress=False)
    sheet = [(q, res.placed_shape(q)) for q in res.parts if q.group == "sheet"]
    mods = [(q, res.placed_shape(q)) for q in res.parts if q.role == "module"]
    pairs = [(mq.name, ms, sq.name, ss) for mq, ms in mods for sq, ss in sheet]
    pairs += [(aq.name, a, bq.name, b) for k, (aq, a) in enumerate(mods) for bq, b in mods[k + 1:]]
    checked, bad = _overlaps(pairs)
    out = {"modules": len(res.modules), "module_parts": len(mods), "checked": checked, "overlaps": bad,
           "clips": []}
    p = res.params
    s, T = p.plate_side_mm_global, p.sheet_thickness_mm
    for spec in res.modules:
        if spec.type != "constraint_clip":
            continue
        x, y, _ = spec.pivot.point_mm
        turn = FreeCAD.Placement(V(x, y, 0.0), FreeCAD.Rotation(V(0, 0, 1), spec.values["angle_deg"])).multiply(
            FreeCAD.Placement(V(-x, -y, 0.0), FreeCAD.Rotation()))
        name_b = f"N{spec.b[0]},{spec.b[1]}"
        nq, node = [(q, sh) for q, sh in sheet if q.info.get("node") == name_b][0]
        c = nq.placement.Base
        node_b = node.transformed(turn.toMatrix())
        plate_b = Part.makeBox(s, s, T, V(c.x - 0.5 * s, c.y - 0.5 * s, 0.0)).transformed(turn.toMatrix())
        for q, sh in mods:
            if q.group != spec.name or not q.info.get("rivet"):
                continue
            lift = q.info.get("lifted_mm", 0.0)
            seated = sh.transformed(FreeCAD.Placement(V(0, 0, -lift), FreeCAD.Rotation()).toMatrix())
            out["clips"].append({"part": q.name, "lifted_mm": lift, "in_node_b": seated.common(node_b).Volume,
                                 "in_plate_b": seated.common(plate_b).Volume})
    return out


def _run(example, tmp_path):
    out = tmp_path / f"{example}.json"
    env = dict(os.environ, MM_OVERLAP_PROBE=json.dumps([REPO, example, str(out)]))
    proc = subprocess.run([sys.executable, os.path.abspath(__file__)], capture_output=True, text=True, timeout=600,
                          cwd=str(tmp_path), env=env)
    if proc.returncode < 0:
        pytest.fail(f"{example}: the child died with {signal.Signals(-proc.returncode).name}\n{proc.stderr[-2000:]}")
    if not out.exists():
        pytest.fail(f"{example}: the child wrote nothing (exit {proc.returncode})\n{proc.stdout[-2000:]}\n"
                    f"{proc.stderr[-3000:]}")
    with open(out, encoding="utf-8") as fh:
        return json.load(fh)


EXAMPLES = _examples_with_modules()
_CACHE = {}


def _result(example, tmp_path):
    if example not in _CACHE:
        _CACHE[example] = _run(example, tmp_path)
    return _CACHE[example]


def test_the_examples_with_modules_include_the_umbrella_clip():
    assert "umbrella_holder" in EXAMPLES and len(EXAMPLES) >= 5, EXAMPLES


@pytest.mark.parametrize("example", EXAMPLES)
def test_no_two_assembled_parts_share_material(example, tmp_path):
    """Every module part against every sheet part and every other module part, at the assembly's placements."""
    r = _result(example, tmp_path)
    assert r["modules"] > 0 and r["module_parts"] > r["modules"] and r["checked"] > 0, r
    assert r["overlaps"] == [], f"{example}: parts that share material (mm3): {r['overlaps']}"


def test_clip_rivets_seat_in_the_held_state(tmp_path):
    """The umbrella clip's rivets, moved back onto their seats (``lifted_mm``), pass through the sockets of node
    B turned by the clip angle about the pivot: each runs through the plate's outline (more than 5 mm3 of it
    there) and shares no material with the node. The two in node B's sockets are the ones the assembly lifts."""
    r = _result("umbrella_holder", tmp_path)
    rivets = {c["part"]: c for c in r["clips"]}
    assert sorted(rivets) == [f"clip_clip_rivet_{k}" for k in (1, 2, 3, 4)], rivets
    for name in ("clip_clip_rivet_3", "clip_clip_rivet_4"):
        c = rivets[name]
        assert c["lifted_mm"] > 0.0, c
        assert c["in_plate_b"] > 5.0 and c["in_node_b"] < TOL_MM3, c
    assert all(rivets[f"clip_clip_rivet_{k}"]["lifted_mm"] == 0.0 for k in (1, 2)), rivets


if __name__ == "__main__":
    _repo, _example, _out = json.loads(os.environ["MM_OVERLAP_PROBE"])
    if sys.path[0] != _repo:
        sys.path.insert(0, _repo)
    _res = probe(_example)
    with open(_out, "w", encoding="utf-8") as _fh:
        json.dump(_res, _fh)
