"""Scene format: loading, layout rules, round trip and the malformed-scene corpus."""
import json
import os
import sys

import pytest

from metamaterial_wb import EXAMPLES_DIR
from metamaterial_wb.core.errors import SceneError
from metamaterial_wb.core.scene import Scene, Topology, parse_joint, validate_layout

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "data"))
from malformed_scenes import CORPUS  # noqa: E402


def test_corpus_is_large_and_unique():
    assert len(CORPUS) >= 30
    assert len({c[0] for c in CORPUS}) == len(CORPUS)


@pytest.mark.parametrize("case", CORPUS, ids=[c[0] for c in CORPUS])
def test_malformed_scene_gives_its_error(case):
    import re
    _id, data, field, pattern = case
    with pytest.raises(SceneError) as e:
        if isinstance(data, str):
            Scene.from_json(data)
        else:
            Scene.from_dict(data)
    assert e.value.field.startswith(field), (e.value.field, field)
    assert re.search(pattern, str(e.value)), str(e.value)


def test_grid_counts_match_seed():
    # R x C cells have (R+1) x (C+1) nodes; joints = R (C+1) vertical + (R+1) C horizontal
    for r, c in ((1, 1), (2, 6), (3, 3), (1, 8)):
        t = Topology([(i, j) for i in range(r) for j in range(c)])
        assert t.n_nodes == (r + 1) * (c + 1)
        assert t.n_joints == r * (c + 1) + (r + 1) * c


def test_joint_naming_follows_seed():
    t = Scene.grid(2, 3).topology
    k = t.joint_index["H1,2"]
    assert {t.nodes[t.joint_pairs[k][0]], t.nodes[t.joint_pairs[k][1]]} == {(1, 2), (1, 3)}
    k = t.joint_index["V0,3"]
    assert {t.nodes[t.joint_pairs[k][0]], t.nodes[t.joint_pairs[k][1]]} == {(0, 3), (1, 3)}
    assert parse_joint("h(1, 2)") == ("H", 1, 2)


def test_branched_layout_shares_nodes_and_hinges():
    # an L plus a branch: neighbouring cells share two nodes and one hinge
    cells = [(0, 0), (0, 1), (0, 2), (1, 1), (2, 1)]
    validate_layout([list(c) for c in cells])
    t = Topology(cells)
    assert t.n_nodes == 5 * 4 - 2 * 2 - 1 * 2 + 0 - 0 or t.n_nodes == len(t.nodes)
    # count directly: each cell adds 4 corners; shared edges remove 2 nodes each
    shared_edges = 4
    assert t.n_nodes == 4 * len(cells) - 2 * shared_edges
    assert t.n_joints == 4 * len(cells) - shared_edges


def test_layout_forms_equivalent():
    a = Scene.from_dict({"layout": {"grid": [1, 4]}})
    b = Scene.from_dict({"layout": {"chain": 4}})
    c = Scene.from_dict({"layout": {"cells": [[0, 3], [0, 1], [0, 0], [0, 2]]}})
    d = Scene.from_dict({"layout": {"rows": ["####"]}})
    assert a.cells == b.cells == c.cells == d.cells


def test_full_grid_is_not_a_hole():
    validate_layout([[i, j] for i in range(5) for j in range(5)])
    # U-shape open to the outside is fine
    validate_layout([[0, 0], [1, 0], [2, 0], [2, 1], [2, 2], [1, 2], [0, 2]])


def test_round_trip_keeps_everything(tmp_path):
    d = {"format": "metamaterial-scene", "version": 1, "name": "rt", "cell_size_mm": 25,
         "hinge": {"length_mm": 3, "width_mm": 1.0, "thickness_mm": 6},
         "layout": {"cells": [[0, 0], [0, 1], [1, 1]]},
         "joints": [{"joint": "H0,1", "k1": 0.9, "k2": 1.0}, {"joint": "V1,1", "length_mm": 4}],
         "axes": [{"direction": "vertical", "line": 1, "fold_deg": 30}],
         "actuators": [{"name": "m1", "joint": "V0,0", "value": 0.8,
                        "profile": {"shape": "sine", "amplitude": 0.5, "frequency_hz": 1, "phase_deg": 90}}],
         "constraints": [{"name": "c1", "joint": "H2,1", "value": -0.5}],
         "modules": [{"type": "friction_pad", "node": "N0,0"}],
         "my_tool": {"anything": [1, 2]}}
    s = Scene.from_dict(d)
    p = tmp_path / "s.json"
    p.write_text(s.to_json())
    s2 = Scene.load(str(p))
    assert s2.to_dict() == s.to_dict()
    assert s2.extra == {"my_tool": {"anything": [1, 2]}}
    assert s2.joint_hinge("V1,1")["length_mm"] == 4 and s2.joint_hinge("H0,1")["length_mm"] == 3


