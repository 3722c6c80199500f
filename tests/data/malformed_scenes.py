"""Corpus of malformed scenes: (id, scene text or dict, expected field substring, expected message regex).

Each entry states the error a user must get. Used by tests/unit/test_scene.py (library) and
tests/unit/test_cli.py (exit status 2, one line on stderr, no output file).
"""

BASE = {"format": "metamaterial-scene", "version": 1, "layout": {"grid": [2, 3]}}


def scene(**kw):
    d = dict(BASE)
    d.update(kw)
    return d


CORPUS = [
    ("not-json", "{\"format\": \"metamaterial-scene\", ", "", r"not valid JSON"),
    ("not-object", [1, 2, 3], "", r"JSON object"),
    ("wrong-format", scene(format="stl"), "format", r"'stl' is not a scene"),
    ("wrong-version", scene(version=7), "version", r"7 is not supported"),
    ("cell-size-zero", scene(cell_size_mm=0), "cell_size_mm", r"0 mm is outside the allowed range \[1\.0, 1000\.0\]"),
    ("cell-size-string", scene(cell_size_mm="20"), "cell_size_mm", r"expected a number"),
    ("hinge-not-object", scene(hinge=3), "hinge", r"expected an object"),
    ("hinge-unknown-field", scene(hinge={"colour": "red"}), "hinge.colour", r"unknown hinge field"),
    ("hinge-too-long", scene(hinge={"length_mm": 12}), "hinge.length_mm", r"12(\.0)? mm is outside the allowed range \(0\.0, 10\.0\)"),
    ("hinge-negative-width", scene(hinge={"width_mm": -1}), "hinge.width_mm", r"-1(\.0)? mm is outside"),
    ("hinge-nan-thickness", scene(hinge={"thickness_mm": float("nan")}), "hinge.thickness_mm", r"expected a number|not a finite"),
    ("layout-missing-kind", scene(layout={}), "layout", r"give exactly one of"),
    ("layout-two-kinds", scene(layout={"grid": [1, 2], "chain": 3}), "layout", r"give exactly one of"),
    ("grid-zero", scene(layout={"grid": [0, 3]}), "layout.grid", r"both cell counts must be >= 1"),
    ("grid-float", scene(layout={"grid": [2.5, 3]}), "layout.grid", r"expected \[rows, columns\]"),
    ("chain-negative", scene(layout={"chain": -2}), "layout.chain", r"expected a cell count >= 1"),
    ("cells-empty", scene(layout={"cells": []}), "layout", r"no cells"),
    ("cells-duplicate", scene(layout={"cells": [[0, 0], [0, 1], [0, 1]]}), "layout.cells[2]", r"listed twice"),
    ("cells-negative", scene(layout={"cells": [[0, 0], [-1, 0]]}), "layout.cells[1]", r"negative index"),
    ("cells-bad-item", scene(layout={"cells": [[0, 0], [0]]}), "layout.cells[1]", r"expected \[row, column\]"),
    ("cells-lonely", scene(layout={"cells": [[0, 0], [0, 1], [2, 2]]}), "layout", r"cell \[2, 2\] shares no edge"),
    ("cells-disconnected", scene(layout={"cells": [[0, 0], [0, 1], [3, 0], [3, 1]]}), "layout", r"not connected"),
    ("cells-hole", scene(layout={"rows": ["###", "#.#", "###"]}), "layout", r"closed contour around the empty cell \[1, 1\]"),
    ("cells-hole-corner", scene(layout={"rows": ["###", "#.#", "##."]}), "layout", r"closed contour around the empty cell \[1, 1\]"),
    ("layout-unknown-key", scene(layout={"grid": [2, 6], "colour": 3}), "layout.colour", r"unknown field; allowed: grid, chain, cells, rows"),
    ("rows-bad-char", scene(layout={"rows": ["#?#"]}), "layout.rows[0]", r"character '\?'"),
    ("joints-not-list", scene(joints={"H0,0": 1}), "joints", r"expected a list"),
    ("joint-bad-name", scene(joints=[{"joint": "X0,0", "k1": 0.5}]), "joints[0].joint", r"not a joint name"),
    ("joint-missing", scene(joints=[{"joint": "H5,0", "k1": 0.5}]), "joints[0].joint", r"joint H5,0 does not exist"),
    ("joint-k1-high", scene(joints=[{"joint": "H0,0", "k1": 1.5}]), "joints[0].k1 (H0,0)", r"1\.5 is outside the allowed range \[0\.0, 1\.0\]"),
    ("joint-k2-zero", scene(joints=[{"joint": "V0,0", "k2": 0}]), "joints[0].k2 (V0,0)", r"0 is outside the allowed range \[1e-09, 1000000000\.0\]"),
    ("joint-unknown-field", scene(joints=[{"joint": "V0,0", "stiff": 2}]), "joints[0].stiff", r"unknown field"),
    ("joint-twice", scene(joints=[{"joint": "V0,0", "k1": 0.2}, {"joint": "V0,0", "k2": 2}]), "joints[1].joint", r"two override entries"),
    ("joint-length-too-long", scene(joints=[{"joint": "V0,0", "length_mm": 11}]), "joints[0] (V0,0).length_mm", r"11 mm is outside"),
    ("actuator-no-joint", scene(actuators=[{"name": "m1", "value": 0.5}]), "actuators[0].joint", r"missing"),
    ("actuator-value-high", scene(actuators=[{"name": "m1", "joint": "V0,0", "value": 1.5}]), "actuators[0].value (m1)", r"1\.5 is outside the allowed range \[-1\.0, 1\.0\]"),
    ("actuator-value-string", scene(actuators=[{"name": "m1", "joint": "V0,0", "value": "high"}]), "actuators[0].value (m1)", r"expected a number"),
    ("actuator-joint-outside", scene(actuators=[{"name": "m1", "joint": "V0,9", "value": 0.5}]), "actuators[0].joint", r"joint V0,9 does not exist"),
    ("actuator-bad-name", scene(actuators=[{"name": "1 bad", "joint": "V0,0"}]), "actuators[0].name", r"not a valid name"),
    ("actuator-duplicate-name", scene(actuators=[{"name": "m", "joint": "V0,0"}, {"name": "m", "joint": "V0,3"}]), "actuators[1].name", r"already used"),
    ("actuator-conflict", scene(actuators=[{"name": "a", "joint": "H0,0", "value": 0.5}, {"name": "b", "joint": "V0,1", "value": -0.2}]), "actuators.b", r"node N0,1"),
    ("actuators-same-joint", scene(actuators=[{"name": "a", "joint": "V0,1", "value": 0.3}, {"name": "b", "joint": "V0,1", "value": 0.3}]), "actuators[1].joint", r"V0,1 already carries actuators\[0\] \('a'\); at most one actuator or constraint per joint"),
    ("constraint-on-actuated-joint", scene(actuators=[{"name": "a", "joint": "V0,1", "value": 0.3}], constraints=[{"name": "c", "joint": "V0,1", "value": 0.3}]), "constraints[0].joint", r"already carries actuators\[0\] \('a'\)"),
    ("constraint-value-low", scene(constraints=[{"name": "c", "joint": "H1,1", "value": -2}]), "constraints[0].value (c)", r"-2 is outside"),
    ("constraint-conflicts-actuator", scene(actuators=[{"name": "a", "joint": "H0,0", "value": 0.5}], constraints=[{"name": "c", "joint": "H0,0", "value": 0.1}]), "constraints[0].joint", r"'a'"),
    ("profile-bad-shape", scene(actuators=[{"name": "m", "joint": "V0,0", "profile": {"shape": "square"}}]), "actuators[0].profile (m).shape", r"'square'; allowed"),
    ("profile-amplitude", scene(actuators=[{"name": "m", "joint": "V0,0", "profile": {"shape": "sine", "amplitude": 0.8, "offset": 0.5}}]), "actuators[0].profile (m)", r"must stay <= 1"),
    ("axes-bad-direction", scene(axes=[{"direction": "diagonal", "line": 1}]), "axes[0].direction", r"'diagonal'; allowed"),
    ("axes-bad-line", scene(axes=[{"direction": "vertical", "line": "1"}]), "axes[0].line", r"expected an integer"),
    ("global-out-of-range", scene(global_deformation=3), "global_deformation", r"3 is outside"),
    ("modules-not-list", scene(modules={"type": "pad"}), "modules", r"expected a list"),
    ("joint-config-bad-tilt", scene(joint_config={"H0,1": {"tilt_deg": 95}}), "joint_config.H0,1.tilt_deg", r"95 deg is outside"),
    # the belt and its gait are read inside `dynamics`; at the top level they were type-checked, then ignored
    # (belt8.json's belt moved up ran as a sheet and crawled 0 mm without a word)
    ("belt-top-level", scene(belt={"cell_length_mm": 38}), "belt", r"belongs inside 'dynamics' \(dynamics\.belt\)"),
    ("gait-top-level", scene(gait={"type": "closed_loop"}), "gait", r"belongs inside 'dynamics' \(dynamics\.gait\)"),
]