def test_minimal_contract_from_issue():
    s = Scene.from_json(json.dumps(
        {"format": "metamaterial-scene", "version": 1, "cell_size_mm": 20,
         "hinge": {"length_mm": 2, "width_mm": 0.8, "thickness_mm": 7}, "layout": {"grid": [2, 6]},
         "joints": [{"joint": "H0,1", "k1": 0.9, "k2": 1.0}],
         "actuators": [{"name": "m1", "joint": "V0,0", "value": 0.8}],
         "constraints": [{"joint": "H0,3", "value": -0.5}]}))
    assert s.topology.n_nodes == 21
    assert s.constraints[0].name == "c1"


def _example_scenes():
    out = []
    for f in sorted(os.listdir(EXAMPLES_DIR)):
        if f.endswith(".json"):
            with open(os.path.join(EXAMPLES_DIR, f)) as fh:
                if json.load(fh).get("format", "metamaterial-scene") == "metamaterial-scene":
                    out.append(f)
    return out


def test_examples_include_the_seed_scenes():
    names = _example_scenes()
    assert {"fish.json", "worm.json", "fish_axes.json", "gripper.json"} <= set(names)


@pytest.mark.parametrize("name", _example_scenes())
def test_examples_load(name):
    s = Scene.load(os.path.join(EXAMPLES_DIR, name))
    assert Scene.from_dict(s.to_dict()).to_dict() == s.to_dict()


def test_calibration_table_and_overrides():
    from metamaterial_wb.core.calibration import default_calibration, joint_stiffness
    cal = default_calibration()
    # monotone: longer hinges propagate less, wider hinges are stiffer
    ks = [cal.k1(L) for L in (0.5, 1, 2, 4, 8)]
    assert all(a > b for a, b in zip(ks, ks[1:])) and all(0 <= k <= 1 for k in ks)
    ws = [cal.k2(w, 7.0) for w in (0.4, 0.8, 1.2)]
    assert all(a < b for a, b in zip(ws, ws[1:]))
    # interpolation lies between table points
    t = cal.table["k1_vs_length"]
    mid = 0.5 * (t["length_mm"][3] + t["length_mm"][4])
    assert min(t["k1"][3], t["k1"][4]) <= cal.k1(mid) <= max(t["k1"][3], t["k1"][4])
    with pytest.raises(SceneError, match="length_mm"):
        cal.k1(50.0)
    s = Scene.from_dict({"layout": {"grid": [1, 2]}, "joints": [{"joint": "H0,0", "k1": 0.123},
                                                                {"joint": "H1,1", "length_mm": 4.0}]})
    k1, k2 = joint_stiffness(s)
    ti = s.topology.joint_index
    assert k1[ti["H0,0"]] == 0.123
    assert k1[ti["H1,1"]] == cal.k1(4.0)
    assert k1[ti["V0,0"]] == cal.k1(2.0)


def test_direct_stiffness_on_every_joint_needs_no_table_entry():
    from metamaterial_wb.core.calibration import joint_stiffness
    base = Scene.from_dict({"layout": {"chain": 2}})
    names = base.topology.joint_names
    # a 0.1 mm wide hinge is outside the table: fine when every joint gives k2 (and k1) directly
    s = Scene.from_dict({"layout": {"chain": 2}, "hinge": {"width_mm": 0.1},
                         "joints": [{"joint": n, "k1": 0.5, "k2": 2.0} for n in names]})
    k1, k2 = joint_stiffness(s)
    assert (k1 == 0.5).all() and (k2 == 2.0).all()
    # one joint without k2 needs the table again, and the error names the hinge width
    s = Scene.from_dict({"layout": {"chain": 2}, "hinge": {"width_mm": 0.1},
                         "joints": [{"joint": n, "k1": 0.5, "k2": 2.0} for n in names[1:]]})
    with pytest.raises(SceneError, match="width_mm"):
        joint_stiffness(s)
